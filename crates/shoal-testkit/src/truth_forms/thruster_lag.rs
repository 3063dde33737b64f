//! `thruster_lag` truth forms — the thrust trails the command, but not through the fitting
//! side's first-order, critically damped second-order or up/down lags:
//!
//! * `thruster_lag/underdamped_one_motor` — one motor (port) has a stiff but poorly damped
//!   speed controller: its speed follows the command as an underdamped second-order system
//!   n̈ = ω²(n_cmd − n) − 2ζω ṅ and overshoots after every step; the other motors follow at once.
//! * `thruster_lag/slew_rate` — every ESC ramps its output toward the command at no more than
//!   R %/s (a current-limited or soft-start ESC): a step becomes a ramp whose length grows with
//!   the step. The catalogue's `slew` form has this law: the form is matched.
//! * `thruster_lag/speed_dependent` — every motor's speed follows the command through a
//!   first-order lag whose time constant falls as the motor speeds up, τ = τ₅₀·50 %/max(|n|,
//!   10 %) (the propeller's load torque grows with the square of its speed, so a spinning
//!   motor settles faster than one starting from rest).
//!
//! All act on the command the thrust curve sees (the motor speed, ∝ command); the log keeps
//! the commanded values.

use super::effect_meta::truth_effect_meta;
use super::exp_kind::ExpKind;
use super::form_param::FormParam;
use super::truth_form::{Part, TruthForm};
use crate::synth::TruthHook;
use shoal_model::control::ActuatorCommands;
use shoal_model::effects::{Effect, ThrusterLagSlew};
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::{VehicleModel, VehicleParams, VehicleState};
use std::sync::Arc;

const SLEW_LAW: &str = "every motor command ramps toward its target at most R %/s";

pub(super) fn forms() -> Vec<TruthForm> {
    vec![
        TruthForm {
            name: "thruster_lag/underdamped_one_motor",
            family: "thruster_lag",
            law: "port motor speed: n̈ = ω²(n_cmd − n) − 2ζω ṅ (underdamped); other motors instant",
            params: vec![
                FormParam::deficit(
                    "omega_rad_s",
                    "rad/s",
                    2.5,
                    5.0,
                    "natural frequency of the port motor's speed response",
                ),
                FormParam::shape("zeta", "-", 0.2, 0.45, "damping ratio (< 1: overshoot)"),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Hook(Box::new(Underdamped {
                    motor: "port",
                    omega: p[0],
                    zeta: p[1],
                    speed: None,
                }))
            },
        },
        TruthForm {
            name: "thruster_lag/slew_rate",
            family: "thruster_lag",
            law: SLEW_LAW,
            params: vec![FormParam::deficit(
                "rate_pct_s",
                "%/s",
                80.0,
                250.0,
                "largest rate of change of the motor command (a 60 % step takes 60/R s)",
            )],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| Part::Effect(Arc::new(SlewRate { rate: p[0] })),
        },
        TruthForm {
            name: "thruster_lag/speed_dependent",
            family: "thruster_lag",
            law: "every motor speed: τ(n)·ṅ = n_cmd − n with τ = τ₅₀·50 %/max(|n|, 10 %)",
            params: vec![FormParam::magnitude(
                "tau50_s",
                "s",
                0.15,
                0.35,
                "time constant of a motor running at 50 % command",
            )],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Hook(Box::new(SpeedDependent {
                    tau50: p[0],
                    speed: Vec::new(),
                }))
            },
        },
    ]
}

/// See the module documentation.
struct SpeedDependent {
    /// Time constant at 50 % command \[s\].
    tau50: f64,
    /// Each motor's speed [%] (starts at zero: the run starts at rest).
    speed: Vec<f64>,
}

impl TruthHook for SpeedDependent {
    fn before_actuate(
        &mut self,
        _model: &VehicleModel,
        _state: &mut VehicleState,
        cmd: &mut ActuatorCommands,
        _env: &mut Environment,
        dt: f64,
    ) {
        self.speed.resize(cmd.thrusters.len(), 0.0);
        for (n, c) in self.speed.iter_mut().zip(cmd.thrusters.iter_mut()) {
            let tau = self.tau50 * 50.0 / n.abs().max(10.0);
            // Exact over the step for the time constant at its start.
            *n = *c + (*n - *c) * (-dt / tau).exp();
            *c = *n;
        }
    }
}

/// See the module documentation.
struct Underdamped {
    /// Name of the motor with the second-order response.
    motor: &'static str,
    /// Natural frequency \[rad/s\].
    omega: f64,
    /// Damping ratio \[-\].
    zeta: f64,
    /// (thruster index, speed [%], speed rate [%/s]) once the motor is found.
    speed: Option<(usize, f64, f64)>,
}

impl TruthHook for Underdamped {
    fn before_actuate(
        &mut self,
        model: &VehicleModel,
        _state: &mut VehicleState,
        cmd: &mut ActuatorCommands,
        _env: &mut Environment,
        dt: f64,
    ) {
        if self.speed.is_none() {
            // The run starts at rest: speed and its rate zero.
            self.speed = model
                .params
                .thrusters
                .iter()
                .position(|t| t.name == self.motor)
                .map(|i| (i, 0.0, 0.0));
        }
        let Some((i, n, dn)) = &mut self.speed else {
            return;
        };
        let target = cmd.thrusters[*i];
        // Semi-implicit Euler: ω·dt ≤ 0.03 at the simulation's 5 ms step.
        *dn += dt * (self.omega * self.omega * (target - *n) - 2.0 * self.zeta * self.omega * *dn);
        *n += dt * *dn;
        cmd.thrusters[*i] = *n;
    }
}

/// See the module documentation.
#[derive(Debug)]
struct SlewRate {
    /// Largest rate of change of a motor command [%/s].
    rate: f64,
}

impl Effect for SlewRate {
    truth_effect_meta!("thruster_lag/slew_rate", SLEW_LAW);
    fn configure(&self, _p: &[f64], vehicle: &mut VehicleParams) {
        // The catalogue's `slew` form has this law (the form is matched): 100 % in 100/R s.
        ThrusterLagSlew.configure(&[100.0 / self.rate], vehicle);
    }
}
