//! `thrust_asymmetry`: reverse thrust scaled by k_rev relative to the baseline curve.
//!
//! A propeller shaped for forward thrust is less efficient backwards (Blue Robotics' T200:
//! reverse ≈ 75–80 % of forward); a baseline curve fitted to forward runs, or assumed
//! symmetric, then over- or under-predicts every reverse manoeuvre. Shows as residuals that
//! change sign with the command.
//!
//! Modelled as `f = k_rev · f_static` for negative thrust; forward thrust is unchanged.

use super::{Effect, ParamInfo, ThrustContext};
use crate::vehicle::VehicleParams;

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrustAsymmetry;

impl Effect for ThrustAsymmetry {
    fn name(&self) -> &'static str {
        "thrust_asymmetry"
    }
    fn summary(&self) -> &'static str {
        "reverse thrust scaled by k_rev relative to the baseline"
    }
    fn explanation(&self) -> &'static str {
        "The propeller is shaped for forward thrust and works differently in reverse: \
         negative thrust is scaled by k_rev, forward thrust is unchanged."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![ParamInfo {
            name: "k_rev",
            unit: "-",
            lo: 0.2,
            hi: 2.0,
            null: 1.0,
            typical: 0.8,
            doc: "scale factor on reverse thrust",
            shape: false,
        }]
    }
    fn thrust(&self, p: &[f64], _ctx: &ThrustContext<'_>, f: f64) -> f64 {
        if f < 0.0 { p[0] * f } else { f }
    }
}
