//! Measured runs: the CSV format of `../shared/spec/validation.md`.
//!
//! One header row, then one row per time stamp: `t` \[s\] (strictly increasing, need not be
//! uniform), inputs `u.<actuator>` held until their next value (zero-order hold), measurements
//! `y.<channel>`, the references the vehicle's controller followed `r.<reference>` (held like
//! inputs; names in [`ReferenceKind::ALL`]), and ignored extra columns `x.<anything>`. An empty
//! cell means "not sampled at this time" (multi-rate logs merged on the union of their time
//! stamps).
//!
//! This module holds the parsed run and knows nothing of how it was read: the reader
//! (`ingest.rs`) makes it from a file (separators, comments, time units, streaming) and
//! records what it found in the run's [`IngestInfo`], `segments.rs` splits it at gaps in time
//! and `limits.rs` checks its inputs against a vehicle's actuator limits.
//!
//! Every problem is a [`RunError`] naming the file, the line and the column.

use crate::log::format::IngestInfo;
use shoal_model::control::Mode;
use std::fmt;
use std::path::PathBuf;

/// What a compared channel is: a `y.` column's measurement, or a thruster command the log's
/// controller sent (`u.<thruster>`), compared as a channel by the closed-loop replay.
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
    /// The command \[%\] the log's controller sent to the thruster of this name (interned
    /// with [`ChannelKind::command`]), compared with the command the replay's controller
    /// computes (`evaluate::open_loop::control`).
    Command(&'static str),
}

/// Thruster names interned for [`ChannelKind::Command`]: one leaked copy per distinct name,
/// for the life of the process (a vehicle has a handful of thrusters).
static COMMAND_NAMES: std::sync::Mutex<Vec<&'static str>> = std::sync::Mutex::new(Vec::new());

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

    /// The command channel of thruster `name`.
    pub fn command(name: &str) -> ChannelKind {
        let mut names = COMMAND_NAMES
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some(n) = names.iter().find(|n| **n == name) {
            return ChannelKind::Command(n);
        }
        let n: &'static str = Box::leak(name.to_string().into_boxed_str());
        names.push(n);
        ChannelKind::Command(n)
    }

    /// Column name without its prefix (`depth`; a command channel's thruster name).
    pub fn name(self) -> &'static str {
        if let ChannelKind::Command(n) = self {
            return n;
        }
        Self::ALL
            .iter()
            .find(|(k, _)| *k == self)
            .map_or("?", |(_, n)| n)
    }

    /// Column name with its prefix: `y.depth`, or `u.port` for a command channel.
    pub fn label(self) -> String {
        match self {
            ChannelKind::Command(n) => format!("u.{n}"),
            k => format!("y.{}", k.name()),
        }
    }

    /// Whether it is a thruster command (see [`ChannelKind::Command`]).
    pub fn is_command(self) -> bool {
        matches!(self, ChannelKind::Command(_))
    }

    /// Unit of the channel.
    pub fn unit(self) -> &'static str {
        use ChannelKind::*;
        match self {
            Depth | X | Y => "m",
            Roll | Pitch | Yaw => "rad",
            P | Q | R => "rad/s",
            U | V | W => "m/s",
            Command(_) => "%",
        }
    }

    /// Angles are compared modulo 2π.
    pub fn is_angle(self) -> bool {
        matches!(
            self,
            ChannelKind::Roll | ChannelKind::Pitch | ChannelKind::Yaw
        )
    }

    /// Whether a re-anchored replay sets this channel's state to the data at each anchor
    /// (depth, attitude, body rates; see `evaluate::open_loop::anchors`).
    pub fn is_anchored(self) -> bool {
        matches!(
            self,
            ChannelKind::Depth
                | ChannelKind::Roll
                | ChannelKind::Pitch
                | ChannelKind::Yaw
                | ChannelKind::P
                | ChannelKind::Q
                | ChannelKind::R
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

/// Written as its column name, e.g. `"y.depth"` or `"u.port"`.
impl serde::Serialize for ChannelKind {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.label())
    }
}

/// What an `r.` column holds: a reference (setpoint) the vehicle's controller followed. The
/// one table of reference names ([`ReferenceKind::ALL`]): the CSV header, the rosbag2 mapping,
/// their messages and the docs take them from here.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ReferenceKind {
    /// Depth setpoint \[m\] (positive down).
    Depth,
    /// Heading setpoint \[rad\].
    Yaw,
    /// Surge force demand \[N\].
    Surge,
    /// Sway force demand \[N\].
    Sway,
    /// The controller's mode, as its code ([`Mode::code`], 0 … 6) \[-\].
    Mode,
}

impl ReferenceKind {
    /// Every kind with its column name (after `r.`) and what it is, with its unit.
    pub const ALL: [(ReferenceKind, &'static str, &'static str); 5] = [
        (ReferenceKind::Depth, "depth", "depth [m, positive down]"),
        (ReferenceKind::Yaw, "yaw", "heading [rad]"),
        (ReferenceKind::Surge, "surge", "surge force [N]"),
        (ReferenceKind::Sway, "sway", "sway force [N]"),
        (ReferenceKind::Mode, "mode", "mode (name or code)"),
    ];

    /// Parses a column name without the `r.` prefix.
    pub fn from_name(s: &str) -> Option<ReferenceKind> {
        Self::ALL
            .iter()
            .find(|(_, n, _)| *n == s)
            .map(|(k, _, _)| *k)
    }

    /// Column name without the `r.` prefix.
    pub fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(k, _, _)| *k == self)
            .map_or("?", |(_, n, _)| n)
    }

    /// What it is, with its unit, e.g. `depth [m, positive down]`.
    pub fn what(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(k, _, _)| *k == self)
            .map_or("?", |(_, _, w)| w)
    }

    /// The allowed values, for messages.
    pub fn allowed_values(self) -> String {
        match self {
            ReferenceKind::Mode => {
                let modes: Vec<String> = Mode::BY_CODE
                    .iter()
                    .map(|m| format!("{} ({})", m.name(), m.code()))
                    .collect();
                format!("a mode name in any case or its code: {}", modes.join(", "))
            }
            _ => format!("a finite {}", self.what()),
        }
    }

    /// A value of this reference as read (a number in its unit; for the mode its code), or
    /// what is wrong with it (naming the allowed values).
    pub fn check(self, v: f64) -> Result<f64, String> {
        let ok = match self {
            ReferenceKind::Mode => {
                v.fract() == 0.0 && (0.0..Mode::BY_CODE.len() as f64).contains(&v)
            }
            _ => v.is_finite(),
        };
        if ok {
            Ok(v)
        } else {
            Err(format!(
                "{v} is not a value of `r.{}` (allowed: {})",
                self.name(),
                self.allowed_values()
            ))
        }
    }

    /// A written mode cell: a mode name (any case) or its code `0` … `6` (`3`, `3.0`), as the
    /// code.
    pub fn parse_mode(cell: &str) -> Option<f64> {
        if let Some(m) = Mode::from_name(&cell.to_ascii_lowercase()) {
            return Some(m.code() as f64);
        }
        let code: f64 = cell.parse().ok()?;
        ReferenceKind::Mode.check(code).ok()
    }
}

/// An actuator input column, zero-order held.
#[derive(Clone, Debug, PartialEq)]
pub struct InputColumn {
    /// Actuator name (after `u.`), or for a reference its name (after `r.`, one of
    /// [`ReferenceKind::ALL`]).
    pub name: String,
    /// 1-based column number in the file.
    pub column: usize,
    /// Value in force at each row (held from the last set value; before the first set value,
    /// the first set value) [unit of the actuator: % for thrusters, rad for tilt drives, −1/0/+1
    /// for the pump; of a reference: see [`ReferenceKind`]].
    pub values: Vec<f64>,
    /// For each row, half a unit of the last written digit of the cell its value comes from
    /// (`-1.5708` → 5·10⁻⁵) [unit of the actuator]: how far the logger may have rounded it.
    /// Empty for runs not read from text: every value is then exact.
    pub precision: Vec<f32>,
    /// Row of the first cell that sets this input (rows before it hold that cell's value).
    pub first_set: usize,
}

impl InputColumn {
    /// A held column (input or reference) named `name` at file column `column`, without
    /// values yet.
    pub fn held(name: &str, column: usize) -> InputColumn {
        InputColumn {
            name: name.to_string(),
            column,
            values: Vec::new(),
            precision: Vec::new(),
            first_set: 0,
        }
    }
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
        self.kind.label()
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
    /// References the vehicle's controller followed (`r.<name>` columns), held like inputs:
    /// `depth` \[m\], `yaw` \[rad\], `surge` and `sway` \[N\], `mode` (the mode's code,
    /// [`shoal_model::control::Mode::code`]); see [`ReferenceKind`]. Empty when the log carries
    /// none.
    pub references: Vec<InputColumn>,
    /// Names of ignored `x.` columns.
    pub extra: Vec<String>,
    /// 1-based line of the header in the file (0 for runs not read from a file).
    pub header_line: usize,
    /// 1-based file line of each row (empty for runs not read from a file).
    pub lines: Vec<usize>,
    /// How the file was read (separator, time unit, comments, segments).
    pub ingest: IngestInfo,
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
    /// Duration from the first to the last row \[s\].
    pub fn duration(&self) -> f64 {
        self.t.last().copied().unwrap_or(0.0) - self.t.first().copied().unwrap_or(0.0)
    }

    /// The input column of that actuator name, if present.
    pub fn input(&self, name: &str) -> Option<&InputColumn> {
        self.inputs.iter().find(|i| i.name == name)
    }

    /// The reference column of that kind, if logged.
    pub fn reference(&self, kind: ReferenceKind) -> Option<&InputColumn> {
        self.references.iter().find(|r| r.name == kind.name())
    }

    /// The channel of that kind, if measured.
    pub fn channel(&self, kind: ChannelKind) -> Option<&Channel> {
        self.channels.iter().find(|c| c.kind == kind)
    }

    /// Writes the run as CSV text (the format [`MeasuredRun::parse`] reads): `t`, the inputs,
    /// the channels, the references. A held column is written where it is first set and where
    /// it changes, so that reading the text back gives the same values and `first_set`.
    pub fn to_csv(&self) -> String {
        let mut out = String::from("t");
        for i in &self.inputs {
            out.push_str(&format!(",u.{}", i.name));
        }
        for c in &self.channels {
            out.push_str(&format!(",{}", c.label()));
        }
        for r in &self.references {
            out.push_str(&format!(",r.{}", r.name));
        }
        out.push('\n');
        let mut cursor = vec![0usize; self.channels.len()];
        for (row, t) in self.t.iter().enumerate() {
            out.push_str(&format!("{t}"));
            for i in &self.inputs {
                held_cell(&mut out, i, row);
            }
            for (k, c) in self.channels.iter().enumerate() {
                if c.rows.get(cursor[k]) == Some(&row) {
                    out.push_str(&format!(",{}", c.values[cursor[k]]));
                    cursor[k] += 1;
                } else {
                    out.push(',');
                }
            }
            for r in &self.references {
                held_cell(&mut out, r, row);
            }
            out.push('\n');
        }
        out
    }
}

/// The cell of a held column at `row`, after its separator: its value where it is first set
/// and where it changes, empty elsewhere.
fn held_cell(out: &mut String, col: &InputColumn, row: usize) {
    let first = col.first_set.min(col.values.len().saturating_sub(1));
    let set = row == first || (row > first && col.values[row] != col.values[row - 1]);
    if set {
        out.push_str(&format!(",{}", col.values[row]));
    } else {
        out.push(',');
    }
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
    use std::path::Path;

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
