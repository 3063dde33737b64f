//! Laws in time that several effects share: the `power` forms' (t / 100 s)^p and the
//! `settling` forms' 1 − e^(−t/τ), with the parameters that shape them.

use super::effect::ParamInfo;

/// Reference time of the `power` forms' laws, (t / T_REF)^p \[s\].
pub(crate) const POWER_T_REF: f64 = 100.0;

/// The exponent p of a law in (t / 100 s)^p, the shape of a `power` form (1: linear in time).
pub(crate) fn time_exponent_param(doc: &'static str) -> ParamInfo {
    ParamInfo {
        name: "p",
        unit: "-",
        lo: 0.5,
        hi: 4.0,
        null: 2.0,
        typical: 2.0,
        doc,
        shape: true,
    }
}

/// The fraction of a settling change reached at time `t` \[s\] with time constant `tau`
/// \[s\], 1 − e^(−t/τ): the law of every `settling` or `exponential` form (a quantity that
/// moves towards a new value and levels off).
pub(crate) fn settled(t: f64, tau: f64) -> f64 {
    1.0 - (-t.max(0.0) / tau.max(1e-3)).exp()
}

/// The time constant τ of a `settling` law, a shape parameter from `lo` to `hi` seconds.
pub(crate) fn settling_tau_param(lo: f64, hi: f64, doc: &'static str) -> ParamInfo {
    ParamInfo {
        name: "tau_s",
        unit: "s",
        lo,
        hi,
        null: 60.0,
        typical: 60.0,
        doc,
        shape: true,
    }
}
