//! `thrust_coupling` truth forms — vertical thrust leaks into a yaw moment, but not in
//! proportion to it as the fitting side's N = k_z·F_z + k_x·F_x assumes:
//!
//! * `thrust_coupling/quadratic_wash` — the wash that hits an appendage grows with the square of
//!   the thrust: N = k·F_z·|F_z|/F_ref (F_ref = 0.1 N, k the arm at that thrust).
//! * `thrust_coupling/direction_dependent` — the wash hits a fin mainly on one side: pushing
//!   down gives N = k_d·F_z, pushing up N = r·k_d·F_z with 0.2 ≤ r ≤ 0.6. The catalogue's
//!   `direction` form has this law: the form is matched.
//! * `thrust_coupling/saturating_wash` — the jet covers a fin completely once it is strong
//!   enough, and more thrust adds little moment: N = k·F₀·tanh(F_z/F₀), the arm k at small
//!   thrust, F₀ 0.03–0.06 N.
//!
//! F_z is the thrusters' force along body z. All reuse the catalogue's moment with an arm that
//! depends on the thrust.

use super::effect_meta::truth_effect_meta;
use super::exp_kind::ExpKind;
use super::form_param::FormParam;
use super::truth_form::{Part, TruthForm};
use shoal_model::effects::{Effect, ForceContext, ThrustCoupling, ThrustCouplingDirection};
use shoal_model::math::Vec6;
use std::sync::Arc;

/// Thrust at which [`QuadraticWash`]'s arm is k \[N\].
const F_REF: f64 = 0.1;

const QUADRATIC: &str = "thrust_coupling/quadratic_wash";
const QUADRATIC_LAW: &str = "yaw moment k·F_z·|F_z|/0.1 N";
const DIRECTION: &str = "thrust_coupling/direction_dependent";
const DIRECTION_LAW: &str = "yaw moment k_d·F_z for F_z > 0, r·k_d·F_z for F_z < 0";
const SATURATING: &str = "thrust_coupling/saturating_wash";
const SATURATING_LAW: &str = "yaw moment k·F₀·tanh(F_z/F₀)";

pub(super) fn forms() -> Vec<TruthForm> {
    vec![
        TruthForm {
            name: QUADRATIC,
            family: "thrust_coupling",
            law: QUADRATIC_LAW,
            params: vec![FormParam::signed(
                "k_m",
                "m",
                0.01,
                0.03,
                "yaw moment per newton of vertical thrust at 0.1 N",
            )],
            excites: &[ExpKind::Heave],
            build: |p| Part::Effect(Arc::new(QuadraticWash { k: p[0] })),
        },
        TruthForm {
            name: DIRECTION,
            family: "thrust_coupling",
            law: DIRECTION_LAW,
            params: vec![
                FormParam::signed(
                    "k_down_m",
                    "m",
                    0.015,
                    0.03,
                    "yaw moment per newton of downward (body +z) thrust",
                ),
                FormParam::shape(
                    "r",
                    "-",
                    0.2,
                    0.6,
                    "upward arm relative to the downward one",
                ),
            ],
            excites: &[ExpKind::Heave],
            build: |p| {
                Part::Effect(Arc::new(DirectionDependent {
                    k_down: p[0],
                    r: p[1],
                }))
            },
        },
        TruthForm {
            name: SATURATING,
            family: "thrust_coupling",
            law: SATURATING_LAW,
            params: vec![
                FormParam::signed(
                    "k_m",
                    "m",
                    0.015,
                    0.03,
                    "yaw moment per newton of vertical thrust at small thrust",
                ),
                FormParam::shape(
                    "f0_n",
                    "N",
                    0.03,
                    0.06,
                    "thrust at which the wash covers the fin",
                ),
            ],
            excites: &[ExpKind::Heave],
            build: |p| Part::Effect(Arc::new(SaturatingWash { k: p[0], f0: p[1] })),
        },
    ]
}

/// See the module documentation.
#[derive(Debug)]
struct QuadraticWash {
    /// Arm at [`F_REF`] \[m\].
    k: f64,
}

impl Effect for QuadraticWash {
    truth_effect_meta!(QUADRATIC, QUADRATIC_LAW);
    fn force(&self, _p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        let arm = self.k * ctx.thrust_force.z.abs() / F_REF;
        ThrustCoupling.force(&[arm, 0.0], ctx)
    }
}

/// See the module documentation.
#[derive(Debug)]
struct DirectionDependent {
    /// Arm for downward thrust \[m\].
    k_down: f64,
    /// Upward arm relative to the downward one \[-\].
    r: f64,
}

impl Effect for DirectionDependent {
    truth_effect_meta!(DIRECTION, DIRECTION_LAW);
    fn force(&self, _p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        // The catalogue's `direction` form has this law (the form is matched).
        ThrustCouplingDirection.force(&[self.k_down, self.r * self.k_down, 0.0], ctx)
    }
}

/// See the module documentation.
#[derive(Debug)]
struct SaturatingWash {
    /// Arm at small thrust \[m\].
    k: f64,
    /// Thrust at which the wash covers the fin \[N\].
    f0: f64,
}

impl Effect for SaturatingWash {
    truth_effect_meta!(SATURATING, SATURATING_LAW);
    fn force(&self, _p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        let mut f = Vec6::zeros();
        f[5] = self.k * self.f0 * (ctx.thrust_force.z / self.f0).tanh();
        f
    }
}
