//! The layout table of the wire structs: every field's name, C type, count and offset, taken
//! from the compiler. The Python mirror is generated from it (`examples/gen_python.rs`) and a
//! test compares the mirror's ctypes offsets with it.

use super::{Command, FRAME_BYTES, Frame, MAX_OUTCOMES, MAX_RX_FRAMES, MAX_THRUSTERS, MAX_TILTS};
use super::{MAX_TX_FRAMES, Observation, Outcome};

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
    /// The [`Outcome`] struct.
    Outcome,
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
                flags: U8 * 1, peer: U32 * 1, tag: U32 * 1, seq: U32 * 1, data: U8 * FRAME_BYTES),
        },
        StructLayout {
            name: "Outcome",
            type_name: "shoal_Outcome",
            size: size_of::<Outcome>(),
            align: align_of::<Outcome>(),
            fields: fields!(Outcome; t: F64 * 1, sent: F64 * 1, to: U32 * 1, tag: U32 * 1,
                seq: U32 * 1, transmissions: U32 * 1, acknowledged: U8 * 1, _pad: U8 * 7),
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
                frames: Frame * MAX_RX_FRAMES, n_outcomes: U32 * 1, outcomes_dropped: U32 * 1,
                outcomes: Outcome * MAX_OUTCOMES),
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
            CType::Outcome => size_of::<Outcome>(),
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
}
