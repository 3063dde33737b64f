//! ROS 2 message definitions as a bag carries them: the `ros2msg` schema encoding of MCAP.
//!
//! A schema is the `.msg` text of the channel's type, followed by the text of every type it
//! uses, each after a line of `=` and a line `MSG: package/Type` (the way rosbag2 and
//! Foxglove write them). Parsed here into a flat table of types ([`Schema`]) that the decoder
//! walks; nothing else of ROS is needed to read a bag.
//!
//! Grammar read (the ROS 2 interface definition, `.msg` files):
//!
//! * `type name` or `type name default` — a field; `type NAME=value` — a constant (no data on
//!   the wire, skipped); `#` starts a comment; blank lines are skipped;
//! * types: `bool byte char int8 uint8 int16 uint16 int32 uint32 int64 uint64 float32 float64
//!   string wstring` (`string<=N` bounded), `package/Type`, `package/msg/Type`, a bare `Type`
//!   (the same package; `Header` is `std_msgs/Header`);
//! * arrays: `type[N]` (fixed: no length on the wire), `type[]` and `type[<=N]` (a sequence:
//!   a `uint32` count, then the elements).
//!
//! `builtin_interfaces/Time` and `Duration` (`int32 sec`, `uint32 nanosec`) are known without
//! their text, as every ROS 2 tool knows them. A type used but not defined, a type that contains
//! itself, or a type without fields is an error naming the type and the line.

use std::collections::HashMap;

/// A primitive type of the ROS 2 interface definition.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Prim {
    /// `bool` (one byte, 0 or 1).
    Bool,
    /// `byte`, `char`, `uint8` (one byte).
    U8,
    /// `int8`.
    I8,
    /// `int16`.
    I16,
    /// `uint16`.
    U16,
    /// `int32`.
    I32,
    /// `uint32`.
    U32,
    /// `int64`.
    I64,
    /// `uint64`.
    U64,
    /// `float32`.
    F32,
    /// `float64`.
    F64,
    /// `string` (a `uint32` length with the terminating NUL, then the bytes).
    Str,
    /// `wstring` (not read: a bag that maps or passes one is refused by name).
    WStr,
}

impl Prim {
    fn parse(s: &str) -> Option<Prim> {
        let base = s.split("<=").next().unwrap_or(s);
        Some(match base {
            "bool" => Prim::Bool,
            "byte" | "char" | "uint8" => Prim::U8,
            "int8" => Prim::I8,
            "int16" => Prim::I16,
            "uint16" => Prim::U16,
            "int32" => Prim::I32,
            "uint32" => Prim::U32,
            "int64" => Prim::I64,
            "uint64" => Prim::U64,
            "float32" => Prim::F32,
            "float64" => Prim::F64,
            "string" => Prim::Str,
            "wstring" => Prim::WStr,
            _ => return None,
        })
    }

    /// Whether a value of this type reads as a number.
    pub fn is_numeric(self) -> bool {
        !matches!(self, Prim::Str | Prim::WStr)
    }
}

/// What one element of a field is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Elem {
    /// A primitive.
    Prim(Prim),
    /// A message: index into [`Schema::types`].
    Msg(usize),
}

/// How many elements a field holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Count {
    /// A single value.
    One,
    /// A fixed-size array (no length on the wire).
    Fixed(usize),
    /// A sequence, bounded or not (a `uint32` count on the wire).
    Seq,
}

/// A field of a message type.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// Its name.
    pub name: String,
    /// Its element type.
    pub elem: Elem,
    /// How many elements.
    pub count: Count,
    /// The type as written (`float64[9]`, `std_msgs/Header`), for messages.
    pub written: String,
}

/// A message type.
#[derive(Clone, Debug, PartialEq)]
pub struct MsgType {
    /// `package/Type`.
    pub name: String,
    /// Its fields in wire order.
    pub fields: Vec<Field>,
}

/// A message type with every type it uses.
#[derive(Clone, Debug, PartialEq)]
pub struct Schema {
    /// The types; [`Schema::root`] is the channel's.
    pub types: Vec<MsgType>,
    /// Index of the channel's own type.
    pub root: usize,
}

/// A schema that cannot be read.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("schema `{schema}`: {message}")]
pub struct SchemaError {
    /// The schema's name.
    pub schema: String,
    /// What is wrong, with the type and line.
    pub message: String,
}

/// `package/msg/Type` → `package/Type`.
pub fn normalise(name: &str) -> String {
    let parts: Vec<&str> = name.split('/').collect();
    match parts.as_slice() {
        [pkg, "msg", ty] => format!("{pkg}/{ty}"),
        _ => name.to_string(),
    }
}

const BUILTIN: [(&str, &str); 2] = [
    ("builtin_interfaces/Time", "int32 sec\nuint32 nanosec\n"),
    ("builtin_interfaces/Duration", "int32 sec\nuint32 nanosec\n"),
];

impl Schema {
    /// Parses the `ros2msg` text of the schema named `name` (`sensor_msgs/msg/Imu`).
    pub fn parse(name: &str, text: &str) -> Result<Schema, SchemaError> {
        let err = |message: String| SchemaError {
            schema: name.to_string(),
            message,
        };
        let mut sections: HashMap<String, String> = HashMap::new();
        let root_name = normalise(name);
        let mut current = root_name.clone();
        let mut body = String::new();
        let mut expect_type = false;
        // Sections are split at lines of `=`; each later one starts with `MSG: package/Type`.
        for line in text.lines() {
            let t = line.trim();
            if !t.is_empty() && t.chars().all(|c| c == '=') {
                sections.insert(current.clone(), std::mem::take(&mut body));
                expect_type = true;
            } else if expect_type {
                if t.is_empty() {
                    continue;
                }
                let Some(ty) = t.strip_prefix("MSG:") else {
                    return Err(err(format!(
                        "a line of `=` must be followed by `MSG: package/Type`, found {t:?}"
                    )));
                };
                current = normalise(ty.trim());
                expect_type = false;
            } else {
                body.push_str(line);
                body.push('\n');
            }
        }
        sections.insert(current, body);
        let mut builder = Builder {
            sections,
            types: Vec::new(),
            index: HashMap::new(),
            stack: Vec::new(),
            schema: name,
        };
        let root = builder.resolve(&root_name)?;
        Ok(Schema {
            types: builder.types,
            root,
        })
    }

    /// The channel's own type.
    pub fn root_type(&self) -> &MsgType {
        &self.types[self.root]
    }
}

struct Builder<'a> {
    sections: HashMap<String, String>,
    types: Vec<MsgType>,
    index: HashMap<String, usize>,
    stack: Vec<String>,
    schema: &'a str,
}

impl Builder<'_> {
    fn err(&self, message: String) -> SchemaError {
        SchemaError {
            schema: self.schema.to_string(),
            message,
        }
    }

    fn resolve(&mut self, name: &str) -> Result<usize, SchemaError> {
        if let Some(&i) = self.index.get(name) {
            return Ok(i);
        }
        if self.stack.iter().any(|s| s == name) {
            return Err(self.err(format!(
                "type `{name}` contains itself ({} → {name})",
                self.stack.join(" → ")
            )));
        }
        let text = match self.sections.get(name) {
            Some(t) => t.clone(),
            None => match BUILTIN.iter().find(|(n, _)| *n == name) {
                Some((_, t)) => t.to_string(),
                None => {
                    return Err(self.err(format!(
                        "type `{name}` is used but its definition is not in the schema \
                         (expected a section `MSG: {name}`)"
                    )));
                }
            },
        };
        self.stack.push(name.to_string());
        let package = name.split('/').next().unwrap_or("").to_string();
        let mut fields = Vec::new();
        for (k, line) in text.lines().enumerate() {
            if let Some(f) = self.field(&package, name, k + 1, line)? {
                fields.push(f);
            }
        }
        self.stack.pop();
        if fields.is_empty() {
            return Err(self.err(format!(
                "type `{name}` has no fields (ROS 2 gives an empty message one `uint8` member)"
            )));
        }
        let i = self.types.len();
        self.types.push(MsgType {
            name: name.to_string(),
            fields,
        });
        self.index.insert(name.to_string(), i);
        Ok(i)
    }

    fn field(
        &mut self,
        package: &str,
        owner: &str,
        line_no: usize,
        line: &str,
    ) -> Result<Option<Field>, SchemaError> {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            return Ok(None);
        }
        let mut tokens = line.splitn(2, char::is_whitespace);
        let written = tokens.next().unwrap_or("");
        let rest = tokens.next().unwrap_or("").trim_start();
        let name: String = rest
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        let after = rest[name.len()..].trim_start();
        if name.is_empty() {
            return Err(self.err(format!(
                "type `{owner}`, line {line_no}: expected `type name`, found {line:?}"
            )));
        }
        if after.starts_with('=') {
            return Ok(None); // a constant
        }
        let (base, count) = match written.find('[') {
            None => (written, Count::One),
            Some(b) => {
                let inner = written[b + 1..].strip_suffix(']').ok_or_else(|| {
                    self.err(format!(
                        "type `{owner}`, line {line_no}: unclosed array type `{written}`"
                    ))
                })?;
                let count = if inner.is_empty() || inner.starts_with("<=") {
                    Count::Seq
                } else {
                    Count::Fixed(inner.parse().map_err(|_| {
                        self.err(format!(
                            "type `{owner}`, line {line_no}: array size `{inner}` is not a number"
                        ))
                    })?)
                };
                (&written[..b], count)
            }
        };
        let elem = match Prim::parse(base) {
            Some(p) => Elem::Prim(p),
            None => {
                let full = if base == "Header" {
                    "std_msgs/Header".to_string()
                } else if base.contains('/') {
                    normalise(base)
                } else {
                    format!("{package}/{base}")
                };
                Elem::Msg(self.resolve(&full)?)
            }
        };
        Ok(Some(Field {
            name,
            elem,
            count,
            written: written.to_string(),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) const IMU: &str = "std_msgs/Header header\n\
        geometry_msgs/Quaternion orientation\n\
        float64[9] orientation_covariance # Row major about x, y, z axes\n\
        geometry_msgs/Vector3 angular_velocity\n\
        float64[9] angular_velocity_covariance\n\
        geometry_msgs/Vector3 linear_acceleration\n\
        float64[9] linear_acceleration_covariance\n\
        ================================================================================\n\
        MSG: std_msgs/Header\n\
        # Standard metadata\n\
        builtin_interfaces/Time stamp\n\
        string frame_id\n\
        ================================================================================\n\
        MSG: geometry_msgs/Quaternion\n\
        float64 x 0\n\
        float64 y 0\n\
        float64 z 0\n\
        float64 w 1\n\
        ================================================================================\n\
        MSG: geometry_msgs/Vector3\n\
        float64 x\n\
        float64 y\n\
        float64 z\n";

    #[test]
    fn an_imu_schema_as_rosbag2_writes_it() {
        let s = Schema::parse("sensor_msgs/msg/Imu", IMU).unwrap();
        let root = s.root_type();
        assert_eq!(root.name, "sensor_msgs/Imu");
        let names: Vec<_> = root.fields.iter().map(|f| f.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "header",
                "orientation",
                "orientation_covariance",
                "angular_velocity",
                "angular_velocity_covariance",
                "linear_acceleration",
                "linear_acceleration_covariance"
            ]
        );
        assert_eq!(root.fields[2].count, Count::Fixed(9));
        let Elem::Msg(h) = root.fields[0].elem else {
            panic!()
        };
        let header = &s.types[h];
        assert_eq!(header.fields[1].elem, Elem::Prim(Prim::Str));
        // builtin_interfaces/Time is known without its text.
        let Elem::Msg(t) = header.fields[0].elem else {
            panic!()
        };
        assert_eq!(s.types[t].fields.len(), 2);
        // A default value (`float64 w 1`) is not a constant.
        let Elem::Msg(q) = root.fields[1].elem else {
            panic!()
        };
        assert_eq!(s.types[q].fields.len(), 4);
    }

    #[test]
    fn constants_sequences_and_bounds() {
        let s = Schema::parse(
            "pkg/msg/T",
            "int8 UP=1\nint8 DOWN = -1\nstring<=8 NAME=\"a#b\"\nint8 direction\n\
             float64[] data\nuint8[<=4] small\nstring<=10[3] names\n",
        )
        .unwrap();
        let f = &s.root_type().fields;
        assert_eq!(f.len(), 4);
        assert_eq!((f[0].name.as_str(), f[0].count), ("direction", Count::One));
        assert_eq!(f[1].count, Count::Seq);
        assert_eq!(f[2].count, Count::Seq);
        assert_eq!(
            (f[3].elem, f[3].count),
            (Elem::Prim(Prim::Str), Count::Fixed(3))
        );
    }

    #[test]
    fn bad_schemas_are_named() {
        let e = Schema::parse("pkg/msg/A", "pkg/B b\n").unwrap_err();
        assert!(e.message.contains("`pkg/B` is used but"), "{e}");
        let e = Schema::parse("pkg/msg/A", "B b\n=====\nMSG: pkg/B\nA a\n").unwrap_err();
        assert!(e.message.contains("contains itself"), "{e}");
        let e = Schema::parse("pkg/msg/A", "# nothing\n").unwrap_err();
        assert!(e.message.contains("no fields"), "{e}");
        let e = Schema::parse("pkg/msg/A", "float64[x] a\n").unwrap_err();
        assert!(e.message.contains("not a number"), "{e}");
    }
}
