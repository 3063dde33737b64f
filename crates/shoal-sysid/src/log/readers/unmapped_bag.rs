//! A rosbag2 given without a mapping: recognised by content (MCAP's magic bytes, a sqlite3
//! bag, a rosbag2 folder) and refused with what is missing, instead of being read as a CSV
//! whose header is not text. A bag reader given a mapping (crate `shoal-rosbag`) comes before
//! this one in [`crate::log::readers::Readers`] and reads the bag.

use crate::log::format::ReadOptions;
use crate::log::readers::reader::{LogReader, Sniff};
use crate::log::run::{MeasuredRun, RunError};
use std::path::Path;

/// Refuses rosbag2s: reading one needs a mapping.
#[derive(Clone, Copy, Debug, Default)]
pub struct UnmappedBag;

impl LogReader for UnmappedBag {
    fn format(&self) -> &'static str {
        "rosbag2 (no mapping)"
    }

    fn recognises(&self, sniff: &Sniff<'_>) -> bool {
        sniff.is_bag()
    }

    fn read(&self, path: &Path, _options: &ReadOptions) -> Result<MeasuredRun, RunError> {
        Err(RunError {
            file: path.to_path_buf(),
            line: 0,
            column: None,
            message: "a rosbag2 (MCAP), not a CSV: reading it needs a mapping file that says \
                      which topic and field is each input and channel (`shoal validate \
                      --mapping MAPPING.toml`, Python `shoal.validate(..., \
                      mapping=\"MAPPING.toml\")`; docs/validation.md \"Your rosbag2\")"
                .into(),
        })
    }
}
