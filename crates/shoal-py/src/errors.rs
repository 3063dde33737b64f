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

/// A Python [`ValidationError`] with message `message` and attributes `setting` (the keyword
/// argument at fault), `file`, `line` and `column` (where a file is at fault; None otherwise).
pub fn validation_error(
    py: Python<'_>,
    message: String,
    setting: Option<&str>,
    file: Option<std::path::PathBuf>,
    line: Option<usize>,
    column: Option<String>,
) -> PyErr {
    let err = ValidationError::new_err(message);
    let v = err.value(py);
    // Setting attributes on a fresh exception cannot fail but for memory; the message says
    // the same.
    let _ = v.setattr("setting", setting);
    let _ = v.setattr("file", file);
    let _ = v.setattr("line", line);
    let _ = v.setattr("column", column);
    err
}

/// A log that cannot be read ([`shoal_sysid::log::run::RunError`]) as a [`ValidationError`]
/// naming its file, line (0: the file as a whole) and column.
pub fn run_error(py: Python<'_>, e: &shoal_sysid::log::run::RunError) -> PyErr {
    validation_error(
        py,
        e.to_string(),
        None,
        Some(e.file.clone()),
        Some(e.line),
        e.column.as_ref().map(|c| c.1.clone()),
    )
}

/// A mapping file that cannot be read as a [`ValidationError`] of setting `mapping`.
pub fn mapping_error(py: Python<'_>, e: &shoal_rosbag::MappingError) -> PyErr {
    validation_error(
        py,
        e.to_string(),
        Some("mapping"),
        Some(e.file.clone()),
        None,
        None,
    )
}
