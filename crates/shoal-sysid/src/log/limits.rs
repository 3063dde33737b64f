//! Measured inputs against the actuator limits of a vehicle: values a logger rounded past a
//! limit are clamped to it and counted; values clearly beyond are errors.
//!
//! A logger writing six significant digits writes the tilt limit −π/2 as `-1.5708`, 3.7·10⁻⁶ rad
//! beyond it. So a value outside `[lo, hi]` is **clamped** to the limit when its distance to
//! the limit is within
//!
//! * the documented tolerance of its kind — [`ANGLE_TOLERANCE`] (10⁻⁴ rad) for tilt drives,
//!   [`COMMAND_TOLERANCE`] (10⁻³ %) for thruster commands — or
//! * the precision it was written with: half a unit of its last written digit (`-1.5708` →
//!   5·10⁻⁵, recorded per value by the reader), counted only up to [`PRECISION_CAP`] of
//!   the actuator's range (3.1·10⁻³ rad for ±π/2, 0.2 % for ±100 %), so that a coarsely
//!   written number (`-2`, `1e9`) is not excused by its own coarseness.
//!
//! Anything further out is an error naming the file, the line of the cell that set the value,
//! the column, the value and the allowed range. The pump takes only −1 (empty), 0 (off) and +1
//! (fill), each within [`PUMP_TOLERANCE`] (values that close are set to the level exactly).
//!
//! Each clamp is reported as a [`ClampNote`] per column and limit: how many values, how far
//! out at most.

use crate::log::numbers::short;
use crate::log::run::{MeasuredRun, RunError};
use std::fmt;

/// Tolerance for tilt angles beyond their limits \[rad\].
pub const ANGLE_TOLERANCE: f64 = 1e-4;
/// Tolerance for thruster commands beyond ±`max_command` \[%\].
pub const COMMAND_TOLERANCE: f64 = 1e-3;
/// Tolerance of pump commands around −1, 0 and +1 \[-\].
pub const PUMP_TOLERANCE: f64 = 1e-6;
/// The written precision excuses at most this fraction of an actuator's range \[-\].
pub const PRECISION_CAP: f64 = 1e-3;

/// The pump's levels: −1 empty, 0 off, +1 fill.
const PUMP_LEVELS: [f64; 3] = [-1.0, 0.0, 1.0];

/// Values of one input column clamped to one limit.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ClampNote {
    /// Column name with its prefix, e.g. `u.beta`.
    pub name: String,
    /// 1-based column in the file.
    pub column: usize,
    /// The limit (or pump level) the values were set to [unit of the input].
    pub limit: f64,
    /// Unit of the input: `%`, `rad`, or empty for the pump.
    pub unit: String,
    /// How many values (rows) were clamped.
    pub count: usize,
    /// Largest distance of a clamped value from the limit [unit of the input].
    pub max_excess: f64,
    /// Largest tolerance that accepted one of them (the kind's tolerance or the written
    /// precision, capped) [unit of the input].
    pub tolerance: f64,
}

impl fmt::Display for ClampNote {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let u = if self.unit.is_empty() {
            String::new()
        } else {
            format!(" {}", self.unit)
        };
        write!(
            f,
            "{}: {} value(s) within {}{u} of the limit {}{u} clamped to it (largest excess {}{u})",
            self.name,
            self.count,
            num(self.tolerance),
            num(self.limit),
            num(self.max_excess)
        )
    }
}

/// A number for messages, with a proper minus sign in front.
fn num(x: f64) -> String {
    let s = short(x);
    match s.strip_prefix('-') {
        Some(rest) => format!("−{rest}"),
        None => s,
    }
}

/// The allowed values of one input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Limits {
    /// A range `[lo, hi]`.
    Range {
        /// Lower limit [unit].
        lo: f64,
        /// Upper limit [unit].
        hi: f64,
        /// Tolerance beyond the limits [unit] (see the module docs).
        tolerance: f64,
        /// What the value is, for messages (`thruster command`).
        what: &'static str,
        /// Unit symbol (`%`, `rad`).
        unit: &'static str,
    },
    /// The pump: −1, 0, +1 within [`PUMP_TOLERANCE`].
    Pump,
}

impl Limits {
    /// A thruster command within ±`max_command` \[%\].
    pub fn thruster(max_command: f64) -> Limits {
        Limits::Range {
            lo: -max_command,
            hi: max_command,
            tolerance: COMMAND_TOLERANCE,
            what: "thruster command",
            unit: "%",
        }
    }

    /// A tilt angle within `[min, max]` \[rad\].
    pub fn tilt(min: f64, max: f64) -> Limits {
        Limits::Range {
            lo: min,
            hi: max,
            tolerance: ANGLE_TOLERANCE,
            what: "tilt angle",
            unit: "rad",
        }
    }

    /// Checks input column `k` of `run`: the clamps it needs, or the first value clearly out
    /// of range. Changes nothing; [`Limits::apply`] does the clamping.
    pub fn check(&self, run: &MeasuredRun, k: usize) -> Result<Vec<ClampNote>, RunError> {
        let Some(inp) = run.inputs.get(k) else {
            return Ok(Vec::new());
        };
        let name = format!("u.{}", inp.name);
        let note = |limit: f64, unit: &str| ClampNote {
            name: name.clone(),
            column: inp.column,
            limit,
            unit: unit.to_string(),
            count: 0,
            max_excess: 0.0,
            tolerance: 0.0,
        };
        let error = |row: usize, message: String| RunError {
            file: run.path.clone(),
            // A value before the column's first cell comes from that cell.
            line: run.lines.get(row.max(inp.first_set)).copied().unwrap_or(0),
            column: Some((inp.column, name.clone())),
            message,
        };
        match *self {
            Limits::Range {
                lo,
                hi,
                tolerance,
                what,
                unit,
            } => {
                let cap = PRECISION_CAP * (hi - lo).abs();
                let mut notes = [note(lo, unit), note(hi, unit)];
                for (row, &v) in inp.values.iter().enumerate() {
                    if v >= lo && v <= hi {
                        continue;
                    }
                    let written = inp.precision.get(row).map_or(0.0, |&p| f64::from(p));
                    let tol = tolerance.max(written.min(cap));
                    let (side, excess) = if v < lo { (0, lo - v) } else { (1, v - hi) };
                    if excess <= tol {
                        let n = &mut notes[side];
                        n.count += 1;
                        n.max_excess = n.max_excess.max(excess);
                        n.tolerance = n.tolerance.max(tol);
                        continue;
                    }
                    return Err(error(
                        row,
                        format!(
                            "{what} {} {unit} is beyond the {} limit {} {unit} by {} {unit}, more \
                             than rounding explains (tolerance {} {unit}, or half the last \
                             written digit up to {} {unit}); allowed: {} … {} {unit}",
                            num(v),
                            if side == 0 { "lower" } else { "upper" },
                            num(if side == 0 { lo } else { hi }),
                            num(excess),
                            num(tolerance),
                            num(cap),
                            num(lo),
                            num(hi)
                        ),
                    ));
                }
                Ok(notes.into_iter().filter(|n| n.count > 0).collect())
            }
            Limits::Pump => {
                let mut notes: Vec<ClampNote> = PUMP_LEVELS.iter().map(|&l| note(l, "")).collect();
                for (row, &v) in inp.values.iter().enumerate() {
                    let nearest = PUMP_LEVELS
                        .iter()
                        .enumerate()
                        .map(|(i, &l)| (i, (v - l).abs()))
                        .min_by(|a, b| a.1.total_cmp(&b.1));
                    match nearest {
                        Some((_, 0.0)) => {}
                        Some((i, d)) if d <= PUMP_TOLERANCE => {
                            let n = &mut notes[i];
                            n.count += 1;
                            n.max_excess = n.max_excess.max(d);
                            n.tolerance = PUMP_TOLERANCE;
                        }
                        _ => {
                            return Err(error(
                                row,
                                format!(
                                    "pump command {} is not a pump state; allowed: −1 (empty), \
                                     0 (off), +1 (fill), each within {}",
                                    num(v),
                                    num(PUMP_TOLERANCE)
                                ),
                            ));
                        }
                    }
                }
                Ok(notes.into_iter().filter(|n| n.count > 0).collect())
            }
        }
    }

    /// Clamps `values` into the limits (the pump: to the nearest level). After a successful
    /// [`Limits::check`] this moves only the values it counted.
    pub fn apply(&self, values: &mut [f64]) {
        match *self {
            Limits::Range { lo, hi, .. } => {
                for v in values {
                    *v = v.clamp(lo, hi);
                }
            }
            Limits::Pump => {
                for v in values {
                    *v = v.round().clamp(-1.0, 1.0);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn run(col: &str, cells: &[&str]) -> MeasuredRun {
        let mut text = format!("t,{col},y.depth\n");
        for (i, c) in cells.iter().enumerate() {
            text.push_str(&format!("{},{c},1\n", i as f64 * 0.1));
        }
        MeasuredRun::parse(&text, Path::new("r.csv")).unwrap()
    }

    #[test]
    fn a_tilt_written_at_six_digits_is_clamped_and_counted() {
        let lim = Limits::tilt(-std::f64::consts::FRAC_PI_2, std::f64::consts::FRAC_PI_2);
        let mut r = run("u.beta", &["-1.5708", "", "0", "1.5708", "-1.571"]);
        let notes = lim.check(&r, 0).unwrap();
        assert_eq!(notes.len(), 2, "{notes:?}");
        assert_eq!((notes[0].count, notes[1].count), (3, 1));
        assert_eq!(notes[0].name, "u.beta");
        assert!((notes[0].max_excess - (1.571 - std::f64::consts::FRAC_PI_2)).abs() < 1e-12);
        // -1.571 needs its written precision (5e-4) beyond the angle tolerance.
        assert!(
            (notes[0].tolerance - 5e-4).abs() < 1e-9,
            "{}",
            notes[0].tolerance
        );
        let text = notes[0].to_string();
        assert!(
            text.starts_with("u.beta: 3 value(s) within 0.0005 rad of the limit −1.570796 rad"),
            "{text}"
        );
        lim.apply(&mut r.inputs[0].values);
        assert_eq!(r.inputs[0].values[0], -std::f64::consts::FRAC_PI_2);
        assert_eq!(r.inputs[0].values[2], 0.0);
    }

    #[test]
    fn values_clearly_beyond_are_errors_on_the_line_that_set_them() {
        let lim = Limits::tilt(-std::f64::consts::FRAC_PI_2, std::f64::consts::FRAC_PI_2);
        // -1.6 is 0.029 rad out: more than its precision (0.05) capped at 3.1e-3.
        for (cells, line) in [
            (&["0", "", "-1.6", ""][..], 4),
            (&["", "-2", "0"][..], 3),
            (&["0", "1.58"][..], 3),
        ] {
            let r = run("u.beta", cells);
            let e = lim.check(&r, 0).unwrap_err();
            assert_eq!(
                (e.line, e.column.clone()),
                (line, Some((2, "u.beta".into())))
            );
            assert!(
                e.message.contains("allowed: −1.570796 … 1.570796 rad"),
                "{e}"
            );
        }
        let lim = Limits::thruster(100.0);
        for cell in ["100.01", "101", "1e9", "-100.5"] {
            let r = run("u.port", &["0", cell]);
            let e = lim.check(&r, 0).unwrap_err();
            assert_eq!(e.line, 3, "{cell}");
            assert!(e.message.contains("allowed: −100 … 100 %"), "{cell}: {e}");
        }
        let r = run("u.port", &["0", "100.0005", "-100", "99.99"]);
        let notes = lim.check(&r, 0).unwrap();
        assert_eq!(notes.len(), 1);
        assert_eq!((notes[0].limit, notes[0].count), (100.0, 1));
    }

    #[test]
    fn the_pump_takes_three_levels() {
        let lim = Limits::Pump;
        for cell in ["0.5", "1e9", "-2", "0.001"] {
            let r = run("u.pump", &["0", "1", cell]);
            let e = lim.check(&r, 0).unwrap_err();
            assert_eq!(
                (e.line, e.column.clone()),
                (4, Some((2, "u.pump".into()))),
                "{cell}"
            );
            assert!(
                e.message
                    .contains("allowed: −1 (empty), 0 (off), +1 (fill)"),
                "{e}"
            );
        }
        let mut r = run("u.pump", &["0", "1", "-1", "0.9999999", "-0"]);
        let notes = lim.check(&r, 0).unwrap();
        assert_eq!(notes.len(), 1);
        assert_eq!((notes[0].limit, notes[0].count), (1.0, 1));
        lim.apply(&mut r.inputs[0].values);
        assert_eq!(r.inputs[0].values, vec![0.0, 1.0, -1.0, 1.0, 0.0]);
    }
}
