//! Reading a log: the first stage of `shoal validate`.
//!
//! * [`run`] — a measured run: time, inputs, measurements, with errors that name line and
//!   column (it knows nothing of how it was read);
//! * [`format`](mod@format) — the vocabulary of a run file: separator, time unit, read options, and what
//!   reading found ([`format::IngestInfo`]);
//! * [`ingest`] — reading runs as loggers write them (separators, comments, time units),
//!   streaming and linear in the rows, on `header.rs` (the header line), `data_lines.rs`
//!   (only the data lines, with the file's line numbers) and `table.rs` (the cells of each
//!   row into the run's columns);
//! * [`segments`] — runs split at gaps in time;
//! * [`limits`] — inputs checked against the actuator limits, rounding clamped and counted;
//! * [`readers`] — the seam every log format implements ([`readers::LogReader`]) and the list
//!   a validation reads its files through ([`readers::Readers`]): CSV here, rosbag2 in crate
//!   `shoal-rosbag`.
//!
//! Nothing here knows the later stages (`evaluate`, `search`, `report`).

mod data_lines;
pub mod format;
mod header;
pub mod ingest;
pub mod limits;
pub(crate) mod numbers;
pub mod readers;
pub mod run;
pub mod segments;
mod table;
