//! The rosbag2 reader behind shoal's one log seam (`shoal_sysid::log::readers`): a bag
//! recognised by content and read through its mapping, its [`BagError`] given as the seam's
//! `RunError` (file, and the topic, message and field in the message).

use crate::assemble::assemble;
use crate::bag::{BagError, read_series};
use crate::mapping::{Mapping, MappingError};
use shoal_sysid::log::format::ReadOptions;
use shoal_sysid::log::readers::{LogReader, Readers, Sniff};
use shoal_sysid::log::run::{MeasuredRun, RunError};
use std::path::Path;
use std::sync::Arc;

/// Reads the bag at `path` (an `.mcap` file or a rosbag2 folder) into one measured run.
pub fn read_bag(path: &Path, mapping: &Mapping) -> Result<MeasuredRun, BagError> {
    let (series, summary) = read_series(path, mapping)?;
    assemble(path, &series, &summary)
}

/// Reads rosbag2s (an `.mcap` file or a rosbag2 folder) through one mapping.
#[derive(Clone, Debug)]
pub struct BagReader {
    /// Which topic and field is each input and channel.
    pub mapping: Mapping,
}

impl LogReader for BagReader {
    fn format(&self) -> &'static str {
        "rosbag2"
    }

    fn recognises(&self, sniff: &Sniff<'_>) -> bool {
        sniff.is_bag()
    }

    fn read(&self, path: &Path, _options: &ReadOptions) -> Result<MeasuredRun, RunError> {
        read_bag(path, &self.mapping).map_err(run_error)
    }
}

/// A bag's error as the seam's: the file, line 0 (a bag has no lines), the place in the text.
fn run_error(e: BagError) -> RunError {
    RunError {
        file: e.file,
        line: 0,
        column: None,
        message: match e.place {
            Some(place) => format!("{place}: {}", e.message),
            None => e.message,
        },
    }
}

/// The readers `shoal validate` and Python's `shoal.validate` read runs through: with the
/// mapping file at `mapping`, rosbag2s read through it; without, refused for want of one; any
/// other file read as CSV.
pub fn readers(mapping: Option<&Path>) -> Result<Readers, MappingError> {
    Ok(match mapping {
        Some(p) => Readers::default().with_first(Arc::new(BagReader {
            mapping: Mapping::read(p)?,
        })),
        None => Readers::default(),
    })
}
