//! # shoal-world
//!
//! World files for shoal. A world is a TOML file ([`spec`]) with the pool, water, obstacles,
//! vehicle groups (a preset plus overrides, placement, mission) and outputs. [`load`] turns it
//! into a validated [`desc::WorldDesc`] in SI units, rejecting typos, wrong units, values out
//! of range, overlapping vehicles and vehicles outside the pool with messages that name the
//! file, line and field ([`error`]). [`geometry`] holds the pool and obstacles as parry3d
//! shapes: hull contacts, swept tests and line of sight. [`access`] is a modem's medium
//! access as a world states it. [`cancel`] lets a caller stop long
//! work (loading, and the crates above: building, running, writing) early.

pub mod access;
pub mod cancel;
pub mod desc;
pub mod error;
pub mod geometry;
pub mod load;
pub mod overrides;
pub mod range;
pub mod spec;

/// The commonly used types.
pub mod prelude {
    pub use crate::cancel::{Cancel, Cause, Interrupted};
    pub use crate::desc::{OutputDesc, VehicleDesc, WorldDesc};
    pub use crate::error::{FieldPath, Problem, ProblemKind, WorldError};
    pub use crate::geometry::{Geometry, HullContact};
    pub use crate::load::{DEFAULT_WORLD, default_world, load_file, load_str};
}
