//! Measured runs: the CSV format of `../shared/spec/validation.md`.
//!
//! One header row, then one row per time stamp: `t` \[s\] (strictly increasing, need not be
//! uniform), inputs `u.<actuator>` held until their next value (zero-order hold), measurements
//! `y.<channel>`, and ignored extra columns `x.<anything>`. An empty cell means "not sampled at
//! this time" (multi-rate logs merged on the union of their time stamps). Lines starting with
//! `#` are comments.
//!
//! Every problem is a [`RunError`] naming the file, the line and the column.

use std::fmt;
use std::path::{Path, PathBuf};

/// What a `y.` column measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ChannelKind {
    /// Depth reading \[m\] (pressure sensor, positive down).
    Depth,
    /// Roll angle \[rad\].
    Roll,
    /// Pitch angle \[rad\].
    Pitch,
    /// Yaw angle \[rad\].
    Yaw,
    /// Roll rate [rad/s].
    P,
    /// Pitch rate [rad/s].
    Q,
    /// Yaw rate [rad/s].
    R,
    /// World position x (north) \[m\].
    X,
    /// World position y (east) \[m\].
    Y,
    /// Surge velocity over ground, body frame [m/s].
    U,
    /// Sway velocity over ground, body frame [m/s].
    V,
    /// Heave velocity over ground, body frame [m/s].
    W,
}

impl ChannelKind {
    /// Every kind with its column name (after `y.`).
    pub const ALL: [(ChannelKind, &'static str); 12] = [
        (ChannelKind::Depth, "depth"),
        (ChannelKind::Roll, "roll"),
        (ChannelKind::Pitch, "pitch"),
        (ChannelKind::Yaw, "yaw"),
        (ChannelKind::P, "p"),
        (ChannelKind::Q, "q"),
        (ChannelKind::R, "r"),
        (ChannelKind::X, "x"),
        (ChannelKind::Y, "y"),
        (ChannelKind::U, "u"),
        (ChannelKind::V, "v"),
        (ChannelKind::W, "w"),
    ];

    /// Parses a column name without the `y.` prefix.
    pub fn from_name(s: &str) -> Option<ChannelKind> {
        Self::ALL.iter().find(|(_, n)| *n == s).map(|(k, _)| *k)
    }

    /// Column name without the `y.` prefix.
    pub fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(k, _)| *k == self)
            .map_or("?", |(_, n)| n)
    }

    /// Unit of the channel.
    pub fn unit(self) -> &'static str {
        use ChannelKind::*;
        match self {
            Depth | X | Y => "m",
            Roll | Pitch | Yaw => "rad",
            P | Q | R => "rad/s",
            U | V | W => "m/s",
        }
    }

    /// Angles are compared modulo 2π.
    pub fn is_angle(self) -> bool {
        matches!(
            self,
            ChannelKind::Roll | ChannelKind::Pitch | ChannelKind::Yaw
        )
    }

    /// Channels whose initial value is a free initial condition of the replay (positions and
    /// heading): their offset is estimated from the data.
    pub fn has_free_offset(self) -> bool {
        matches!(
            self,
            ChannelKind::Depth | ChannelKind::Yaw | ChannelKind::X | ChannelKind::Y
        )
    }
}

/// An actuator input column, zero-order held.
#[derive(Clone, Debug, PartialEq)]
pub struct InputColumn {
    /// Actuator name (after `u.`).
    pub name: String,
    /// 1-based column number in the file.
    pub column: usize,
    /// Value in force at each row (held from the last set value; before the first set value,
    /// the first set value).
    pub values: Vec<f64>,
}

/// A measurement column.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// What it measures.
    pub kind: ChannelKind,
    /// 1-based column number in the file.
    pub column: usize,
    /// Rows (indices into [`MeasuredRun::t`]) at which it was sampled.
    pub rows: Vec<usize>,
    /// The samples, one per entry of `rows` (units of [`ChannelKind::unit`]).
    pub values: Vec<f64>,
}

impl Channel {
    /// Column name with prefix, e.g. `y.depth`.
    pub fn label(&self) -> String {
        format!("y.{}", self.kind.name())
    }
}

/// A measured run, parsed.
#[derive(Clone, Debug, PartialEq)]
pub struct MeasuredRun {
    /// Where it came from (for messages).
    pub path: PathBuf,
    /// Short name (the file stem).
    pub name: String,
    /// Time of each row \[s\].
    pub t: Vec<f64>,
    /// Inputs.
    pub inputs: Vec<InputColumn>,
    /// Measurements.
    pub channels: Vec<Channel>,
    /// Names of ignored `x.` columns.
    pub extra: Vec<String>,
    /// 1-based line of the header in the file (0 for runs not read from a file).
    pub header_line: usize,
    /// 1-based file line of each row (empty for runs not read from a file).
    pub lines: Vec<usize>,
}

/// A problem with a measured-run file.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct RunError {
    /// The file.
    pub file: PathBuf,
    /// 1-based line (0: the file as a whole).
    pub line: usize,
    /// 1-based column number and its header name, if the problem is in one column.
    pub column: Option<(usize, String)>,
    /// What is wrong and what is allowed.
    pub message: String,
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if self.line > 0 {
            write!(f, ":{}", self.line)?;
        }
        if let Some((c, name)) = &self.column {
            write!(f, ": column {c} `{name}`")?;
        }
        write!(f, ": {}", self.message)
    }
}

impl MeasuredRun {
    /// Reads and parses a measured-run CSV file.
    pub fn read(path: &Path) -> Result<MeasuredRun, RunError> {
        let text = std::fs::read_to_string(path).map_err(|e| RunError {
            file: path.to_path_buf(),
            line: 0,
            column: None,
            message: format!("cannot read the file: {e}"),
        })?;
        Self::parse(&text, path)
    }

    /// Parses CSV text; `path` names the file in messages.
    pub fn parse(text: &str, path: &Path) -> Result<MeasuredRun, RunError> {
        let err = |line: usize, column: Option<(usize, &str)>, message: String| RunError {
            file: path.to_path_buf(),
            line,
            column: column.map(|(c, n)| (c, n.to_string())),
            message,
        };
        let mut rdr = csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .trim(csv::Trim::All)
            .comment(Some(b'#'))
            .from_reader(text.as_bytes());
        let mut records = rdr.records();
        let header = match records.next() {
            Some(Ok(h)) => h,
            Some(Err(e)) => {
                return Err(err(
                    line_of(text, e.position()),
                    None,
                    format!("not valid CSV: {e}"),
                ));
            }
            None => {
                return Err(err(
                    0,
                    None,
                    "the file is empty: expected a header row starting with `t`".into(),
                ));
            }
        };
        let header_line = line_of(text, header.position());
        let names: Vec<String> = header.iter().map(str::to_string).collect();
        enum Col {
            Time,
            Input(usize),
            Output(usize),
            Extra,
        }
        let mut cols = Vec::with_capacity(names.len());
        let mut time_col = None;
        let mut inputs: Vec<InputColumn> = Vec::new();
        let mut raw_inputs: Vec<Vec<Option<f64>>> = Vec::new();
        let mut channels: Vec<Channel> = Vec::new();
        let mut extra = Vec::new();
        for (i, n) in names.iter().enumerate() {
            let c = i + 1;
            if names[..i].contains(n) {
                return Err(err(
                    header_line,
                    Some((c, n)),
                    "this column name appears twice".into(),
                ));
            }
            if n == "t" {
                time_col = Some(i);
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
                });
                raw_inputs.push(Vec::new());
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
                            "unknown measurement `{n}`{} (allowed: {})",
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
                        "unknown column `{n}`: allowed are `t`, `u.<actuator>`, `y.<measurement>` \
                         and `x.<anything>` (ignored){}",
                        if n.is_empty() {
                            String::new()
                        } else {
                            format!(" — to keep it, name it `x.{n}`")
                        }
                    ),
                ));
            }
        }
        let Some(time_col) = time_col else {
            return Err(err(
                header_line,
                None,
                format!(
                    "no time column: the header must contain `t` (it has: {})",
                    names.join(", ")
                ),
            ));
        };
        if channels.is_empty() {
            return Err(err(
                header_line,
                None,
                "no measurement column: at least one `y.` column is needed (e.g. y.depth, y.yaw, y.r)"
                    .into(),
            ));
        }
        let mut t: Vec<f64> = Vec::new();
        let mut lines: Vec<usize> = Vec::new();
        for rec in records {
            let rec = rec.map_err(|e| {
                err(
                    line_of(text, e.position()),
                    None,
                    format!("not valid CSV: {e}"),
                )
            })?;
            let line = line_of(text, rec.position());
            if rec.len() == 1 && rec.get(0).is_some_and(str::is_empty) {
                continue; // blank line
            }
            if rec.len() != names.len() {
                return Err(err(
                    line,
                    None,
                    format!(
                        "{} fields, but the header has {} columns",
                        rec.len(),
                        names.len()
                    ),
                ));
            }
            let row = t.len();
            for (i, cell) in rec.iter().enumerate() {
                let c = i + 1;
                if matches!(cols[i], Col::Extra) {
                    continue; // kept as text, never parsed
                }
                let value = if cell.is_empty() {
                    None
                } else {
                    match cell.parse::<f64>() {
                        Ok(v) if v.is_finite() => Some(v),
                        Ok(_) => {
                            return Err(err(
                                line,
                                Some((c, &names[i])),
                                format!("`{cell}` is not a finite number"),
                            ));
                        }
                        Err(_) => {
                            return Err(err(
                                line,
                                Some((c, &names[i])),
                                format!("`{cell}` is not a number"),
                            ));
                        }
                    }
                };
                match cols[i] {
                    Col::Time => {
                        let Some(v) = value else {
                            return Err(err(
                                line,
                                Some((c, &names[i])),
                                "the time is missing: every row needs `t`".into(),
                            ));
                        };
                        if let Some(&prev) = t.last()
                            && v <= prev
                        {
                            return Err(err(
                                line,
                                Some((c, &names[i])),
                                format!(
                                    "time {v} s does not increase (previous row: {prev} s); \
                                     times must be strictly increasing"
                                ),
                            ));
                        }
                        t.push(v);
                        lines.push(line);
                    }
                    Col::Input(k) => raw_inputs[k].push(value),
                    Col::Output(k) => {
                        if let Some(v) = value {
                            channels[k].rows.push(row);
                            channels[k].values.push(v);
                        }
                    }
                    Col::Extra => {}
                }
            }
            debug_assert_eq!(t.len(), row + 1, "time column {time_col}");
        }
        if t.len() < 2 {
            return Err(err(
                0,
                None,
                format!("{} data rows: a run needs at least 2", t.len()),
            ));
        }
        for (inp, raw) in inputs.iter_mut().zip(raw_inputs) {
            let Some(first) = raw.iter().flatten().next().copied() else {
                return Err(err(
                    header_line,
                    Some((inp.column, &format!("u.{}", inp.name))),
                    "this input is never set (every cell is empty)".into(),
                ));
            };
            let mut cur = first;
            inp.values = raw
                .into_iter()
                .map(|v| {
                    if let Some(v) = v {
                        cur = v;
                    }
                    cur
                })
                .collect();
        }
        for ch in &channels {
            if ch.values.is_empty() {
                return Err(err(
                    header_line,
                    Some((ch.column, &ch.label())),
                    "this measurement has no samples (every cell is empty)".into(),
                ));
            }
        }
        let name = path
            .file_stem()
            .map_or_else(|| "run".to_string(), |s| s.to_string_lossy().into_owned());
        Ok(MeasuredRun {
            path: path.to_path_buf(),
            name,
            t,
            inputs,
            channels,
            extra,
            header_line,
            lines,
        })
    }

    /// Duration from the first to the last row \[s\].
    pub fn duration(&self) -> f64 {
        self.t.last().copied().unwrap_or(0.0) - self.t.first().copied().unwrap_or(0.0)
    }

    /// The input column of that actuator name, if present.
    pub fn input(&self, name: &str) -> Option<&InputColumn> {
        self.inputs.iter().find(|i| i.name == name)
    }

    /// The channel of that kind, if measured.
    pub fn channel(&self, kind: ChannelKind) -> Option<&Channel> {
        self.channels.iter().find(|c| c.kind == kind)
    }

    /// Writes the run as CSV text (the format [`MeasuredRun::parse`] reads).
    pub fn to_csv(&self) -> String {
        let mut out = String::from("t");
        for i in &self.inputs {
            out.push_str(&format!(",u.{}", i.name));
        }
        for c in &self.channels {
            out.push_str(&format!(",{}", c.label()));
        }
        out.push('\n');
        let mut cursor = vec![0usize; self.channels.len()];
        for (row, t) in self.t.iter().enumerate() {
            out.push_str(&format!("{t}"));
            for i in &self.inputs {
                let changed = row == 0 || i.values[row] != i.values[row - 1];
                if changed {
                    out.push_str(&format!(",{}", i.values[row]));
                } else {
                    out.push(',');
                }
            }
            for (k, c) in self.channels.iter().enumerate() {
                if c.rows.get(cursor[k]) == Some(&row) {
                    out.push_str(&format!(",{}", c.values[cursor[k]]));
                    cursor[k] += 1;
                } else {
                    out.push(',');
                }
            }
            out.push('\n');
        }
        out
    }
}

/// 1-based line of the record at a csv position (0 if unknown). The csv crate neither counts
/// comment lines nor skips them in the position it reports, so the line is counted from the
/// byte offset, past any comment lines there.
fn line_of(text: &str, p: Option<&csv::Position>) -> usize {
    let Some(p) = p else { return 0 };
    let mut at = (p.byte() as usize).min(text.len());
    let mut line = 1 + text.as_bytes()[..at]
        .iter()
        .filter(|b| **b == b'\n')
        .count();
    while text[at..].trim_start_matches([' ', '\t']).starts_with('#') {
        match text[at..].find('\n') {
            Some(n) => {
                at += n + 1;
                line += 1;
            }
            None => break,
        }
    }
    line
}

/// The closest name within edit distance 2, if any.
pub(crate) fn suggest<'a>(name: &str, names: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    names
        .into_iter()
        .map(|n| (edit_distance(name, n), n))
        .filter(|(d, _)| *d <= 2)
        .min_by_key(|(d, _)| *d)
        .map(|(_, n)| n)
}

fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            cur[j + 1] = (prev[j] + usize::from(ca != *cb))
                .min(prev[j + 1] + 1)
                .min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(s: &str) -> Result<MeasuredRun, RunError> {
        MeasuredRun::parse(s, Path::new("run.csv"))
    }

    #[test]
    fn zero_order_hold_and_multirate() {
        let r = parse("t,u.port,y.depth,y.yaw,x.note\n0,10,1.0,,a\n0.1,,1.1,0.5,\n0.2,20,,0.6,\n")
            .unwrap();
        assert_eq!(r.inputs[0].values, vec![10.0, 10.0, 20.0]);
        assert_eq!(r.channels[0].rows, vec![0, 1]);
        assert_eq!(r.channels[1].rows, vec![1, 2]);
        assert_eq!(r.extra, vec!["x.note".to_string()]);
        let again = parse(&r.to_csv()).unwrap();
        assert_eq!(again.t, r.t);
        assert_eq!(again.inputs, r.inputs);
        assert_eq!(again.channels, r.channels);
    }

    #[test]
    fn errors_name_line_and_column() {
        let e = parse("t,u.port,y.depth\n0,1,2\n0.1,1,2\n0.1,1,2\n").unwrap_err();
        assert_eq!((e.line, e.column.clone()), (4, Some((1, "t".into()))));
        assert!(
            e.to_string()
                .starts_with("run.csv:4: column 1 `t`: time 0.1 s does not increase")
        );
        let e = parse("t,u.port,y.depth\n0,1,2\n0.1,abc,2\n").unwrap_err();
        assert_eq!((e.line, e.column.clone()), (3, Some((2, "u.port".into()))));
        assert!(e.message.contains("`abc` is not a number"), "{e}");
        // Comment lines (before the header and between rows) count as lines.
        let e =
            parse("# from a logger\nt,u.port,y.depth\n0,1,2\n# pause\n0.1,abc,2\n").unwrap_err();
        assert_eq!((e.line, e.column.clone()), (5, Some((2, "u.port".into()))));
        let e = parse("# from a logger\nt,u.port,y.dpth\n0,1,2\n").unwrap_err();
        assert_eq!(e.line, 2);
        let e = parse("t,u.port,y.dpth\n0,1,2\n").unwrap_err();
        assert_eq!((e.line, e.column.clone()), (1, Some((3, "y.dpth".into()))));
        assert!(e.message.contains("did you mean `y.depth`"), "{e}");
        let e = parse("t,u.port,speed\n0,1,2\n").unwrap_err();
        assert!(e.message.contains("unknown column `speed`"), "{e}");
        let e = parse("t,u.port,x.a\n0,1,2\n0.1,1,2\n").unwrap_err();
        assert_eq!(e.line, 1);
        assert!(e.message.contains("no measurement column"), "{e}");
        let e = parse("t,u.port,y.depth\n0,,2\n0.1,,2\n").unwrap_err();
        assert_eq!(e.column, Some((2, "u.port".into())));
        assert!(e.message.contains("never set"), "{e}");
        let e = parse("t,u.port,y.depth\n0,1\n").unwrap_err();
        assert_eq!(e.line, 2);
        let e = parse("t,u.port,y.depth\n0,1,nan\n0.1,1,1\n").unwrap_err();
        assert!(e.message.contains("not a finite number"), "{e}");
    }
}
