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

use iceoryx2::prelude::ZeroCopySend;

/// Version of this protocol; a message with another version is rejected and counted.
pub const PROTOCOL_VERSION: u32 = 1;
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
    /// Padding (zero).
    pub _pad: [u8; 5],
    /// Payload (the first `len` bytes).
    pub data: [u8; FRAME_BYTES],
}

impl Frame {
    /// An empty frame.
    pub const EMPTY: Frame = Frame {
        t: 0.0,
        power: 0.0,
        len: 0,
        modem: 0,
        _pad: [0; 5],
        data: [0; FRAME_BYTES],
    };

    /// The payload bytes (at most [`FRAME_BYTES`], whatever `len` claims).
    pub fn payload(&self) -> &[u8] {
        &self.data[..(self.len as usize).min(FRAME_BYTES)]
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
    };

    /// The received frames.
    pub fn received(&self) -> &[Frame] {
        &self.frames[..(self.n_frames as usize).min(MAX_RX_FRAMES)]
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

    /// Adds a frame for modem `modem` ([`ALL_MODEMS`] for all), `delay` \[s\] after the tick.
    /// Returns `false` (and adds nothing) when the payload exceeds [`FRAME_BYTES`] or the
    /// command already holds [`MAX_TX_FRAMES`] frames.
    pub fn send(&mut self, modem: u8, payload: &[u8], delay: f64) -> bool {
        let n = self.n_frames as usize;
        if n >= MAX_TX_FRAMES || payload.len() > FRAME_BYTES {
            return false;
        }
        let f = &mut self.frames[n];
        f.t = delay;
        f.modem = modem;
        f.len = payload.len() as u16;
        f.data[..payload.len()].copy_from_slice(payload);
        self.n_frames += 1;
        true
    }
}

/// A C type of the layout table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CType {
    /// `uint8_t`.
    U8,
    /// `uint16_t`.
    U16,
    /// `uint32_t`.
    U32,
    /// `int32_t`.
    I32,
    /// `uint64_t`.
    U64,
    /// `double`.
    F64,
    /// The [`Frame`] struct.
    Frame,
}

/// One field of a wire struct: name, type, array length (1 for scalars), byte offset.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Field {
    /// Field name.
    pub name: &'static str,
    /// Element type.
    pub ty: CType,
    /// Number of elements (1: a scalar).
    pub count: usize,
    /// Byte offset in the struct.
    pub offset: usize,
}

/// One wire struct: its iceoryx2 type name, size, alignment and fields in order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StructLayout {
    /// Rust name.
    pub name: &'static str,
    /// The iceoryx2 type name.
    pub type_name: &'static str,
    /// `size_of` \[bytes\].
    pub size: usize,
    /// `align_of` \[bytes\].
    pub align: usize,
    /// Fields in declaration order.
    pub fields: Vec<Field>,
}

macro_rules! fields {
    ($t:ty; $($f:ident : $ty:ident * $n:expr),* $(,)?) => {
        vec![$(Field {
            name: stringify!($f),
            ty: CType::$ty,
            count: $n,
            offset: core::mem::offset_of!($t, $f),
        }),*]
    };
}

/// The layout of every wire struct, with offsets taken from the compiler; the Python
/// structs are generated from it and checked against it.
pub fn layout() -> Vec<StructLayout> {
    use core::mem::{align_of, size_of};
    vec![
        StructLayout {
            name: "Frame",
            type_name: "shoal_Frame",
            size: size_of::<Frame>(),
            align: align_of::<Frame>(),
            fields: fields!(Frame; t: F64 * 1, power: F64 * 1, len: U16 * 1, modem: U8 * 1,
                _pad: U8 * 5, data: U8 * FRAME_BYTES),
        },
        StructLayout {
            name: "Observation",
            type_name: "shoal_Observation",
            size: size_of::<Observation>(),
            align: align_of::<Observation>(),
            fields: fields!(Observation; version: U32 * 1, vehicle: U32 * 1, step: U64 * 1,
                time: F64 * 1, flags: U32 * 1, n_frames: U32 * 1, frames_dropped: U32 * 1,
                n_tilts: U32 * 1, depth: F64 * 1, roll: F64 * 1, pitch: F64 * 1, yaw: F64 * 1,
                rates: F64 * 3, accel: F64 * 3, position: F64 * 3, tilts: F64 * MAX_TILTS,
                frames: Frame * MAX_RX_FRAMES),
        },
        StructLayout {
            name: "Command",
            type_name: "shoal_Command",
            size: size_of::<Command>(),
            align: align_of::<Command>(),
            fields: fields!(Command; version: U32 * 1, vehicle: U32 * 1, step: U64 * 1,
                kind: U32 * 1, mode: U32 * 1, depth: F64 * 1, yaw: F64 * 1, surge: F64 * 1,
                sway: F64 * 1, thrusters: F64 * MAX_THRUSTERS, tilts: F64 * MAX_TILTS,
                pump: I32 * 1, n_frames: U32 * 1, frames: Frame * MAX_TX_FRAMES),
        },
    ]
}

impl CType {
    /// Size of one element \[bytes\].
    pub fn size(self) -> usize {
        match self {
            CType::U8 => 1,
            CType::U16 => 2,
            CType::U32 | CType::I32 => 4,
            CType::U64 | CType::F64 => 8,
            CType::Frame => size_of::<Frame>(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table covers every byte of each struct exactly once, in order: a field added to a
    /// struct but not to the table (or reordered) fails here.
    #[test]
    fn layout_table_covers_each_struct_without_gaps() {
        for s in layout() {
            let mut at = 0;
            for f in &s.fields {
                assert_eq!(f.offset, at, "{}.{} starts at {}", s.name, f.name, f.offset);
                at += f.ty.size() * f.count;
            }
            assert_eq!(
                at, s.size,
                "{}: fields cover {at} of {} bytes",
                s.name, s.size
            );
            assert_eq!(s.align, 8, "{}", s.name);
        }
    }

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
    }
}
