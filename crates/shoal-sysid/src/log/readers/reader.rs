//! The seam every log format implements: [`LogReader`] (does this log look like mine? read
//! it into a [`MeasuredRun`]) and what a reader is shown to decide, [`Sniff`]: the path, whether
//! it is a folder, and the file's first bytes.

use crate::log::format::ReadOptions;
use crate::log::run::{MeasuredRun, RunError};
use std::path::Path;

/// MCAP's magic bytes, the start of every MCAP file (a rosbag2's storage).
pub const MCAP_MAGIC: &[u8] = b"\x89MCAP0\r\n";

/// SQLite's magic bytes, the start of a rosbag2 in the older sqlite3 storage (`.db3`).
pub const SQLITE_MAGIC: &[u8] = b"SQLite format 3\0";

/// What a reader sees of a log before reading it.
#[derive(Clone, Copy, Debug)]
pub struct Sniff<'a> {
    /// The log's path.
    pub path: &'a Path,
    /// Whether the path is a folder (a rosbag2 folder holds `metadata.yaml` and `.mcap` files).
    pub is_dir: bool,
    /// The file's first bytes (at most [`Sniff::HEAD_BYTES`]; empty for a folder).
    pub head: &'a [u8],
}

impl Sniff<'_> {
    /// How many of a file's first bytes a reader is shown.
    pub const HEAD_BYTES: usize = 16;

    /// Whether the log is a rosbag2, by content: an MCAP file, a sqlite3 bag, or a folder
    /// holding `metadata.yaml` or `.mcap` files — or by name, a file named `.mcap` or `.db3`
    /// (so that a damaged bag gets the bag reader's diagnosis, not the CSV reader's).
    pub fn is_bag(&self) -> bool {
        if self.is_dir {
            let Ok(dir) = std::fs::read_dir(self.path) else {
                return false;
            };
            return dir.filter_map(Result::ok).any(|e| {
                let p = e.path();
                p.file_name().is_some_and(|n| n == "metadata.yaml")
                    || p.extension().is_some_and(|x| x == "mcap" || x == "db3")
            });
        }
        self.head.starts_with(MCAP_MAGIC)
            || self.head.starts_with(SQLITE_MAGIC)
            || self
                .path
                .extension()
                .is_some_and(|x| x == "mcap" || x == "db3")
    }
}

/// One log format: recognises its logs by content and reads them into a measured run.
pub trait LogReader: Send + Sync {
    /// The format's name in messages (`CSV`, `rosbag2`).
    fn format(&self) -> &'static str;

    /// Whether the log `sniff` shows is in this format.
    fn recognises(&self, sniff: &Sniff<'_>) -> bool;

    /// Reads the log at `path` into one measured run; errors name the file and, where the
    /// format has them, line and column (or topic and field).
    fn read(&self, path: &Path, options: &ReadOptions) -> Result<MeasuredRun, RunError>;
}
