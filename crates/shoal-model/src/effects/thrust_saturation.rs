//! `thrust_saturation`: thrust capped below the curve's maximum.
//!
//! A current limit in the ESC, a weak battery or a power supply that sags under load caps
//! the thrust below what the curve promises at high commands; small commands are unaffected.
//! Shows as residuals only in the hardest manoeuvres.
//!
//! Modelled as `|f| ≤ fraction · f_max` with f_max the curve's thrust at full command in the
//! same direction. Applied after every other thrust effect.

use super::{Effect, ParamInfo, Stage, ThrustContext};
use crate::vehicle::VehicleParams;

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrustSaturation;

impl Effect for ThrustSaturation {
    fn name(&self) -> &'static str {
        "thrust_saturation"
    }
    fn summary(&self) -> &'static str {
        "thrust capped below nominal"
    }
    fn explanation(&self) -> &'static str {
        "Current limit or weak battery: thrust cannot exceed a fraction of the curve's \
         maximum in either direction; small commands are unaffected."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![ParamInfo {
            name: "fraction",
            unit: "-",
            lo: 0.1,
            hi: 1.0,
            null: 1.0,
            typical: 0.8,
            doc: "largest thrust as a fraction of the curve's maximum",
        }]
    }
    fn stage(&self) -> Stage {
        Stage::Limit
    }
    fn thrust(&self, p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        let (fwd, rev) = ctx.thruster.curve.limits(ctx.thruster.max_command);
        f.clamp(-p[0] * rev, p[0] * fwd)
    }
}
