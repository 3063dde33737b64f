//! The header line of a measured run: its separator, what each column is, the time unit.
//!
//! The separator is the one of `,`, `;` and tab that occurs in the header line (none, or more
//! than one of them, is an error). A last, empty header field (a trailing separator) is
//! dropped. Columns: the time (`t`, `t_s`, `t[s]`, `t_ms`, `t[ms]`), inputs `u.<actuator>`,
//! measurements `y.<channel>`, the controller's references `r.<reference>` (the names of
//! [`ReferenceKind::ALL`]: `depth yaw surge sway mode`), ignored `x.<anything>`; anything
//! else (an unknown measurement or reference with a "did you mean"), a repeated name or a
//! second time column is an error naming the header line and the column.

use crate::log::format::{ReadOptions, Separator, TimeUnit};
use crate::log::run::{Channel, ChannelKind, InputColumn, ReferenceKind, RunError, suggest};
use std::collections::HashSet;
use std::path::Path;

/// What a column is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Col {
    /// The time.
    Time,
    /// Input column (index into the inputs).
    Input(usize),
    /// Measurement (index into the channels).
    Output(usize),
    /// Reference (index into the references, and its kind).
    Reference(usize, ReferenceKind),
    /// Ignored `x.` column.
    Extra,
}

/// At most this many characters of a bad cell are quoted in a message.
pub(crate) const QUOTE_CHARS: usize = 40;

pub(crate) fn quote(cell: &str) -> String {
    if cell.chars().count() <= QUOTE_CHARS {
        cell.to_string()
    } else {
        let s: String = cell.chars().take(QUOTE_CHARS).collect();
        format!("{s}…")
    }
}

/// The text of a cell written in quotes after a space (` "2"`, `t, "u.port"`): the csv
/// reader takes quotes only at a cell's first byte, so with the spaces trimmed such a cell
/// still holds its quotes. `None` for any other cell. A doubled quote inside is one quote, as
/// in a quoted cell.
pub(crate) fn unquote(cell: &[u8]) -> Option<Vec<u8>> {
    let inner = cell.strip_prefix(b"\"")?.strip_suffix(b"\"")?;
    let mut out = Vec::with_capacity(inner.len());
    let mut bytes = inner.iter().copied().peekable();
    while let Some(b) = bytes.next() {
        out.push(b);
        if b == b'"' && bytes.peek() == Some(&b'"') {
            bytes.next();
        }
    }
    Some(out)
}

/// A parsed header.
pub(crate) struct Header {
    /// 1-based file line.
    pub line: usize,
    /// Column separator.
    pub separator: Separator,
    /// Column names (without a trailing empty one).
    pub names: Vec<String>,
    /// What each column is.
    pub cols: Vec<Col>,
    /// 1-based column of the time.
    pub time_column: usize,
    /// Unit of the time.
    pub time_unit: TimeUnit,
    /// Whether the header ended with a separator.
    pub trailing_separator: bool,
    /// The input columns, without values.
    pub inputs: Vec<InputColumn>,
    /// The measurement columns, without samples.
    pub channels: Vec<Channel>,
    /// The reference columns, without values.
    pub references: Vec<InputColumn>,
    /// Names of the `x.` columns.
    pub extra: Vec<String>,
}

impl Header {
    /// Parses the header line `raw` (without its terminator), line `header_line` of `path`.
    pub fn parse(
        raw: &[u8],
        header_line: usize,
        path: &Path,
        opts: &ReadOptions,
    ) -> Result<Header, RunError> {
        let err = |line: usize, column: Option<(usize, &str)>, message: String| RunError {
            file: path.to_path_buf(),
            line,
            column: column.map(|(c, n)| (c, n.to_string())),
            message,
        };
        let header_text = std::str::from_utf8(raw).map_err(|e| {
            err(
                header_line,
                None,
                format!(
                    "the header is not valid UTF-8 text (bad byte at position {})",
                    e.valid_up_to() + 1
                ),
            )
        })?;
        let sep = separator(header_text).map_err(|m| err(header_line, None, m))?;
        let mut names = split(header_text, sep).map_err(|m| err(header_line, None, m))?;
        let mut trailing_separator = false;
        if names.len() > 1 && names.last().is_some_and(String::is_empty) {
            names.pop();
            trailing_separator = true;
        }

        // What each column is.
        let mut found = Columns::default();
        let mut seen: HashSet<&str> = HashSet::with_capacity(names.len());
        for (i, n) in names.iter().enumerate() {
            let c = i + 1;
            if !seen.insert(n.as_str()) {
                return Err(err(
                    header_line,
                    Some((c, n)),
                    "this column name appears twice".into(),
                ));
            }
            found
                .add(c, n, &names)
                .map_err(|m| err(header_line, Some((c, n)), m))?;
        }
        let Columns {
            cols,
            time,
            inputs,
            channels,
            references,
            extra,
        } = found;
        let Some((time_col, declared)) = time else {
            return Err(err(
                header_line,
                None,
                format!(
                    "no time column: the header must contain `t` (or `t_s`, `t[s]`, `t_ms`, `t[ms]`); \
                     it has: {}",
                    quote(&names.join(", "))
                ),
            ));
        };
        let time_name = names.get(time_col - 1).map_or("t", String::as_str);
        let unit = match (declared, opts.time_unit) {
            (None, None) => TimeUnit::Seconds,
            (None, Some(u)) | (Some(u), None) => u,
            (Some(d), Some(u)) if d == u => d,
            (Some(d), Some(u)) => {
                return Err(err(
                    header_line,
                    Some((time_col, time_name)),
                    format!(
                        "the header declares the time in {d}, but the time unit {u} was asked for \
                         (--time-unit {u}); name the column `t` or make them agree"
                    ),
                ));
            }
        };
        if channels.is_empty() {
            return Err(err(
                header_line,
                None,
                "no measurement column: at least one `y.` column is needed (e.g. y.depth, y.yaw, y.r)"
                    .into(),
            ));
        }

        Ok(Header {
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
        })
    }
}

/// The one of `,`, `;` and tab that occurs in the header.
fn separator(header_text: &str) -> Result<Separator, String> {
    let found: Vec<Separator> = Separator::ALL
        .into_iter()
        .filter(|s| header_text.as_bytes().contains(&s.byte()))
        .collect();
    match found.as_slice() {
        [s] => Ok(*s),
        [] => Err(format!(
            "no column separator in the header `{}`: columns must be separated by `,`, `;` or a \
             tab (and the header needs `t` and at least one `y.` column)",
            quote(header_text)
        )),
        many => {
            let names: Vec<&str> = many.iter().map(|s| s.name()).collect();
            Err(format!(
                "the header mixes the separators {}: use one of `,`, `;` or tab throughout",
                names.join(" and ")
            ))
        }
    }
}

/// The header's column names, trimmed and unquoted.
fn split(header_text: &str, sep: Separator) -> Result<Vec<String>, String> {
    let mut hr = csv::ReaderBuilder::new()
        .has_headers(false)
        .delimiter(sep.byte())
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(header_text.as_bytes());
    let mut rec = csv::StringRecord::new();
    hr.read_record(&mut rec)
        .map_err(|e| format!("the header is not valid CSV: {e}"))?;
    Ok(rec
        .iter()
        .map(|c| match unquote(c.as_bytes()) {
            Some(u) => String::from_utf8_lossy(&u).into_owned(),
            None => c.to_string(),
        })
        .collect())
}

/// The columns of a header, as they are classified.
#[derive(Default)]
struct Columns {
    cols: Vec<Col>,
    /// 1-based column of the time and the unit its name declares.
    time: Option<(usize, Option<TimeUnit>)>,
    inputs: Vec<InputColumn>,
    channels: Vec<Channel>,
    references: Vec<InputColumn>,
    extra: Vec<String>,
}

/// "unknown measurement `y.dpth` — did you mean `y.depth`? (allowed: …)".
fn unknown(what: &str, prefix: &str, name: &str, names: &[&str]) -> String {
    let allowed: Vec<String> = names.iter().map(|n| format!("{prefix}{n}")).collect();
    format!(
        "unknown {what} `{}`{} (allowed: {})",
        quote(&format!("{prefix}{name}")),
        suggest(name, names.iter().copied())
            .map(|s| format!(" — did you mean `{prefix}{s}`?"))
            .unwrap_or_default(),
        allowed.join(", ")
    )
}

impl Columns {
    /// Classifies column `c` named `n` (`names`: every column's name); an error message if
    /// it is not a column of a run.
    fn add(&mut self, c: usize, n: &str, names: &[String]) -> Result<(), String> {
        if let Some(unit) = TimeUnit::from_column(n) {
            if let Some((tc, _)) = self.time {
                return Err(format!(
                    "a second time column (the first is column {tc} `{}`): keep one",
                    names.get(tc - 1).map_or("", String::as_str)
                ));
            }
            self.time = Some((c, unit));
            self.cols.push(Col::Time);
        } else if let Some(a) = n.strip_prefix("u.") {
            if a.is_empty() {
                return Err("an input column needs an actuator name after `u.`".into());
            }
            self.cols.push(Col::Input(self.inputs.len()));
            self.inputs.push(InputColumn::held(a, c));
        } else if let Some(y) = n.strip_prefix("y.") {
            let Some(kind) = ChannelKind::from_name(y) else {
                let names: Vec<&str> = ChannelKind::ALL.iter().map(|(_, n)| *n).collect();
                return Err(unknown("measurement", "y.", y, &names));
            };
            self.cols.push(Col::Output(self.channels.len()));
            self.channels.push(Channel {
                kind,
                column: c,
                rows: Vec::new(),
                values: Vec::new(),
            });
        } else if let Some(r) = n.strip_prefix("r.") {
            let Some(kind) = ReferenceKind::from_name(r) else {
                let names: Vec<&str> = ReferenceKind::ALL.iter().map(|(_, n, _)| *n).collect();
                return Err(unknown("reference", "r.", r, &names));
            };
            self.cols.push(Col::Reference(self.references.len(), kind));
            self.references.push(InputColumn::held(r, c));
        } else if n.starts_with("x.") {
            self.cols.push(Col::Extra);
            self.extra.push(n.to_string());
        } else {
            return Err(format!(
                "unknown column `{}`: allowed are the time (`t`, `t_s`, `t[s]`, `t_ms`, \
                 `t[ms]`), `u.<actuator>`, `y.<measurement>`, `r.<reference>` and \
                 `x.<anything>` (ignored){}",
                quote(n),
                if n.is_empty() {
                    String::new()
                } else {
                    format!(" — to keep it, name it `x.{}`", quote(n))
                }
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cell_quoted_after_a_space_is_read_as_its_text() {
        assert_eq!(unquote(b"\"2\""), Some(b"2".to_vec()));
        assert_eq!(unquote(b"\"a\"\"b\""), Some(b"a\"b".to_vec()));
        assert_eq!(unquote(b"\"\""), Some(Vec::new()));
        for plain in [&b"2"[..], b"\"", b"\"2", b"2\""] {
            assert_eq!(unquote(plain), None, "{plain:?}");
        }
    }
}
