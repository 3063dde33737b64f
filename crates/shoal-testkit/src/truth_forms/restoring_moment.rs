//! `restoring_moment` truth forms — the centre of gravity is off its nominal place, but not by
//! a constant shift Δr, one that drifts steadily, Δr₀ + ṙ·t, or one that settles,
//! Δr₀ + Δr₁·(1 − e^(−t/τ)), as the fitting side assumes:
//!
//! * `restoring_moment/sliding_mass` — a battery pack or a weight held loosely (by foam, in a
//!   tube) sits off-centre and slides downhill as the hull tilts: Δx(θ) = x₀ − s·sin θ,
//!   Δy(φ) = y₀ + s·sin φ. The hull trims further than a fixed shift would tilt it, and its
//!   righting moment is weaker (as if the metacentric height were s smaller).
//! * `restoring_moment/sloshing_water` — water in a partly flooded compartment off-centre
//!   (x₀, y₀): its free surface follows the hull's tilt with a lag τ, and its centre moves
//!   downhill by s per unit of sin(tilt) once settled (the free-surface effect that lowers a
//!   ship's metacentric height): Δx = x₀ − s·ξ_θ, Δy = y₀ + s·ξ_φ, τ·ξ̇ = sin(tilt) − ξ.
//! * `restoring_moment/flooding_end` — a compartment at one end floods after the dive starts
//!   and fills: the centre of gravity moves by x₁ and levels off,
//!   Δx(t) = x₁·(1 − e^(−t/τ)), beside a constant sideways shift y₀. The catalogue's
//!   `settling` form has this law: the form is matched.
//!
//! All act as the catalogue's moment of the weight about the displaced centre of gravity.

use super::effect_meta::truth_effect_meta;
use super::exp_kind::ExpKind;
use super::form_param::FormParam;
use super::truth_form::{Part, TruthForm};
use crate::synth::TruthHook;
use shoal_model::effects::{Effect, ForceContext, RestoringMoment, RestoringMomentSettling};
use shoal_model::math::Vec6;
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::{VehicleModel, VehicleState};
use std::sync::Arc;

const SLIDING: &str = "restoring_moment/sliding_mass";
const SLIDING_LAW: &str = "Δx(θ) = x₀ − s·sin θ, Δy(φ) = y₀ + s·sin φ";
const SLOSHING: &str = "restoring_moment/sloshing_water";
const FLOODING: &str = "restoring_moment/flooding_end";
const FLOODING_LAW: &str = "Δx(t) = x₁·(1 − e^(−t/τ)), Δy = y₀";

pub(super) fn forms() -> Vec<TruthForm> {
    vec![
        TruthForm {
            name: SLIDING,
            family: "restoring_moment",
            law: SLIDING_LAW,
            params: downhill(
                "how far the loose mass's share of the centre of gravity slides per unit of \
                 sin(tilt) (a fifth to two fifths of the metacentric height)",
            ),
            excites: &[ExpKind::Trim],
            build: |p| {
                Part::Effect(Arc::new(SlidingMass {
                    x0: p[0],
                    y0: p[1],
                    s: p[2],
                }))
            },
        },
        TruthForm {
            name: SLOSHING,
            family: "restoring_moment",
            law: "Δx = x₀ − s·ξ_θ, Δy = y₀ + s·ξ_φ, τ·ξ̇ = sin(tilt) − ξ",
            params: [
                downhill("downhill shift per unit of sin(tilt), once the surface has settled"),
                vec![FormParam::shape(
                    "tau_s",
                    "s",
                    0.5,
                    2.0,
                    "lag of the free surface",
                )],
            ]
            .concat(),
            excites: &[ExpKind::Trim],
            build: |p| {
                Part::Hook(Box::new(SloshingWater {
                    x0: p[0],
                    y0: p[1],
                    s: p[2],
                    tau: p[3],
                    surface: None,
                }))
            },
        },
        TruthForm {
            name: FLOODING,
            family: "restoring_moment",
            law: FLOODING_LAW,
            params: vec![
                FormParam::signed(
                    "x1_m",
                    "m",
                    0.001,
                    0.0025,
                    "forward shift once the compartment is full (a pitch of 3.8–9.5°)",
                ),
                FormParam::shape("y0_m", "m", -0.0005, 0.0005, "constant starboard shift"),
                FormParam::shape("tau_s", "s", 15.0, 40.0, "time constant of the flooding"),
            ],
            excites: &[ExpKind::Trim],
            build: |p| {
                Part::Effect(Arc::new(FloodingEnd {
                    x1: p[0],
                    y0: p[1],
                    tau: p[2],
                }))
            },
        },
    ]
}

/// The parameters of a share of the centre of gravity that sits off-centre and moves downhill
/// as the hull tilts (the sliding mass, the sloshing water): its shifts on the level hull and
/// the slide per unit of sin(tilt), described by `slide`.
fn downhill(slide: &'static str) -> Vec<FormParam> {
    vec![
        FormParam::signed(
            "x0_m",
            "m",
            0.0008,
            0.002,
            "forward shift on the level hull (a pitch of 3–7.6°)",
        ),
        FormParam::signed(
            "y0_m",
            "m",
            0.0004,
            0.001,
            "starboard shift on the level hull (a roll of 1.5–3.8°)",
        ),
        FormParam::shape("s_m", "m", 0.003, 0.006, slide),
    ]
}

/// See the module documentation.
#[derive(Debug)]
struct SlidingMass {
    /// Forward shift at rest, level \[m\].
    x0: f64,
    /// Starboard shift at rest, level \[m\].
    y0: f64,
    /// Slide per unit of sin(tilt) \[m\].
    s: f64,
}

impl Effect for SlidingMass {
    truth_effect_meta!(SLIDING, SLIDING_LAW);
    fn force(&self, _p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        let (roll, pitch, _) = ctx.rigid.attitude.euler_angles();
        let dx = self.x0 - self.s * pitch.sin();
        let dy = self.y0 + self.s * roll.sin();
        RestoringMoment.force(&[dx, dy], ctx)
    }
}

/// See the module documentation.
#[derive(Debug)]
struct FloodingEnd {
    /// Forward shift once full \[m\].
    x1: f64,
    /// Constant starboard shift \[m\].
    y0: f64,
    /// Time constant of the flooding \[s\].
    tau: f64,
}

impl Effect for FloodingEnd {
    truth_effect_meta!(FLOODING, FLOODING_LAW);
    fn force(&self, _p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        // The catalogue's `settling` form has this law (the form is matched).
        RestoringMomentSettling.force(&[0.0, self.y0, self.x1, 0.0, self.tau], ctx)
    }
}

/// See the module documentation.
struct SloshingWater {
    /// Forward shift, level \[m\].
    x0: f64,
    /// Starboard shift, level \[m\].
    y0: f64,
    /// Downhill shift per unit of sin(tilt), settled \[m\].
    s: f64,
    /// Lag of the free surface \[s\].
    tau: f64,
    /// The surface's lagged sin(roll) and sin(pitch) (the run starts with it settled).
    surface: Option<(f64, f64)>,
}

impl TruthHook for SloshingWater {
    fn before_integrate(
        &mut self,
        model: &VehicleModel,
        state: &mut VehicleState,
        env: &Environment,
        dt: f64,
    ) {
        let rigid = &state.rigid;
        let (roll, pitch, _) = rigid.attitude.euler_angles();
        let (xi_r, xi_p) = self.surface.get_or_insert((roll.sin(), pitch.sin()));
        let dr = [self.x0 - self.s * *xi_p, self.y0 + self.s * *xi_r];
        let ctx = ForceContext::idle(state.time, rigid, &model.params, env);
        let m = RestoringMoment.force(&dr, &ctx);
        // The moment, held over the step like every other force.
        state.tau += m;
        let a = dt / self.tau;
        *xi_r += a * (roll.sin() - *xi_r);
        *xi_p += a * (pitch.sin() - *xi_p);
    }
}
