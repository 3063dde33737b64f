//! The bridge's error: what can go wrong opening or running it.

/// A problem opening or running the bridge.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Ros2Error {
    /// The world has no group with `agent = "ros2"`.
    #[error("the world has no vehicle group with agent = \"ros2\"")]
    NotConfigured,
    /// A topic or node name ROS 2 does not accept.
    #[error("ROS 2 name: {0}")]
    Name(String),
    /// DDS refused an operation (participant, topic, publish).
    #[error("DDS: {0}")]
    Dds(String),
}
