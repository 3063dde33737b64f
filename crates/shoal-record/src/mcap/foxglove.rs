//! Foxglove's scene messages as `run.mcap` writes them (`/scene`, `/links`): the ROS 2
//! package `foxglove_msgs`' `SceneUpdate` and the types it uses, field for field in wire order
//! as in that package's `.msg` files (the form without the later `uuid` and `lineage` fields,
//! which Foxglove reads as well, since it decodes by the schema in the file), written in CDR
//! like every message of the file, so that the file keeps the ROS 2 profile and `ros2 bag`
//! and `rosbags` read it. Definitions: [`DEFS`] (comments are shoal's).
//!
//! Lengths are in metres, times in seconds and nanoseconds, colours in 0 … 1.

use super::msgdef::MsgDef;
use super::ros2::{Duration, Point, Pose, Time, Vector3};
use serde::{Deserialize, Serialize};

/// `foxglove_msgs/msg/Color`: sRGB and opacity, each 0 … 1.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Color {
    /// Red, 0 … 1.
    pub r: f64,
    /// Green, 0 … 1.
    pub g: f64,
    /// Blue, 0 … 1.
    pub b: f64,
    /// Opacity, 0 (clear) … 1.
    pub a: f64,
}

impl Color {
    /// The 8-bit sRGB colour `rgb` with opacity `a` (0 … 1).
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

/// A list of primitives of a kind `run.mcap` never draws (arrows, triangles, models): always
/// empty, written as a sequence of length 0.
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

/// `foxglove_msgs/msg/CubePrimitive`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CubePrimitive {
    /// Centre and orientation \[m\].
    pub pose: Pose,
    /// Edge lengths \[m\].
    pub size: Vector3,
    /// Colour.
    pub color: Color,
}

/// `foxglove_msgs/msg/SpherePrimitive`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SpherePrimitive {
    /// Centre and orientation \[m\].
    pub pose: Pose,
    /// Diameters along x, y, z \[m\].
    pub size: Vector3,
    /// Colour.
    pub color: Color,
}

/// `foxglove_msgs/msg/CylinderPrimitive`: flat faces perpendicular to z.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CylinderPrimitive {
    /// Centre and orientation \[m\].
    pub pose: Pose,
    /// Size of its bounding box \[m\].
    pub size: Vector3,
    /// Bottom face's diameter over the box's, 0 … 1.
    pub bottom_scale: f64,
    /// Top face's diameter over the box's, 0 … 1.
    pub top_scale: f64,
    /// Colour.
    pub color: Color,
}

/// `foxglove_msgs/msg/LinePrimitive`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LinePrimitive {
    /// [`LINE_LIST`] and the other drawing modes of the type.
    #[serde(rename = "type")]
    pub kind: u8,
    /// Origin of the points \[m\].
    pub pose: Pose,
    /// Line width \[m\] (or pixels when `scale_invariant`).
    pub thickness: f64,
    /// Whether `thickness` is in screen pixels.
    pub scale_invariant: bool,
    /// The points \[m\].
    pub points: Vec<Point>,
    /// Colour of the whole line (when `colors` is empty).
    pub color: Color,
    /// Colours per point.
    pub colors: Vec<Color>,
    /// Indices into `points` (empty: all, in order).
    pub indices: Vec<u32>,
}

/// `LinePrimitive::kind` of separate segments: 0–1, 2–3, …
pub const LINE_LIST: u8 = 2;

/// `foxglove_msgs/msg/TextPrimitive`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TextPrimitive {
    /// Centre of the text \[m\].
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

/// `foxglove_msgs/msg/KeyValuePair`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct KeyValuePair {
    /// Key.
    pub key: String,
    /// Value.
    pub value: String,
}

/// `foxglove_msgs/msg/SceneEntity`: primitives sharing one frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneEntity {
    /// When it was made (simulated time).
    pub timestamp: Time,
    /// Its frame.
    pub frame_id: String,
    /// Replaces an earlier entity of the same id on the topic.
    pub id: String,
    /// Removed after this long (0: stays).
    pub lifetime: Duration,
    /// Whether it follows its frame as the frame moves.
    pub frame_locked: bool,
    /// Key-value pairs shown beside it.
    pub metadata: Vec<KeyValuePair>,
    /// Arrows (none).
    pub arrows: Empty,
    /// Cubes.
    pub cubes: Vec<CubePrimitive>,
    /// Spheres.
    pub spheres: Vec<SpherePrimitive>,
    /// Cylinders.
    pub cylinders: Vec<CylinderPrimitive>,
    /// Lines.
    pub lines: Vec<LinePrimitive>,
    /// Triangle lists (none).
    pub triangles: Empty,
    /// Texts.
    pub texts: Vec<TextPrimitive>,
    /// Models (none).
    pub models: Empty,
}

impl SceneEntity {
    /// An entity with no primitives, at `timestamp` in `frame_id`.
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

/// `foxglove_msgs/msg/SceneUpdate`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneUpdate {
    /// Entities to delete (none: entities are replaced by id or expire).
    pub deletions: Empty,
    /// Entities to add or replace.
    pub entities: Vec<SceneEntity>,
}

/// The definitions of `foxglove_msgs/msg/SceneUpdate` and the types it uses.
pub const DEFS: &[MsgDef] = &[
    MsgDef {
        name: "foxglove_msgs/msg/SceneUpdate",
        text: "# An update to the entities of a 3D scene.\nfoxglove_msgs/SceneEntityDeletion[] deletions\nfoxglove_msgs/SceneEntity[] entities\n",
        uses: &[
            "foxglove_msgs/SceneEntityDeletion",
            "foxglove_msgs/SceneEntity",
        ],
    },
    MsgDef {
        name: "foxglove_msgs/SceneEntityDeletion",
        text: "# Removes entities published earlier.\nbuiltin_interfaces/Time timestamp\nuint8 MATCHING_ID=0\nuint8 ALL=1\nuint8 type\nstring id\n",
        uses: &["builtin_interfaces/Time"],
    },
    MsgDef {
        name: "foxglove_msgs/SceneEntity",
        text: "# Primitives in one frame of reference.\nbuiltin_interfaces/Time timestamp\nstring frame_id\nstring id\nbuiltin_interfaces/Duration lifetime # 0: stays\nbool frame_locked\nfoxglove_msgs/KeyValuePair[] metadata\nfoxglove_msgs/ArrowPrimitive[] arrows\nfoxglove_msgs/CubePrimitive[] cubes\nfoxglove_msgs/SpherePrimitive[] spheres\nfoxglove_msgs/CylinderPrimitive[] cylinders\nfoxglove_msgs/LinePrimitive[] lines\nfoxglove_msgs/TriangleListPrimitive[] triangles\nfoxglove_msgs/TextPrimitive[] texts\nfoxglove_msgs/ModelPrimitive[] models\n",
        uses: &[
            "builtin_interfaces/Time",
            "builtin_interfaces/Duration",
            "foxglove_msgs/KeyValuePair",
            "foxglove_msgs/ArrowPrimitive",
            "foxglove_msgs/CubePrimitive",
            "foxglove_msgs/SpherePrimitive",
            "foxglove_msgs/CylinderPrimitive",
            "foxglove_msgs/LinePrimitive",
            "foxglove_msgs/TriangleListPrimitive",
            "foxglove_msgs/TextPrimitive",
            "foxglove_msgs/ModelPrimitive",
        ],
    },
    MsgDef {
        name: "foxglove_msgs/KeyValuePair",
        text: "# A key and its value.\nstring key\nstring value\n",
        uses: &[],
    },
    MsgDef {
        name: "foxglove_msgs/ArrowPrimitive",
        text: "# An arrow along +x of its pose (lengths in m).\ngeometry_msgs/Pose pose\nfloat64 shaft_length\nfloat64 shaft_diameter\nfloat64 head_length\nfloat64 head_diameter\nfoxglove_msgs/Color color\n",
        uses: &["geometry_msgs/Pose", "foxglove_msgs/Color"],
    },
    MsgDef {
        name: "foxglove_msgs/CubePrimitive",
        text: "# A box (m).\ngeometry_msgs/Pose pose\ngeometry_msgs/Vector3 size\nfoxglove_msgs/Color color\n",
        uses: &[
            "geometry_msgs/Pose",
            "geometry_msgs/Vector3",
            "foxglove_msgs/Color",
        ],
    },
    MsgDef {
        name: "foxglove_msgs/SpherePrimitive",
        text: "# An ellipsoid (diameters in m).\ngeometry_msgs/Pose pose\ngeometry_msgs/Vector3 size\nfoxglove_msgs/Color color\n",
        uses: &[
            "geometry_msgs/Pose",
            "geometry_msgs/Vector3",
            "foxglove_msgs/Color",
        ],
    },
    MsgDef {
        name: "foxglove_msgs/CylinderPrimitive",
        text: "# A cylinder or truncated cone, flat faces perpendicular to z (m).\ngeometry_msgs/Pose pose\ngeometry_msgs/Vector3 size\nfloat64 bottom_scale\nfloat64 top_scale\nfoxglove_msgs/Color color\n",
        uses: &[
            "geometry_msgs/Pose",
            "geometry_msgs/Vector3",
            "foxglove_msgs/Color",
        ],
    },
    MsgDef {
        name: "foxglove_msgs/LinePrimitive",
        text: "# Points joined by lines (m).\nuint8 LINE_STRIP=0\nuint8 LINE_LOOP=1\nuint8 LINE_LIST=2\nuint8 type\ngeometry_msgs/Pose pose\nfloat64 thickness\nbool scale_invariant\ngeometry_msgs/Point[] points\nfoxglove_msgs/Color color\nfoxglove_msgs/Color[] colors\nuint32[] indices\n",
        uses: &[
            "geometry_msgs/Pose",
            "geometry_msgs/Point",
            "foxglove_msgs/Color",
        ],
    },
    MsgDef {
        name: "foxglove_msgs/TriangleListPrimitive",
        text: "# Triangles from triples of points (m).\ngeometry_msgs/Pose pose\ngeometry_msgs/Point[] points\nfoxglove_msgs/Color color\nfoxglove_msgs/Color[] colors\nuint32[] indices\n",
        uses: &[
            "geometry_msgs/Pose",
            "geometry_msgs/Point",
            "foxglove_msgs/Color",
        ],
    },
    MsgDef {
        name: "foxglove_msgs/TextPrimitive",
        text: "# A text label (m).\ngeometry_msgs/Pose pose\nbool billboard\nfloat64 font_size\nbool scale_invariant\nfoxglove_msgs/Color color\nstring text\n",
        uses: &["geometry_msgs/Pose", "foxglove_msgs/Color"],
    },
    MsgDef {
        name: "foxglove_msgs/ModelPrimitive",
        text: "# A 3D model from a URL or embedded data.\ngeometry_msgs/Pose pose\ngeometry_msgs/Vector3 scale\nfoxglove_msgs/Color color\nbool override_color\nstring url\nstring media_type\nuint8[] data\n",
        uses: &[
            "geometry_msgs/Pose",
            "geometry_msgs/Vector3",
            "foxglove_msgs/Color",
        ],
    },
    MsgDef {
        name: "foxglove_msgs/Color",
        text: "# sRGB and opacity, each 0 to 1.\nfloat64 r\nfloat64 g\nfloat64 b\nfloat64 a\n",
        uses: &[],
    },
];
