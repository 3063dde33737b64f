//! `thrust_gain`: all thrust scaled by a factor k.
//!
//! The thrust curve was measured at one battery voltage and one set-up; a fuller battery, a
//! different propeller or a calibration error scale every thruster's force alike. Shows as
//! measured accelerations and speeds that are uniformly larger (k > 1) or smaller (k < 1)
//! than the replay's — unlike a damping error, also in the first instant after a step, when
//! the hull is still slow.
//!
//! Modelled as `f = k · f_static`.

use super::{Effect, ParamInfo, ThrustContext};
use crate::vehicle::VehicleParams;

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrustGain;

impl Effect for ThrustGain {
    fn name(&self) -> &'static str {
        "thrust_gain"
    }
    fn summary(&self) -> &'static str {
        "all thrust scaled by k"
    }
    fn explanation(&self) -> &'static str {
        "Battery above or below the voltage at which the thrust curve was measured, or a \
         calibration error: every thruster's force is scaled by the same factor."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![ParamInfo {
            name: "k",
            unit: "-",
            lo: 0.1,
            hi: 3.0,
            null: 1.0,
            typical: 1.2,
            doc: "thrust scale factor",
            shape: false,
        }]
    }
    fn thrust(&self, p: &[f64], _ctx: &ThrustContext<'_>, f: f64) -> f64 {
        p[0] * f
    }
}
