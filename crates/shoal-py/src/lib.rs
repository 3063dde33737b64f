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
//! - [`validate`]: `shoal validate` on measured runs (paths or columns of numbers), whose
//!   settings errors raise [`ValidationError`] naming the setting, file, line or column.
//!
//! The GIL is released while the world steps and while a validation searches. Python-facing units are SI, angles in radians.

pub mod args;
pub mod observe;
pub mod plot;
pub mod run;
pub mod source;
pub mod validate;
pub mod world;

use pyo3::prelude::*;

pyo3::create_exception!(
    _shoal,
    WorldError,
    pyo3::exceptions::PyValueError,
    "A world file (or world text) that cannot be loaded: every problem with its line, field \
     and allowed range."
);
pyo3::create_exception!(
    _shoal,
    CommandError,
    pyo3::exceptions::PyValueError,
    "A bad command: NaN or infinite, out of range, an unknown mode, a wrong shape. Attributes: \
     `vehicle` (id or None), `name` (vehicle name or None), `field`."
);
pyo3::create_exception!(
    _shoal,
    ValidationError,
    pyo3::exceptions::PyValueError,
    "A validation that cannot run: a setting out of range or an unknown name (attribute \
     `setting`), or a run that cannot be read or does not fit the vehicle (attributes `file`, \
     `line`, `column`); the message names the allowed range."
);
pyo3::create_exception!(
    _shoal,
    SimulationError,
    pyo3::exceptions::PyRuntimeError,
    "A vehicle's state stopped being finite: the world cannot continue (reset it). The \
     message names the vehicle, the time and the last finite state."
);

/// Turns a [`shoal_sim::batch::CommandError`] into a Python [`CommandError`] with attributes
/// `vehicle`, `name` and `field`.
pub fn command_error(py: Python<'_>, e: &shoal_sim::batch::CommandError) -> PyErr {
    let err = CommandError::new_err(e.to_string());
    let v = err.value(py);
    // Setting attributes on a fresh exception instance cannot fail but for memory; the
    // message carries the same information anyway.
    let _ = v.setattr("vehicle", e.vehicle);
    let _ = v.setattr("name", e.name.clone());
    let _ = v.setattr("field", e.field.clone());
    err
}

/// The extension module `shoal._shoal`.
#[pymodule]
fn _shoal(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<world::World>()?;
    m.add_function(wrap_pyfunction!(plot::plot, m)?)?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_class::<validate::Validation>()?;
    m.add_function(wrap_pyfunction!(validate::validate, m)?)?;
    m.add("ValidationError", py.get_type::<ValidationError>())?;
    m.add("WorldError", py.get_type::<WorldError>())?;
    m.add("CommandError", py.get_type::<CommandError>())?;
    m.add("SimulationError", py.get_type::<SimulationError>())?;
    let modes: Vec<&str> = shoal_sim::batch::MODES.iter().map(|m| m.name()).collect();
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
