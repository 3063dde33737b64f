//! CDR-encoded ROS 2 messages decoded by their schema, keeping only the selected numbers.
//!
//! The bytes are the message as a bag stores it: a four-byte encapsulation header (`00 01`:
//! plain CDR, little-endian; `00 00`: big-endian; two option bytes), then the fields in order
//! with CDR's alignment counted from after the header. The reading itself — alignment,
//! byte order, lengths, strings — is the `cdr-encoding` crate's (serde): the schema drives it
//! through serde's `DeserializeSeed`, one seed per message type, field and array, so no Rust
//! type per ROS message is needed. Numbers selected by the [`Sel`] tree are written as `f64`
//! into their slots; everything else is read past.
//!
//! A message that ends before its schema does, a sequence longer than the message, a
//! non-boolean byte in a `bool`, a string that is not UTF-8: each an error, never a panic. An
//! encapsulation other than plain CDR (XCDR2, parameter lists) is refused by name.

use crate::schema::{Count, Elem, Field, Prim, Schema};
use crate::select::{SKIP, Sel};
use byteorder::{BigEndian, LittleEndian};
use cdr_encoding::CdrDeserializer;
use serde::de::{self, DeserializeSeed, Deserializer, Error as _, SeqAccess, Visitor};
use std::fmt;

/// Decodes one message (encapsulation header first) into `out` (one value per slot; slots
/// not reached, e.g. an index past a sequence's end, are left as they were).
pub fn decode(schema: &Schema, sel: &Sel, data: &[u8], out: &mut [f64]) -> Result<(), String> {
    if data.len() < 4 {
        return Err(format!(
            "{} byte(s): shorter than the 4-byte CDR encapsulation header",
            data.len()
        ));
    }
    let seed = MsgSeed {
        schema,
        ty: schema.root,
        sel,
        out,
    };
    let body = &data[4..];
    let read = match (data[0], data[1]) {
        (0, 1) => seed.deserialize(&mut CdrDeserializer::<LittleEndian>::new(body)),
        (0, 0) => seed.deserialize(&mut CdrDeserializer::<BigEndian>::new(body)),
        (a, b) => {
            return Err(format!(
                "encapsulation {a:02x} {b:02x} is not plain CDR (00 00 or 00 01; XCDR2 and \
                 parameter lists are not read)"
            ));
        }
    };
    read.map_err(|e| match e {
        cdr_encoding::Error::Eof => "the message ends before its schema does (truncated, or \
                                     written with another definition of the type)"
            .to_string(),
        e => e.to_string(),
    })
}

struct MsgSeed<'s, 'o> {
    schema: &'s Schema,
    ty: usize,
    sel: &'s Sel,
    out: &'o mut [f64],
}

impl<'de> DeserializeSeed<'de> for MsgSeed<'_, '_> {
    type Value = ();
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        let n = self.schema.types[self.ty].fields.len();
        d.deserialize_tuple(n, self)
    }
}

impl<'de> Visitor<'de> for MsgSeed<'_, '_> {
    type Value = ();
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "a {}", self.schema.types[self.ty].name)
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        let msg = &self.schema.types[self.ty];
        for (i, field) in msg.fields.iter().enumerate() {
            let sel = match self.sel {
                Sel::Fields(v) => &v[i],
                _ => &SKIP,
            };
            let seed = FieldSeed {
                schema: self.schema,
                field,
                sel,
                out: &mut *self.out,
            };
            seq.next_element_seed(seed)?.ok_or_else(|| {
                A::Error::custom(format!("{} ends before `{}`", msg.name, field.name))
            })?;
        }
        Ok(())
    }
}

struct FieldSeed<'s, 'o> {
    schema: &'s Schema,
    field: &'s Field,
    sel: &'s Sel,
    out: &'o mut [f64],
}

impl<'de> DeserializeSeed<'de> for FieldSeed<'_, '_> {
    type Value = ();
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        let elems = ArraySeed {
            schema: self.schema,
            field: self.field,
            sel: self.sel,
            out: self.out,
        };
        match (self.field.count, self.field.elem) {
            (Count::One, elem) => ElemSeed {
                schema: self.schema,
                elem,
                sel: self.sel,
                out: elems.out,
            }
            .deserialize(d),
            (Count::Fixed(n), _) => d.deserialize_tuple(n, elems),
            // A byte sequence nobody reads (an image, a blob) is skipped in one piece.
            (Count::Seq, Elem::Prim(Prim::U8)) if matches!(self.sel, Sel::Skip) => {
                d.deserialize_bytes(Ignore)
            }
            (Count::Seq, _) => d.deserialize_seq(elems),
        }
    }
}

struct ArraySeed<'s, 'o> {
    schema: &'s Schema,
    field: &'s Field,
    sel: &'s Sel,
    out: &'o mut [f64],
}

impl<'de> Visitor<'de> for ArraySeed<'_, '_> {
    type Value = ();
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "the elements of `{}`", self.field.name)
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        let mut i = 0usize;
        loop {
            let sel = match self.sel {
                Sel::Elems(list) => list.iter().find(|(k, _)| *k == i).map_or(&SKIP, |(_, s)| s),
                _ => &SKIP,
            };
            let seed = ElemSeed {
                schema: self.schema,
                elem: self.field.elem,
                sel,
                out: &mut *self.out,
            };
            match seq.next_element_seed(seed)? {
                Some(()) => i += 1,
                None => break,
            }
        }
        // An index the mapping reads that this message's array does not reach.
        let past = match self.sel {
            Sel::Elems(list) => list.iter().map(|(k, _)| *k).filter(|&k| k >= i).min(),
            _ => None,
        };
        match past {
            Some(k) => Err(A::Error::custom(format!(
                "`{name}[{k}]` is past the end of `{name}`: index {k}, but this message's \
                 `{name}` has {i} element(s)",
                name = self.field.name
            ))),
            None => Ok(()),
        }
    }
}

struct ElemSeed<'s, 'o> {
    schema: &'s Schema,
    elem: Elem,
    sel: &'s Sel,
    out: &'o mut [f64],
}

impl<'de> DeserializeSeed<'de> for ElemSeed<'_, '_> {
    type Value = ();
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        let p = match self.elem {
            Elem::Msg(ty) => {
                return MsgSeed {
                    schema: self.schema,
                    ty,
                    sel: self.sel,
                    out: self.out,
                }
                .deserialize(d);
            }
            Elem::Prim(p) => p,
        };
        let v = Number {
            slot: match self.sel {
                Sel::Leaf(k) => Some(*k),
                _ => None,
            },
            out: self.out,
        };
        match p {
            Prim::Bool => d.deserialize_bool(v),
            Prim::U8 => d.deserialize_u8(v),
            Prim::I8 => d.deserialize_i8(v),
            Prim::I16 => d.deserialize_i16(v),
            Prim::U16 => d.deserialize_u16(v),
            Prim::I32 => d.deserialize_i32(v),
            Prim::U32 => d.deserialize_u32(v),
            Prim::I64 => d.deserialize_i64(v),
            Prim::U64 => d.deserialize_u64(v),
            Prim::F32 => d.deserialize_f32(v),
            Prim::F64 => d.deserialize_f64(v),
            Prim::Str => d.deserialize_str(Ignore),
            Prim::WStr => Err(D::Error::custom(
                "a `wstring` field: wide strings are not read (map a topic without one)",
            )),
        }
    }
}

/// A primitive value, kept in its slot if selected.
struct Number<'o> {
    slot: Option<usize>,
    out: &'o mut [f64],
}

impl Number<'_> {
    fn keep<E>(self, v: f64) -> Result<(), E> {
        if let Some(k) = self.slot {
            self.out[k] = v;
        }
        Ok(())
    }
}

macro_rules! visit_numbers {
    ($($name:ident: $t:ty),*) => {
        $(fn $name<E: de::Error>(self, v: $t) -> Result<(), E> {
            self.keep(v as f64)
        })*
    };
}

impl<'de> Visitor<'de> for Number<'_> {
    type Value = ();
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "a number")
    }
    visit_numbers!(visit_u8: u8, visit_i8: i8, visit_i16: i16, visit_u16: u16, visit_i32: i32,
        visit_u32: u32, visit_i64: i64, visit_u64: u64, visit_f32: f32, visit_f64: f64);
    fn visit_bool<E: de::Error>(self, v: bool) -> Result<(), E> {
        self.keep(if v { 1.0 } else { 0.0 })
    }
}

/// Reads past a string or a byte sequence.
struct Ignore;

impl<'de> Visitor<'de> for Ignore {
    type Value = ();
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "a string or bytes")
    }
    fn visit_str<E: de::Error>(self, _: &str) -> Result<(), E> {
        Ok(())
    }
    fn visit_bytes<E: de::Error>(self, _: &[u8]) -> Result<(), E> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::select::{Plan, Target};

    const FLUID: &str = "std_msgs/Header header\nfloat64 fluid_pressure\nfloat64 variance\n\
        ================================================================================\n\
        MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n";

    /// A FluidPressure as rclcpp serialises it, by hand: stamp 12 s + 500 ns, frame "base",
    /// pressure 111 135.4 Pa, variance 0.25.
    fn fluid_bytes(little: bool) -> Vec<u8> {
        let mut b = vec![0u8, u8::from(little), 0, 0];
        let put = |b: &mut Vec<u8>, bytes: &[u8]| b.extend_from_slice(bytes);
        let w32 = |v: u32| {
            if little {
                v.to_le_bytes()
            } else {
                v.to_be_bytes()
            }
        };
        let wf = |v: f64| {
            if little {
                v.to_le_bytes()
            } else {
                v.to_be_bytes()
            }
        };
        put(&mut b, &w32(12)); // sec (int32)
        put(&mut b, &w32(500)); // nanosec
        put(&mut b, &w32(5)); // "base\0"
        put(&mut b, b"base\0");
        // offset (after the header) 17 → pad to 24 for the float64
        put(&mut b, &[0; 7]);
        put(&mut b, &wf(111_135.4));
        put(&mut b, &wf(0.25));
        b
    }

    #[test]
    fn a_fluid_pressure_decoded_by_its_schema_in_both_byte_orders() {
        let schema = Schema::parse("sensor_msgs/msg/FluidPressure", FLUID).unwrap();
        let mut plan = Plan::new();
        let p = plan.add(&schema, "fluid_pressure").unwrap();
        let s = plan.add(&schema, "header.stamp.sec").unwrap();
        let n = plan.add(&schema, "header.stamp.nanosec").unwrap();
        assert_eq!(
            plan.add(&schema, "fluid_pressure").unwrap(),
            p,
            "shared slot"
        );
        for little in [true, false] {
            let mut out = vec![f64::NAN; plan.slots];
            decode(&schema, &plan.sel, &fluid_bytes(little), &mut out).unwrap();
            let at = |t: Target| match t {
                Target::Number(k) => out[k],
                Target::Quaternion(_) => panic!(),
            };
            assert_eq!((at(p), at(s), at(n)), (111_135.4, 12.0, 500.0));
        }
    }

    #[test]
    fn truncated_and_foreign_encodings_are_errors() {
        let schema = Schema::parse("sensor_msgs/msg/FluidPressure", FLUID).unwrap();
        let mut plan = Plan::new();
        plan.add(&schema, "variance").unwrap();
        let bytes = fluid_bytes(true);
        let mut out = vec![0.0; 1];
        for cut in 0..bytes.len() {
            let e = decode(&schema, &plan.sel, &bytes[..cut], &mut out).unwrap_err();
            assert!(!e.is_empty());
        }
        let mut xcdr2 = bytes.clone();
        xcdr2[1] = 7;
        let e = decode(&schema, &plan.sel, &xcdr2, &mut out).unwrap_err();
        assert!(e.contains("not plain CDR"), "{e}");
    }

    #[test]
    fn sequences_of_messages_and_elements_by_index() {
        let schema = Schema::parse(
            "pkg/msg/T",
            "uint8[] blob\nP[] pts\nint16[3] fixed\n=====\nMSG: pkg/P\nfloat32 x\nbool ok\n",
        )
        .unwrap();
        let mut plan = Plan::new();
        let Target::Number(x1) = plan.add(&schema, "pts[1].x").unwrap() else {
            panic!()
        };
        let Target::Number(ok0) = plan.add(&schema, "pts[0].ok").unwrap() else {
            panic!()
        };
        let Target::Number(f2) = plan.add(&schema, "fixed[2]").unwrap() else {
            panic!()
        };
        let mut b = vec![0u8, 1, 0, 0];
        b.extend_from_slice(&3u32.to_le_bytes());
        b.extend_from_slice(&[9, 9, 9, 0]); // blob + pad to 8
        b.extend_from_slice(&2u32.to_le_bytes()); // two points
        b.extend_from_slice(&1.5f32.to_le_bytes());
        b.extend_from_slice(&[1, 0, 0, 0]);
        b.extend_from_slice(&(-2.5f32).to_le_bytes());
        b.extend_from_slice(&[0, 0]); // ok = false, pad to 2
        for v in [7i16, 8, -9] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        let mut out = vec![f64::NAN; plan.slots];
        decode(&schema, &plan.sel, &b, &mut out).unwrap();
        assert_eq!((out[x1], out[ok0], out[f2]), (-2.5, 1.0, -9.0));
        // A sequence that claims more elements than the message holds.
        let mut long = b.clone();
        long[12..16].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(decode(&schema, &plan.sel, &long, &mut out).is_err());
    }
}
