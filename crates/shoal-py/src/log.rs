//! `shoal.read_log`'s compiled half: one measured run read as `shoal validate` reads it —
//! a CSV, or a rosbag2 through a mapping file (`shoal_rosbag::readers`) — and handed back as
//! columns of numbers, without a search: what a user plots or checks before validating. The
//! Python half (`python/shoal/logs.py`) makes a `Log` of them.

use crate::errors;
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use shoal_sysid::log::format::{ReadOptions, TimeUnit};
use shoal_sysid::log::run::MeasuredRun;
use std::path::PathBuf;

/// A run's columns in the CSV format's names: `t` [s], each input `u.NAME` (the value in
/// force at every row, zero-order held), each channel `y.NAME` (its samples at the rows it
/// was sampled at, NaN at the others), each reference `r.NAME` (held as the inputs are; the
/// mode as its code).
fn columns(run: &MeasuredRun) -> Vec<(String, Vec<f64>)> {
    let mut out = vec![("t".to_string(), run.t.clone())];
    for i in &run.inputs {
        out.push((format!("u.{}", i.name), i.values.clone()));
    }
    for c in &run.channels {
        let mut v = vec![f64::NAN; run.t.len()];
        for (&row, &x) in c.rows.iter().zip(&c.values) {
            v[row] = x;
        }
        out.push((c.label(), v));
    }
    for r in &run.references {
        out.push((format!("r.{}", r.name), r.values.clone()));
    }
    out
}

/// A `time_unit` argument (`"s"`, `"ms"` or None) as the readers take it; anything else
/// raises `ValueError` naming the allowed units.
pub fn parse_time_unit(unit: Option<&str>) -> PyResult<Option<TimeUnit>> {
    unit.map(|u| u.parse::<TimeUnit>().map_err(PyValueError::new_err))
        .transpose()
}

/// A log as Python receives it: `(name, how it was read, [(header, values)])`.
type LogColumns = (String, String, Vec<(String, Py<PyArray1<f64>>)>);

/// The compiled `shoal._shoal.read_log`: `(name, how it was read, [(header, values)])`.
#[pyfunction]
#[pyo3(signature = (path, mapping=None, time_unit=None))]
pub fn read_log(
    py: Python<'_>,
    path: PathBuf,
    mapping: Option<PathBuf>,
    time_unit: Option<String>,
) -> PyResult<LogColumns> {
    let time_unit = parse_time_unit(time_unit.as_deref())?;
    let readers =
        shoal_rosbag::readers(mapping.as_deref()).map_err(|e| errors::mapping_error(py, &e))?;
    let run = py
        .detach(|| readers.read(&path, &ReadOptions { time_unit }))
        .map_err(|e| errors::run_error(py, &e))?;
    let cols = columns(&run)
        .into_iter()
        .map(|(h, v)| (h, v.into_pyarray(py).unbind()))
        .collect();
    Ok((run.name.clone(), run.ingest.to_string(), cols))
}
