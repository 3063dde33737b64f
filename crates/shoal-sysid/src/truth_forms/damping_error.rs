//! `damping_error` truth forms — the hull's drag differs from the baseline's, but not by scale
//! factors on its linear and quadratic terms as the fitting side assumes:
//!
//! * `damping_error/direction_dependent` — the drag depends on the direction of motion (a dome
//!   or a skid on one side): every damping term is scaled by k₊ while the velocity component is
//!   positive and by k₋ (near one) while it is negative (diving vs rising, turning right vs
//!   left).
//! * `damping_error/speed_exponent` — an extra drag term of another power of the speed, as
//!   from an appendage in turbulent flow: −s·d_quad·ν_ref^(2−p)·|ν|^(p−1)·ν per degree of
//!   freedom, i.e. s times the quadratic damping at the reference speed ν_ref (0.1 m/s,
//!   1 rad/s) and growing faster above it.
//!
//! Both are forces on the hull computed from its velocity through the water.

use super::{ExpKind, FormParam, NU_REF, Part, TruthForm, truth_effect_meta};
use shoal_model::effects::{Effect, ForceContext};
use shoal_model::math::Vec6;
use std::sync::Arc;

const DIRECTION: &str = "damping_error/direction_dependent";
const DIRECTION_LAW: &str = "damping × k₊ for ν > 0, × k₋ for ν < 0, per degree of freedom";
const EXPONENT: &str = "damping_error/speed_exponent";
const EXPONENT_LAW: &str = "extra drag s·d_quad·ν_ref^(2−p)·|ν|^(p−1)·ν";

pub(super) fn forms() -> Vec<TruthForm> {
    vec![
        TruthForm {
            name: DIRECTION,
            family: "damping_error",
            law: DIRECTION_LAW,
            params: vec![
                FormParam::magnitude("k_pos", "-", 1.3, 1.6, "damping factor for ν > 0"),
                FormParam::shape("k_neg", "-", 0.95, 1.1, "damping factor for ν < 0"),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Effect(Arc::new(DirectionDependent {
                    k_pos: p[0],
                    k_neg: p[1],
                }))
            },
        },
        TruthForm {
            name: EXPONENT,
            family: "damping_error",
            law: EXPONENT_LAW,
            params: vec![
                FormParam::magnitude(
                    "s",
                    "-",
                    0.4,
                    0.8,
                    "extra drag at the reference speed, relative to the quadratic damping",
                ),
                FormParam::shape("p", "-", 2.6, 3.2, "power of the speed"),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| Part::Effect(Arc::new(SpeedExponent { s: p[0], p: p[1] })),
        },
    ]
}

/// See the module documentation.
#[derive(Debug)]
struct DirectionDependent {
    /// Factor for positive velocity \[-\].
    k_pos: f64,
    /// Factor for negative velocity \[-\].
    k_neg: f64,
}

impl Effect for DirectionDependent {
    truth_effect_meta!(DIRECTION, DIRECTION_LAW);
    fn force(&self, _p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        let nu = &ctx.rigid.nu;
        let base = ctx.vehicle.body.damping(nu);
        Vec6::from_fn(|i, _| {
            let k = if nu[i] > 0.0 { self.k_pos } else { self.k_neg };
            -(k - 1.0) * base[i]
        })
    }
}

/// See the module documentation.
#[derive(Debug)]
struct SpeedExponent {
    /// Extra drag at the reference speed relative to the quadratic damping \[-\].
    s: f64,
    /// Power of the speed \[-\].
    p: f64,
}

impl Effect for SpeedExponent {
    truth_effect_meta!(EXPONENT, EXPONENT_LAW);
    fn force(&self, _p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        let nu = &ctx.rigid.nu;
        let d = &ctx.vehicle.body.damping_quadratic;
        Vec6::from_fn(|i, _| {
            let x = nu[i] / NU_REF[i];
            -self.s * d[i] * NU_REF[i] * NU_REF[i] * x.abs().powf(self.p - 1.0) * x
        })
    }
}
