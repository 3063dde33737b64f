//! The CSV reader: runs as loggers write them (`crate::log::ingest`), the format every log
//! that no other reader claims is read as.

use crate::log::format::ReadOptions;
use crate::log::readers::reader::{LogReader, Sniff};
use crate::log::run::{MeasuredRun, RunError};
use std::path::Path;

/// Reads CSV runs (docs/validation.md "The log format").
#[derive(Clone, Copy, Debug, Default)]
pub struct CsvReader;

impl LogReader for CsvReader {
    fn format(&self) -> &'static str {
        "CSV"
    }

    /// Any file: CSV is the fallback, so it comes last in [`crate::log::readers::Readers`].
    fn recognises(&self, sniff: &Sniff<'_>) -> bool {
        !sniff.is_dir
    }

    fn read(&self, path: &Path, options: &ReadOptions) -> Result<MeasuredRun, RunError> {
        MeasuredRun::read_with(path, options)
    }
}
