//! `shoal.validate`'s compiled half: measured runs (paths, or columns of numbers) and settings
//! handed to [`shoal_sysid::validate::validate`] on a thread of its own (the caller waits with
//! the GIL released and Ctrl-C still raising `KeyboardInterrupt`), files read through
//! `shoal_rosbag::readers` (CSV, and rosbag2s through `mapping`, as `shoal validate` reads
//! them), progress passed back to a Python callable, and the finished validation kept as [`Validation`] (its report as
//! JSON text, the fitted vehicle as a world file, the report files written on request). The
//! Python half (`python/shoal/validate.py`) builds the `Report` objects from it.

use crate::errors;
use numpy::{AllowTypeChange, PyArrayLike1};
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use shoal_sysid::log::segments::GapMode;
use shoal_sysid::validate::{Config, Progress, RunInput, ValidateError, Vehicle};
use std::fmt::Write as _;
use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{RecvTimeoutError, channel};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// A finished validation (see `shoal.validate`).
#[pyclass(frozen, module = "shoal._shoal")]
pub struct Validation(shoal_sysid::validate::Validation);

#[pymethods]
impl Validation {
    /// The content of `report.json` (without plots) as JSON text.
    fn report_json(&self) -> String {
        self.0.report_value().to_string()
    }

    /// The fitted vehicle as a world file (the text of `vehicle.toml`).
    fn vehicle_toml(&self) -> PyResult<String> {
        self.0
            .vehicle_toml(std::path::Path::new("vehicle.toml"))
            .map_err(|e| PyOSError::new_err(e.to_string()))
    }

    /// The suggested next experiment as a world file (the text of `next_experiment.toml`), or
    /// `None` when the log leaves no question open.
    fn next_experiment_toml(&self) -> PyResult<Option<String>> {
        self.0
            .next_experiment_toml()
            .map_err(|e| PyOSError::new_err(e.to_string()))
    }

    /// Writes `report.json`, `report.md`, `vehicle.toml`, `next_experiment.toml` (when one is
    /// suggested) and (with `plots`) the plots into `dir`; returns their paths `(json,
    /// markdown, vehicle, next experiment or None, [plots])`.
    #[pyo3(signature = (dir, plots=true))]
    #[allow(clippy::type_complexity)]
    fn write(
        &self,
        py: Python<'_>,
        dir: PathBuf,
        plots: bool,
    ) -> PyResult<(PathBuf, PathBuf, PathBuf, Option<PathBuf>, Vec<PathBuf>)> {
        let w = py
            .detach(|| self.0.write(&dir, plots))
            .map_err(|e| PyOSError::new_err(e.to_string()))?;
        Ok((w.json, w.markdown, w.vehicle, w.next_experiment, w.plots))
    }
}

/// One run from Python: a path (str or os.PathLike), or `(name, columns)` with `columns` a
/// list of `(header, values)` pairs (the CSV format's column names, 1-D numbers).
fn run_input(item: &Bound<'_, PyAny>, which: &str) -> PyResult<RunInput> {
    if let Ok(path) = item.extract::<PathBuf>() {
        return Ok(RunInput::File(path));
    }
    let bad = |m: String| PyValueError::new_err(format!("{which}: {m}"));
    let tuple = item
        .cast::<PyTuple>()
        .map_err(|_| bad("expected a path or (name, columns)".into()))?;
    if tuple.len() != 2 {
        return Err(bad("expected a path or (name, columns)".into()));
    }
    let name: String = tuple.get_item(0)?.extract()?;
    let mut headers = Vec::new();
    let mut columns: Vec<Vec<f64>> = Vec::new();
    for pair in tuple.get_item(1)?.try_iter()? {
        let pair = pair?;
        let (header, values): (String, Bound<'_, PyAny>) = pair.extract()?;
        let v: PyArrayLike1<'_, f64, AllowTypeChange> = values
            .extract()
            .map_err(|_| bad(format!("column `{header}` is not a 1-D array of numbers")))?;
        columns.push(v.as_array().to_vec());
        headers.push(header);
    }
    let rows = columns.first().map_or(0, Vec::len);
    if let Some((h, c)) = headers.iter().zip(&columns).find(|(_, c)| c.len() != rows) {
        return Err(bad(format!(
            "column `{h}` has {} values, column `{}` {rows}",
            c.len(),
            headers[0]
        )));
    }
    // Rust's float formatting is the shortest text that reads back as the same number, so
    // the reader sees exactly the values given.
    let mut csv = headers.join(",");
    csv.push('\n');
    for r in 0..rows {
        for (k, c) in columns.iter().enumerate() {
            let sep = if k == 0 { "" } else { "," };
            let _ = write!(csv, "{sep}{}", c[r]);
        }
        csv.push('\n');
    }
    Ok(RunInput::Text { name, csv })
}

/// A [`ValidateError`] as a Python `ValidationError` with attributes `setting` (the keyword
/// argument at fault, or None), `file`, `line` and `column` (where a run is at fault, else
/// None).
fn error(py: Python<'_>, e: &ValidateError) -> PyErr {
    match e {
        ValidateError::Setting { setting, .. } | ValidateError::UnknownName { setting, .. } => {
            errors::validation_error(py, e.to_string(), Some(setting), None, None, None)
        }
        ValidateError::Run(r) => errors::run_error(py, r),
        _ => errors::validation_error(py, e.to_string(), None, None, None, None),
    }
}

/// Progress as `(kind, message)`: kind `read`, `clamped`, `start` or `fit`.
fn progress_message(p: &Progress<'_>) -> (&'static str, String) {
    match p {
        Progress::Read { path, segments } => (
            "read",
            format!(
                "{}: {} segment(s){}",
                path.display(),
                segments.runs.len(),
                segments
                    .runs
                    .first()
                    .map(|r| format!(", {}", r.ingest))
                    .unwrap_or_default()
            ),
        ),
        Progress::Clamped { run, note } => ("clamped", format!("{run}: {note}")),
        Progress::Start {
            vehicle,
            estimation,
            holdout,
            families,
            forms,
            threads,
            ..
        } => (
            "start",
            format!(
                "validating `{vehicle}` on {estimation} run(s) + {holdout} hold-out run(s), \
                 {families} effect families in {forms} forms, {threads} thread(s)"
            ),
        ),
        Progress::Stage { stage, fits } => (
            "stage",
            match fits {
                Some(n) => format!("{stage} ({n} fits)"),
                None => stage.to_string(),
            },
        ),
        Progress::Fit { name } => ("fit", name.to_string()),
    }
}

/// The compiled `shoal._shoal.validate`: see `shoal.validate` (python/shoal/validate.py),
/// which normalises the runs into paths and `(name, [(header, values)])` tuples.
#[pyfunction]
#[pyo3(signature = (runs, holdout, vehicle, channels, effects, split, dt, time_unit, gaps, max_gap, min_segment, threads, progress, horizon, mapping=None))]
pub fn validate(
    py: Python<'_>,
    runs: Vec<Bound<'_, PyAny>>,
    holdout: Vec<Bound<'_, PyAny>>,
    vehicle: Option<PathBuf>,
    channels: Vec<String>,
    effects: Vec<String>,
    split: f64,
    dt: f64,
    time_unit: Option<String>,
    gaps: &str,
    max_gap: Option<f64>,
    min_segment: f64,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
    horizon: &str,
    mapping: Option<PathBuf>,
) -> PyResult<Validation> {
    let inputs = |list: &[Bound<'_, PyAny>], what: &str| -> PyResult<Vec<RunInput>> {
        list.iter()
            .enumerate()
            .map(|(i, r)| run_input(r, &format!("{what}[{i}]")))
            .collect()
    };
    let (runs, holdout) = (inputs(&runs, "runs")?, inputs(&holdout, "holdout")?);
    let time_unit = crate::log::parse_time_unit(time_unit.as_deref())?;
    let readers =
        shoal_rosbag::readers(mapping.as_deref()).map_err(|e| errors::mapping_error(py, &e))?;
    let config = Config {
        vehicle: vehicle.map_or(Vehicle::Preset, Vehicle::File),
        split,
        dt,
        time_unit,
        gaps: gaps.parse::<GapMode>().map_err(PyValueError::new_err)?,
        max_gap,
        min_segment,
        channels,
        effects,
        threads,
        horizon: horizon.parse().map_err(PyValueError::new_err)?,
        readers,
    };
    let done = run_interruptibly(py, config, runs, holdout, progress)?;
    done.map(Validation).map_err(|e| error(py, &e))
}

/// What the validation's thread unwinds with when Ctrl-C stopped it.
struct Cancelled;

/// Runs the validation on a thread of its own while this one waits with the GIL released,
/// looking for signals every 0.1 s: Ctrl-C raises `KeyboardInterrupt` at once and stops the
/// search at its next stage (its fits in flight finish unheard). The progress callable is
/// called from the search's threads, each taking the GIL for the call; the first exception it
/// raises is raised once the search is done.
fn run_interruptibly(
    py: Python<'_>,
    config: Config,
    runs: Vec<RunInput>,
    holdout: Vec<RunInput>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Result<shoal_sysid::validate::Validation, ValidateError>> {
    let cancelled = Arc::new(AtomicBool::new(false));
    let stop = Arc::clone(&cancelled);
    let (tx, rx) = channel();
    std::thread::spawn(move || {
        let failed: Mutex<Option<PyErr>> = Mutex::new(None);
        let report = |p: Progress<'_>| {
            if stop.load(Ordering::Relaxed) {
                if matches!(p, Progress::Stage { .. }) {
                    resume_unwind(Box::new(Cancelled));
                }
                return;
            }
            let Some(cb) = &progress else { return };
            let (kind, message) = progress_message(&p);
            Python::attach(|py| {
                if let Err(e) = cb.call1(py, (kind, message))
                    && let Ok(mut f) = failed.lock()
                {
                    f.get_or_insert(e);
                }
            });
        };
        let done = catch_unwind(AssertUnwindSafe(|| {
            shoal_sysid::validate::validate(&config, &runs, &holdout, &report)
        }));
        let _ = tx.send((done, failed.into_inner().ok().flatten()));
    });
    // A receiver is not shared between threads; behind a lock, the wait releases the GIL.
    let rx = Mutex::new(rx);
    let wait = || match rx.lock() {
        Ok(r) => r.recv_timeout(Duration::from_millis(100)),
        Err(_) => Err(RecvTimeoutError::Disconnected),
    };
    loop {
        match py.detach(wait) {
            Ok((Ok(done), None)) => return Ok(done),
            Ok((Ok(_), Some(e))) => return Err(e),
            Ok((Err(panic), _)) => resume_unwind(panic),
            Err(RecvTimeoutError::Timeout) => {
                if let Err(e) = py.check_signals() {
                    cancelled.store(true, Ordering::Relaxed);
                    return Err(e);
                }
            }
            Err(RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err(
                    "the validation's thread ended without a result",
                ));
            }
        }
    }
}
