//! Every vehicle's quantities as numpy arrays, one row per vehicle in id order: the world
//! fills a fresh buffer straight from its components in one pass ([`Sim::read_f64`] …) and
//! hands the buffer to numpy without another copy. The arrays are the caller's: they do not
//! change when the world steps on.
//!
//! The frames delivered in the last step are returned the same way, as parallel arrays with
//! one entry per frame ([`received`]), and the outcomes of acknowledged unicasts ([`outcomes`]).

use numpy::IntoPyArray;
use numpy::ndarray::{Array1, Array2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use shoal_sim::batch::{BatchShape, Dtype, Quantity};
use shoal_sim::comm::{FrameEvent, FrameOutcome, Received};
use shoal_sim::sim::Sim;

/// Turns a flat buffer of `n` rows into a numpy array: 1-D when `width` is `None`.
fn to_numpy<'py, T: numpy::Element>(
    py: Python<'py>,
    data: Vec<T>,
    n: usize,
    width: Option<usize>,
) -> PyResult<Bound<'py, PyAny>> {
    Ok(match width {
        None => Array1::from_vec(data).into_pyarray(py).into_any(),
        Some(w) => Array2::from_shape_vec((n, w), data)
            .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?
            .into_pyarray(py)
            .into_any(),
    })
}

/// Quantity `q` of every vehicle as a numpy array (float64, int64 or bool).
pub fn quantity<'py>(
    py: Python<'py>,
    sim: &mut Sim,
    shape: &BatchShape,
    q: Quantity,
) -> PyResult<Bound<'py, PyAny>> {
    let n = shape.vehicles;
    let width = q.width(shape);
    let len = n * width.unwrap_or(1);
    let err = |e: shoal_sim::batch::CommandError| crate::errors::command_error(py, &e);
    match q.dtype() {
        Dtype::F64 => {
            let mut v = vec![0.0; len];
            sim.read_f64(q, &mut v).map_err(err)?;
            to_numpy(py, v, n, width)
        }
        Dtype::I64 => {
            let mut v = vec![0i64; len];
            sim.read_i64(q, &mut v).map_err(err)?;
            to_numpy(py, v, n, width)
        }
        Dtype::Bool => {
            let mut v = vec![false; len];
            sim.read_bool(q, &mut v).map_err(err)?;
            to_numpy(py, v, n, width)
        }
    }
}

/// The frames in `frames` as a dict of parallel numpy arrays: `vehicle` (receiver id),
/// `sender` (id from the link-layer header), `seq` (the sender's frame number), `modem`
/// (receiving modem), `t` (end of reception \[s\]), `sent` (hand-over at the sender \[s\]),
/// `power` (received optical power \[W\]), `snr` (electrical SNR, linear), `length`
/// (payload bytes) and `payload` (uint8, `max_payload` columns, zero after `length`).
pub fn received<'py>(
    py: Python<'py>,
    frames: &[(u32, Received)],
    max_payload: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let k = frames.len();
    let d = PyDict::new(py);
    let ints = |f: &dyn Fn(&(u32, Received)) -> i64| -> Vec<i64> { frames.iter().map(f).collect() };
    let floats =
        |f: &dyn Fn(&Received) -> f64| -> Vec<f64> { frames.iter().map(|(_, r)| f(r)).collect() };
    d.set_item("vehicle", ints(&|x| i64::from(x.0)).into_pyarray(py))?;
    d.set_item("sender", ints(&|x| i64::from(x.1.from)).into_pyarray(py))?;
    d.set_item("seq", ints(&|x| i64::from(x.1.seq)).into_pyarray(py))?;
    d.set_item("modem", ints(&|x| x.1.modem as i64).into_pyarray(py))?;
    d.set_item("t", floats(&|r| r.t).into_pyarray(py))?;
    d.set_item("sent", floats(&|r| r.sent).into_pyarray(py))?;
    d.set_item("power", floats(&|r| r.power).into_pyarray(py))?;
    d.set_item("snr", floats(&|r| r.snr).into_pyarray(py))?;
    let unicast: Vec<bool> = frames.iter().map(|(_, r)| r.unicast).collect();
    d.set_item("unicast", unicast.into_pyarray(py))?;
    d.set_item(
        "length",
        ints(&|x| x.1.payload.len() as i64).into_pyarray(py),
    )?;
    let mut payload = vec![0u8; k * max_payload];
    for (row, (_, r)) in payload.chunks_mut(max_payload.max(1)).zip(frames) {
        let m = r.payload.len().min(max_payload);
        row[..m].copy_from_slice(&r.payload[..m]);
    }
    d.set_item("payload", to_numpy(py, payload, k, Some(max_payload))?)?;
    Ok(d)
}

/// The outcomes in `events` as a dict of parallel numpy arrays: `vehicle` (sender id), `to`
/// (destination id), `tag` (the sender's), `seq` (its frame number), `acknowledged` (bool),
/// `transmissions` (1 + retransmissions; 0: refused by a full queue), `sent` (hand-over
/// \[s\]) and `t` (acknowledgement decoded, or the last wait ended \[s\]).
pub fn outcomes<'py>(
    py: Python<'py>,
    events: &[(u32, FrameEvent)],
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let ints =
        |f: &dyn Fn(&(u32, FrameEvent)) -> i64| -> Vec<i64> { events.iter().map(f).collect() };
    let floats =
        |f: &dyn Fn(&FrameEvent) -> f64| -> Vec<f64> { events.iter().map(|(_, e)| f(e)).collect() };
    d.set_item("vehicle", ints(&|x| i64::from(x.0)).into_pyarray(py))?;
    d.set_item("to", ints(&|x| i64::from(x.1.to)).into_pyarray(py))?;
    d.set_item("tag", ints(&|x| i64::from(x.1.tag)).into_pyarray(py))?;
    d.set_item("seq", ints(&|x| i64::from(x.1.seq)).into_pyarray(py))?;
    let acked: Vec<bool> = events
        .iter()
        .map(|(_, e)| e.outcome == FrameOutcome::Acknowledged)
        .collect();
    d.set_item("acknowledged", acked.into_pyarray(py))?;
    d.set_item(
        "transmissions",
        ints(&|x| i64::from(x.1.transmissions)).into_pyarray(py),
    )?;
    d.set_item("sent", floats(&|e| e.sent).into_pyarray(py))?;
    d.set_item("t", floats(&|e| e.t).into_pyarray(py))?;
    Ok(d)
}
