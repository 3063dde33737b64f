//! Reading measured runs as real loggers write them: streaming, one pass, linear in the rows.
//!
//! The format is the one of [`crate::log::run`] (`../shared/spec/validation.md`), read leniently
//! where loggers differ and strictly where a value would be wrong:
//!
//! * **Separator**: `,`, `;` or a tab, taken from the header line — the one of the three that
//!   occurs in it (a header with none, or with more than one of them, is an error naming the
//!   header line). Quoted fields (`"…"`) are read as in RFC 4180.
//! * **Trailing separator**: a header whose last field is empty (`t,u.port,y.depth,`) and rows
//!   with one extra, empty last field are accepted; the empty field is ignored.
//! * **Comments**: a line whose first character that is not a space or tab is `#`, anywhere in
//!   the file (before the header, between rows, indented or not). A `#` after data on the same
//!   line is *not* a comment: the cell is then not a number, and the message says so.
//!   Blank lines are skipped. Line numbers in messages count every line of the file.
//! * **Line ends**: `\n`, `\r\n` or `\r`; a UTF-8 byte-order mark is ignored.
//! * **Time unit**: the time column is `t`, `t_s` or `t[s]` (seconds) or `t_ms` or `t[ms]`
//!   (milliseconds). A plain `t` is in seconds unless [`ReadOptions::time_unit`] says
//!   otherwise (`shoal validate --time-unit ms`); a header that declares a unit which
//!   disagrees with that option is an error. Times are converted to seconds as they are read.
//! * **Numbers**: anything Rust's `f64` parser reads (`1`, `-1.5708`, `2.5e-3`, `+.5`); an
//!   empty cell means "not sampled"; `nan`, `inf` and numbers beyond the `f64` range are
//!   errors. For each input cell the reader records half a unit of its last written digit
//!   (`-1.5708` → 5·10⁻⁵), so that the limit check ([`crate::log::limits`]) can
//!   tell a value rounded by the logger from one that is really out of range.
//! * **References** `r.<reference>` ([`ReferenceKind::ALL`]: `depth` \[m\], `yaw` \[rad\],
//!   `surge`, `sway` \[N\], `mode`) are held like inputs: an empty cell keeps the value in
//!   force, rows before the first set value take that value. An `r.mode` cell is a mode name
//!   (`off diving buoyancy turning drift auto raw`, any case) or its code `0` … `6`, kept as
//!   the code.
//!
//! Rejected, each with file, line and column: a header without `t` or without a `y.` column,
//! an unknown or repeated column, a row with too many or too few fields, invalid UTF-8, a
//! missing, non-increasing or non-finite time, a cell that is not a finite number, an
//! `r.mode` cell that is not a mode, an input or reference never set, a measurement never
//! sampled, fewer than two data rows, a line longer than 1 MiB. Gaps in time are handled afterwards by [`MeasuredRun::split_at_gaps`].
//!
//! Memory is the parsed columns (a few bytes per cell) plus one line; the text is never held
//! whole.

use crate::log::data_lines::{LineTooLong, LogLines};
use crate::log::format::{IngestInfo, ReadOptions, Separator, TimeUnit};
use crate::log::header::{Col, Header, quote, unquote};
use crate::log::run::{MeasuredRun, RunError};
use crate::log::table::Table;
use std::fs::File;
use std::io::{self, BufRead, BufReader};
use std::path::Path;

impl MeasuredRun {
    /// Reads and parses a measured-run CSV file (times in seconds unless the header says
    /// otherwise).
    pub fn read(path: &Path) -> Result<MeasuredRun, RunError> {
        Self::read_with(path, &ReadOptions::default())
    }

    /// Reads and parses a measured-run CSV file, streaming.
    pub fn read_with(path: &Path, opts: &ReadOptions) -> Result<MeasuredRun, RunError> {
        let file = File::open(path).map_err(|e| RunError {
            file: path.to_path_buf(),
            line: 0,
            column: None,
            message: format!("cannot read the file: {e}"),
        })?;
        Self::from_reader(BufReader::with_capacity(1 << 16, file), path, opts)
    }

    /// Parses CSV text; `path` names the file in messages.
    pub fn parse(text: &str, path: &Path) -> Result<MeasuredRun, RunError> {
        Self::parse_with(text, path, &ReadOptions::default())
    }

    /// Parses CSV text with options; `path` names the file in messages.
    pub fn parse_with(
        text: &str,
        path: &Path,
        opts: &ReadOptions,
    ) -> Result<MeasuredRun, RunError> {
        Self::from_reader(text.as_bytes(), path, opts)
    }

    /// Parses CSV from any buffered reader (the one code path of [`MeasuredRun::read`] and
    /// [`MeasuredRun::parse`]); `path` names the file in messages.
    pub fn from_reader<R: BufRead>(
        src: R,
        path: &Path,
        opts: &ReadOptions,
    ) -> Result<MeasuredRun, RunError> {
        read_run(src, path, opts)
    }
}

/// An I/O error at `line`, or the over-long line inside it.
fn io_error(path: &Path, line: usize, e: &io::Error) -> RunError {
    if let Some(t) = e.get_ref().and_then(|e| e.downcast_ref::<LineTooLong>()) {
        return RunError {
            file: path.to_path_buf(),
            line: t.line,
            column: None,
            message: format!("{t}: is this a measured-run CSV file?"),
        };
    }
    RunError {
        file: path.to_path_buf(),
        line,
        column: None,
        message: format!("cannot read the file: {e}"),
    }
}

fn read_run<R: BufRead>(src: R, path: &Path, opts: &ReadOptions) -> Result<MeasuredRun, RunError> {
    let err = |line: usize, column: Option<(usize, &str)>, message: String| RunError {
        file: path.to_path_buf(),
        line,
        column: column.map(|(c, n)| (c, n.to_string())),
        message,
    };
    let mut lines = BufReader::with_capacity(1 << 16, LogLines::new(src));

    // The header: the first line that is neither blank nor a comment (`LogLines` leaves
    // those out).
    let mut raw = Vec::new();
    let k = lines
        .read_until(b'\n', &mut raw)
        .map_err(|e| io_error(path, 1, &e))?;
    if k == 0 {
        return Err(err(
            0,
            None,
            "no header row: the file is empty or holds only comments and blank lines; \
             expected a header such as `t,u.port,y.depth`"
                .into(),
        ));
    }
    let header_line = lines.get_mut().file_line(1);
    if raw.last() == Some(&b'\n') {
        raw.pop();
    }
    let Header {
        line: header_line,
        separator: sep,
        names,
        cols,
        time_column: time_col,
        time_unit: unit,
        trailing_separator,
        inputs,
        channels,
        references,
        extra,
    } = Header::parse(&raw, header_line, path, opts)?;
    let time_name = names.get(time_col - 1).cloned().unwrap_or_default();
    let mut table = Table::new(inputs, channels, references);

    // The rows.
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(false)
        .delimiter(sep.byte())
        .flexible(true)
        .trim(csv::Trim::All)
        .buffer_capacity(1 << 16)
        .from_reader(lines);
    let trailing_separator = read_rows(
        &mut rdr,
        (&names, &cols, sep, unit),
        path,
        header_line,
        &mut table,
    )? || trailing_separator;
    table.finish(path, header_line)?;
    let Table {
        t,
        lines: row_lines,
        inputs,
        channels,
        references,
        ..
    } = table;
    let filter = rdr.get_ref().get_ref();
    let ingest = IngestInfo {
        separator: sep,
        time_unit: unit,
        time_column: time_col,
        time_header: time_name,
        comment_lines: filter.comment_lines(),
        blank_lines: filter.blank_lines(),
        trailing_separator,
        file_rows: t.len(),
        segment: None,
        segments: 0,
        dropped_segments: 0,
        gap_limit: 0.0,
        source: None,
    };
    let name = path
        .file_stem()
        .map_or_else(|| "run".to_string(), |s| s.to_string_lossy().into_owned());
    Ok(MeasuredRun {
        path: path.to_path_buf(),
        name,
        t,
        inputs,
        channels,
        references,
        extra,
        header_line,
        lines: row_lines,
        ingest,
    })
}

/// Reads the data rows into `table`; whether a row ended with an extra, empty field (a
/// trailing separator).
fn read_rows<R: BufRead>(
    rdr: &mut csv::Reader<BufReader<LogLines<R>>>,
    header: (&[String], &[Col], Separator, TimeUnit),
    path: &Path,
    header_line: usize,
    table: &mut Table,
) -> Result<bool, RunError> {
    let (names, cols, sep, unit) = header;
    let err = |line: usize, column: Option<(usize, &str)>, message: String| RunError {
        file: path.to_path_buf(),
        line,
        column: column.map(|(c, n)| (c, n.to_string())),
        message,
    };
    let mut trailing_separator = false;
    let n_cols = names.len();
    let mut rec = csv::ByteRecord::new();
    let mut last_line = header_line;
    loop {
        match rdr.read_byte_record(&mut rec) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => {
                let line = match e.position() {
                    Some(p) => rdr.get_mut().get_mut().file_line(p.line() + 1),
                    None => last_line + 1,
                };
                return Err(match e.kind() {
                    csv::ErrorKind::Io(io) => io_error(path, line, io),
                    _ => err(line, None, format!("not valid CSV: {e}")),
                });
            }
        }
        if rec.iter().any(|c| c.first() == Some(&b'"')) {
            // A cell quoted after a space (see `unquote`): read as its text.
            let pos = rec.position().cloned();
            rec = rec
                .iter()
                .map(|c| unquote(c).unwrap_or_else(|| c.to_vec()))
                .collect();
            rec.set_position(pos);
        }
        // The csv reader starts after the header: its line 1 is output line 2.
        let out_line = rec.position().map_or(1, csv::Position::line) + 1;
        let line = rdr.get_mut().get_mut().file_line(out_line);
        last_line = line;
        let k = rec.len();
        if k == 1 && rec.get(0).is_some_and(<[u8]>::is_empty) {
            continue; // a line holding only `""`
        }
        let extra_field = k == n_cols + 1 && rec.get(n_cols).is_some_and(<[u8]>::is_empty);
        if k < n_cols {
            let missing = names.get(k).map_or("", String::as_str);
            return Err(err(
                line,
                Some((k + 1, missing)),
                format!(
                    "the row has {k} field(s), but the header has {n_cols} columns: this one \
                 and any after it are missing (write an empty field for \"not sampled\")"
                ),
            ));
        }
        if k > n_cols && !extra_field {
            let cell = String::from_utf8_lossy(rec.get(n_cols).unwrap_or_default());
            return Err(err(
                line,
                None,
                format!(
                    "the row has {k} fields, but the header has {n_cols} columns: field {} \
                 (`{}`) has no column",
                    n_cols + 1,
                    quote(&cell)
                ),
            ));
        }
        if extra_field {
            trailing_separator = true;
        }
        table
            .push_row(&rec, cols, sep, unit, line)
            .map_err(|(i, m)| {
                err(
                    line,
                    Some((i + 1, names.get(i).map_or("", String::as_str))),
                    m,
                )
            })?;
    }
    Ok(trailing_separator)
}
