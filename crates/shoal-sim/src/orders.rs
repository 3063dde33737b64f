//! What an order from outside the world may ask of a vehicle, whoever gives it — an external
//! agent (`agents`) or a binding that commands the whole swarm at once (`batch`): a frame for
//! its modems ([`FrameOrder`]) and the limits every such order is checked against
//! ([`force_limit`], [`check_frame`], [`MAX_FRAME_DELAY`]). Both kinds of command take their
//! rules from here, so they have one source; agents clamp a value outside them, the whole-swarm
//! commands refuse it unless asked to clip.

use crate::comm::OutFrame;
use shoal_model::optics::ModemParams;
use shoal_model::vehicle::VehicleModel;
use std::fmt;

/// A frame handed to a vehicle's modems from outside the world (by an agent or a whole-swarm
/// command).
#[derive(Clone, Debug, PartialEq)]
pub struct FrameOrder {
    /// Modem index, or `None` for all modems in sync.
    pub modem: Option<usize>,
    /// Payload bytes.
    pub payload: Vec<u8>,
    /// Delay after the moment the frame is handed over (an agent's control tick, or now for a
    /// whole-swarm command), 0 … [`MAX_FRAME_DELAY`] \[s\].
    pub delay: f64,
    /// Destination vehicle id, or `None` for a broadcast.
    pub to: Option<u32>,
    /// With a destination: acknowledged, and retransmitted until it is (stop-and-wait ARQ);
    /// its outcome comes back as a [`crate::comm::FrameEvent`] carrying `tag`.
    pub ack: bool,
    /// A number of the sender's choosing, returned with the frame's outcome.
    pub tag: u32,
}

impl FrameOrder {
    /// A broadcast of `payload` on `modem` (`None`: all), `delay` \[s\] after hand-over.
    pub fn broadcast(modem: Option<usize>, payload: Vec<u8>, delay: f64) -> Self {
        Self {
            modem,
            payload,
            delay,
            to: None,
            ack: false,
            tag: 0,
        }
    }

    /// The frame for the modems, handed over at `t` \[s\] (the delay clamped to
    /// 0 … [`MAX_FRAME_DELAY`]).
    pub fn out_frame(&self, t: f64) -> OutFrame {
        OutFrame {
            modem: self.modem,
            payload: self.payload.clone(),
            ready: t + self.delay.clamp(0.0, MAX_FRAME_DELAY),
            to: self.to,
            ack: self.ack,
            tag: self.tag,
        }
    }
}

/// Who a frame may be addressed to: the sender and the number of vehicles in the world.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Peers {
    /// The sending vehicle's id.
    pub me: u32,
    /// Vehicles in the world (ids 0 … count − 1).
    pub count: usize,
}

/// Largest |surge| or |sway| force a command may ask for \[N\]: the sum of every thruster's
/// larger thrust limit (more than the vehicle can produce in any direction).
pub fn force_limit(m: &VehicleModel) -> f64 {
    m.params
        .thrusters
        .iter()
        .map(|t| {
            let (a, b) = t.curve.limits(t.max_command);
            a.max(b)
        })
        .sum()
}

/// Why a frame cannot be sent by a vehicle (see [`check_frame`]).
#[derive(Clone, Debug, PartialEq)]
pub enum FrameProblem {
    /// The vehicle has no modem.
    NoModem,
    /// The modem index is not one of the vehicle's (it has `count`).
    UnknownModem {
        /// The index asked for.
        modem: usize,
        /// The vehicle's number of modems.
        count: usize,
    },
    /// The payload is empty or longer than the modem(s) carry.
    Length {
        /// Payload length \[bytes\].
        len: usize,
        /// Longest payload of the modem (all modems: the smallest limit) \[bytes\].
        max: usize,
    },
    /// The delay is NaN or infinite.
    Delay,
    /// The destination is not another vehicle of the world.
    Destination {
        /// The destination asked for.
        to: u32,
        /// The sender.
        me: u32,
        /// Vehicles in the world.
        count: usize,
    },
    /// An acknowledgement was asked for a broadcast.
    AckWithoutDestination,
}

impl fmt::Display for FrameProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NoModem => write!(f, "the vehicle has no modem"),
            Self::UnknownModem { modem, count } => write!(
                f,
                "modem {modem} does not exist (the vehicle has {count}: 0 … {})",
                count.saturating_sub(1)
            ),
            Self::Length { len, max } => write!(
                f,
                "payload of {len} bytes: allowed 1 … {max} bytes for this modem"
            ),
            Self::Delay => write!(f, "the delay is not a finite number of seconds"),
            Self::Destination { to, me, count } if to == me => write!(
                f,
                "destination {to} is the sending vehicle itself (allowed: another vehicle, 0 … {})",
                count.saturating_sub(1)
            ),
            Self::Destination { to, count, .. } => write!(
                f,
                "destination vehicle {to} does not exist (the world has 0 … {})",
                count.saturating_sub(1)
            ),
            Self::AckWithoutDestination => write!(
                f,
                "an acknowledgement needs a destination: a broadcast is never acknowledged"
            ),
        }
    }
}

/// Checks that a vehicle with modems `modems` can send `frame` to its destination among
/// `peers` (the rules of agents' frames).
pub fn check_frame(
    modems: &[ModemParams],
    frame: &FrameOrder,
    peers: Peers,
) -> Result<(), FrameProblem> {
    if modems.is_empty() {
        return Err(FrameProblem::NoModem);
    }
    let max = match frame.modem {
        Some(k) => match modems.get(k) {
            Some(m) => m.max_payload,
            None => {
                return Err(FrameProblem::UnknownModem {
                    modem: k,
                    count: modems.len(),
                });
            }
        },
        None => modems.iter().map(|m| m.max_payload).min().unwrap_or(0),
    };
    if frame.payload.is_empty() || frame.payload.len() > max {
        return Err(FrameProblem::Length {
            len: frame.payload.len(),
            max,
        });
    }
    if !frame.delay.is_finite() {
        return Err(FrameProblem::Delay);
    }
    match frame.to {
        Some(to) if to == peers.me || to as usize >= peers.count => {
            Err(FrameProblem::Destination {
                to,
                me: peers.me,
                count: peers.count,
            })
        }
        None if frame.ack => Err(FrameProblem::AckWithoutDestination),
        _ => Ok(()),
    }
}

/// Longest delay of a frame after the moment it is queued \[s\] (agents' frames are clamped
/// to it).
pub const MAX_FRAME_DELAY: f64 = 1.0;
