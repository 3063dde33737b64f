//! `ballast_mass` truth forms — the pump moves water at another rate than the baseline's, but
//! not at one constant flow q as the fitting side assumes:
//!
//! * `ballast_mass/flow_falls_with_depth` — the pump works against the water pressure: its
//!   flow falls linearly with the tank's depth, q(z) = q₀·max(1 − z/z_stall, 0).
//! * `ballast_mass/startup_ramp` — the pump takes time to prime and spin up: after each start
//!   (or reversal) its flow rises as q₀·(1 − e^(−(t − t_on)/τ)).
//!
//! Both integrate the tank volume themselves (the mass and weight follow it as in the
//! baseline's variable-mass model) and hand the actuators a stopped pump.

use super::exp_kind::ExpKind;
use super::form_param::FormParam;
use super::truth_form::{Part, TruthForm};
use crate::synth::TruthHook;
use shoal_model::ballast::Pump;
use shoal_model::control::ActuatorCommands;
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::{VehicleModel, VehicleState};

pub(super) fn forms() -> Vec<TruthForm> {
    vec![
        TruthForm {
            name: "ballast_mass/flow_falls_with_depth",
            family: "ballast_mass",
            law: "pump flow q₀·max(1 − z/z_stall, 0) at tank depth z",
            params: vec![
                FormParam::magnitude("q0_ml_s", "ml/s", 0.2, 0.35, "flow at the surface"),
                FormParam::shape("z_stall_m", "m", 2.5, 5.0, "depth at which the pump stalls"),
            ],
            excites: &[ExpKind::Heave],
            build: |p| {
                Part::Hook(Box::new(TankPump {
                    law: FlowLaw::Depth {
                        q0: p[0] * 1e-6,
                        z_stall: p[1],
                    },
                    on_since: None,
                }))
            },
        },
        TruthForm {
            name: "ballast_mass/startup_ramp",
            family: "ballast_mass",
            law: "pump flow q₀·(1 − e^(−(t − t_on)/τ)) after each start",
            params: vec![
                FormParam::magnitude("q0_ml_s", "ml/s", 0.1, 0.25, "flow once up to speed"),
                FormParam::shape("tau_s", "s", 1.0, 3.0, "spin-up time constant"),
            ],
            excites: &[ExpKind::Heave],
            build: |p| {
                Part::Hook(Box::new(TankPump {
                    law: FlowLaw::Startup {
                        q0: p[0] * 1e-6,
                        tau: p[1],
                    },
                    on_since: None,
                }))
            },
        },
    ]
}

/// How the pump's flow varies.
enum FlowLaw {
    /// q₀ [m³/s] at the surface, zero at `z_stall` \[m\].
    Depth { q0: f64, z_stall: f64 },
    /// q₀ [m³/s] approached with time constant `tau` \[s\] after each start.
    Startup { q0: f64, tau: f64 },
}

/// See the module documentation.
struct TankPump {
    /// The flow law.
    law: FlowLaw,
    /// Direction (±1) and start time \[s\] of the current pumping phase.
    on_since: Option<(f64, f64)>,
}

impl TruthHook for TankPump {
    fn before_actuate(
        &mut self,
        model: &VehicleModel,
        state: &mut VehicleState,
        cmd: &mut ActuatorCommands,
        env: &mut Environment,
        dt: f64,
    ) {
        let Some(b) = &model.params.ballast else {
            return;
        };
        let sign = cmd.pump.sign();
        cmd.pump = Pump::Off;
        if sign == 0.0 {
            self.on_since = None;
            return;
        }
        let t = state.time;
        let since = match self.on_since {
            Some((s, t0)) if s == sign => t - t0,
            _ => {
                self.on_since = Some((sign, t));
                0.0
            }
        };
        let q = match self.law {
            FlowLaw::Depth { q0, z_stall } => {
                q0 * (1.0 - state.depth_of(&b.position) / z_stall).max(0.0)
            }
            // The mean flow over the step, so that the volume does not depend on the step.
            FlowLaw::Startup { q0, tau } => {
                let ramp = |s: f64| s + tau * (-s / tau).exp();
                q0 * (ramp(since + dt) - ramp(since)) / dt
            }
        };
        let v = (state.ballast_volume + sign * q * dt).clamp(0.0, b.capacity);
        if v != state.ballast_volume {
            state.ballast_volume = v;
            state.set_mass(model.params.mass_properties(v, env.density));
        }
    }
}
