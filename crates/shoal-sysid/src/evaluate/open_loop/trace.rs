//! A replay's record: the model's outputs on a uniform time grid ([`Trace`]), read at sample
//! times by linear interpolation ([`grid_position`]).

use crate::log::run::ChannelKind;
use shoal_model::math::wrap_pi;

/// A replayed run: the model's outputs on a uniform time grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Trace {
    /// Time of the first grid point (the run's first time) \[s\].
    pub t0: f64,
    /// Grid step \[s\].
    pub dt: f64,
    /// The recorded kinds, in column order of `values`.
    pub kinds: Vec<ChannelKind>,
    /// Row-major: grid point × kind (units of [`ChannelKind::unit`]).
    pub values: Vec<f64>,
}

impl Trace {
    /// Number of grid points.
    pub fn len(&self) -> usize {
        self.values.len() / self.kinds.len().max(1)
    }

    /// Whether the trace is empty.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The value of column `col` at time `t` \[s\] (linear interpolation, angles along the
    /// shorter arc; held constant outside the grid).
    pub fn at(&self, col: usize, t: f64) -> f64 {
        self.at_position(col, grid_position(self.t0, self.dt, self.len(), t))
    }

    /// The value of column `col` at a grid position from [`grid_position`] for this trace's
    /// grid (as [`Trace::at`], with the position computed once for many replays).
    #[inline]
    pub fn at_position(&self, col: usize, (k, f): (usize, f64)) -> f64 {
        let n = self.len();
        let stride = self.kinds.len();
        let a = self.values[k * stride + col];
        if k + 1 >= n {
            return a;
        }
        let b = self.values[(k + 1) * stride + col];
        if self.kinds[col].is_angle() {
            wrap_pi(a + wrap_pi(b - a) * f)
        } else {
            a + (b - a) * f
        }
    }
}

/// Where time `t` \[s\] falls on a grid of `n` (≥ 1) points `t0 + i·dt`: the index of the
/// point at or before it (clamped to the grid) and the fraction of the step beyond it.
#[inline]
pub fn grid_position(t0: f64, dt: f64, n: usize, t: f64) -> (usize, f64) {
    let x = ((t - t0) / dt).max(0.0);
    let k = (x.floor() as usize).min(n - 1);
    (k, x - k as f64)
}
