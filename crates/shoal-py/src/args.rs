//! Python values → the whole-swarm commands of [`shoal_sim::batch`]. A column is a number
//! (the same for every vehicle) or a 1-D array-like with one value per vehicle; a C-contiguous
//! float64 numpy array is read in place (no copy), anything else is converted once. Shapes,
//! types and vehicle ids are checked here; values (NaN, ranges, codes) by
//! [`shoal_sim::batch`], and every problem is a [`crate::errors::CommandError`].

use crate::errors::CommandError;
use numpy::{
    AllowTypeChange, PyArrayDescrMethods, PyArrayLike1, PyArrayLike2, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyBytes, PyString};
use shoal_sim::batch::{Column, MODES, Rows};
use shoal_sim::orders::FrameOrder;

/// A [`crate::errors::CommandError`] about `field` (no vehicle).
pub fn bad(field: &str, message: impl std::fmt::Display) -> PyErr {
    CommandError::new_err(format!("{field}: {message}"))
}

/// The dimensionality of `obj` if it is a numpy array.
fn ndim(obj: &Bound<'_, PyAny>) -> Option<usize> {
    obj.cast::<PyUntypedArray>().ok().map(|a| a.ndim())
}

/// Whether `obj` is a numpy array of floating-point or complex values.
fn is_float_array(obj: &Bound<'_, PyAny>) -> bool {
    obj.cast::<PyUntypedArray>()
        .is_ok_and(|a| matches!(a.dtype().kind(), b'f' | b'c'))
}

/// A float column: one number for all rows, or one per row.
pub enum FloatCol<'py> {
    /// The same value for every row.
    Scalar(f64),
    /// A numpy array read in place.
    View(PyArrayLike1<'py, f64, AllowTypeChange>),
    /// A copy (the array was not contiguous).
    Owned(Vec<f64>),
}

impl FloatCol<'_> {
    /// The column for [`shoal_sim::batch`].
    pub fn column(&self) -> Column<'_, f64> {
        match self {
            Self::Scalar(x) => Column::All(*x),
            Self::View(a) => Column::Each(a.as_slice().unwrap_or(&[])),
            Self::Owned(v) => Column::Each(v),
        }
    }
}

/// Reads a float column named `field`.
pub fn float_column<'py>(obj: &Bound<'py, PyAny>, field: &str) -> PyResult<FloatCol<'py>> {
    if ndim(obj).is_none_or(|d| d == 0)
        && let Ok(x) = obj.extract::<f64>()
    {
        return Ok(FloatCol::Scalar(x));
    }
    let a: PyArrayLike1<'py, f64, AllowTypeChange> = obj.extract().map_err(|_| {
        bad(
            field,
            "expected a number or a 1-D array of numbers (one per vehicle)",
        )
    })?;
    if a.as_slice().is_ok() {
        Ok(FloatCol::View(a))
    } else {
        Ok(FloatCol::Owned(a.as_array().to_vec()))
    }
}

/// An integer column: one code for all rows, or one per row.
pub enum IntCol {
    /// The same value for every row.
    Scalar(i64),
    /// One value per row.
    Each(Vec<i64>),
}

impl IntCol {
    /// The column for [`shoal_sim::batch`].
    pub fn column(&self) -> Column<'_, i64> {
        match self {
            Self::Scalar(x) => Column::All(*x),
            Self::Each(v) => Column::Each(v),
        }
    }
}

/// Reads an integer column named `field` (floats are refused, not truncated).
pub fn int_column(obj: &Bound<'_, PyAny>, field: &str) -> PyResult<IntCol> {
    if obj
        .cast::<PyUntypedArray>()
        .is_ok_and(|a| a.dtype().kind() == b'b')
    {
        return Err(bad(
            field,
            "expected integers, got booleans (for a mask of vehicles use np.flatnonzero(mask))",
        ));
    }
    if is_float_array(obj) || obj.extract::<f64>().is_ok() && obj.extract::<i64>().is_err() {
        return Err(bad(field, "expected integers, got floating-point values"));
    }
    if ndim(obj).is_none_or(|d| d == 0)
        && let Ok(x) = obj.extract::<i64>()
    {
        return Ok(IntCol::Scalar(x));
    }
    let a: PyArrayLike1<'_, i64, AllowTypeChange> = obj.extract().map_err(|_| {
        bad(
            field,
            "expected an integer or a 1-D array of integers (one per vehicle)",
        )
    })?;
    Ok(IntCol::Each(a.as_array().to_vec()))
}

/// Reads a mode column: a mode name (`"auto"`), a code (index in `MODES`) or an array of
/// codes.
pub fn mode_column(obj: &Bound<'_, PyAny>) -> PyResult<IntCol> {
    if let Ok(s) = obj.cast::<PyString>() {
        let name = s.to_cow()?;
        return MODES
            .iter()
            .position(|m| m.name() == name)
            .map(|i| IntCol::Scalar(i as i64))
            .ok_or_else(|| {
                bad(
                    "mode",
                    format!(
                        "`{name}` is not a mode: use one of {} (raw actuator commands go \
                         through `thrusters`, `tilts`, `pump`)",
                        MODES.map(|m| m.name()).join(", ")
                    ),
                )
            });
    }
    int_column(obj, "mode")
}

/// A row-major float matrix read from a 2-D array-like (or a 1-D one, the same row for
/// every vehicle).
pub struct FloatRows {
    data: Vec<f64>,
    width: usize,
}

impl FloatRows {
    /// The rows for [`shoal_sim::batch`].
    pub fn rows(&self) -> Rows<'_> {
        Rows {
            data: &self.data,
            width: self.width,
        }
    }
}

/// Reads `rows` × `width` floats named `field`.
pub fn float_rows(
    obj: &Bound<'_, PyAny>,
    field: &str,
    rows: usize,
    width: usize,
) -> PyResult<FloatRows> {
    let shape_err = |got: String| {
        bad(
            field,
            format!(
                "expected an array of shape ({rows}, {width}) (or ({width},) for every \
                 vehicle), got {got}"
            ),
        )
    };
    let one_row = match ndim(obj) {
        Some(d) => d == 1,
        None => obj.extract::<Vec<f64>>().is_ok(),
    };
    if one_row {
        let a: PyArrayLike1<'_, f64, AllowTypeChange> = obj
            .extract()
            .map_err(|_| shape_err("something else".into()))?;
        let row = a.as_array();
        if row.len() != width {
            return Err(shape_err(format!("({},)", row.len())));
        }
        let data = (0..rows).flat_map(|_| row.iter().copied()).collect();
        return Ok(FloatRows { data, width });
    }
    let a: PyArrayLike2<'_, f64, AllowTypeChange> = obj
        .extract()
        .map_err(|_| shape_err("something that is not a 2-D array of numbers".into()))?;
    let shape = a.shape();
    if shape != [rows, width] {
        return Err(shape_err(format!("({}, {})", shape[0], shape[1])));
    }
    let data = match a.as_slice() {
        Ok(s) => s.to_vec(),
        Err(_) => a.as_array().iter().copied().collect(),
    };
    Ok(FloatRows { data, width })
}

/// Vehicle ids: `None` (all vehicles), one id or a 1-D array of ids.
pub fn vehicle_ids(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Vec<usize>>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(None);
    };
    let ids = match int_column(obj, "vehicles")? {
        IntCol::Scalar(x) => vec![x],
        IntCol::Each(v) => v,
    };
    ids.into_iter()
        .map(|x| {
            usize::try_from(x)
                .map_err(|_| bad("vehicles", format!("{x} is not a vehicle id (ids are ≥ 0)")))
        })
        .collect::<PyResult<Vec<_>>>()
        .map(Some)
}

/// The payloads of `count` frames: one bytes-like for all, a sequence of bytes-likes, or a
/// 2-D uint8 array (one row per frame).
pub fn payloads(obj: &Bound<'_, PyAny>, count: usize) -> PyResult<Vec<Vec<u8>>> {
    let one = |o: &Bound<'_, PyAny>| -> Option<Vec<u8>> {
        if let Ok(b) = o.cast::<PyBytes>() {
            Some(b.as_bytes().to_vec())
        } else if let Ok(b) = o.cast::<PyByteArray>() {
            Some(b.to_vec())
        } else {
            None
        }
    };
    if let Some(p) = one(obj) {
        return Ok(vec![p; count]);
    }
    if ndim(obj) == Some(2) {
        let a: PyArrayLike2<'_, u8, AllowTypeChange> = obj
            .extract()
            .map_err(|_| bad("payload", "a 2-D payload array must hold bytes (uint8)"))?;
        let rows: Vec<Vec<u8>> = a.as_array().outer_iter().map(|r| r.to_vec()).collect();
        if rows.len() != count {
            return Err(bad(
                "payload",
                format!("{} rows for {count} frames", rows.len()),
            ));
        }
        return Ok(rows);
    }
    let items: Vec<Bound<'_, PyAny>> = obj
        .try_iter()
        .map_err(|_| {
            bad(
                "payload",
                "expected bytes, a sequence of bytes or a 2-D uint8 array",
            )
        })?
        .collect::<PyResult<_>>()?;
    if items.len() != count {
        return Err(bad(
            "payload",
            format!("{} payloads for {count} frames", items.len()),
        ));
    }
    items
        .iter()
        .enumerate()
        .map(|(i, o)| one(o).ok_or_else(|| bad(&format!("payload[{i}]"), "expected bytes")))
        .collect()
}

/// The arguments of `World.send`, as Python gave them (see [`frames`]).
pub struct SendArgs<'a, 'py> {
    /// One id or k ids.
    pub vehicles: &'a Bound<'py, PyAny>,
    /// Bytes for all, k bytes objects, or a (k, length) uint8 array.
    pub payload: &'a Bound<'py, PyAny>,
    /// `None` or −1 (every modem in sync), an index, or k of them.
    pub modem: Option<&'a Bound<'py, PyAny>>,
    /// Delay after now \[s\]: a number or k numbers.
    pub delay: &'a Bound<'py, PyAny>,
    /// Destination: `None` or −1 (broadcast), a vehicle id, or k of them.
    pub to: Option<&'a Bound<'py, PyAny>>,
    /// Acknowledgement asked: a bool or k bools.
    pub ack: Option<&'a Bound<'py, PyAny>>,
    /// Tags returned with the outcomes: an integer 0 … 2³² − 1 or k of them.
    pub tag: Option<&'a Bound<'py, PyAny>>,
}

/// A column of booleans read from Python.
enum BoolCol {
    /// The same value for every row.
    Scalar(bool),
    /// One value per row.
    Each(Vec<bool>),
}

impl BoolCol {
    /// The column for [`shoal_sim::batch`].
    fn column(&self) -> Column<'_, bool> {
        match self {
            Self::Scalar(x) => Column::All(*x),
            Self::Each(v) => Column::Each(v),
        }
    }
}

/// Reads a column of booleans named `field`: one bool, or a sequence or array of them.
fn bool_column(obj: &Bound<'_, PyAny>, field: &str) -> PyResult<BoolCol> {
    if let Ok(b) = obj.extract::<bool>() {
        return Ok(BoolCol::Scalar(b));
    }
    obj.extract().map(BoolCol::Each).map_err(|_| {
        bad(
            field,
            "expected a bool or a 1-D array of bools (one per frame)",
        )
    })
}

/// Whether column `c` has a length other than `k` rows.
fn wrong_len<T>(c: &Column<'_, T>, k: usize) -> bool {
    matches!(c, Column::Each(v) if v.len() != k)
}

/// An optional integer column named `field`, `default` when absent.
fn int_or(obj: Option<&Bound<'_, PyAny>>, field: &str, default: i64) -> PyResult<IntCol> {
    match obj.filter(|o| !o.is_none()) {
        None => Ok(IntCol::Scalar(default)),
        Some(o) => int_column(o, field),
    }
}

/// The frames of `World.send` (see [`SendArgs`]): every column one value for all frames or
/// one per frame.
pub fn frames(a: &SendArgs<'_, '_>) -> PyResult<Vec<(usize, FrameOrder)>> {
    let ids = vehicle_ids(Some(a.vehicles))?.unwrap_or_default();
    let k = ids.len();
    let payloads = payloads(a.payload, k)?;
    let modems = int_or(a.modem, "modem", -1)?;
    let delays = float_column(a.delay, "delay")?;
    let tos = int_or(a.to, "to", -1)?;
    let tags = int_or(a.tag, "tag", 0)?;
    let acks = match a.ack.filter(|o| !o.is_none()) {
        None => BoolCol::Scalar(false),
        Some(o) => bool_column(o, "ack")?,
    };
    let (mc, dc, toc, tagc) = (
        modems.column(),
        delays.column(),
        tos.column(),
        tags.column(),
    );
    let ackc = acks.column();
    for (name, n) in [
        ("modem", wrong_len(&mc, k)),
        ("delay", wrong_len(&dc, k)),
        ("to", wrong_len(&toc, k)),
        ("ack", wrong_len(&ackc, k)),
        ("tag", wrong_len(&tagc, k)),
    ] {
        if n {
            return Err(bad(name, format!("needs one value per frame ({k})")));
        }
    }
    let index = |field: &str, x: i64, what: &str| {
        usize::try_from(x).map_err(|_| bad(field, format!("{x}: {what}")))
    };
    ids.into_iter()
        .zip(payloads)
        .enumerate()
        .map(|(i, (id, payload))| {
            let modem = match mc.get(i) {
                -1 => None,
                m => Some(index(
                    "modem",
                    m,
                    "a modem index ≥ 0, or −1 for every modem",
                )?),
            };
            let to = match toc.get(i) {
                -1 => None,
                v => Some(u32::try_from(v).map_err(|_| {
                    bad(
                        "to",
                        format!("{v}: a vehicle id ≥ 0, or −1 for a broadcast"),
                    )
                })?),
            };
            let tag = u32::try_from(tagc.get(i))
                .map_err(|_| bad("tag", format!("{}: allowed 0 … {}", tagc.get(i), u32::MAX)))?;
            Ok((
                id,
                FrameOrder {
                    to,
                    ack: ackc.get(i),
                    tag,
                    ..FrameOrder::broadcast(modem, payload, dc.get(i))
                },
            ))
        })
        .collect()
}

/// Warns once per world (`warned`) when the frames of several vehicles all start at the same
/// instant: their half-duplex modems are deaf while they transmit, so they cannot hear each
/// other.
pub fn warn_if_simultaneous(
    py: Python<'_>,
    frames: &[(usize, FrameOrder)],
    warned: &mut bool,
) -> PyResult<()> {
    let first = frames.first().map(|f| (f.0, f.1.delay));
    if !*warned
        && let Some((v0, d0)) = first
        && frames.iter().any(|f| f.0 != v0)
        && frames.iter().all(|f| f.1.delay == d0)
    {
        *warned = true;
        let msg = c"World.send: several vehicles' frames start at the same instant (equal \
             `delay`); their half-duplex modems are deaf while they transmit, so they cannot \
             hear each other — spread the delays (this warning is shown once per world)";
        PyErr::warn(
            py,
            &py.get_type::<pyo3::exceptions::PyUserWarning>(),
            msg,
            1,
        )?;
    }
    Ok(())
}
