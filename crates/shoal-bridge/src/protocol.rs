//! The wire protocol, version [`PROTOCOL_VERSION`]: two `#[repr(C)]` message types exchanged
//! as slices over iceoryx2 publish–subscribe services, per agent and per world:
//!
//! | service | publisher → subscriber | payload |
//! |---|---|---|
//! | `shoal/<prefix>/<agent>/obs` | world → agent | `[Observation]`, one per vehicle of the agent whose control tick it is |
//! | `shoal/<prefix>/<agent>/cmd` | agent → world | `[Command]`, at least one, each for one of the agent's vehicles |
//!
//! Every element carries the protocol version, the vehicle id and the physics step of the
//! observation it belongs to. A reply answers step `s` when its elements carry `step = s`; in
//! lock-step the world waits for that reply. The last observation slice of a run has
//! [`flags::END`] set: agents then leave (the world waits briefly for them, an acknowledged
//! shutdown). All numbers are SI (m, rad, s, N, W); angles in radians.
//!
//! The Python package (`python/shoal/agent/protocol.py`) is generated from [`layout`] by
//! `cargo run -p shoal-bridge --example gen_python`, and a test compares its ctypes offsets with
//! these structs'. iceoryx2 matches types across languages only by name, size and alignment,
//! so the layout is checked field by field, never trusted.
//!
//! Version 2 added addressed frames: a [`Frame`] to send names its destination (`peer`, or
//! [`BROADCAST`]), may ask for an acknowledgement ([`frame_flags::ACK`]: stop-and-wait ARQ,
//! `docs/mac.md`) and carries a `tag` of the agent's choosing; a received frame names its
//! sender and says whether it was addressed to this vehicle ([`frame_flags::UNICAST`]); an
//! [`Observation`] reports what became of the vehicle's acknowledged frames ([`Outcome`]).

use iceoryx2::prelude::ZeroCopySend;

/// Version of this protocol; a message with another version is rejected and counted.
pub const PROTOCOL_VERSION: u32 = 2;
/// Payload capacity of one frame \[bytes\] (a μAUV² modem carries at most 58).
pub const FRAME_BYTES: usize = 64;
/// Received frames per observation; more are counted in `frames_dropped`.
pub const MAX_RX_FRAMES: usize = 8;
/// Frames an agent may send per command.
pub const MAX_TX_FRAMES: usize = 4;
/// Thruster commands per command (vehicles with more cannot be driven raw).
pub const MAX_THRUSTERS: usize = 8;
/// Tilt drives per observation and command.
pub const MAX_TILTS: usize = 4;
/// `Frame::modem` value for "all modems in sync" (sending only).
pub const ALL_MODEMS: u8 = 255;
/// `Frame::peer` value of a frame to send to everyone in range (a broadcast).
pub const BROADCAST: u32 = u32::MAX;
/// Outcomes of acknowledged frames per observation; more are counted in `outcomes_dropped`.
pub const MAX_OUTCOMES: usize = 4;

/// Bits of [`Observation::flags`].
pub mod flags {
    /// `position` holds the true position (the world grants it).
    pub const POSITION: u32 = 1;
    /// The buoyancy tank's full switch is closed.
    pub const TANK_FULL: u32 = 2;
    /// The vehicle is under the world's fallback (its agent was absent or late).
    pub const FALLBACK: u32 = 4;
    /// The run is over: do not answer, leave.
    pub const END: u32 = 8;
}

/// Bits of [`Frame::flags`].
pub mod frame_flags {
    /// To send: ask the destination for an acknowledgement, and retransmit until it comes
    /// (at most the modem's `arq_retries` times); the frame's end comes back as an
    /// [`Outcome`](super::Outcome). Needs a destination (`peer` not
    /// [`BROADCAST`](super::BROADCAST)).
    pub const ACK: u8 = 1;
    /// Received: the frame was addressed to this vehicle alone (a unicast), not broadcast.
    /// Ignored when sending.
    pub const UNICAST: u8 = 2;
}

/// Values of [`Command::kind`].
pub mod kind {
    /// Keep the setpoints in force (frames are still sent).
    pub const KEEP: u32 = 0;
    /// Controller mode `mode` with `depth`, `yaw`, `surge`, `sway`.
    pub const MODE: u32 = 1;
    /// Raw actuator commands `thrusters`, `tilts`, `pump`.
    pub const RAW: u32 = 2;
    /// The agent detaches: sent alone, in a one-element slice, as it closes (`vehicle` and
    /// `step` are ignored). The world answers with an observation slice flagged
    /// [`flags::END`](super::flags::END), records `left` (not `gone`) and puts the agent's
    /// vehicles under the fallback.
    pub const LEAVE: u32 = 3;
}

/// Values of [`Command::mode`] (the μAUV² paper's modes).
pub mod mode {
    /// Everything off.
    pub const OFF: u32 = 0;
    /// Mode 1: heave only.
    pub const DIVING: u32 = 1;
    /// Mode 2: heave with the buoyancy pump.
    pub const BUOYANCY: u32 = 2;
    /// Mode 3: yaw only.
    pub const TURNING: u32 = 3;
    /// Mode 4: yaw, surge and sway.
    pub const DRIFT: u32 = 4;
    /// Mode 5: depth, heading and surge together.
    pub const AUTO: u32 = 5;
}

/// One optical frame, received or to send.
#[derive(Debug, Clone, Copy, ZeroCopySend)]
#[type_name("shoal_Frame")]
#[repr(C)]
pub struct Frame {
    /// Received: end of reception \[s\]. To send: delay after the tick \[s\], 0…1.
    pub t: f64,
    /// Received: optical power at the receiving modem \[W\]. To send: unused.
    pub power: f64,
    /// Payload length \[bytes\], ≤ [`FRAME_BYTES`] and ≤ the modem's payload limit.
    pub len: u16,
    /// Modem index on the vehicle; to send, [`ALL_MODEMS`] for all in sync.
    pub modem: u8,
    /// Bits of [`frame_flags`]: to send, [`frame_flags::ACK`]; received,
    /// [`frame_flags::UNICAST`].
    pub flags: u8,
    /// To send: the destination vehicle id, or [`BROADCAST`]. Received: the sending vehicle's
    /// id.
    pub peer: u32,
    /// To send: a number of the agent's choosing, returned with the frame's [`Outcome`].
    /// Received: 0 (tags stay with their sender).
    pub tag: u32,
    /// Received: the sender's sequence number of the frame (its [`Outcome::seq`] at the
    /// sender). To send: unused (the world numbers frames).
    pub seq: u32,
    /// Payload (the first `len` bytes).
    pub data: [u8; FRAME_BYTES],
}

impl Frame {
    /// An empty frame (a broadcast).
    pub const EMPTY: Frame = Frame {
        t: 0.0,
        power: 0.0,
        len: 0,
        modem: 0,
        flags: 0,
        peer: BROADCAST,
        tag: 0,
        seq: 0,
        data: [0; FRAME_BYTES],
    };

    /// The payload bytes (at most [`FRAME_BYTES`], whatever `len` claims).
    pub fn payload(&self) -> &[u8] {
        &self.data[..(self.len as usize).min(FRAME_BYTES)]
    }

    /// Received: whether it was addressed to this vehicle alone ([`frame_flags::UNICAST`]).
    pub fn is_unicast(&self) -> bool {
        self.flags & frame_flags::UNICAST != 0
    }
}

/// What became of one of the vehicle's frames sent with [`frame_flags::ACK`]: acknowledged
/// by its destination, or given up after the modem's retries.
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("shoal_Outcome")]
#[repr(C)]
pub struct Outcome {
    /// When it ended: the acknowledgement decoded, or the wait after the last transmission
    /// ran out \[s\].
    pub t: f64,
    /// When it was handed over to the modems (the tick plus the frame's delay) \[s\].
    pub sent: f64,
    /// Its destination vehicle id.
    pub to: u32,
    /// The tag the agent gave it.
    pub tag: u32,
    /// The sender's sequence number of the frame (the destination sees it as
    /// [`Frame::seq`]).
    pub seq: u32,
    /// Times it went on the air: 1 + retransmissions (0: refused by a full transmit queue).
    pub transmissions: u32,
    /// 1: acknowledged; 0: given up.
    pub acknowledged: u8,
    /// Padding (zero).
    pub _pad: [u8; 7],
}

impl Outcome {
    /// An empty outcome.
    pub const EMPTY: Outcome = Outcome {
        t: 0.0,
        sent: 0.0,
        to: 0,
        tag: 0,
        seq: 0,
        transmissions: 0,
        acknowledged: 0,
        _pad: [0; 7],
    };

    /// Whether the destination acknowledged the frame (else the sender gave up).
    pub fn is_acknowledged(&self) -> bool {
        self.acknowledged != 0
    }
}

/// What an agent sees of one vehicle on one control tick (world → agent).
#[derive(Debug, Clone, Copy, ZeroCopySend)]
#[type_name("shoal_Observation")]
#[repr(C)]
pub struct Observation {
    /// [`PROTOCOL_VERSION`].
    pub version: u32,
    /// Vehicle id in the world.
    pub vehicle: u32,
    /// Physics step of this tick (answer with the same).
    pub step: u64,
    /// Simulated time \[s\].
    pub time: f64,
    /// Bits of [`flags`].
    pub flags: u32,
    /// Valid entries of `frames`.
    pub n_frames: u32,
    /// Frames received since the last tick that did not fit into `frames`.
    pub frames_dropped: u32,
    /// Valid entries of `tilts`.
    pub n_tilts: u32,
    /// Depth from the pressure sensor, quantised [m, positive down].
    pub depth: f64,
    /// Roll from the IMU \[rad\].
    pub roll: f64,
    /// Pitch from the IMU \[rad\].
    pub pitch: f64,
    /// Heading from the IMU \[rad\], −π…π.
    pub yaw: f64,
    /// Body rates p, q, r from the gyros [rad/s].
    pub rates: [f64; 3],
    /// Specific force from the accelerometer, body frame [m/s²].
    pub accel: [f64; 3],
    /// True position (north, east, down) \[m\], if [`flags::POSITION`]; else zeros.
    pub position: [f64; 3],
    /// Tilt angles from the potentiometers \[rad\].
    pub tilts: [f64; MAX_TILTS],
    /// Received frames, in order of arrival.
    pub frames: [Frame; MAX_RX_FRAMES],
    /// Valid entries of `outcomes`.
    pub n_outcomes: u32,
    /// Outcomes since the last tick that did not fit into `outcomes`.
    pub outcomes_dropped: u32,
    /// What became of the vehicle's acknowledged frames since the last tick, in order.
    pub outcomes: [Outcome; MAX_OUTCOMES],
}

/// What an agent asks of one vehicle (agent → world).
#[derive(Debug, Clone, Copy, ZeroCopySend)]
#[type_name("shoal_Command")]
#[repr(C)]
pub struct Command {
    /// [`PROTOCOL_VERSION`].
    pub version: u32,
    /// Vehicle id (one of this agent's).
    pub vehicle: u32,
    /// Step of the observation this answers.
    pub step: u64,
    /// One of [`kind`].
    pub kind: u32,
    /// One of [`mode`] (with [`kind::MODE`]).
    pub mode: u32,
    /// Depth setpoint [m, positive down], clamped to the pool.
    pub depth: f64,
    /// Heading setpoint \[rad\].
    pub yaw: f64,
    /// Surge force \[N\] (drift and auto modes).
    pub surge: f64,
    /// Sway force \[N\] (drift mode).
    pub sway: f64,
    /// Raw thruster commands [% of full scale], clamped to ±`max_command`.
    pub thrusters: [f64; MAX_THRUSTERS],
    /// Raw tilt targets \[rad\], clamped to the drive's range.
    pub tilts: [f64; MAX_TILTS],
    /// Raw pump: −1 empty, 0 off, +1 fill.
    pub pump: i32,
    /// Valid entries of `frames`.
    pub n_frames: u32,
    /// Frames to send.
    pub frames: [Frame; MAX_TX_FRAMES],
}

impl Observation {
    /// An observation with every field zero but the version.
    pub const EMPTY: Observation = Observation {
        version: PROTOCOL_VERSION,
        vehicle: 0,
        step: 0,
        time: 0.0,
        flags: 0,
        n_frames: 0,
        frames_dropped: 0,
        n_tilts: 0,
        depth: 0.0,
        roll: 0.0,
        pitch: 0.0,
        yaw: 0.0,
        rates: [0.0; 3],
        accel: [0.0; 3],
        position: [0.0; 3],
        tilts: [0.0; MAX_TILTS],
        frames: [Frame::EMPTY; MAX_RX_FRAMES],
        n_outcomes: 0,
        outcomes_dropped: 0,
        outcomes: [Outcome::EMPTY; MAX_OUTCOMES],
    };

    /// The received frames.
    pub fn received(&self) -> &[Frame] {
        &self.frames[..(self.n_frames as usize).min(MAX_RX_FRAMES)]
    }

    /// What became of the vehicle's acknowledged frames since the last tick.
    pub fn outcomes(&self) -> &[Outcome] {
        &self.outcomes[..(self.n_outcomes as usize).min(MAX_OUTCOMES)]
    }
}

impl Command {
    /// "Keep the setpoints" for the vehicle and step of `obs`.
    pub fn keep(obs: &Observation) -> Command {
        Command {
            version: PROTOCOL_VERSION,
            vehicle: obs.vehicle,
            step: obs.step,
            kind: kind::KEEP,
            mode: mode::OFF,
            depth: 0.0,
            yaw: 0.0,
            surge: 0.0,
            sway: 0.0,
            thrusters: [0.0; MAX_THRUSTERS],
            tilts: [0.0; MAX_TILTS],
            pump: 0,
            n_frames: 0,
            frames: [Frame::EMPTY; MAX_TX_FRAMES],
        }
    }

    /// The goodbye an agent sends as it closes ([`kind::LEAVE`]).
    pub fn leave() -> Command {
        Command {
            vehicle: u32::MAX,
            kind: kind::LEAVE,
            ..Command::keep(&Observation::EMPTY)
        }
    }

    /// Sets a controller mode with its setpoints.
    pub fn set_mode(&mut self, mode: u32, depth: f64, yaw: f64, surge: f64, sway: f64) {
        self.kind = kind::MODE;
        self.mode = mode;
        self.depth = depth;
        self.yaw = yaw;
        self.surge = surge;
        self.sway = sway;
    }

    /// Adds a broadcast for modem `modem` ([`ALL_MODEMS`] for all), `delay` \[s\] after the
    /// tick. Returns `false` (and adds nothing) when the payload exceeds [`FRAME_BYTES`] or
    /// the command already holds [`MAX_TX_FRAMES`] frames.
    pub fn send(&mut self, modem: u8, payload: &[u8], delay: f64) -> bool {
        self.push(
            Frame {
                t: delay,
                modem,
                ..Frame::EMPTY
            },
            payload,
        )
    }

    /// Adds a frame for vehicle `to` alone (a unicast) on modem `modem` ([`ALL_MODEMS`] for
    /// all), `delay` \[s\] after the tick; with `ack`, acknowledged and retransmitted until
    /// it is (its [`Outcome`], carrying `tag`, comes with a later observation). Returns
    /// `false` (and adds nothing) like [`Command::send`]. The world checks the destination
    /// (another vehicle of the world, not [`BROADCAST`] with `ack`): a frame it refuses is
    /// counted in the agent's `bad_frames`.
    pub fn send_to(
        &mut self,
        to: u32,
        modem: u8,
        payload: &[u8],
        delay: f64,
        ack: bool,
        tag: u32,
    ) -> bool {
        let flags = if ack { frame_flags::ACK } else { 0 };
        self.push(
            Frame {
                t: delay,
                modem,
                flags,
                peer: to,
                tag,
                ..Frame::EMPTY
            },
            payload,
        )
    }

    /// Adds `frame` with `payload` as its data, if both fit.
    fn push(&mut self, mut frame: Frame, payload: &[u8]) -> bool {
        let n = self.n_frames as usize;
        if n >= MAX_TX_FRAMES || payload.len() > FRAME_BYTES {
            return false;
        }
        frame.len = payload.len() as u16;
        frame.data[..payload.len()].copy_from_slice(payload);
        self.frames[n] = frame;
        self.n_frames += 1;
        true
    }
}

mod layout;
pub use layout::{CType, Field, StructLayout, layout};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_bounded() {
        let obs = Observation::EMPTY;
        let mut c = Command::keep(&obs);
        assert!(c.send(ALL_MODEMS, &[1, 2, 3], 0.0));
        assert_eq!(c.frames[0].payload(), &[1, 2, 3]);
        assert!(!c.send(0, &[0; FRAME_BYTES + 1], 0.0));
        for _ in 1..MAX_TX_FRAMES {
            assert!(c.send(0, &[7], 0.0));
        }
        assert!(!c.send(0, &[7], 0.0), "no more than MAX_TX_FRAMES");
        let mut f = Frame::EMPTY;
        f.len = 1000; // a lying length never reads past the buffer
        assert_eq!(f.payload().len(), FRAME_BYTES);
        let mut o = Observation::EMPTY;
        o.n_outcomes = 1000; // nor a lying count
        assert_eq!(o.outcomes().len(), MAX_OUTCOMES);
    }

    /// A broadcast names no destination and asks for nothing; a unicast carries its
    /// destination, the acknowledgement bit and its tag, and nothing of an earlier frame.
    #[test]
    fn frames_say_where_they_go() {
        let mut c = Command::keep(&Observation::EMPTY);
        assert!(c.send_to(3, 0, &[1; 20], 0.25, true, 77));
        assert!(c.send(ALL_MODEMS, &[2; 5], 0.0));
        assert!(c.send_to(4, 1, &[3], 0.5, false, 9));
        let [u, b, plain, _] = c.frames;
        assert_eq!(
            (u.peer, u.flags, u.tag, u.t, u.modem),
            (3, frame_flags::ACK, 77, 0.25, 0)
        );
        assert_eq!(u.payload(), &[1; 20]);
        assert_eq!((b.peer, b.flags, b.tag), (BROADCAST, 0, 0));
        assert_eq!(b.payload(), &[2; 5]);
        assert_eq!(
            (plain.peer, plain.flags, plain.tag, plain.modem),
            (4, 0, 9, 1)
        );
        assert!(!c.send_to(5, 0, &[0; FRAME_BYTES + 1], 0.0, true, 1));
        assert_eq!(c.n_frames, 3, "an oversized frame adds nothing");
    }

    /// The sizes and the offsets docs/agents.md gives (v2): a frame grew from 88 to 96 bytes
    /// (its destination or sender, tag and sequence number), an outcome is 40.
    #[test]
    fn wire_sizes_are_the_documented_ones() {
        use core::mem::{offset_of, size_of};
        assert_eq!(size_of::<Frame>(), 96);
        assert_eq!(
            [
                offset_of!(Frame, flags),
                offset_of!(Frame, peer),
                offset_of!(Frame, tag),
                offset_of!(Frame, seq),
                offset_of!(Frame, data)
            ],
            [19, 20, 24, 28, 32]
        );
        assert_eq!(size_of::<Outcome>(), 40);
        assert_eq!(size_of::<Observation>(), 1112);
        assert_eq!(offset_of!(Observation, outcomes), 952);
        assert_eq!(size_of::<Command>(), 544);
    }
}
