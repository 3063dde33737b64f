//! Log readers: one seam for every log format, one file per format, laid out as
//! `shoal_model::effects` is.
//!
//! * `reader.rs` — the seam: [`LogReader`] (recognise a log by content, read it into a
//!   [`MeasuredRun`]) and what it is shown, [`Sniff`];
//! * `csv.rs` — [`CsvReader`], CSV runs as loggers write them (the fallback);
//! * `unmapped_bag.rs` — [`UnmappedBag`], a rosbag2 given without a mapping, refused with
//!   what is missing.
//!
//! [`Readers`] is the list a validation reads its files through: the first reader that
//! recognises a log reads it. Why the rosbag2 reader is not here: it needs the `mcap` and CDR
//! crates and a mapping file, and it builds on this crate's [`MeasuredRun`]; so crate
//! `shoal-rosbag` implements [`LogReader`] (`shoal_rosbag::BagReader`) and its
//! `shoal_rosbag::readers` puts it first in the list — the dependency runs one way,
//! `shoal-rosbag` → `shoal-sysid`, and the validation (`crate::validate`) reads every file
//! through whatever list its caller (`shoal validate`, Python's `shoal.validate`) gives.

mod csv;
mod reader;
mod unmapped_bag;

pub use csv::CsvReader;
pub use reader::{LogReader, MCAP_MAGIC, SQLITE_MAGIC, Sniff};
pub use unmapped_bag::UnmappedBag;

use crate::log::format::ReadOptions;
use crate::log::run::{MeasuredRun, RunError};
use std::fmt;
use std::io::Read;
use std::path::Path;
use std::sync::Arc;

/// The readers a validation reads its files through, in order: the first that recognises a
/// log reads it.
#[derive(Clone)]
pub struct Readers(Vec<Arc<dyn LogReader>>);

impl Default for Readers {
    /// A rosbag2 refused for want of a mapping ([`UnmappedBag`]), anything else read as CSV.
    fn default() -> Self {
        Readers(vec![Arc::new(UnmappedBag), Arc::new(CsvReader)])
    }
}

impl fmt::Debug for Readers {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list()
            .entries(self.0.iter().map(|r| r.format()))
            .finish()
    }
}

impl Readers {
    /// These readers with `reader` asked first.
    pub fn with_first(mut self, reader: Arc<dyn LogReader>) -> Self {
        self.0.insert(0, reader);
        self
    }

    /// The formats, in the order they are asked.
    pub fn formats(&self) -> Vec<&'static str> {
        self.0.iter().map(|r| r.format()).collect()
    }

    /// Reads the log at `path` with the first reader that recognises it.
    pub fn read(&self, path: &Path, options: &ReadOptions) -> Result<MeasuredRun, RunError> {
        let fail = |message: String| RunError {
            file: path.to_path_buf(),
            line: 0,
            column: None,
            message,
        };
        let is_dir = path.is_dir();
        let mut head = Vec::with_capacity(Sniff::HEAD_BYTES);
        if !is_dir {
            std::fs::File::open(path)
                .and_then(|f| f.take(Sniff::HEAD_BYTES as u64).read_to_end(&mut head))
                .map_err(|e| fail(format!("cannot read the file: {e}")))?;
        }
        let sniff = Sniff {
            path,
            is_dir,
            head: &head,
        };
        match self.0.iter().find(|r| r.recognises(&sniff)) {
            Some(reader) => reader.read(path, options),
            None => Err(fail(format!(
                "a folder that is not a rosbag2 (no metadata.yaml, no .mcap file); logs read \
                 are files ({}) or rosbag2 folders",
                self.formats().join(", ")
            ))),
        }
    }
}
