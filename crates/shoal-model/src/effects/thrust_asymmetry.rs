//! `thrust_asymmetry`: reverse thrust scaled by k_rev relative to the baseline curve.
//!
//! A propeller shaped for forward thrust is less efficient backwards (Blue Robotics' T200:
//! reverse ≈ 75–80 % of forward); a baseline curve fitted to forward runs, or assumed
//! symmetric, then over- or under-predicts every reverse manoeuvre. Shows as residuals that
//! change sign with the command.
//!
//! Modelled as `f = k_rev · f_static` for negative thrust; forward thrust is unchanged.
//!
//! A `curve` form competes: reverse thrust scaled by `k_rev·(|n|/50 %)^e`, a reverse thrust
//! curve with an exponent of its own; and a `sided` form: the reverse factor differs from side
//! to side, `k_rev·(1 + d·s)` with s = −1 for a thruster on the port side, +1 on the starboard
//! side and 0 on the centre line (propellers of one type mounted with different clearances to
//! the hull, or one of them nicked).

use super::effect::{Effect, ParamInfo, ThrustContext};
use super::family::{Family, FamilyFacts, Regressor};
use super::thrust_gain::command_factor;
use crate::vehicle_params::VehicleParams;
use std::sync::Arc;

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

/// The `curve` form: reverse thrust scaled by `k_rev·(|n|/50 %)^e` — a reverse thrust curve
/// whose exponent differs from the forward one's (a propeller pitched for forward thrust that
/// stalls at small reverse commands, or loses more at large ones); forward thrust unchanged.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrustAsymmetryCurve;

impl Effect for ThrustAsymmetryCurve {
    fn name(&self) -> &'static str {
        "thrust_asymmetry"
    }
    fn form(&self) -> &'static str {
        "curve"
    }
    fn summary(&self) -> &'static str {
        "reverse thrust scaled by k_rev·(|n|/50 %)^e, a reverse curve of its own exponent"
    }
    fn explanation(&self) -> &'static str {
        "The propeller works differently in reverse, and by how much depends on the command: \
         negative thrust is scaled by k_rev at half command and by a factor that grows or \
         shrinks with the command (exponent e); forward thrust is unchanged."
    }
    fn params(&self, vehicle: &VehicleParams) -> Vec<ParamInfo> {
        let mut p = ThrustAsymmetry.params(vehicle);
        p[0].doc = "scale factor on reverse thrust at half command";
        p.push(ParamInfo {
            name: "e",
            unit: "-",
            lo: -1.0,
            hi: 1.0,
            null: 0.0,
            typical: 0.2,
            doc: "exponent of the reverse factor's change with the command",
            // Not a shape: with e ≠ 0 reverse thrust differs from the baseline even at k_rev = 1.
            shape: false,
        });
        p
    }
    fn thrust(&self, p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        if f < 0.0 {
            p[0] * command_factor(ctx.command, p[1]) * f
        } else {
            f
        }
    }
}

/// Lateral offset from the centre line \[m\] within which a thruster counts as central.
const CENTRE_LINE_M: f64 = 0.01;

/// The side of a thruster at body-frame position `y` \[m\]: −1 port, +1 starboard, 0 on the
/// centre line (body frame: y to starboard).
fn side(y: f64) -> f64 {
    if y.abs() <= CENTRE_LINE_M {
        0.0
    } else {
        y.signum()
    }
}

/// The `sided` form: reverse thrust scaled by `k_rev·(1 + d·s)`, s the thruster's side
/// (−1 port, +1 starboard, 0 on the centre line); forward thrust unchanged.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrustAsymmetrySided;

impl Effect for ThrustAsymmetrySided {
    fn name(&self) -> &'static str {
        "thrust_asymmetry"
    }
    fn form(&self) -> &'static str {
        "sided"
    }
    fn summary(&self) -> &'static str {
        "reverse thrust scaled by k_rev·(1 + d·s), s = −1 port, +1 starboard, 0 centre line"
    }
    fn explanation(&self) -> &'static str {
        "The propellers work differently in reverse, and not all alike (mounted with different \
         clearances to the hull, one of them nicked): negative thrust is scaled by k_rev on the \
         centre line, by k_rev·(1 − d) on the port side and k_rev·(1 + d) on the starboard \
         side; forward thrust is unchanged."
    }
    fn params(&self, vehicle: &VehicleParams) -> Vec<ParamInfo> {
        let mut p = ThrustAsymmetry.params(vehicle);
        p[0].doc = "scale factor on reverse thrust, mean of the two sides";
        p.push(ParamInfo {
            name: "d",
            unit: "-",
            lo: -0.5,
            hi: 0.5,
            null: 0.0,
            typical: 0.1,
            doc: "relative difference of the reverse factor, starboard minus port over two",
            // Not a shape: with d ≠ 0 reverse thrust differs from the baseline even at k_rev = 1.
            shape: false,
        });
        p
    }
    fn thrust(&self, p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        if f < 0.0 {
            p[0] * (1.0 + p[1] * side(ctx.thruster.position.y)) * f
        } else {
            f
        }
    }
}

/// The family: its forms, default first, and its facts.
pub(super) fn family() -> Family {
    Family {
        forms: vec![
            Arc::new(ThrustAsymmetry),
            Arc::new(ThrustAsymmetryCurve),
            Arc::new(ThrustAsymmetrySided),
        ],
        facts: FamilyFacts {
            excitation: "equal forward and reverse commands",
            direct: None,
            regressor: Regressor::Command,
            thrust_map: true,
            separations: &[],
        },
    }
}
