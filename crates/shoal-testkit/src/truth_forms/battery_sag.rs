//! `battery_sag` truth forms — thrust fades as the battery discharges, but neither linearly nor
//! exponentially in time as the fitting side assumes:
//!
//! * `battery_sag/quadratic` — k(t) = 1 − c·t²: a pack that holds its voltage at first and
//!   sags ever faster (the knee of a discharge curve). The catalogue's `power` form has this
//!   law (p = 2): the form is matched.
//! * `battery_sag/charge_used` — the voltage falls with the charge drawn, not with the time:
//!   V/V₀ = 1 − σ·E with E = ∫ Σᵢ |nᵢ/n_max|³ dt over the speeds the motors actually turn
//!   (a propeller's electrical power ∝ speed³). A motor's speed is ∝ voltage × duty, so each
//!   command acts as n·V/V₀ and the thrust as (V/V₀)². It sags during hard manoeuvres and not
//!   while the thrusters idle.
//! * `battery_sag/knee` — k(t) = 1 − a·(σ(x) − σ(x₀))/(1 − σ(x₀)), x = (t − t_k)/w,
//!   x₀ = −t_k/w, σ the logistic function: the pack passes the knee of its discharge curve
//!   mid-run and the ESCs' low-voltage protection limits their output, so the thrust holds,
//!   drops by a within a few w around t_k and stays down (k(0) = 1).

use super::effect_meta::truth_effect_meta;
use super::exp_kind::ExpKind;
use super::form_param::FormParam;
use super::logistic::logistic;
use super::truth_form::{Part, TruthForm};
use crate::synth::TruthHook;
use shoal_model::control::ActuatorCommands;
use shoal_model::effects::{Effect, ThrustContext};
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::{VehicleModel, VehicleState};
use std::sync::Arc;

const QUADRATIC: &str = "battery_sag/quadratic";
const QUADRATIC_LAW: &str = "thrust × max(1 − c·t², 0)";
const KNEE: &str = "battery_sag/knee";
const KNEE_LAW: &str =
    "thrust × (1 − a·(σ(x) − σ(x₀))/(1 − σ(x₀))), x = (t − t_k)/w, x₀ = −t_k/w, σ logistic";

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
        TruthForm {
            name: KNEE,
            family: "battery_sag",
            law: KNEE_LAW,
            params: vec![
                FormParam::magnitude("a", "-", 0.2, 0.35, "fraction of the thrust lost"),
                FormParam::shape("t_k_s", "s", 45.0, 75.0, "time of the knee t_k"),
                FormParam::shape("w_s", "s", 8.0, 15.0, "width of the drop w"),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Effect(Arc::new(Knee {
                    a: p[0],
                    t_k: p[1],
                    w: p[2],
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

/// See the module documentation.
#[derive(Debug)]
struct Knee {
    /// Fraction of the thrust lost \[-\].
    a: f64,
    /// Time of the knee \[s\].
    t_k: f64,
    /// Width of the drop \[s\].
    w: f64,
}

impl Knee {
    /// The thrust factor at time `t` \[s\].
    fn factor(&self, t: f64) -> f64 {
        let s0 = logistic(-self.t_k / self.w);
        let s = logistic((t - self.t_k) / self.w);
        1.0 - self.a * ((s - s0) / (1.0 - s0)).max(0.0)
    }
}

impl Effect for Knee {
    truth_effect_meta!(KNEE, KNEE_LAW);
    fn thrust(&self, _p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        self.factor(ctx.t) * f
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn knee_holds_then_drops_by_a_around_t_k() {
        let form = forms().into_iter().find(|f| f.name == KNEE);
        let form = form.expect("registered");
        assert!(matches!(form.part(&[0.3, 60.0, 10.0]), Part::Effect(_)));
        let knee = Knee {
            a: 0.3,
            t_k: 60.0,
            w: 10.0,
        };
        // σ(−6) = 1/(1 + e⁶) = 0.002473; at t_k σ = 1/2, at t_k + w σ(1) = 0.731059.
        let s0 = 1.0 / (1.0 + 6f64.exp());
        let k = |s: f64| 1.0 - 0.3 * (s - s0) / (1.0 - s0);
        assert_eq!(knee.factor(0.0), 1.0);
        assert!((knee.factor(60.0) - k(0.5)).abs() < 1e-12);
        assert!((knee.factor(60.0) - 0.850372).abs() < 1e-6);
        assert!((knee.factor(70.0) - k(1.0 / (1.0 + (-1f64).exp()))).abs() < 1e-12);
        // Long after the knee the thrust has lost a.
        assert!((knee.factor(400.0) - 0.7).abs() < 1e-9);
        // Monotone: the thrust never recovers.
        let mut last = 1.0;
        for i in 0..=240 {
            let k = knee.factor(0.5 * f64::from(i));
            assert!(k <= last && k >= 0.7, "t = {}: {k}", 0.5 * f64::from(i));
            last = k;
        }
        // a = 0: the baseline.
        let null = Knee {
            a: 0.0,
            t_k: 60.0,
            w: 10.0,
        };
        assert!((0..=120).all(|t| null.factor(f64::from(t)) == 1.0));
    }
}
