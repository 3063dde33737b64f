//! The logistic function, the S-shaped law several truth forms share.

/// The logistic function 1/(1 + e^(−x)): the S-shaped law of several truth forms (a battery's
/// knee, a thermocline, a throttle map that bends smoothly).
pub(crate) fn logistic(x: f64) -> f64 {
    1.0 / (1.0 + (-x).exp())
}
