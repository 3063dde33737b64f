//! The standard ROS 2 messages of `run.mcap` and the ROS 2 bridge (`sensor_msgs`
//! `FluidPressure` and `Imu`, `std_msgs` `Float64MultiArray` and `Header`, `geometry_msgs`,
//! `tf2_msgs/msg/TFMessage`, `builtin_interfaces`) as serde structs, their message definitions,
//! and the CDR encoding of every message in the file — what `ros2 bag record` writes into an MCAP file, so that the topics
//! read like a logged vehicle's (e.g. by `shoal validate` through a mapping file).
//!
//! * **Schemas** (encoding `ros2msg`): the type's `.msg` definition followed by those of every
//!   type it uses, the way rosbag2 stores them — depth first, each dependency once, after a
//!   line of 80 `=` and a line `MSG: <package>/<Type>` ([`super::definitions`]). The definitions here
//!   declare the same fields, in the same order, as the ROS 2 packages' files (`sensor_msgs`,
//!   `std_msgs`, `geometry_msgs`, `tf2_msgs`, `builtin_interfaces`); their comments are shoal's.
//! * **Messages** (encoding `cdr`): plain CDR, little-endian, after the 4-byte encapsulation
//!   header `00 01 00 00` ([`encode`], [`decode`]), serialized by the `cdr-encoding` crate;
//!   alignment counts from the end of that header, as in ROS 2.

use super::msgdef::MsgDef;
use byteorder::LittleEndian;
use serde::{Deserialize, Serialize};

/// The encapsulation header of little-endian plain CDR (`CDR_LE`, no options).
pub const CDR_LE: [u8; 4] = [0x00, 0x01, 0x00, 0x00];

/// Standard atmospheric pressure at the water's surface \[Pa\].
pub const SURFACE_PRESSURE_PA: f64 = 101_325.0;

/// `builtin_interfaces/msg/Time`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Time {
    /// Whole seconds \[s\].
    pub sec: i32,
    /// Nanoseconds, below 10⁹ \[ns\].
    pub nanosec: u32,
}

impl Time {
    /// The time `ns` nanoseconds after the start.
    pub fn from_ns(ns: u64) -> Self {
        Self {
            sec: i32::try_from(ns / 1_000_000_000).unwrap_or(i32::MAX),
            nanosec: (ns % 1_000_000_000) as u32,
        }
    }
}

/// `std_msgs/msg/Header`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// When the values were sampled (simulated time).
    pub stamp: Time,
    /// The frame they are in (the vehicle's name: its FLU body frame).
    pub frame_id: String,
}

/// `sensor_msgs/msg/FluidPressure`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FluidPressure {
    /// Stamp and frame.
    pub header: Header,
    /// Absolute pressure \[Pa\].
    pub fluid_pressure: f64,
    /// Variance \[Pa²\] (0: unknown).
    pub variance: f64,
}

/// `geometry_msgs/msg/Quaternion` (dimensionless).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Quaternion {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
    /// w.
    pub w: f64,
}

/// `geometry_msgs/msg/Vector3` (units by use).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Vector3 {
    /// x (the field's unit).
    pub x: f64,
    /// y (the field's unit).
    pub y: f64,
    /// z (the field's unit).
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

/// `builtin_interfaces/msg/Duration`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Duration {
    /// Whole seconds \[s\].
    pub sec: i32,
    /// Nanoseconds, below 10⁹ \[ns\].
    pub nanosec: u32,
}

impl Duration {
    /// `s` seconds, to the nearest nanosecond (at most `i32::MAX` s).
    pub fn from_secs(s: f64) -> Self {
        let ns = (s.max(0.0) * 1e9).round() as u64;
        Self {
            sec: i32::try_from(ns / 1_000_000_000).unwrap_or(i32::MAX),
            nanosec: (ns % 1_000_000_000) as u32,
        }
    }
}

/// `geometry_msgs/msg/Point` \[m\].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Point {
    /// x \[m\].
    pub x: f64,
    /// y \[m\].
    pub y: f64,
    /// z \[m\].
    pub z: f64,
}

impl From<[f64; 3]> for Point {
    fn from(v: [f64; 3]) -> Self {
        Self {
            x: v[0],
            y: v[1],
            z: v[2],
        }
    }
}

/// `geometry_msgs/msg/Pose`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Position \[m\].
    pub position: Point,
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

/// `geometry_msgs/msg/Transform`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Transform {
    /// Translation \[m\].
    pub translation: Vector3,
    /// Rotation.
    pub rotation: Quaternion,
}

/// `geometry_msgs/msg/TransformStamped`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TransformStamped {
    /// Stamp and parent frame.
    pub header: Header,
    /// The child frame.
    pub child_frame_id: String,
    /// Parent to child.
    pub transform: Transform,
}

/// `tf2_msgs/msg/TFMessage`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TfMessage {
    /// The transforms.
    pub transforms: Vec<TransformStamped>,
}

/// `sensor_msgs/msg/Imu`, in ROS's frames (ENU world, FLU body).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Imu {
    /// Stamp and frame.
    pub header: Header,
    /// Attitude, FLU body to ENU world.
    pub orientation: Quaternion,
    /// Covariance of the attitude about x, y, z, row-major \[rad²\] (all 0: unknown).
    pub orientation_covariance: [f64; 9],
    /// Angular velocity in the body frame \[rad/s\].
    pub angular_velocity: Vector3,
    /// Its covariance, row-major \[(rad/s)²\] (all 0: unknown).
    pub angular_velocity_covariance: [f64; 9],
    /// Linear acceleration \[m/s²\].
    pub linear_acceleration: Vector3,
    /// Its covariance, row-major \[(m/s²)²\] (element 0 = −1: no estimate).
    pub linear_acceleration_covariance: [f64; 9],
}

/// `std_msgs/msg/MultiArrayDimension`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MultiArrayDimension {
    /// What the dimension counts (here: the actuators' names, comma-separated, in order).
    pub label: String,
    /// Elements along it.
    pub size: u32,
    /// Elements from one index of it to the next, times the size of the dimensions after it.
    pub stride: u32,
}

/// `std_msgs/msg/MultiArrayLayout`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MultiArrayLayout {
    /// The dimensions, outermost first.
    pub dim: Vec<MultiArrayDimension>,
    /// Elements before the first \[count\].
    pub data_offset: u32,
}

/// `std_msgs/msg/Float64MultiArray` (units by topic).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Float64MultiArray {
    /// Layout of `data`.
    pub layout: MultiArrayLayout,
    /// The values (the topic's unit).
    pub data: Vec<f64>,
}

impl Float64MultiArray {
    /// A one-dimensional array of `data` whose elements are `label` (e.g. the actuators'
    /// names, comma-separated).
    pub fn vector(label: &str, data: Vec<f64>) -> Self {
        let n = u32::try_from(data.len()).unwrap_or(u32::MAX);
        Self {
            layout: MultiArrayLayout {
                dim: vec![MultiArrayDimension {
                    label: label.to_string(),
                    size: n,
                    stride: n,
                }],
                data_offset: 0,
            },
            data,
        }
    }
}

/// The standard types' definitions.
pub const DEFS: &[MsgDef] = &[
    MsgDef {
        name: "sensor_msgs/msg/FluidPressure",
        text: "# Pressure of a fluid.\nstd_msgs/Header header\nfloat64 fluid_pressure # absolute, in Pa\nfloat64 variance # in Pa^2; 0: unknown\n",
        uses: &["std_msgs/Header"],
    },
    MsgDef {
        name: "sensor_msgs/msg/Imu",
        text: "# An inertial measurement. Covariances are row-major about x, y, z; all zeros: unknown;\n# element 0 = -1: no estimate of that quantity.\nstd_msgs/Header header\ngeometry_msgs/Quaternion orientation\nfloat64[9] orientation_covariance # rad^2\ngeometry_msgs/Vector3 angular_velocity # rad/s\nfloat64[9] angular_velocity_covariance # (rad/s)^2\ngeometry_msgs/Vector3 linear_acceleration # m/s^2\nfloat64[9] linear_acceleration_covariance # (m/s^2)^2\n",
        uses: &[
            "geometry_msgs/Quaternion",
            "geometry_msgs/Vector3",
            "std_msgs/Header",
        ],
    },
    MsgDef {
        name: "std_msgs/msg/Float64MultiArray",
        text: "# An array of float64 values and its layout.\nMultiArrayLayout layout\nfloat64[] data\n",
        uses: &["std_msgs/MultiArrayLayout"],
    },
    MsgDef {
        name: "std_msgs/MultiArrayLayout",
        text: "# The dimensions of a multi-array, outermost first.\nMultiArrayDimension[] dim\nuint32 data_offset # elements before the first\n",
        uses: &["std_msgs/MultiArrayDimension"],
    },
    MsgDef {
        name: "std_msgs/MultiArrayDimension",
        text: "# One dimension of a multi-array.\nstring label\nuint32 size # elements along it\nuint32 stride # elements per step of it, times the inner dimensions\n",
        uses: &[],
    },
    MsgDef {
        name: "std_msgs/Header",
        text: "# When and in which frame data were taken.\nbuiltin_interfaces/Time stamp\nstring frame_id\n",
        uses: &["builtin_interfaces/Time"],
    },
    MsgDef {
        name: "builtin_interfaces/Time",
        text: "# A time: whole seconds and nanoseconds.\nint32 sec\nuint32 nanosec # below 1e9\n",
        uses: &[],
    },
    MsgDef {
        name: "geometry_msgs/Quaternion",
        text: "# A rotation as a unit quaternion.\nfloat64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n",
        uses: &[],
    },
    MsgDef {
        name: "geometry_msgs/Vector3",
        text: "# A vector in free space.\nfloat64 x\nfloat64 y\nfloat64 z\n",
        uses: &[],
    },
    MsgDef {
        name: "geometry_msgs/Point",
        text: "# A position in free space.\nfloat64 x\nfloat64 y\nfloat64 z\n",
        uses: &[],
    },
    MsgDef {
        name: "geometry_msgs/Pose",
        text: "# A position and an orientation.\nPoint position\nQuaternion orientation\n",
        uses: &["geometry_msgs/Point", "geometry_msgs/Quaternion"],
    },
    MsgDef {
        name: "geometry_msgs/Transform",
        text: "# A transform from a parent frame to a child frame.\nVector3 translation\nQuaternion rotation\n",
        uses: &["geometry_msgs/Vector3", "geometry_msgs/Quaternion"],
    },
    MsgDef {
        name: "geometry_msgs/TransformStamped",
        text: "# A transform from header.frame_id to child_frame_id at header.stamp.\nstd_msgs/Header header\nstring child_frame_id\nTransform transform\n",
        uses: &["std_msgs/Header", "geometry_msgs/Transform"],
    },
    MsgDef {
        name: "tf2_msgs/msg/TFMessage",
        text: "# Transforms between frames.\ngeometry_msgs/TransformStamped[] transforms\n",
        uses: &["geometry_msgs/TransformStamped"],
    },
    MsgDef {
        name: "builtin_interfaces/Duration",
        text: "# A duration: whole seconds and nanoseconds.\nint32 sec\nuint32 nanosec # below 1e9\n",
        uses: &[],
    },
];

/// `msg` in CDR, little-endian, after the encapsulation header [`CDR_LE`].
pub fn encode<T: Serialize>(msg: &T) -> std::io::Result<Vec<u8>> {
    let mut out = CDR_LE.to_vec();
    cdr_encoding::to_writer::<T, LittleEndian, _>(&mut out, msg).map_err(std::io::Error::other)?;
    Ok(out)
}

/// A message of type `T` from its CDR bytes (encapsulation header [`CDR_LE`] first).
pub fn decode<T: serde::de::DeserializeOwned>(bytes: &[u8]) -> std::io::Result<T> {
    let body = bytes
        .strip_prefix(&CDR_LE)
        .ok_or_else(|| std::io::Error::other("not little-endian plain CDR (00 01 00 00)"))?;
    let (msg, _) =
        cdr_encoding::from_bytes::<T, LittleEndian>(body).map_err(std::io::Error::other)?;
    Ok(msg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cdr_has_the_header_alignment_and_round_trips() {
        let m = FluidPressure {
            header: Header {
                stamp: Time::from_ns(2_500_000_000),
                frame_id: "a".into(),
            },
            fluid_pressure: 101_325.0,
            variance: 0.0,
        };
        let b = encode(&m).unwrap();
        // Header, sec 2, nanosec 5e8, frame "a" (length 2 with its NUL), padding to 8, then
        // two float64.
        assert_eq!(&b[..4], &CDR_LE);
        assert_eq!(&b[4..8], &2i32.to_le_bytes());
        assert_eq!(&b[8..12], &500_000_000u32.to_le_bytes());
        assert_eq!(&b[12..16], &2u32.to_le_bytes());
        assert_eq!(&b[16..18], b"a\0");
        assert_eq!(&b[18..20], &[0, 0]);
        assert_eq!(&b[20..28], &101_325f64.to_le_bytes());
        assert_eq!(b.len(), 36);
        assert_eq!(decode::<FluidPressure>(&b).unwrap(), m);
        let a = Float64MultiArray::vector("left,right", vec![1.5, -2.0]);
        assert_eq!(
            decode::<Float64MultiArray>(&encode(&a).unwrap()).unwrap(),
            a
        );
        assert!(decode::<FluidPressure>(&b[1..]).is_err());
    }
}
