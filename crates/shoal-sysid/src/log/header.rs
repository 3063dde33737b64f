//! The header line of a measured run: its separator, what each column is, the time unit.
//!
//! The separator is the one of `,`, `;` and tab that occurs in the header line (none, or more
//! than one of them, is an error). A last, empty header field (a trailing separator) is
//! dropped. Columns: the time (`t`, `t_s`, `t[s]`, `t_ms`, `t[ms]`), inputs `u.<actuator>`,
//! measurements `y.<channel>`, ignored `x.<anything>`; anything else, a repeated name or a
//! second time column is an error naming the header line and the column.

use crate::log::format::{ReadOptions, Separator, TimeUnit};
use crate::log::run::{Channel, ChannelKind, InputColumn, RunError, suggest};
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
        let found: Vec<Separator> = Separator::ALL
            .into_iter()
            .filter(|s| header_text.as_bytes().contains(&s.byte()))
            .collect();
        let sep = match found.as_slice() {
            [s] => *s,
            [] => {
                return Err(err(
                    header_line,
                    None,
                    format!(
                        "no column separator in the header `{}`: columns must be separated by `,`, \
                         `;` or a tab (and the header needs `t` and at least one `y.` column)",
                        quote(header_text)
                    ),
                ));
            }
            many => {
                let names: Vec<&str> = many.iter().map(|s| s.name()).collect();
                return Err(err(
                    header_line,
                    None,
                    format!(
                        "the header mixes the separators {}: use one of `,`, `;` or tab throughout",
                        names.join(" and ")
                    ),
                ));
            }
        };
        let mut names: Vec<String> = {
            let mut hr = csv::ReaderBuilder::new()
                .has_headers(false)
                .delimiter(sep.byte())
                .flexible(true)
                .trim(csv::Trim::All)
                .from_reader(header_text.as_bytes());
            let mut rec = csv::StringRecord::new();
            hr.read_record(&mut rec).map_err(|e| {
                err(
                    header_line,
                    None,
                    format!("the header is not valid CSV: {e}"),
                )
            })?;
            rec.iter()
                .map(|c| match unquote(c.as_bytes()) {
                    Some(u) => String::from_utf8_lossy(&u).into_owned(),
                    None => c.to_string(),
                })
                .collect()
        };
        let mut trailing_separator = false;
        if names.len() > 1 && names.last().is_some_and(String::is_empty) {
            names.pop();
            trailing_separator = true;
        }

        // What each column is.
        let mut cols = Vec::with_capacity(names.len());
        let mut time: Option<(usize, Option<TimeUnit>)> = None;
        let mut inputs: Vec<InputColumn> = Vec::new();
        let mut channels: Vec<Channel> = Vec::new();
        let mut extra = Vec::new();
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
            if let Some(unit) = TimeUnit::from_column(n) {
                if let Some((tc, _)) = time {
                    return Err(err(
                        header_line,
                        Some((c, n)),
                        format!(
                            "a second time column (the first is column {tc} `{}`): keep one",
                            names.get(tc - 1).map_or("", String::as_str)
                        ),
                    ));
                }
                time = Some((c, unit));
                cols.push(Col::Time);
            } else if let Some(a) = n.strip_prefix("u.") {
                if a.is_empty() {
                    return Err(err(
                        header_line,
                        Some((c, n)),
                        "an input column needs an actuator name after `u.`".into(),
                    ));
                }
                cols.push(Col::Input(inputs.len()));
                inputs.push(InputColumn {
                    name: a.to_string(),
                    column: c,
                    values: Vec::new(),
                    precision: Vec::new(),
                    first_set: 0,
                });
            } else if let Some(y) = n.strip_prefix("y.") {
                let Some(kind) = ChannelKind::from_name(y) else {
                    let allowed: Vec<String> = ChannelKind::ALL
                        .iter()
                        .map(|(_, n)| format!("y.{n}"))
                        .collect();
                    return Err(err(
                        header_line,
                        Some((c, n)),
                        format!(
                            "unknown measurement `{}`{} (allowed: {})",
                            quote(n),
                            suggest(y, ChannelKind::ALL.iter().map(|(_, n)| *n))
                                .map(|s| format!(" — did you mean `y.{s}`?"))
                                .unwrap_or_default(),
                            allowed.join(", ")
                        ),
                    ));
                };
                cols.push(Col::Output(channels.len()));
                channels.push(Channel {
                    kind,
                    column: c,
                    rows: Vec::new(),
                    values: Vec::new(),
                });
            } else if n.starts_with("x.") {
                cols.push(Col::Extra);
                extra.push(n.clone());
            } else {
                return Err(err(
                    header_line,
                    Some((c, n)),
                    format!(
                        "unknown column `{}`: allowed are the time (`t`, `t_s`, `t[s]`, `t_ms`, \
                         `t[ms]`), `u.<actuator>`, `y.<measurement>` and `x.<anything>` \
                         (ignored){}",
                        quote(n),
                        if n.is_empty() {
                            String::new()
                        } else {
                            format!(" — to keep it, name it `x.{}`", quote(n))
                        }
                    ),
                ));
            }
        }
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
            extra,
        })
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
