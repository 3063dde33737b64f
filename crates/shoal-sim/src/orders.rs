//! What an order from outside the world may ask of a vehicle, whoever gives it — an external
//! agent (`agents`) or a binding that commands the whole swarm at once (`batch`): a frame for
//! its modems ([`FrameOrder`]) and the limits every such order is checked against
//! ([`force_limit`], [`check_frame`], [`MAX_FRAME_DELAY`]). Both kinds of command take their
//! rules from here, so they have one source; agents clamp a value outside them, the whole-swarm
//! commands refuse it unless asked to clip.

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
        }
    }
}

/// Checks that a vehicle with modems `modems` can send `frame` (the rules of agents' frames).
pub fn check_frame(modems: &[ModemParams], frame: &FrameOrder) -> Result<(), FrameProblem> {
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
    Ok(())
}

/// Longest delay of a frame after the moment it is queued \[s\] (agents' frames are clamped
/// to it).
pub const MAX_FRAME_DELAY: f64 = 1.0;
