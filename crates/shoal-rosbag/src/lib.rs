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
//!   one from a multi-rate log.
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
pub mod schema;
pub mod select;

pub use bag::BagError;
pub use mapping::{Mapping, MappingError};
use shoal_sysid::log::run::MeasuredRun;
use std::path::Path;

/// Reads the bag at `path` (an `.mcap` file or a rosbag2 folder) into one measured run.
pub fn read_bag(path: &Path, mapping: &Mapping) -> Result<MeasuredRun, BagError> {
    let (series, summary) = bag::read_series(path, mapping)?;
    assemble::assemble(path, &series, &summary)
}

/// Whether `path` names a bag rather than a CSV run: an `.mcap` file, or a folder (a rosbag2
/// folder holds `metadata.yaml` and `.mcap` files).
pub fn is_bag(path: &Path) -> bool {
    path.is_dir() || path.extension().is_some_and(|x| x == "mcap" || x == "db3")
}
