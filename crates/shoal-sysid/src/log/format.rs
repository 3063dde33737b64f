//! The vocabulary of a measured-run file: its column separator, the unit of its time column,
//! how to read it ([`ReadOptions`]) and what reading it found ([`IngestInfo`], carried by every
//! run for the report). The header parser and the reader (`ingest.rs`) use these; the run
//! itself only carries them.

use crate::log::numbers::short;
use std::fmt;

/// The unit the time column is written in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize)]
pub enum TimeUnit {
    /// Seconds.
    #[default]
    #[serde(rename = "s")]
    Seconds,
    /// Milliseconds.
    #[serde(rename = "ms")]
    Milliseconds,
}

impl TimeUnit {
    /// Symbol: `s` or `ms`.
    pub fn symbol(self) -> &'static str {
        match self {
            TimeUnit::Seconds => "s",
            TimeUnit::Milliseconds => "ms",
        }
    }

    /// Converts a time written in this unit to seconds.
    pub fn to_seconds(self, t: f64) -> f64 {
        match self {
            TimeUnit::Seconds => t,
            TimeUnit::Milliseconds => t / 1000.0,
        }
    }

    /// The unit a time column name declares: `Some(None)` for a plain `t`, `None` if the name
    /// is not a time column.
    pub fn from_column(name: &str) -> Option<Option<TimeUnit>> {
        match name {
            "t" => Some(None),
            "t_s" | "t[s]" => Some(Some(TimeUnit::Seconds)),
            "t_ms" | "t[ms]" => Some(Some(TimeUnit::Milliseconds)),
            _ => None,
        }
    }
}

impl std::str::FromStr for TimeUnit {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "s" => Ok(TimeUnit::Seconds),
            "ms" => Ok(TimeUnit::Milliseconds),
            _ => Err(format!("unknown time unit `{s}` (allowed: s, ms)")),
        }
    }
}

impl fmt::Display for TimeUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.symbol())
    }
}

/// The column separator of a file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Separator {
    /// `,`
    #[default]
    Comma,
    /// `;`
    Semicolon,
    /// A tab character.
    Tab,
}

impl Separator {
    /// Every separator the reader knows.
    pub const ALL: [Separator; 3] = [Separator::Comma, Separator::Semicolon, Separator::Tab];

    /// The separator byte.
    pub fn byte(self) -> u8 {
        match self {
            Separator::Comma => b',',
            Separator::Semicolon => b';',
            Separator::Tab => b'\t',
        }
    }

    /// Name for messages: `` `,` ``, `` `;` `` or `tab`.
    pub fn name(self) -> &'static str {
        match self {
            Separator::Comma => "`,`",
            Separator::Semicolon => "`;`",
            Separator::Tab => "tab",
        }
    }
}

/// How to read a measured run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct ReadOptions {
    /// The unit of a plain `t` column (seconds when `None`); a header that declares another
    /// unit (`t_ms`, `t[s]`, …) is then an error.
    pub time_unit: Option<TimeUnit>,
}

/// How a file was read: what the reader found and how it split the file (for the report).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct IngestInfo {
    /// Column separator found in the header.
    pub separator: Separator,
    /// Unit the times were written in (they are converted to seconds when read).
    pub time_unit: TimeUnit,
    /// 1-based column of the time (0 for runs not read from a file).
    pub time_column: usize,
    /// Header name of the time column (`t`, `t_ms`, …).
    pub time_header: String,
    /// Comment lines in the file.
    pub comment_lines: usize,
    /// Empty or blank lines in the file.
    pub blank_lines: usize,
    /// Whether the header or a row ended with a separator (an empty last field, ignored).
    pub trailing_separator: bool,
    /// Data rows in the whole file.
    pub file_rows: usize,
    /// This run's 1-based place among the file's segments when the file was split at gaps in
    /// time (`None`: the run is the whole file).
    pub segment: Option<usize>,
    /// Segments found in the file, dropped ones included (1: no gap; 0: not checked).
    pub segments: usize,
    /// Segments dropped as too short.
    pub dropped_segments: usize,
    /// Largest step between rows allowed within a segment \[s\] (0: not checked).
    pub gap_limit: f64,
    /// For runs read by another reader than the CSV one (a rosbag2): what it read, in its
    /// words; the CSV fields above are then unused.
    pub source: Option<String>,
}

impl fmt::Display for IngestInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.source {
            Some(s) => write!(f, "{} rows, {s}", self.file_rows)?,
            None => write!(
                f,
                "{} rows, separator {}, time in {}, {} comment line(s)",
                self.file_rows,
                self.separator.name(),
                self.time_unit,
                self.comment_lines
            )?,
        }
        if self.trailing_separator {
            write!(f, ", trailing separators")?;
        }
        if self.segments > 1 {
            write!(
                f,
                ", {} segments split at gaps > {} s ({} dropped as too short)",
                self.segments,
                short(self.gap_limit),
                self.dropped_segments
            )?;
        }
        Ok(())
    }
}
