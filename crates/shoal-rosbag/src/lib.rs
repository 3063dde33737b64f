//! # shoal-rosbag
//!
//! Logs as robots write them: a rosbag2 (MCAP storage, CDR-encoded ROS 2 messages) read into
//! a [`MeasuredRun`] for `shoal validate`, through a small mapping file that says, for each
//! input and channel, the topic, the field, the unit conversion, the clock and the axes.
//!
//! * [`mapping`] — the mapping file, checked;
//! * [`schema`] — the message definitions the bag carries (`ros2msg`), parsed;
//! * [`select`] — field paths resolved against a message type;
//! * [`decode`] — messages decoded by their schema (CDR with the `cdr-encoding` crate);
//! * [`bag`] — the bag's files and messages (Foxglove's `mcap` crate) into time series;
//! * [`assemble`] — the series onto one time base: a measured run, as the CSV reader makes
//!   one from a multi-rate log;
//! * [`reader`] — [`BagReader`], this crate behind the validation's one log seam
//!   (`shoal_sysid::log::readers::LogReader`), and [`readers`], the list `shoal validate`
//!   and Python's `shoal.validate` read runs through.
//!
//! Why the seam is in `shoal-sysid` and this reader here: a bag read becomes shoal-sysid's
//! `MeasuredRun`, so this crate depends on `shoal-sysid`; the seam there lets the validation
//! read any format without knowing MCAP, CDR or mappings, and keeps the dependencies one way.
//!
//! Only the bag's own schemas are used: any ROS 2 message type with numbers in it can be
//! mapped, standard (sensor_msgs/FluidPressure, sensor_msgs/Imu, nav_msgs/Odometry,
//! std_msgs/Float64MultiArray) or a vendor's. Every problem is a [`BagError`] naming the
//! file, the topic, the message and the field, or a [`MappingError`] naming the entry.
//!
//! ```no_run
//! use shoal_rosbag::{Mapping, read_bag};
//! use std::path::Path;
//! let mapping = Mapping::read(Path::new("mappings/uauv2.toml"))?;
//! let run = read_bag(Path::new("pool_dive_3.mcap"), &mapping)?;
//! println!("{} rows over {:.1} s", run.t.len(), run.duration());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod assemble;
pub mod bag;
pub mod decode;
pub mod mapping;
pub mod reader;
pub mod schema;
pub mod select;

pub use bag::BagError;
pub use mapping::{Mapping, MappingError};
pub use reader::{BagReader, read_bag, readers};
