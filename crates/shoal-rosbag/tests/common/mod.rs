//! The test kit of the rosbag2 reader's tests and benchmark.

pub mod bagkit;
