//! `shoal.plot`: line plots (PNG and SVG) drawn by shoal's own plotting ([`shoal_output::plot`]:
//! axes that cover every point, a legend that never covers data, an embedded font), so the
//! examples need no plotting package.

use numpy::{AllowTypeChange, PyArrayLike1};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use shoal_output::plot::{Plot, Series};
use std::path::PathBuf;

/// Draws lines to `<stem>.png` and `<stem>.svg` and returns both paths.
///
/// `series` is a list of `(label, x, y)` or `(label, x, y, dashed)` tuples: a legend label
/// (str or None), the x and y values (equal-length 1-D array-likes; a NaN breaks a line)
/// and whether the line is dashed (for references). `title`, `x_label` and `y_label` label
/// the plot (put units in the axis labels).
#[pyfunction]
#[pyo3(signature = (stem, series, title="", x_label="", y_label=""))]
pub fn plot(
    py: Python<'_>,
    stem: PathBuf,
    series: Vec<Bound<'_, PyAny>>,
    title: &str,
    x_label: &str,
    y_label: &str,
) -> PyResult<Vec<PathBuf>> {
    let mut lines = Vec::with_capacity(series.len());
    for (i, s) in series.iter().enumerate() {
        let bad = |m: &str| PyValueError::new_err(format!("series[{i}]: {m}"));
        let n = s
            .len()
            .map_err(|_| bad("expected a tuple (label, x, y[, dashed])"))?;
        if !(3..=4).contains(&n) {
            return Err(bad("expected a tuple (label, x, y[, dashed])"));
        }
        let label: Option<String> = s.get_item(0)?.extract()?;
        let x: PyArrayLike1<'_, f64, AllowTypeChange> = s
            .get_item(1)?
            .extract()
            .map_err(|_| bad("x must be a 1-D array of numbers"))?;
        let y: PyArrayLike1<'_, f64, AllowTypeChange> = s
            .get_item(2)?
            .extract()
            .map_err(|_| bad("y must be a 1-D array of numbers"))?;
        let (x, y) = (x.as_array(), y.as_array());
        if x.len() != y.len() {
            return Err(bad(&format!(
                "{} x values and {} y values",
                x.len(),
                y.len()
            )));
        }
        let dashed = if n == 4 {
            s.get_item(3)?.extract()?
        } else {
            false
        };
        lines.push(Series {
            label,
            points: x.iter().copied().zip(y.iter().copied()).collect(),
            color: i,
            dashed,
            ..Default::default()
        });
    }
    let p = Plot {
        title: title.to_owned(),
        x_label: x_label.to_owned(),
        y_label: y_label.to_owned(),
        series: lines,
        size: (900, 560),
        ..Default::default()
    };
    py.detach(|| p.write(&stem))
        .map_err(|e| PyOSError::new_err(e.to_string()))
}
