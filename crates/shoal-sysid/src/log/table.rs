//! The columns of a measured run filled row by row, as the reader (`ingest.rs`) hands it each
//! row's cells: the time (strictly increasing, in seconds), the inputs and references held
//! (zero-order hold, back-filled before their first value), the measurements at the rows they
//! were sampled at. Every problem names the column; the reader adds the file and the line.

use crate::log::format::{Separator, TimeUnit};
use crate::log::header::{Col, quote};
use crate::log::numbers::{half_ulp, short};
use crate::log::run::{Channel, InputColumn, ReferenceKind, RunError};
use std::path::Path;

/// The columns of a run as its rows are read.
pub(crate) struct Table {
    /// Time of each row \[s\].
    pub t: Vec<f64>,
    /// 1-based file line of each row.
    pub lines: Vec<usize>,
    /// The previous row's time as written \[unit of the time column\] and its line.
    prev_time: Option<(f64, usize)>,
    pub inputs: Vec<InputColumn>,
    pub channels: Vec<Channel>,
    pub references: Vec<InputColumn>,
    /// Row of each input's first set cell.
    inputs_first: Vec<Option<usize>>,
    /// Row of each reference's first set cell.
    references_first: Vec<Option<usize>>,
}

impl Table {
    pub fn new(
        inputs: Vec<InputColumn>,
        channels: Vec<Channel>,
        references: Vec<InputColumn>,
    ) -> Table {
        Table {
            t: Vec::new(),
            lines: Vec::new(),
            prev_time: None,
            inputs_first: vec![None; inputs.len()],
            references_first: vec![None; references.len()],
            inputs,
            channels,
            references,
        }
    }

    /// Reads the cells of the row at file line `line`; an error names the 0-based column.
    pub fn push_row(
        &mut self,
        rec: &csv::ByteRecord,
        cols: &[Col],
        sep: Separator,
        unit: TimeUnit,
        line: usize,
    ) -> Result<(), (usize, String)> {
        let row = self.t.len();
        for (i, (field, col)) in rec.iter().zip(cols).enumerate() {
            let cell = std::str::from_utf8(field).map_err(|e| {
                let m = format!(
                    "the cell is not valid UTF-8 text (bad byte at position {} of the cell)",
                    e.valid_up_to() + 1
                );
                (i, m)
            })?;
            let at = |m: String| (i, m);
            match *col {
                Col::Extra => {} // kept as text, never parsed
                Col::Time => self.push_time(cell, sep, unit, line).map_err(at)?,
                Col::Input(k) => {
                    let v = number(cell, sep).map_err(at)?;
                    let p = half_ulp(cell);
                    hold(&mut self.inputs[k], &mut self.inputs_first[k], row, v, p);
                }
                Col::Output(k) => {
                    if let Some(v) = number(cell, sep).map_err(at)? {
                        self.channels[k].rows.push(row);
                        self.channels[k].values.push(v);
                    }
                }
                Col::Reference(k, kind) => {
                    let v = reference(kind, cell, sep).map_err(at)?;
                    let p = if kind == ReferenceKind::Mode {
                        0.0
                    } else {
                        half_ulp(cell)
                    };
                    hold(
                        &mut self.references[k],
                        &mut self.references_first[k],
                        row,
                        v,
                        p,
                    );
                }
            }
        }
        Ok(())
    }

    /// The row's time cell: converted to seconds, strictly after the previous row's.
    fn push_time(
        &mut self,
        cell: &str,
        sep: Separator,
        unit: TimeUnit,
        line: usize,
    ) -> Result<(), String> {
        let Some(v) = number(cell, sep)? else {
            return Err("the time is missing: every row needs one".into());
        };
        let secs = unit.to_seconds(v);
        if let Some((prev, prev_line)) = self.prev_time
            && self.t.last().is_some_and(|&last| secs <= last)
        {
            return Err(format!(
                "time {} {unit} does not increase (line {prev_line}: {} {unit}); times must be \
                 strictly increasing",
                quote(cell),
                short(prev)
            ));
        }
        self.prev_time = Some((v, line));
        self.t.push(secs);
        self.lines.push(line);
        Ok(())
    }

    /// After the last row: at least two rows, every held column set (and back-filled before
    /// its first value), every channel sampled.
    pub fn finish(&mut self, path: &Path, header_line: usize) -> Result<(), RunError> {
        let err = |column: Option<(usize, &str)>, message: String| RunError {
            file: path.to_path_buf(),
            line: header_line,
            column: column.map(|(c, n)| (c, n.to_string())),
            message,
        };
        let rows = self.t.len();
        if rows < 2 {
            return Err(err(
                None,
                if rows == 0 {
                    format!(
                        "the header (line {header_line}) is followed by no data row: a run needs \
                         at least 2"
                    )
                } else {
                    format!(
                        "only 1 data row after the header (line {header_line}): a run needs at \
                         least 2"
                    )
                },
            ));
        }
        for (cols, first, prefix, what) in [
            (&mut self.inputs, &self.inputs_first, "u.", "input"),
            (
                &mut self.references,
                &self.references_first,
                "r.",
                "reference",
            ),
        ] {
            back_fill(cols, first).map_err(|col| {
                err(
                    Some((col.column, &format!("{prefix}{}", col.name))),
                    format!("this {what} is never set (every cell is empty)"),
                )
            })?;
        }
        for ch in &self.channels {
            if ch.values.is_empty() {
                return Err(err(
                    Some((ch.column, &ch.label())),
                    "this measurement has no samples (every cell is empty)".into(),
                ));
            }
        }
        Ok(())
    }
}

/// Row `row` of a held column: the cell's value `v` written with precision `p`, or for an
/// empty cell the value in force (back-filled by [`back_fill`] if none is yet).
fn hold(col: &mut InputColumn, first: &mut Option<usize>, row: usize, v: Option<f64>, p: f32) {
    match v {
        Some(v) => {
            first.get_or_insert(row);
            col.values.push(v);
            col.precision.push(p);
        }
        None => {
            let v = col.values.last().copied().unwrap_or(f64::NAN);
            let p = col.precision.last().copied().unwrap_or(0.0);
            col.values.push(v);
            col.precision.push(p);
        }
    }
}

/// Before its first value a held column holds that value; a column never set is returned as
/// the error.
fn back_fill<'a>(
    cols: &'a mut [InputColumn],
    first_set: &[Option<usize>],
) -> Result<(), &'a InputColumn> {
    for (col, first) in cols.iter_mut().zip(first_set) {
        let Some(first) = *first else {
            return Err(col);
        };
        let (v, p) = (col.values[first], col.precision[first]);
        col.values[..first].fill(v);
        col.precision[..first].fill(p);
        col.first_set = first;
    }
    Ok(())
}

/// A reference cell: `None` when empty (the value in force holds); for `r.mode` a mode name
/// or code, as the code; else a finite number. An error names the allowed values.
fn reference(kind: ReferenceKind, cell: &str, sep: Separator) -> Result<Option<f64>, String> {
    if cell.is_empty() {
        return Ok(None);
    }
    if kind == ReferenceKind::Mode {
        return match ReferenceKind::parse_mode(cell) {
            Some(code) => Ok(Some(code)),
            None => Err(format!(
                "`{}` is not a mode (allowed: {}; or an empty cell for the mode in force)",
                quote(cell),
                kind.allowed_values()
            )),
        };
    }
    match cell.parse::<f64>() {
        Ok(v) if !v.is_finite() => Err(format!(
            "`{}` is not a finite number (allowed for `r.{}`: {})",
            quote(cell),
            kind.name(),
            kind.allowed_values()
        )),
        _ => number(cell, sep),
    }
}

/// A cell as a number: `None` when empty; an error message when it is not a finite number.
fn number(cell: &str, sep: Separator) -> Result<Option<f64>, String> {
    if cell.is_empty() {
        return Ok(None);
    }
    match cell.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(Some(v)),
        Ok(_) => Err(format!(
            "`{}` is not a finite number (allowed: finite numbers such as -1.5708 or 2.5e-3)",
            quote(cell)
        )),
        Err(_) => {
            let hint = if cell.contains('#') {
                " (a `#` comment must stand on its own line)"
            } else if sep != Separator::Comma && cell.contains(',') {
                " (decimal commas are not read: write 0.5, not 0,5)"
            } else {
                ""
            };
            Err(format!(
                "`{}` is not a number{hint} (allowed: finite numbers such as -1.5708 or 2.5e-3, \
                 or an empty cell for \"not sampled\")",
                quote(cell)
            ))
        }
    }
}
