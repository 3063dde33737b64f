//! `battery_sag` truth forms — thrust fades as the battery discharges, but neither linearly nor
//! exponentially in time as the fitting side assumes:
//!
//! * `battery_sag/quadratic` — k(t) = 1 − c·t²: a pack that holds its voltage at first and
//!   sags ever faster (the knee of a discharge curve).
//! * `battery_sag/charge_used` — the voltage falls with the charge drawn, not with the time:
//!   V/V₀ = 1 − σ·E with E = ∫ Σᵢ |nᵢ/n_max|³ dt over the speeds the motors actually turn
//!   (a propeller's electrical power ∝ speed³). A motor's speed is ∝ voltage × duty, so each
//!   command acts as n·V/V₀ and the thrust as (V/V₀)². It sags during hard manoeuvres and not
//!   while the thrusters idle.

use super::{ExpKind, FormParam, Part, TruthForm, truth_effect_meta};
use crate::synth::TruthHook;
use shoal_model::control::ActuatorCommands;
use shoal_model::effects::{Effect, ThrustContext};
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::{VehicleModel, VehicleState};
use std::sync::Arc;

const QUADRATIC: &str = "battery_sag/quadratic";
const QUADRATIC_LAW: &str = "thrust × max(1 − c·t², 0)";

pub(super) fn forms() -> Vec<TruthForm> {
    vec![
        TruthForm {
            name: QUADRATIC,
            family: "battery_sag",
            law: QUADRATIC_LAW,
            params: vec![FormParam::magnitude(
                "c_per_s2",
                "1/s²",
                1.2e-5,
                2.5e-5,
                "curvature of the thrust loss (17–36 % lost after 120 s)",
            )],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| Part::Effect(Arc::new(Quadratic { c: p[0] })),
        },
        TruthForm {
            name: "battery_sag/charge_used",
            family: "battery_sag",
            law: "commands × V/V₀ = 1 − σ·∫Σ|n/n_max|³dt (thrust × (V/V₀)²)",
            params: vec![FormParam::magnitude(
                "sigma_per_s",
                "1/s",
                0.003,
                0.006,
                "relative voltage lost per second of one thruster at full command",
            )],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Hook(Box::new(ChargeUsed {
                    sigma: p[0],
                    energy: 0.0,
                }))
            },
        },
    ]
}

/// See the module documentation.
#[derive(Debug)]
struct Quadratic {
    /// Curvature [1/s²].
    c: f64,
}

impl Effect for Quadratic {
    truth_effect_meta!(QUADRATIC, QUADRATIC_LAW);
    fn thrust(&self, _p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        (1.0 - self.c * ctx.t * ctx.t).max(0.0) * f
    }
}

/// Lowest relative voltage: the pack's cut-off \[-\].
const V_MIN: f64 = 0.5;

/// See the module documentation.
struct ChargeUsed {
    /// Relative voltage lost per full-command thruster-second [1/s].
    sigma: f64,
    /// Σᵢ ∫ |nᵢ/n_max|³ dt so far \[s\].
    energy: f64,
}

impl TruthHook for ChargeUsed {
    fn before_actuate(
        &mut self,
        model: &VehicleModel,
        _state: &mut VehicleState,
        cmd: &mut ActuatorCommands,
        _env: &mut Environment,
        dt: f64,
    ) {
        let v = (1.0 - self.sigma * self.energy).max(V_MIN);
        for (c, th) in cmd.thrusters.iter_mut().zip(&model.params.thrusters) {
            let x = (*c / th.max_command).clamp(-1.0, 1.0);
            self.energy += (x.abs() * v).powi(3) * dt;
            *c *= v;
        }
    }
}
