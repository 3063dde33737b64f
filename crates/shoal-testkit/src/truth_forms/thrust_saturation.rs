//! `thrust_saturation` truth forms — large thrusts are capped, but neither by a hard clamp at
//! one fraction of both directions' maxima nor by F·tanh(f/F) as the fitting side assumes:
//!
//! * `thrust_saturation/algebraic_soft` — f/(1 + |f/F|^p)^(1/p) with F a fraction of the
//!   direction's maximum and p ≈ 3–5: sharper than tanh, softer than a clamp (a current
//!   limiter that folds back gradually).
//! * `thrust_saturation/asymmetric_caps` — the ESC's limit binds at different fractions of the
//!   forward and the reverse maximum (a hard clamp at c₊·f_max⁺ and −c₋·f_max⁻, c₊ < c₋).
//! * `thrust_saturation/exponential_knee` — sign(f)·F·(1 − e^(−|f|/F)) with F a fraction of
//!   the direction's maximum: the thrust bends over from the first newton on and approaches F
//!   (a supply whose voltage drops in proportion to the current drawn).
//!
//! * `thrust_saturation/command_limit` — the ESC limits its *input*: the command reaching the
//!   motor bends over as N·tanh(n/N), N = c·n_max, and the thrust follows the curve of that
//!   command (a throttle map that compresses its top end), so the thrust's knee has the
//!   curve's shape, not a law in thrust.
//!
//! The thrust forms limit the thrust after every other thrust change (the catalogue's `Limit`
//! stage). Fitting forms have since matched `asymmetric_caps` (`asymmetric`) and
//! `algebraic_soft` (`smooth`, whose sharpness is fitted).

use super::effect_meta::truth_effect_meta;
use super::exp_kind::ExpKind;
use super::form_param::FormParam;
use super::truth_form::{Part, TruthForm};
use shoal_model::effects::{
    Effect, Stage, ThrustContext, ThrustSaturationAsymmetric, ThrustSaturationSmooth,
};
use shoal_model::thruster::ThrusterParams;
use std::sync::Arc;

const SOFT: &str = "thrust_saturation/algebraic_soft";
const SOFT_LAW: &str = "thrust f/(1 + |f/F|^p)^(1/p), F = c·f_max per direction";
const CAPS: &str = "thrust_saturation/asymmetric_caps";
const CAPS_LAW: &str = "thrust clamped to −c₋·f_max⁻ … c₊·f_max⁺";
const KNEE: &str = "thrust_saturation/exponential_knee";
const KNEE_LAW: &str = "thrust sign(f)·F·(1 − e^(−|f|/F)), F = c·f_max per direction";
const CMD: &str = "thrust_saturation/command_limit";
const CMD_LAW: &str = "command N·tanh(n/N), N = c·n_max, before the thrust curve";

pub(super) fn forms() -> Vec<TruthForm> {
    vec![
        TruthForm {
            name: SOFT,
            family: "thrust_saturation",
            law: SOFT_LAW,
            params: vec![
                FormParam::deficit(
                    "c",
                    "-",
                    0.5,
                    0.8,
                    "soft limit F as a fraction of the direction's maximum thrust",
                ),
                FormParam::shape("p", "-", 3.0, 5.0, "sharpness of the knee"),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| Part::Effect(Arc::new(AlgebraicSoft { c: p[0], p: p[1] })),
        },
        TruthForm {
            name: CAPS,
            family: "thrust_saturation",
            law: CAPS_LAW,
            params: vec![
                FormParam::deficit(
                    "c_fwd",
                    "-",
                    0.4,
                    0.55,
                    "forward cap c₊ per forward maximum",
                ),
                FormParam::shape(
                    "gap",
                    "-",
                    0.15,
                    0.3,
                    "reverse cap minus forward cap, c₋ − c₊",
                ),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Effect(Arc::new(AsymmetricCaps {
                    c_fwd: p[0],
                    c_rev: p[0] + p[1],
                }))
            },
        },
        TruthForm {
            name: KNEE,
            family: "thrust_saturation",
            law: KNEE_LAW,
            params: vec![FormParam::deficit(
                "c",
                "-",
                0.5,
                0.8,
                "level F approached, as a fraction of the direction's maximum thrust",
            )],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| Part::Effect(Arc::new(ExponentialKnee { c: p[0] })),
        },
        TruthForm {
            name: CMD,
            family: "thrust_saturation",
            law: CMD_LAW,
            params: vec![FormParam::deficit(
                "c",
                "-",
                0.6,
                0.85,
                "soft command limit N as a fraction of the largest command",
            )],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| Part::Effect(Arc::new(CommandLimit { c: p[0] })),
        },
    ]
}

/// See the module documentation.
#[derive(Debug)]
struct AlgebraicSoft {
    /// Soft limit per maximum thrust \[-\].
    c: f64,
    /// Sharpness \[-\].
    p: f64,
}

impl Effect for AlgebraicSoft {
    truth_effect_meta!(SOFT, SOFT_LAW);
    fn stage(&self) -> Stage {
        Stage::Limit
    }
    fn thrust(&self, _p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        // The catalogue's `smooth` form has this law (the form is matched): its cap is
        // f_max/c', so c' = 1/c.
        ThrustSaturationSmooth.thrust(&[1.0 / self.c, self.p], ctx, f)
    }
}

/// See the module documentation.
#[derive(Debug)]
struct AsymmetricCaps {
    /// Forward cap per forward maximum \[-\].
    c_fwd: f64,
    /// Reverse cap per reverse maximum \[-\].
    c_rev: f64,
}

impl Effect for AsymmetricCaps {
    truth_effect_meta!(CAPS, CAPS_LAW);
    fn stage(&self) -> Stage {
        Stage::Limit
    }
    fn thrust(&self, _p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        // The catalogue's `asymmetric` form has this law (the form is matched).
        ThrustSaturationAsymmetric.thrust(&[self.c_fwd, self.c_rev], ctx, f)
    }
}

/// See the module documentation.
#[derive(Debug)]
struct ExponentialKnee {
    /// Level approached per maximum thrust \[-\].
    c: f64,
}

impl Effect for ExponentialKnee {
    truth_effect_meta!(KNEE, KNEE_LAW);
    fn stage(&self) -> Stage {
        Stage::Limit
    }
    fn thrust(&self, _p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        let Some(big) = level(self.c, ctx, f) else {
            return f;
        };
        f.signum() * big * (1.0 - (-f.abs() / big).exp())
    }
}

/// See the module documentation.
#[derive(Debug)]
struct CommandLimit {
    /// Soft command limit per largest command \[-\].
    c: f64,
}

impl Effect for CommandLimit {
    truth_effect_meta!(CMD, CMD_LAW);
    fn command(&self, _p: &[f64], thruster: &ThrusterParams, n: f64) -> f64 {
        let big = self.c * thruster.max_command;
        if big <= 0.0 {
            return n;
        }
        big * (n / big).tanh()
    }
}

/// The level F = c·f_max of thrust `f`'s direction \[N\] (`None`: the thruster has no
/// thrust that way).
fn level(c: f64, ctx: &ThrustContext<'_>, f: f64) -> Option<f64> {
    let big = c * ctx.thruster.max_thrust_towards(f);
    (big > 0.0).then_some(big)
}
