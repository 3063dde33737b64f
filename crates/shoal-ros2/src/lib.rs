//! # shoal-ros2
//!
//! Plug a ROS 2 stack into the swarm: the vehicles of every group that says
//! `agent = "ros2"` are driven by ROS 2 nodes over DDS, with ROS 2's topic and type names and
//! QoS, so any ROS 2 node (rclcpp, rclpy, on Fast DDS or Cyclone DDS) or a plain DDS program
//! can talk to them. The only crate that knows DDS: it uses `ros2-client` on RustDDS (pure
//! Rust, nothing of ROS 2 installed).
//!
//! * [`msgs`] — the messages, field for field as their ROS 2 definitions, and the
//!   `shoal_msgs` interface package (`crates/shoal-ros2/shoal_msgs/`, built with colcon by a
//!   ROS 2 user);
//! * [`names`] — vehicles by their ROS names (topics, frames' senders and destinations);
//! * [`topics`] — one vehicle's topics and QoS;
//! * [`convert`] — observations to ROS messages in ROS's axes, commands back;
//! * [`host`] — the world's end: publishing, lock-step or free-running timing, fallback;
//! * [`error`] — what can go wrong opening or running the bridge.
//!
//! The rules for commands (validation, fallback, what is counted) are `shoal_sim::agents`',
//! the same as for iceoryx2 agents (`shoal-bridge`); docs/ros2.md has the topics, the timing
//! and how to use the bridge from a ROS 2 installation.

pub mod convert;
pub mod error;
pub mod host;
pub mod msgs;
pub mod names;
pub mod topics;

pub use error::Ros2Error;
pub use host::Ros2Host;
