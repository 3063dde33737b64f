//! The error of a whole-swarm command ([`CommandError`]): which vehicle, which field, and what
//! is allowed.

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
