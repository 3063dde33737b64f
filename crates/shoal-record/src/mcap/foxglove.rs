//! Foxglove's message types as `run.mcap` writes them in JSON: `foxglove.FrameTransforms`
//! (`/tf`) and `foxglove.SceneUpdate` (`/scene`, `/links`), field for field as in the JSON
//! Schemas Foxglove publishes, which are vendored beside this file (`schemas/`, from
//! <https://github.com/foxglove/foxglove-sdk> `schemas/jsonschema` at ca8a1ce, MIT licence)
//! and written into the file as the channels' schemas. Those schemas require every field, so
//! the primitives a message does not use are written as empty lists ([`Empty`]).
//!
//! Lengths are in metres, times in seconds and nanoseconds, colours in 0 … 1.

use serde::{Deserialize, Serialize};

/// The JSON Schema of `foxglove.FrameTransforms`.
pub const FRAME_TRANSFORMS_SCHEMA: &str = include_str!("schemas/FrameTransforms.json");
/// The JSON Schema of `foxglove.SceneUpdate`.
pub const SCENE_UPDATE_SCHEMA: &str = include_str!("schemas/SceneUpdate.json");

/// A time: whole seconds and nanoseconds (`time` in Foxglove's schemas).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Time {
    /// Whole seconds \[s\].
    pub sec: u32,
    /// Nanoseconds, below 10⁹ \[ns\].
    pub nsec: u32,
}

impl Time {
    /// The time `ns` nanoseconds after the start.
    pub fn from_ns(ns: u64) -> Self {
        Self {
            sec: u32::try_from(ns / 1_000_000_000).unwrap_or(u32::MAX),
            nsec: (ns % 1_000_000_000) as u32,
        }
    }
}

/// A length of time (`duration` in Foxglove's schemas).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Duration {
    /// Whole seconds \[s\].
    pub sec: i32,
    /// Nanoseconds, below 10⁹ \[ns\].
    pub nsec: u32,
}

/// A vector or a point \[m\] (or sizes \[m\]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Vector3 {
    /// x \[m\].
    pub x: f64,
    /// y \[m\].
    pub y: f64,
    /// z \[m\].
    pub z: f64,
}

impl From<[f64; 3]> for Vector3 {
    fn from(v: [f64; 3]) -> Self {
        Self {
            x: v[0],
            y: v[1],
            z: v[2],
        }
    }
}

/// A rotation as a unit quaternion (dimensionless).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Quaternion {
    /// x (dimensionless).
    pub x: f64,
    /// y (dimensionless).
    pub y: f64,
    /// z (dimensionless).
    pub z: f64,
    /// w (dimensionless).
    pub w: f64,
}

impl Quaternion {
    /// No rotation.
    pub const IDENTITY: Self = Self {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        w: 1.0,
    };
}

impl From<shoal_model::math::Quat> for Quaternion {
    fn from(q: shoal_model::math::Quat) -> Self {
        let q = q.quaternion();
        Self {
            x: q.i,
            y: q.j,
            z: q.k,
            w: q.w,
        }
    }
}

/// A position \[m\] and an orientation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Position \[m\].
    pub position: Vector3,
    /// Orientation.
    pub orientation: Quaternion,
}

impl Pose {
    /// At `position` \[m\], not rotated.
    pub fn at(position: [f64; 3]) -> Self {
        Self {
            position: position.into(),
            orientation: Quaternion::IDENTITY,
        }
    }
}

/// A colour: red, green, blue and opacity, each 0 … 1.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Color {
    /// Red, 0 … 1.
    pub r: f64,
    /// Green, 0 … 1.
    pub g: f64,
    /// Blue, 0 … 1.
    pub b: f64,
    /// Opacity, 0 … 1.
    pub a: f64,
}

impl Color {
    /// The sRGB colour `rgb` (0 … 255 each) with opacity `a` (0 … 1).
    pub fn rgb(rgb: (u8, u8, u8), a: f64) -> Self {
        let c = |x: u8| f64::from(x) / 255.0;
        Self {
            r: c(rgb.0),
            g: c(rgb.1),
            b: c(rgb.2),
            a,
        }
    }
}

/// An empty list: a primitive kind a message does not use (the schemas require the field).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Empty;

impl Serialize for Empty {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeSeq;
        s.serialize_seq(Some(0))?.end()
    }
}

impl<'de> Deserialize<'de> for Empty {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Vec::<serde::de::IgnoredAny>::deserialize(d)?;
        if v.is_empty() {
            Ok(Empty)
        } else {
            Err(serde::de::Error::invalid_length(v.len(), &"an empty list"))
        }
    }
}

/// Where a child frame is in its parent frame (`foxglove.FrameTransform`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrameTransform {
    /// When.
    pub timestamp: Time,
    /// The parent frame (`world`).
    pub parent_frame_id: String,
    /// The child frame (a vehicle's name).
    pub child_frame_id: String,
    /// The child's origin in the parent frame \[m\].
    pub translation: Vector3,
    /// The child's orientation in the parent frame.
    pub rotation: Quaternion,
}

/// Several transforms at once (`foxglove.FrameTransforms`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrameTransforms {
    /// The transforms.
    pub transforms: Vec<FrameTransform>,
}

/// A box (`foxglove.CubePrimitive`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CubePrimitive {
    /// Centre and orientation.
    pub pose: Pose,
    /// Extents along its axes \[m\].
    pub size: Vector3,
    /// Colour.
    pub color: Color,
}

/// A sphere or ellipsoid (`foxglove.SpherePrimitive`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SpherePrimitive {
    /// Centre and orientation.
    pub pose: Pose,
    /// Diameters along its axes \[m\].
    pub size: Vector3,
    /// Colour.
    pub color: Color,
}

/// A cylinder along its local z axis (`foxglove.CylinderPrimitive`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CylinderPrimitive {
    /// Centre and orientation.
    pub pose: Pose,
    /// Diameters along x and y, height along z \[m\].
    pub size: Vector3,
    /// Bottom radius as a fraction of the size (1: a cylinder).
    pub bottom_scale: f64,
    /// Top radius as a fraction of the size (1: a cylinder).
    pub top_scale: f64,
    /// Colour.
    pub color: Color,
}

/// Line segments (`foxglove.LinePrimitive`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LinePrimitive {
    /// 0 line strip, 1 line loop, 2 line list (segments 0-1, 2-3, …).
    #[serde(rename = "type")]
    pub kind: u8,
    /// Origin of the points.
    pub pose: Pose,
    /// Thickness \[m\] (or pixels when `scale_invariant`).
    pub thickness: f64,
    /// Whether `thickness` is in screen pixels.
    pub scale_invariant: bool,
    /// The points \[m\].
    pub points: Vec<Vector3>,
    /// Colour of every segment.
    pub color: Color,
    /// Per-point colours (none: `color`).
    pub colors: Vec<Color>,
    /// Point indices (none: the points in order).
    pub indices: Vec<u32>,
}

/// The line list kind of [`LinePrimitive::kind`].
pub const LINE_LIST: u8 = 2;

/// A text label (`foxglove.TextPrimitive`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TextPrimitive {
    /// Where.
    pub pose: Pose,
    /// Whether it always faces the camera.
    pub billboard: bool,
    /// Height of a line \[m\] (or pixels when `scale_invariant`).
    pub font_size: f64,
    /// Whether `font_size` is in screen pixels.
    pub scale_invariant: bool,
    /// Colour.
    pub color: Color,
    /// The text.
    pub text: String,
}

/// A key and its value (`foxglove.KeyValuePair`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct KeyValuePair {
    /// Key.
    pub key: String,
    /// Value.
    pub value: String,
}

/// One thing in the 3D scene (`foxglove.SceneEntity`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneEntity {
    /// When.
    pub timestamp: Time,
    /// The frame its primitives are in.
    pub frame_id: String,
    /// Identifier: an entity replaces the one of the same id on its topic.
    pub id: String,
    /// How long it stays (zero: until replaced).
    pub lifetime: Duration,
    /// Whether it moves with `frame_id` (true) or stays where it was put in the fixed frame.
    pub frame_locked: bool,
    /// Extra facts.
    pub metadata: Vec<KeyValuePair>,
    /// Arrows (none).
    pub arrows: Empty,
    /// Boxes.
    pub cubes: Vec<CubePrimitive>,
    /// Spheres.
    pub spheres: Vec<SpherePrimitive>,
    /// Cylinders.
    pub cylinders: Vec<CylinderPrimitive>,
    /// Lines.
    pub lines: Vec<LinePrimitive>,
    /// Triangles (none).
    pub triangles: Empty,
    /// Labels.
    pub texts: Vec<TextPrimitive>,
    /// Meshes (none).
    pub models: Empty,
}

impl SceneEntity {
    /// An entity with no primitives yet.
    pub fn new(timestamp: Time, frame_id: &str, id: String) -> Self {
        Self {
            timestamp,
            frame_id: frame_id.to_string(),
            id,
            lifetime: Duration::default(),
            frame_locked: false,
            metadata: Vec::new(),
            arrows: Empty,
            cubes: Vec::new(),
            spheres: Vec::new(),
            cylinders: Vec::new(),
            lines: Vec::new(),
            triangles: Empty,
            texts: Vec::new(),
            models: Empty,
        }
    }
}

/// Entities added or replaced (`foxglove.SceneUpdate`; `run.mcap` deletes none).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneUpdate {
    /// Deletions (none: entities end by their lifetime).
    pub deletions: Empty,
    /// The entities.
    pub entities: Vec<SceneEntity>,
}
