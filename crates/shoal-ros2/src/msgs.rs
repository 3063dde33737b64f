//! The messages of the bridge as serde structs, field for field as their ROS 2 definitions
//! (the order is the wire order of CDR):
//!
//! * the standard ones the world publishes: `sensor_msgs/Imu` and `FluidPressure`,
//!   `std_msgs/Header`, `builtin_interfaces/Time`, `tf2_msgs/TFMessage` and `geometry_msgs`
//!   `Point`, `Pose`, `Quaternion`, `Transform`, `TransformStamped`, `Vector3` are `run.mcap`'s
//!   ([`shoal_record::mcap::ros2`], one definition in the workspace); `nav_msgs/Odometry` and
//!   `rosgraph_msgs/Clock` are here;
//! * `shoal_msgs` ([`Setpoint`], [`Actuators`], [`OpticalFrame`], [`FrameOutcome`]): the
//!   interface package in `crates/shoal-ros2/shoal_msgs/` that a ROS 2 user builds with
//!   colcon; a test parses its `.msg` files and checks these structs against them (names,
//!   types, order).

use serde::{Deserialize, Serialize};
pub use shoal_record::mcap::ros2::{
    FluidPressure, Header, Imu, Point, Pose, Quaternion, TfMessage, Time, Transform,
    TransformStamped, Vector3,
};

/// `geometry_msgs/msg/PoseWithCovariance`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PoseWithCovariance {
    /// The pose.
    pub pose: Pose,
    /// Row-major 6×6 covariance of x, y, z, rotation about x, y, z \[m², rad²\]
    /// (`float64[36]`: six rows of six, the same 36 numbers on the wire).
    pub covariance: [[f64; 6]; 6],
}

/// `geometry_msgs/msg/Twist`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Twist {
    /// Linear velocity \[m/s\].
    pub linear: Vector3,
    /// Angular velocity \[rad/s\].
    pub angular: Vector3,
}

/// `geometry_msgs/msg/TwistWithCovariance`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TwistWithCovariance {
    /// The twist.
    pub twist: Twist,
    /// Row-major 6×6 covariance \[(m/s)², (rad/s)²\] (`float64[36]`, as six rows).
    pub covariance: [[f64; 6]; 6],
}

/// `nav_msgs/msg/Odometry`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Odometry {
    /// Stamp and frame of the pose (`world`).
    pub header: Header,
    /// Frame of the twist (`<vehicle>/base_link`).
    pub child_frame_id: String,
    /// Pose in `header.frame_id`.
    pub pose: PoseWithCovariance,
    /// Velocity in `child_frame_id`.
    pub twist: TwistWithCovariance,
}

/// `rosgraph_msgs/msg/Clock`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Clock {
    /// Simulated time.
    pub clock: Time,
}

/// `shoal_msgs/msg/Setpoint`: setpoints for one vehicle's controller, answering a tick.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Setpoint {
    /// The control tick answered (its `/clock` time).
    pub stamp: Time,
    /// One of the `MODE_*` constants.
    pub mode: u8,
    /// Depth setpoint \[m, positive down\].
    pub depth: f64,
    /// Heading setpoint, NED \[rad\].
    pub heading: f64,
    /// Surge force \[N\].
    pub surge: f64,
    /// Sway force \[N\].
    pub sway: f64,
    /// `modem/tx` messages stamped with this tick, sent before this one.
    pub frames: u32,
}

/// `Setpoint.mode` values (the `.msg` file's constants).
pub mod mode {
    #![allow(missing_docs)]
    pub const KEEP: u8 = 0;
    pub const OFF: u8 = 1;
    pub const DIVING: u8 = 2;
    pub const BUOYANCY: u8 = 3;
    pub const TURNING: u8 = 4;
    pub const DRIFT: u8 = 5;
    pub const AUTO: u8 = 6;
}

/// `shoal_msgs/msg/Actuators`: raw actuator commands, answering a tick.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Actuators {
    /// The control tick answered (its `/clock` time).
    pub stamp: Time,
    /// Per thruster, in the vehicle file's order \[%\].
    pub thrusters: Vec<f64>,
    /// Per tilt drive, in the vehicle file's order \[rad\].
    pub tilts: Vec<f64>,
    /// −1 empty, 0 off, +1 fill.
    pub pump: i8,
    /// `modem/tx` messages stamped with this tick, sent before this one.
    pub frames: u32,
}

/// `shoal_msgs/msg/OpticalFrame`: a frame received (`modem/rx`) or to send (`modem/tx`).
/// Vehicles are named by their ROS names (`crate::names`), as in their topics.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct OpticalFrame {
    /// rx: end of the reception; tx: the control tick it belongs to.
    pub stamp: Time,
    /// rx: the sending vehicle's ROS name; tx: unused (empty).
    pub sender: String,
    /// tx: the destination vehicle's ROS name, empty for a broadcast; rx: the receiving
    /// vehicle's own name when the frame was a unicast to it, empty for a broadcast.
    pub to: String,
    /// tx: with `to`, acknowledged and retransmitted until it is (stop-and-wait ARQ), its
    /// end published on `modem/outcome`; rx: unused (false).
    pub ack: bool,
    /// tx: a number of the sender's choosing, returned on `modem/outcome`; rx: unused (0).
    pub tag: u32,
    /// rx: the sender's sequence number.
    pub seq: u32,
    /// rx: the receiving modem; tx: the sending one, or [`ALL_MODEMS`].
    pub modem: i32,
    /// rx: received optical power \[W\].
    pub power: f64,
    /// rx: electrical signal-to-noise ratio \[-\].
    pub snr: f64,
    /// tx: delay after the tick before the frame is handed to the modem \[s\].
    pub delay: f64,
    /// The payload \[bytes\].
    pub payload: Vec<u8>,
}

/// `shoal_msgs/msg/FrameOutcome`: what became of an acknowledged unicast (`modem/outcome`
/// of its sender).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FrameOutcome {
    /// When it ended: the acknowledgement decoded, or the wait after the last
    /// transmission ran out (simulated time).
    pub stamp: Time,
    /// The destination vehicle's ROS name.
    pub to: String,
    /// The `tag` it was sent with.
    pub tag: u32,
    /// The sender's sequence number of the frame (the destination's `modem/rx` `seq`).
    pub seq: u32,
    /// Times it went on the air: 1 + retransmissions (0: never, its queue was full) \[-\].
    pub transmissions: u32,
    /// Whether the destination acknowledged it (else: given up).
    pub acknowledged: bool,
    /// When it was handed to the link layer: the tick's time plus the frame's `delay`.
    pub sent: Time,
}

/// `OpticalFrame.modem` for "every modem at once".
pub const ALL_MODEMS: i32 = -1;

/// A time in nanoseconds since the start, as a stamp.
pub fn stamp(t_s: f64) -> Time {
    Time::from_ns((t_s.max(0.0) * 1e9).round() as u64)
}
