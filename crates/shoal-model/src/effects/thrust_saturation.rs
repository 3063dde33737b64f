//! `thrust_saturation`: thrust capped below the curve's maximum.
//!
//! A current limit in the ESC, a weak battery or a power supply that sags under load caps
//! the thrust below what the curve promises at high commands; small commands are unaffected.
//! Shows as residuals only in the hardest manoeuvres.
//!
//! Modelled as `|f| ≤ fraction · f_max` with f_max the curve's thrust at full command in the
//! same direction. Applied after every other thrust effect.

//!
//! Two forms compete with the hard clamp: `smooth`, `f' = f/(1 + |f/F|^p)^(1/p)` with
//! F = f_max/c and a fitted sharpness p (p = 1 a knee from the first newton on, p ≈ 2 close
//! to F·tanh(f/F), p → ∞ the hard clamp), and `asymmetric`, a hard clamp at its own fraction
//! of each direction's maximum (an ESC whose current limit binds earlier one way than the
//! other).
use super::effect::{Effect, ParamInfo, Stage, ThrustContext};
use super::family::{Family, FamilyFacts, Regressor};
use crate::vehicle_params::VehicleParams;
use std::sync::Arc;

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
        vec![fraction_param(
            "largest thrust as a fraction of the curve's maximum",
        )]
    }
    fn stage(&self) -> Stage {
        Stage::Limit
    }
    fn thrust(&self, p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        let (fwd, rev) = ctx.thruster.curve.limits(ctx.thruster.max_command);
        f.clamp(-p[0] * rev, p[0] * fwd)
    }
}

/// The `smooth` form: thrust bends over towards a cap, `f' = f/(1 + |f/F|^p)^(1/p)` with
/// F = f_max/c: small thrusts are unaffected and large ones approach F. The sharpness p is
/// fitted (1: the thrust bends over from the first newton on; ≈ 2: close to F·tanh(f/F);
/// large: the hard clamp), so one form covers a limiter of any softness.
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
        "thrust bends towards a cap f_max/c, sharpness fitted"
    }
    fn explanation(&self) -> &'static str {
        "Current limit acting gradually (a supply that sags under load, a limiter that folds \
         back): thrust grows less and less with the command and approaches f_max/c, through a \
         knee whose sharpness is fitted."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![
            ParamInfo {
                name: "c",
                unit: "-",
                lo: 0.0,
                hi: 10.0,
                null: 0.0,
                typical: 1.25,
                doc: "inverse of the cap as a fraction of the curve's maximum (0: no cap)",
                shape: false,
            },
            ParamInfo {
                name: "sharpness",
                unit: "-",
                lo: 1.0,
                hi: 12.0,
                null: 2.0,
                typical: 2.0,
                doc: "exponent p of the knee (1: gradual from zero, large: a hard clamp)",
                shape: true,
            },
        ]
    }
    fn stage(&self) -> Stage {
        Stage::Limit
    }
    fn thrust(&self, p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        let c = p[0];
        if c <= 0.0 {
            return f;
        }
        let cap = ctx.thruster.max_thrust_towards(f) / c;
        if cap <= 0.0 {
            return f;
        }
        let sharp = p[1];
        f / (1.0 + (f / cap).abs().powf(sharp)).powf(1.0 / sharp)
    }
}

/// The cap's parameter: a fraction of the curve's maximum thrust, 0.1 … 1 (1: no cap).
fn fraction_param(doc: &'static str) -> ParamInfo {
    ParamInfo {
        name: "fraction",
        unit: "-",
        lo: 0.1,
        hi: 1.0,
        null: 1.0,
        typical: 0.8,
        doc,
        shape: false,
    }
}

/// The `asymmetric` form: a hard clamp at `fraction · f_max⁺` forward and at
/// `fraction_rev · f_max⁻` in reverse, each a fraction of that direction's maximum.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrustSaturationAsymmetric;

impl Effect for ThrustSaturationAsymmetric {
    fn name(&self) -> &'static str {
        "thrust_saturation"
    }
    fn form(&self) -> &'static str {
        "asymmetric"
    }
    fn summary(&self) -> &'static str {
        "thrust capped at its own fraction of the maximum in each direction"
    }
    fn explanation(&self) -> &'static str {
        "Current limit that binds earlier in one direction (ESC limits, a propeller less \
         efficient in reverse): forward thrust cannot exceed one fraction of the forward \
         maximum, reverse thrust another of the reverse maximum."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![
            fraction_param("largest forward thrust as a fraction of the forward maximum"),
            ParamInfo {
                name: "fraction_rev",
                ..fraction_param("largest reverse thrust as a fraction of the reverse maximum")
            },
        ]
    }
    fn stage(&self) -> Stage {
        Stage::Limit
    }
    fn thrust(&self, p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        let (fwd, rev) = ctx.thruster.curve.limits(ctx.thruster.max_command);
        f.clamp(-p[1] * rev, p[0] * fwd)
    }
}

/// The family: its forms, default first, and its facts.
pub(super) fn family() -> Family {
    Family {
        forms: vec![
            Arc::new(ThrustSaturation),
            Arc::new(ThrustSaturationSmooth),
            Arc::new(ThrustSaturationAsymmetric),
        ],
        facts: FamilyFacts {
            excitation: "full-scale commands next to half-scale ones",
            direct: None,
            regressor: Regressor::Command,
            thrust_map: true,
            separations: &[],
        },
    }
}
