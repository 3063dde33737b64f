//! # shoal-py
//!
//! The compiled part of the `shoal` Python package (`python/`, built with maturin into the
//! extension module `shoal._shoal`): a whole shoal world in the Python process, stepped and
//! observed through numpy arrays over all vehicles at once.
//!
//! - [`world`]: the `World` class — loading, reset, stepping, the state digest;
//! - [`observe`]: every vehicle's state, readings, setpoints and modem counters as numpy
//!   arrays, and the frames delivered in the last step;
//! - [`args`]: numpy arrays and Python values turned into the whole-swarm commands of
//!   [`shoal_sim::batch`], whose checks raise [`CommandError`] naming the vehicle and field;
//! - [`plot`]: line plots (PNG, SVG) for the examples, drawn by shoal's own plotting;
//! - [`errors`]: the Python exceptions (`WorldError`, `CommandError`, `ValidationError`,
//!   `SimulationError`);
//! - [`log`]: one measured run (a CSV, or a rosbag2 through a mapping) read into columns of
//!   numbers, without a search;
//! - [`validate`]: `shoal validate` on measured runs (paths or columns of numbers), whose
//!   settings errors raise [`ValidationError`] naming the setting, file, line or column.
//!
//! The GIL is released while the world steps and while a validation searches. Python-facing units are SI, angles in radians.

pub mod args;
pub mod errors;
pub mod log;
pub mod observe;
pub mod plot;
pub mod run;
pub mod source;
pub mod validate;
pub mod world;

use pyo3::prelude::*;

use errors::{CommandError, SimulationError, ValidationError, WorldError};

/// The extension module `shoal._shoal`.
#[pymodule]
fn _shoal(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<world::World>()?;
    m.add_function(wrap_pyfunction!(plot::plot, m)?)?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(log::read_log, m)?)?;
    m.add_class::<validate::Validation>()?;
    m.add_function(wrap_pyfunction!(validate::validate, m)?)?;
    m.add("ValidationError", py.get_type::<ValidationError>())?;
    m.add("WorldError", py.get_type::<WorldError>())?;
    m.add("CommandError", py.get_type::<CommandError>())?;
    m.add("SimulationError", py.get_type::<SimulationError>())?;
    // Every mode code the `mode` quantity reports (6: raw), from the one table.
    let modes: Vec<&str> = shoal_model::control::Mode::BY_CODE
        .iter()
        .map(|m| m.name())
        .collect();
    m.add("MODES", modes)?;
    m.add(
        "QUANTITIES",
        shoal_sim::batch::Quantity::ALL
            .iter()
            .map(|q| q.name())
            .collect::<Vec<_>>(),
    )?;
    m.add("MAX_FRAME_DELAY", shoal_sim::orders::MAX_FRAME_DELAY)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
