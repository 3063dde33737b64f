//! `water_current` truth forms — the water moves, but not at one constant velocity as the
//! fitting side assumes:
//!
//! * `water_current/oscillating` — a circulation that pulses: the current keeps its direction
//!   θ while its speed swings, v(t) = m₀ + m₁·sin(2πt/P + φ).
//! * `water_current/rotating` — a slowly veering flow (an eddy drifting past): the current keeps
//!   its speed m while its direction turns at a steady rate Ω, θ(t) = θ₀ + Ω·t, by about a
//!   radian over a two-minute run.
//!
//! Both are horizontal currents in the world frame, changed every simulation step (slowly
//! enough that the hull's inertia against the changing flow is negligible).

use super::exp_kind::ExpKind;
use super::form_param::FormParam;
use super::truth_form::{Part, TruthForm};
use crate::synth::TruthHook;
use shoal_model::control::ActuatorCommands;
use shoal_model::math::Vec3;
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::{VehicleModel, VehicleState};
use std::f64::consts::TAU;

pub(super) fn forms() -> Vec<TruthForm> {
    vec![
        TruthForm {
            name: "water_current/oscillating",
            family: "water_current",
            law: "speed m₀ + m₁·sin(2πt/P + φ) along a fixed direction θ",
            params: vec![
                FormParam::magnitude("m0_m_s", "m/s", 0.02, 0.05, "mean speed"),
                FormParam::magnitude("m1_m_s", "m/s", 0.02, 0.04, "amplitude of the swing"),
                FormParam::shape("period_s", "s", 40.0, 90.0, "period of the swing"),
                FormParam::shape("theta_rad", "rad", 0.0, TAU, "direction (from world x)"),
                FormParam::shape("phi_rad", "rad", 0.0, TAU, "phase of the swing at t = 0"),
            ],
            excites: &[ExpKind::Yaw],
            build: |p| {
                Part::Hook(Box::new(Current::Oscillating {
                    m0: p[0],
                    m1: p[1],
                    period: p[2],
                    theta: p[3],
                    phi: p[4],
                }))
            },
        },
        TruthForm {
            name: "water_current/rotating",
            family: "water_current",
            law: "speed m along a direction θ₀ + Ω·t",
            params: vec![
                FormParam::magnitude("m_m_s", "m/s", 0.02, 0.05, "speed"),
                FormParam::signed(
                    "omega_rad_s",
                    "rad/s",
                    0.004,
                    0.01,
                    "turn rate of the direction (0.5–1.2 rad over 120 s)",
                ),
                FormParam::shape("theta0_rad", "rad", 0.0, TAU, "direction at t = 0"),
            ],
            excites: &[ExpKind::Yaw],
            build: |p| {
                Part::Hook(Box::new(Current::Rotating {
                    m: p[0],
                    omega: p[1],
                    theta0: p[2],
                }))
            },
        },
    ]
}

/// See the module documentation (speeds [m/s], angles \[rad\], rates \[rad/s\], times \[s\]).
enum Current {
    Oscillating {
        m0: f64,
        m1: f64,
        period: f64,
        theta: f64,
        phi: f64,
    },
    Rotating {
        m: f64,
        omega: f64,
        theta0: f64,
    },
}

impl Current {
    /// The current at time `t` \[s\], world frame [m/s].
    fn at(&self, t: f64) -> Vec3 {
        let (speed, dir) = match *self {
            Current::Oscillating {
                m0,
                m1,
                period,
                theta,
                phi,
            } => (m0 + m1 * (TAU * t / period + phi).sin(), theta),
            Current::Rotating { m, omega, theta0 } => (m, theta0 + omega * t),
        };
        Vec3::new(speed * dir.cos(), speed * dir.sin(), 0.0)
    }
}

impl TruthHook for Current {
    fn before_actuate(
        &mut self,
        _model: &VehicleModel,
        state: &mut VehicleState,
        _cmd: &mut ActuatorCommands,
        env: &mut Environment,
        dt: f64,
    ) {
        env.current += self.at(state.time + 0.5 * dt);
    }
}
