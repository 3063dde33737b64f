//! One ROS 2 message definition ([`MsgDef`]): what the tables beside the types
//! ([`super::ros2`], [`super::foxglove`], [`super::plain`]) hold and
//! [`super::definitions`] assembles.

/// A `.msg` definition: type name, text, and the types it uses (in the order rosbag2 visits
/// them: the order of first use in the text).
pub struct MsgDef {
    /// The type's name as a schema names it (`sensor_msgs/msg/Imu`) or a dependency line
    /// does (`std_msgs/Header`).
    pub name: &'static str,
    /// The `.msg` text (fields in wire order; comments are shoal's).
    pub text: &'static str,
    /// The types the text uses.
    pub uses: &'static [&'static str],
}
