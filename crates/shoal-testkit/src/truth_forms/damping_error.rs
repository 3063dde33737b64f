//! `damping_error` truth forms — the hull's drag differs from the baseline's, but not by scale
//! factors on its linear and quadratic terms as the fitting side assumes:
//!
//! * `damping_error/direction_dependent` — the drag depends on the direction of motion (a dome
//!   or a skid on one side): every damping term is scaled by k₊ while the velocity component is
//!   positive and by k₋ (near one) while it is negative (diving vs rising, turning right vs
//!   left). The catalogue's `direction` form has this law: the form is matched.
//! * `damping_error/speed_exponent` — an extra drag term of another power of the speed, as
//!   from an appendage in turbulent flow: −s·d_quad·ν_ref^(2−p)·|ν|^(p−1)·ν per degree of
//!   freedom, i.e. s times the quadratic damping at the reference speed ν_ref (0.1 m/s,
//!   1 rad/s) and growing faster above it. The catalogue's `power` form has this law: the
//!   form is matched.
//! * `damping_error/quadratic_direction` — only the quadratic (form, or pressure) drag depends
//!   on the direction of motion: the pressure drag follows the shape the flow meets (a blunt
//!   dome one way, a tapered tail the other), the skin friction behind the linear term does
//!   not. The quadratic term is scaled by k₊ > 1 while the velocity component is positive and
//!   by k₋ < 1 while it is negative; the linear term is the baseline's.
//! * `damping_error/transition` — the boundary layer turns turbulent above a critical speed:
//!   the quadratic drag coefficient rises by a factor 1 + s across a transition speed ν_t,
//!   smoothly, d_quad·(1 + s·r⁴/(1 + r⁴)) with r = |ν|/ν_t; slow motion keeps the baseline's
//!   drag, fast motion meets more. Neither a scale factor nor a single power of the speed.
//!
//! All are forces on the hull computed from its velocity through the water.

use super::effect_meta::truth_effect_meta;
use super::exp_kind::ExpKind;
use super::form_param::FormParam;
use super::truth_form::{Part, TruthForm};
use shoal_model::effects::NU_REF;
use shoal_model::effects::{DampingErrorDirection, DampingErrorPower, Effect, ForceContext};
use shoal_model::math::Vec6;
use std::sync::Arc;

const DIRECTION: &str = "damping_error/direction_dependent";
const DIRECTION_LAW: &str = "damping × k₊ for ν > 0, × k₋ for ν < 0, per degree of freedom";
const EXPONENT: &str = "damping_error/speed_exponent";
const EXPONENT_LAW: &str = "extra drag s·d_quad·ν_ref^(2−p)·|ν|^(p−1)·ν";
const QUAD_DIRECTION: &str = "damping_error/quadratic_direction";
const QUAD_DIRECTION_LAW: &str =
    "quadratic damping × k₊ for ν > 0, × k₋ for ν < 0, linear damping unchanged";
const TRANSITION: &str = "damping_error/transition";
const TRANSITION_LAW: &str = "quadratic damping × (1 + s·r⁴/(1 + r⁴)), r = |ν|/ν_t";

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
        TruthForm {
            name: QUAD_DIRECTION,
            family: "damping_error",
            law: QUAD_DIRECTION_LAW,
            params: vec![
                FormParam::magnitude("k_pos", "-", 1.4, 1.8, "quadratic damping factor for ν > 0"),
                FormParam::deficit("k_neg", "-", 0.7, 0.9, "quadratic damping factor for ν < 0"),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Effect(Arc::new(QuadraticDirection {
                    k_pos: p[0],
                    k_neg: p[1],
                }))
            },
        },
        TruthForm {
            name: TRANSITION,
            family: "damping_error",
            law: TRANSITION_LAW,
            params: vec![
                FormParam::magnitude(
                    "s",
                    "-",
                    0.6,
                    1.2,
                    "rise of the quadratic drag coefficient across the transition",
                ),
                FormParam::shape(
                    "nu_t_rel",
                    "-",
                    0.5,
                    1.0,
                    "transition speed as a fraction of the reference speed",
                ),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Effect(Arc::new(Transition {
                    s: p[0],
                    nu_t_rel: p[1],
                }))
            },
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
        // The catalogue's `direction` form has this law (the form is matched).
        DampingErrorDirection.force(&[self.k_pos, self.k_neg], ctx)
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
        // The catalogue's `power` form has this law (the form is matched).
        DampingErrorPower.force(&[self.s, self.p], ctx)
    }
}

/// See the module documentation.
#[derive(Debug)]
struct QuadraticDirection {
    /// Quadratic damping factor for positive velocity \[-\].
    k_pos: f64,
    /// Quadratic damping factor for negative velocity \[-\].
    k_neg: f64,
}

impl Effect for QuadraticDirection {
    truth_effect_meta!(QUAD_DIRECTION, QUAD_DIRECTION_LAW);
    fn force(&self, _p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        let nu = &ctx.rigid.nu;
        let d = &ctx.vehicle.body.damping_quadratic;
        Vec6::from_fn(|i, _| {
            let k = if nu[i] > 0.0 { self.k_pos } else { self.k_neg };
            -(k - 1.0) * d[i] * nu[i].abs() * nu[i]
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shoal_model::dynamics::RigidState;
    use shoal_model::math::{Quat, Vec3};
    use shoal_model::presets;

    /// The total drag (baseline plus `e`'s extra force) at velocity `nu`, as a resisting force.
    fn drag(e: &dyn Effect, nu: Vec6) -> Vec6 {
        let vehicle = presets::uauv2();
        let mut rigid = RigidState::at_rest(Vec3::new(0.0, 0.0, 1.0), Quat::identity());
        rigid.nu = nu;
        let env = shoal_model::rigid_body::Environment::default();
        let ctx = ForceContext::idle(0.0, &rigid, &vehicle, &env);
        vehicle.body.damping(&nu) - e.force(&[], &ctx)
    }

    #[test]
    fn quadratic_direction_scales_only_the_quadratic_drag_per_direction() {
        let form = forms().into_iter().find(|f| f.name == QUAD_DIRECTION);
        let form = form.expect("registered");
        let Part::Effect(e) = form.part(&[1.5, 0.8]) else {
            panic!("an effect")
        };
        let body = presets::uauv2().body;
        let (zw, zww) = (body.damping_linear[2], body.damping_quadratic[2]);
        let (nr, nrr) = (body.damping_linear[5], body.damping_quadratic[5]);
        // Diving at 0.1 m/s and turning at −1 rad/s: Z_w·w + 1.5·Z_w|w|·w², N_r·r − 0.8·N_r|r|.
        let d = drag(e.as_ref(), Vec6::new(0.0, 0.0, 0.1, 0.0, 0.0, -1.0));
        assert!((d[2] - (zw * 0.1 + 1.5 * zww * 0.01)).abs() < 1e-12, "{d}");
        assert!((d[5] - (-nr - 0.8 * nrr)).abs() < 1e-12, "{d}");
        // Rising at 0.05 m/s and turning at +0.5 rad/s.
        let d = drag(e.as_ref(), Vec6::new(0.0, 0.0, -0.05, 0.0, 0.0, 0.5));
        assert!(
            (d[2] - (-zw * 0.05 - 0.8 * zww * 0.0025)).abs() < 1e-12,
            "{d}"
        );
        assert!((d[5] - (nr * 0.5 + 1.5 * nrr * 0.25)).abs() < 1e-12, "{d}");
        // At rest nothing; factors of one: the baseline.
        assert_eq!(drag(e.as_ref(), Vec6::zeros()), Vec6::zeros());
        let null = QuadraticDirection {
            k_pos: 1.0,
            k_neg: 1.0,
        };
        let nu = Vec6::new(0.02, -0.03, 0.1, 0.2, -0.1, 0.8);
        assert_eq!(drag(&null, nu), body.damping(&nu));
    }
}

/// See the module documentation.
#[derive(Debug)]
struct Transition {
    /// Rise of the quadratic drag coefficient across the transition \[-\].
    s: f64,
    /// Transition speed as a fraction of [`NU_REF`] \[-\].
    nu_t_rel: f64,
}

impl Effect for Transition {
    truth_effect_meta!(TRANSITION, TRANSITION_LAW);
    fn force(&self, _p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        let nu = &ctx.rigid.nu;
        let d = &ctx.vehicle.body.damping_quadratic;
        Vec6::from_fn(|i, _| {
            let r4 = (nu[i] / (self.nu_t_rel * NU_REF[i])).powi(4);
            -self.s * r4 / (1.0 + r4) * d[i] * nu[i].abs() * nu[i]
        })
    }
}
