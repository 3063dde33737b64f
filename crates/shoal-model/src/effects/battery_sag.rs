//! `battery_sag`: the thrust scale falls during the run, k(t) = 1 − s·t.
//!
//! A discharging battery's voltage drops, and with it the motor speed and the thrust at a
//! given command (T200 maximum thrust grows roughly as V^1.2). Over a long run the same
//! command pushes less and less: residuals that grow with time.
//!
//! Modelled as `f = max(1 − s·t, 0) · f_static`, t from the start of the run.

use super::{Effect, ParamInfo, ThrustContext};
use crate::vehicle::VehicleParams;

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct BatterySag;

impl Effect for BatterySag {
    fn name(&self) -> &'static str {
        "battery_sag"
    }
    fn summary(&self) -> &'static str {
        "thrust scale falls during the run, k(t) = 1 − s·t"
    }
    fn explanation(&self) -> &'static str {
        "Battery discharge: the voltage, and with it the thrust at a given command, falls \
         steadily over the run."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![ParamInfo {
            name: "s_per_s",
            unit: "1/s",
            lo: 0.0,
            hi: 0.01,
            null: 0.0,
            typical: 0.001,
            doc: "relative thrust lost per second",
        }]
    }
    fn thrust(&self, p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        (1.0 - p[0] * ctx.t).max(0.0) * f
    }
}
