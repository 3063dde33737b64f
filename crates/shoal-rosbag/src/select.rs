//! Field paths (`data[1]`, `angular_velocity.z`, `pose.pose.orientation`) resolved against a
//! message type into the values a decoder keeps.
//!
//! A path is a chain of field names separated by `.`, each with an optional element index
//! `[k]` for an array field. It ends at a number (any numeric primitive) or at a quaternion
//! (a message of four floating-point fields `x y z w`, e.g. `geometry_msgs/Quaternion`),
//! which gives an angle. Resolving a path checks it against the type (every name a field,
//! every index within a fixed array's size, an array indexed, the end a number or a
//! quaternion) and gives it *slots*: places in the decoder's output, one per number, four
//! per quaternion. Paths shared by several mapping entries share their slots.
//!
//! All paths of one topic make one selection tree ([`Sel`]) that the decoder walks beside
//! the message; everything not selected is read past and dropped.

use crate::schema::{Count, Elem, Prim, Schema};
use std::collections::HashMap;

/// What the decoder keeps of a value.
#[derive(Clone, Debug, PartialEq)]
pub enum Sel {
    /// Nothing.
    Skip,
    /// A number, into this slot.
    Leaf(usize),
    /// A message: one selection per field, in field order.
    Fields(Vec<Sel>),
    /// An array: selections of some elements by index.
    Elems(Vec<(usize, Sel)>),
}

/// The nothing-selected selection, for borrowing.
pub static SKIP: Sel = Sel::Skip;

/// Where a resolved path's values land.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// A number in this slot.
    Number(usize),
    /// A quaternion's x, y, z, w in these slots.
    Quaternion([usize; 4]),
}

/// The selection of one topic: the tree and its slots.
#[derive(Clone, Debug)]
pub struct Plan {
    /// What to keep of each message.
    pub sel: Sel,
    /// Number of slots.
    pub slots: usize,
    /// Slot of each leaf path already selected.
    leaves: HashMap<String, usize>,
}

#[derive(Clone, Debug)]
struct Step {
    field: usize,
    index: Option<usize>,
}

impl Plan {
    /// An empty selection.
    pub fn new() -> Plan {
        Plan {
            sel: Sel::Skip,
            slots: 0,
            leaves: HashMap::new(),
        }
    }

    /// Selects `path` in messages of `schema`; the error says what is wrong with the path.
    pub fn add(&mut self, schema: &Schema, path: &str) -> Result<Target, String> {
        let (steps, end) = resolve(schema, path)?;
        match end {
            End::Number => Ok(Target::Number(self.leaf(schema, &steps, path))),
            End::Quaternion(fields) => {
                let mut slots = [0; 4];
                for (k, f) in fields.iter().enumerate() {
                    let mut s = steps.clone();
                    s.push(Step {
                        field: *f,
                        index: None,
                    });
                    slots[k] =
                        self.leaf(schema, &s, &format!("{path}.{}", ["x", "y", "z", "w"][k]));
                }
                Ok(Target::Quaternion(slots))
            }
        }
    }

    fn leaf(&mut self, schema: &Schema, steps: &[Step], key: &str) -> usize {
        if let Some(&k) = self.leaves.get(key) {
            return k;
        }
        let slot = self.slots;
        self.slots += 1;
        self.leaves.insert(key.to_string(), slot);
        insert(&mut self.sel, schema, schema.root, steps, slot);
        slot
    }
}

impl Default for Plan {
    fn default() -> Self {
        Plan::new()
    }
}

fn insert(sel: &mut Sel, schema: &Schema, ty: usize, steps: &[Step], slot: usize) {
    let Some((first, rest)) = steps.split_first() else {
        *sel = Sel::Leaf(slot);
        return;
    };
    let fields = &schema.types[ty].fields;
    if !matches!(sel, Sel::Fields(_)) {
        *sel = Sel::Fields(vec![Sel::Skip; fields.len()]);
    }
    let Sel::Fields(children) = sel else {
        unreachable!("set just above")
    };
    let field = &fields[first.field];
    let child = &mut children[first.field];
    let target = match first.index {
        None => child,
        Some(i) => {
            if !matches!(child, Sel::Elems(_)) {
                *child = Sel::Elems(Vec::new());
            }
            let Sel::Elems(elems) = child else {
                unreachable!("set just above")
            };
            let at = match elems.iter().position(|(k, _)| *k == i) {
                Some(at) => at,
                None => {
                    elems.push((i, Sel::Skip));
                    elems.len() - 1
                }
            };
            &mut elems[at].1
        }
    };
    match field.elem {
        Elem::Msg(t) => insert(target, schema, t, rest, slot),
        Elem::Prim(_) => *target = Sel::Leaf(slot),
    }
}

enum End {
    Number,
    Quaternion([usize; 4]),
}

fn resolve(schema: &Schema, path: &str) -> Result<(Vec<Step>, End), String> {
    if path.trim().is_empty() {
        return Err("the field path is empty".into());
    }
    let mut ty = schema.root;
    let mut steps = Vec::new();
    let segments: Vec<&str> = path.split('.').collect();
    for (k, seg) in segments.iter().enumerate() {
        let last = k + 1 == segments.len();
        let (name, index) = parse_segment(seg)?;
        let msg = &schema.types[ty];
        let Some(fi) = msg.fields.iter().position(|f| f.name == name) else {
            let names: Vec<&str> = msg.fields.iter().map(|f| f.name.as_str()).collect();
            return Err(format!(
                "`{name}` is not a field of {} (its fields: {})",
                msg.name,
                names.join(", ")
            ));
        };
        let field = &msg.fields[fi];
        match (field.count, index) {
            (Count::One, Some(_)) => {
                return Err(format!(
                    "`{name}` ({}) is not an array: drop the `[…]`",
                    field.written
                ));
            }
            (Count::Fixed(_) | Count::Seq, None) => {
                return Err(format!(
                    "`{name}` ({}) is an array: pick an element, e.g. `{name}[0]`",
                    field.written
                ));
            }
            (Count::Fixed(n), Some(i)) if i >= n => {
                return Err(format!(
                    "`{name}[{i}]` is past the end of `{name}` ({}, {n} elements)",
                    field.written
                ));
            }
            _ => {}
        }
        steps.push(Step { field: fi, index });
        match field.elem {
            Elem::Prim(p) if last => {
                if p.is_numeric() {
                    return Ok((steps, End::Number));
                }
                return Err(format!("`{name}` is a {}, not a number", field.written));
            }
            Elem::Prim(_) => {
                return Err(format!(
                    "`{name}` is a {} and has no field `{}`",
                    field.written,
                    segments[k + 1]
                ));
            }
            Elem::Msg(t) if last => {
                return quaternion(schema, t)
                    .map(|q| (steps, End::Quaternion(q)))
                    .ok_or_else(|| {
                        format!(
                            "`{name}` is a {} message, not a number or a quaternion: name one of \
                         its fields ({})",
                            schema.types[t].name,
                            schema.types[t]
                                .fields
                                .iter()
                                .map(|f| format!("`{path}.{}`", f.name))
                                .collect::<Vec<_>>()
                                .join(", ")
                        )
                    });
            }
            Elem::Msg(t) => ty = t,
        }
    }
    unreachable!("a path has at least one segment and every segment returns or continues")
}

/// The fields x, y, z, w of a quaternion-shaped message.
fn quaternion(schema: &Schema, ty: usize) -> Option<[usize; 4]> {
    let fields = &schema.types[ty].fields;
    if fields.len() != 4 {
        return None;
    }
    let mut at = [0; 4];
    for (k, n) in ["x", "y", "z", "w"].iter().enumerate() {
        let i = fields.iter().position(|f| f.name == *n)?;
        let f = &fields[i];
        if f.count != Count::One || !matches!(f.elem, Elem::Prim(Prim::F32 | Prim::F64)) {
            return None;
        }
        at[k] = i;
    }
    Some(at)
}

fn parse_segment(seg: &str) -> Result<(&str, Option<usize>), String> {
    let (name, index) = match seg.find('[') {
        None => (seg, None),
        Some(b) => {
            let inner = seg[b + 1..]
                .strip_suffix(']')
                .ok_or_else(|| format!("`{seg}`: an index is written `name[k]`"))?;
            let k = inner
                .trim()
                .parse::<usize>()
                .map_err(|_| format!("`{seg}`: the index `{inner}` is not a whole number ≥ 0"))?;
            (&seg[..b], Some(k))
        }
    };
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err(format!(
            "`{seg}` is not a field name (letters, digits and `_`, with an optional `[k]`)"
        ));
    }
    Ok((name, index))
}
