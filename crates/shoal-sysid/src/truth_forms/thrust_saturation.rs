//! `thrust_saturation` truth forms — large thrusts are capped, but neither by a hard clamp at
//! one fraction of both directions' maxima nor by F·tanh(f/F) as the fitting side assumes:
//!
//! * `thrust_saturation/algebraic_soft` — f/(1 + |f/F|^p)^(1/p) with F a fraction of the
//!   direction's maximum and p ≈ 3–5: sharper than tanh, softer than a clamp (a current
//!   limiter that folds back gradually).
//! * `thrust_saturation/asymmetric_caps` — the ESC's limit binds at different fractions of the
//!   forward and the reverse maximum (a hard clamp at c₊·f_max⁺ and −c₋·f_max⁻, c₊ < c₋).
//!
//! Both limit the thrust after every other thrust change (the catalogue's `Limit` stage).

use super::{ExpKind, FormParam, Part, TruthForm, truth_effect_meta};
use shoal_model::effects::{Effect, Stage, ThrustContext};
use std::sync::Arc;

const SOFT: &str = "thrust_saturation/algebraic_soft";
const SOFT_LAW: &str = "thrust f/(1 + |f/F|^p)^(1/p), F = c·f_max per direction";
const CAPS: &str = "thrust_saturation/asymmetric_caps";
const CAPS_LAW: &str = "thrust clamped to −c₋·f_max⁻ … c₊·f_max⁺";

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
        let (fwd, rev) = ctx.thruster.curve.limits(ctx.thruster.max_command);
        let big = self.c * if f >= 0.0 { fwd } else { rev };
        if big <= 0.0 {
            return f;
        }
        f / (1.0 + (f / big).abs().powf(self.p)).powf(1.0 / self.p)
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
        let (fwd, rev) = ctx.thruster.curve.limits(ctx.thruster.max_command);
        f.clamp(-self.c_rev * rev, self.c_fwd * fwd)
    }
}
