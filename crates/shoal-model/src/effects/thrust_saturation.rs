//! `thrust_saturation`: thrust capped below the curve's maximum.
//!
//! A current limit in the ESC, a weak battery or a power supply that sags under load caps
//! the thrust below what the curve promises at high commands; small commands are unaffected.
//! Shows as residuals only in the hardest manoeuvres.
//!
//! Modelled as `|f| ≤ fraction · f_max` with f_max the curve's thrust at full command in the
//! same direction. Applied after every other thrust effect.

//!
//! A `smooth` form competes with the hard clamp: `f' = F·tanh(f/F)`, F = f_max/c.
use super::{Effect, ParamInfo, Stage, ThrustContext};
use crate::vehicle::VehicleParams;

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrustSaturation;

impl Effect for ThrustSaturation {
    fn form(&self) -> &'static str {
        "hard"
    }
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
            shape: false,
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

/// The `smooth` form: thrust bends over smoothly towards a cap, `f' = F·tanh(f/F)` with
/// F = f_max/c, so that small thrusts are unaffected and large ones approach F.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrustSaturationSmooth;

impl Effect for ThrustSaturationSmooth {
    fn name(&self) -> &'static str {
        "thrust_saturation"
    }
    fn form(&self) -> &'static str {
        "smooth"
    }
    fn summary(&self) -> &'static str {
        "thrust bends smoothly towards a cap f_max/c"
    }
    fn explanation(&self) -> &'static str {
        "Current limit acting gradually (a supply that sags under load): thrust grows less \
         and less with the command and approaches f_max/c."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![ParamInfo {
            name: "c",
            unit: "-",
            lo: 0.0,
            hi: 10.0,
            null: 0.0,
            typical: 1.25,
            doc: "inverse of the cap as a fraction of the curve's maximum (0: no cap)",
            shape: false,
        }]
    }
    fn stage(&self) -> Stage {
        Stage::Limit
    }
    fn thrust(&self, p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        let c = p[0];
        if c <= 0.0 {
            return f;
        }
        let (fwd, rev) = ctx.thruster.curve.limits(ctx.thruster.max_command);
        let cap = if f >= 0.0 { fwd } else { rev } / c;
        if cap <= 0.0 {
            return f;
        }
        cap * (f / cap).tanh()
    }
}
