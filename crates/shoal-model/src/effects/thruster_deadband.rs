//! `thruster_deadband`: no thrust for |command| < d₀.
//!
//! An ESC needs a minimum duty cycle before the motor overcomes its static friction and
//! cogging; Blue Robotics' T200 bench data show a dead band of ±30–40 µs around 1500 µs.
//! Small commands — the ones a controller near its setpoint gives all the time — then do
//! nothing.
//!
//! Modelled by remapping the command before the thrust curve so that the curve's range is
//! kept: `n' = sign(n) · n_max · max(|n| − d₀, 0) / (n_max − d₀)`. Full command still gives
//! full thrust, the map is continuous in n and in d₀, and d₀ = 0 is the baseline.

//!
//! A `soft` form competes with the hard cut: `n' = n − d₀·tanh(n/d₀)`, a dead band whose
//! edge is a smooth knee and whose curve outside is shifted rather than stretched.
//! A `gate` form: `n' = n·x^p/(x^p + 1)`, x = |n|/d₀, no thrust well inside the band and the
//! unchanged curve well outside it, with a fitted sharpness p.
//! An `asymmetric` form: the hard cut with its own width for forward (d₀) and reverse (d_rev)
//! commands — an ESC whose neutral point is off centre.
//! A `soft_asymmetric` form: the soft knee with its own width for each direction.

use super::effect::{Effect, ParamInfo};
use super::family::{Family, FamilyFacts, Regressor};
use crate::thruster::ThrusterParams;
use crate::vehicle_params::VehicleParams;
use std::sync::Arc;

/// The band's width d₀ \[%\], shared by every form (`doc` says what it means in that form).
fn d0_param(doc: &'static str) -> ParamInfo {
    ParamInfo {
        name: "d0_pct",
        unit: "%",
        lo: 0.0,
        hi: 40.0,
        null: 0.0,
        typical: 8.0,
        doc,
        shape: false,
    }
}

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrusterDeadband;

impl Effect for ThrusterDeadband {
    fn form(&self) -> &'static str {
        "hard"
    }
    fn name(&self) -> &'static str {
        "thruster_deadband"
    }
    fn summary(&self) -> &'static str {
        "no thrust for |command| < d₀"
    }
    fn explanation(&self) -> &'static str {
        "ESC and motor static friction: commands below d₀ produce no thrust; above it the \
         thrust curve is stretched over the remaining command range."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![d0_param("dead band half-width in command percent")]
    }
    fn command(&self, p: &[f64], thruster: &ThrusterParams, n: f64) -> f64 {
        let d0 = p[0];
        let max = thruster.max_command;
        if d0 <= 0.0 || max <= d0 {
            return n;
        }
        n.signum() * max * (n.abs() - d0).max(0.0) / (max - d0)
    }
}

/// The `soft` form: the command is shifted towards zero by d₀ with a smooth knee,
/// `n' = n − d₀·tanh(n/d₀)`: almost no thrust well inside the band (n'≈ n³/3d₀²), the full
/// curve shifted by d₀ outside it — a motor whose friction fades in rather than cutting off.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrusterDeadbandSoft;

impl Effect for ThrusterDeadbandSoft {
    fn name(&self) -> &'static str {
        "thruster_deadband"
    }
    fn form(&self) -> &'static str {
        "soft"
    }
    fn summary(&self) -> &'static str {
        "little thrust for |command| < d₀, with a smooth knee"
    }
    fn explanation(&self) -> &'static str {
        "ESC and motor static friction that fades in: small commands give almost no thrust, \
         larger ones the thrust of a command d₀ smaller."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![d0_param("width of the soft dead band in command percent")]
    }
    fn command(&self, p: &[f64], _thruster: &ThrusterParams, n: f64) -> f64 {
        let d0 = p[0];
        if d0 <= 0.0 {
            return n;
        }
        n - d0 * (n / d0).tanh()
    }
}

/// The `soft_asymmetric` form: the `soft` band with its own width for forward (d₀) and reverse
/// (d_rev) commands — friction that fades in, and more of it one way (a propeller less
/// efficient and a motor with more cogging in reverse).
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrusterDeadbandSoftAsymmetric;

impl Effect for ThrusterDeadbandSoftAsymmetric {
    fn name(&self) -> &'static str {
        "thruster_deadband"
    }
    fn form(&self) -> &'static str {
        "soft_asymmetric"
    }
    fn summary(&self) -> &'static str {
        "little thrust for commands in (−d_rev, d₀), with a smooth knee on each side"
    }
    fn explanation(&self) -> &'static str {
        "Static friction that fades in, stronger one way: small commands give almost no \
         thrust, larger ones the thrust of a command d₀ (forward) or d_rev (reverse) smaller."
    }
    fn params(&self, vehicle: &VehicleParams) -> Vec<ParamInfo> {
        ThrusterDeadbandAsymmetric.params(vehicle)
    }
    fn command(&self, p: &[f64], thruster: &ThrusterParams, n: f64) -> f64 {
        let d = if n >= 0.0 { p[0] } else { p[1] };
        ThrusterDeadbandSoft.command(&[d], thruster, n)
    }
}

/// The `gate` form: commands well below d₀ give no thrust, commands well above it the full
/// curve, unchanged, with a gate of sharpness p between, `n' = n·x^p/(x^p + 1)`, x = |n|/d₀ —
/// static friction that stops the motor at small commands but does not change the thrust once
/// it turns. p → ∞ is a hard cut without stretching; p ≈ 2–4 a soft onset.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrusterDeadbandGate;

impl Effect for ThrusterDeadbandGate {
    fn name(&self) -> &'static str {
        "thruster_deadband"
    }
    fn form(&self) -> &'static str {
        "gate"
    }
    fn summary(&self) -> &'static str {
        "no thrust for |command| below d₀, the unchanged curve above it"
    }
    fn explanation(&self) -> &'static str {
        "ESC and motor static friction: small commands do not turn the motor, larger ones \
         give the thrust the curve promises; a gate of width d₀ and sharpness p between."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![
            d0_param("command at which half the command gets through"),
            ParamInfo {
                name: "sharpness",
                unit: "-",
                lo: 2.0,
                hi: 40.0,
                null: 8.0,
                typical: 8.0,
                doc: "exponent p of the gate (large: a hard cut)",
                shape: true,
            },
        ]
    }
    fn command(&self, p: &[f64], _thruster: &ThrusterParams, n: f64) -> f64 {
        let d0 = p[0];
        if d0 <= 0.0 {
            return n;
        }
        let xp = (n.abs() / d0).powf(p[1].clamp(1.0, 64.0));
        if !xp.is_finite() {
            return n;
        }
        n * xp / (xp + 1.0)
    }
}

/// The `asymmetric` form: the hard cut of [`ThrusterDeadband`] with width d₀ for forward and
/// d_rev for reverse commands.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrusterDeadbandAsymmetric;

impl Effect for ThrusterDeadbandAsymmetric {
    fn name(&self) -> &'static str {
        "thruster_deadband"
    }
    fn form(&self) -> &'static str {
        "asymmetric"
    }
    fn summary(&self) -> &'static str {
        "no thrust for commands in (−d_rev, d₀): a dead band off centre"
    }
    fn explanation(&self) -> &'static str {
        "ESC and motor static friction with the ESC's neutral point off centre: forward \
         commands below d₀ and reverse commands below d_rev produce no thrust."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![
            d0_param("dead band width for forward commands"),
            ParamInfo {
                name: "d_rev_pct",
                ..d0_param("dead band width for reverse commands")
            },
        ]
    }
    fn command(&self, p: &[f64], thruster: &ThrusterParams, n: f64) -> f64 {
        let d = if n >= 0.0 { p[0] } else { p[1] };
        ThrusterDeadband.command(&[d], thruster, n)
    }
}

/// The family: its forms, default first, and its facts.
pub(super) fn family() -> Family {
    Family {
        forms: vec![
            Arc::new(ThrusterDeadband),
            Arc::new(ThrusterDeadbandSoft),
            Arc::new(ThrusterDeadbandGate),
            Arc::new(ThrusterDeadbandAsymmetric),
            Arc::new(ThrusterDeadbandSoftAsymmetric),
        ],
        facts: FamilyFacts {
            excitation: "slow ramps through zero and small commands (±5–15 %)",
            direct: None,
            regressor: Regressor::Command,
            thrust_map: true,
            separations: &[],
        },
    }
}
