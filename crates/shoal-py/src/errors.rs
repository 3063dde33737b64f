//! The module's Python exceptions and the conversion of a command error into one.

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
