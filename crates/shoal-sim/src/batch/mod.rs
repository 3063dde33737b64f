//! Whole-swarm access through flat arrays, one row per vehicle in id order, for bindings that
//! drive every vehicle at once without a loop per vehicle in their own language (the Python
//! package, `crates/shoal-py`):
//! - read a [`Quantity`] of every vehicle (state, sensor readings, setpoints, actuators, modem
//!   counters) into one slice ([`Sim::read_f64`], [`Sim::read_i64`], [`Sim::read_bool`]);
//! - set the setpoints ([`Sim::set_setpoints`]) or raw actuator commands
//!   ([`Sim::set_actuators`]) of all vehicles or a subset, every value checked before
//!   anything changes: a NaN or infinite number, an unknown mode or pump code, or (unless
//!   clipping was asked for) a value outside its range is a [`CommandError`] naming the
//!   vehicle, the field and the allowed range;
//! - queue frames on vehicles' modems ([`Sim::queue_frames`]) and collect the frames
//!   delivered in a step ([`Sim::collect_received`]).
//!
//! A command written here acts like an external agent's ([`crate::agents`]): it replaces the
//! setpoints the built-in controller follows from its next control tick on, and ends the
//! agent fallback of an agent-driven vehicle. A vehicle's mission and built-in behaviour
//! still run and may replace the setpoints again. The ranges are the agents' (one source:
//! [`crate::orders`]); agents clamp values outside them, here they are errors unless the
//! caller clips.
//!
//! `quantity` holds what can be read and the reads; `commands` the commands and the
//! frames; this file the error and the column types both use.

mod commands;
mod quantity;

pub use commands::{ActuatorOrder, MODES, SetpointOrder, mode_code};
pub use quantity::{BatchShape, Dtype, Quantity};

use std::fmt;

/// A bad command: which vehicle (if one), which field, and what is allowed.
#[derive(Clone, Debug, PartialEq)]
pub struct CommandError {
    /// Vehicle id, when the problem is one vehicle's.
    pub vehicle: Option<usize>,
    /// The vehicle's name.
    pub name: Option<String>,
    /// The field, e.g. `depth` or `thrusters[1]`.
    pub field: String,
    /// What is wrong and what is allowed (units SI).
    pub message: String,
}

impl fmt::Display for CommandError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.vehicle, &self.name) {
            (Some(v), Some(n)) => {
                write!(f, "vehicle {v} (`{n}`), {}: {}", self.field, self.message)
            }
            (Some(v), None) => write!(f, "vehicle {v}, {}: {}", self.field, self.message),
            _ => write!(f, "{}: {}", self.field, self.message),
        }
    }
}

impl std::error::Error for CommandError {}

impl CommandError {
    pub(crate) fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            vehicle: None,
            name: None,
            field: field.into(),
            message: message.into(),
        }
    }
}
/// One value per row, or one value for every row.
#[derive(Clone, Copy, Debug)]
pub enum Column<'a, T> {
    /// The same value for every row.
    All(T),
    /// One value per row.
    Each(&'a [T]),
}

impl<T: Copy> Column<'_, T> {
    /// The value of row `row`.
    pub fn get(&self, row: usize) -> T {
        match self {
            Self::All(x) => *x,
            Self::Each(xs) => xs[row],
        }
    }

    pub(crate) fn check_len(&self, field: &str, rows: usize) -> Result<(), CommandError> {
        match self {
            Self::Each(xs) if xs.len() != rows => Err(CommandError::field(
                field,
                format!("{} values for {rows} vehicles", xs.len()),
            )),
            _ => Ok(()),
        }
    }
}

/// A row-major matrix: `width` values per row.
#[derive(Clone, Copy, Debug)]
pub struct Rows<'a> {
    /// The values, row after row.
    pub data: &'a [f64],
    /// Values per row.
    pub width: usize,
}

impl Rows<'_> {
    pub(crate) fn row(&self, r: usize) -> &[f64] {
        &self.data[r * self.width..(r + 1) * self.width]
    }

    pub(crate) fn check_len(&self, field: &str, rows: usize) -> Result<(), CommandError> {
        if self.data.len() != rows * self.width {
            return Err(CommandError::field(
                field,
                format!(
                    "{} values for {rows} vehicles × {} columns",
                    self.data.len(),
                    self.width
                ),
            ));
        }
        Ok(())
    }
}
