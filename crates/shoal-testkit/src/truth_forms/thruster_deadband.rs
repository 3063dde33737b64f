//! `thruster_deadband` truth forms — small commands give no thrust, but not through the fitting
//! side's hard cut with a stretched curve or its tanh-softened band:
//!
//! * `thruster_deadband/linear_ramp` — no thrust below d₀; between d₀ and d₁ the effective
//!   command ramps linearly from 0 to d₁; from d₁ on the thrust curve is the baseline's (a motor
//!   that starts sluggishly and is fully up to speed past d₁).
//! * `thruster_deadband/asymmetric` — the ESC's band is wider in reverse than forward
//!   (d₋ > d₊); each side is a hard cut with the curve stretched over the rest of its range.
//!   The catalogue's `asymmetric` form has this law: the form is matched.
//! * `thruster_deadband/asymmetric_soft` — friction that fades in, stronger in reverse: each
//!   side is a soft knee n' = n − d·tanh(n/d) with its own width (d₊ forward, d₋ > d₊ reverse),
//!   so small commands give almost no thrust and larger ones the thrust of a command d smaller
//!   (a propeller that is less efficient and a motor with more cogging in reverse). The
//!   catalogue's `soft_asymmetric` form has this law: the form is matched.
//! * `thruster_deadband/exponential_onset` — the share of the command that gets through grows
//!   as 1 − e^(−(|n|/d)²): nothing at the smallest commands, the unchanged curve well above d,
//!   a Gaussian-shaped onset between (friction that a turning motor sheds gradually).

use super::effect_meta::truth_effect_meta;
use super::exp_kind::ExpKind;
use super::form_param::FormParam;
use super::truth_form::{Part, TruthForm};
use shoal_model::effects::{Effect, ThrusterDeadbandAsymmetric, ThrusterDeadbandSoftAsymmetric};
use shoal_model::thruster::ThrusterParams;
use std::sync::Arc;

const LINEAR_RAMP: &str = "thruster_deadband/linear_ramp";
const LINEAR_RAMP_LAW: &str =
    "command 0 for |n| ≤ d₀, ramps 0 → d₁ between d₀ and d₁, unchanged above d₁";
const ASYMMETRIC: &str = "thruster_deadband/asymmetric";
const ASYMMETRIC_LAW: &str =
    "hard dead band d₊ forward and d₋ reverse, curve stretched on each side";
const ASYMMETRIC_SOFT: &str = "thruster_deadband/asymmetric_soft";
const ASYMMETRIC_SOFT_LAW: &str = "command n − d·tanh(n/d), d = d₊ for n ≥ 0 and d₋ for n < 0";
const ONSET: &str = "thruster_deadband/exponential_onset";
const ONSET_LAW: &str = "command n·(1 − e^(−(|n|/d)²))";

pub(super) fn forms() -> Vec<TruthForm> {
    vec![
        TruthForm {
            name: LINEAR_RAMP,
            family: "thruster_deadband",
            law: LINEAR_RAMP_LAW,
            params: vec![
                FormParam::magnitude("d0_pct", "%", 7.0, 10.0, "edge of the dead band"),
                FormParam::magnitude("ramp_pct", "%", 8.0, 16.0, "width of the ramp, d₁ − d₀"),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Effect(Arc::new(LinearRamp {
                    d0: p[0],
                    d1: p[0] + p[1],
                }))
            },
        },
        TruthForm {
            name: ASYMMETRIC,
            family: "thruster_deadband",
            law: ASYMMETRIC_LAW,
            params: vec![
                FormParam::magnitude("d_fwd_pct", "%", 3.0, 7.0, "forward dead band d₊"),
                FormParam::magnitude("d_rev_pct", "%", 10.0, 16.0, "reverse dead band d₋"),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Effect(Arc::new(Asymmetric {
                    d_fwd: p[0],
                    d_rev: p[1],
                }))
            },
        },
        TruthForm {
            name: ASYMMETRIC_SOFT,
            family: "thruster_deadband",
            law: ASYMMETRIC_SOFT_LAW,
            params: vec![
                FormParam::magnitude("d_fwd_pct", "%", 4.0, 8.0, "forward knee width d₊"),
                FormParam::magnitude("d_rev_pct", "%", 10.0, 16.0, "reverse knee width d₋"),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Effect(Arc::new(AsymmetricSoft {
                    d_fwd: p[0],
                    d_rev: p[1],
                }))
            },
        },
        TruthForm {
            name: ONSET,
            family: "thruster_deadband",
            law: ONSET_LAW,
            params: vec![FormParam::magnitude(
                "d_pct",
                "%",
                10.0,
                16.0,
                "command at which 63 % of it gets through",
            )],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| Part::Effect(Arc::new(ExponentialOnset { d: p[0] })),
        },
    ]
}

/// See the module documentation.
#[derive(Debug)]
struct ExponentialOnset {
    /// Onset width [%].
    d: f64,
}

impl Effect for ExponentialOnset {
    truth_effect_meta!(ONSET, ONSET_LAW);
    fn command(&self, _p: &[f64], _thruster: &ThrusterParams, n: f64) -> f64 {
        n * (1.0 - (-(n / self.d).powi(2)).exp())
    }
}

/// See the module documentation.
#[derive(Debug)]
struct LinearRamp {
    /// Edge of the band [%].
    d0: f64,
    /// End of the ramp [%].
    d1: f64,
}

impl Effect for LinearRamp {
    truth_effect_meta!(LINEAR_RAMP, LINEAR_RAMP_LAW);
    fn command(&self, _p: &[f64], _thruster: &ThrusterParams, n: f64) -> f64 {
        let a = n.abs();
        if a >= self.d1 {
            n
        } else if a <= self.d0 {
            0.0
        } else {
            n.signum() * self.d1 * (a - self.d0) / (self.d1 - self.d0)
        }
    }
}

/// See the module documentation.
#[derive(Debug)]
struct Asymmetric {
    /// Forward band [%].
    d_fwd: f64,
    /// Reverse band [%].
    d_rev: f64,
}

impl Effect for Asymmetric {
    truth_effect_meta!(ASYMMETRIC, ASYMMETRIC_LAW);
    fn command(&self, _p: &[f64], thruster: &ThrusterParams, n: f64) -> f64 {
        // The catalogue's `asymmetric` form has this law (the form is matched).
        ThrusterDeadbandAsymmetric.command(&[self.d_fwd, self.d_rev], thruster, n)
    }
}

/// See the module documentation.
#[derive(Debug)]
struct AsymmetricSoft {
    /// Forward knee width [%].
    d_fwd: f64,
    /// Reverse knee width [%].
    d_rev: f64,
}

impl Effect for AsymmetricSoft {
    truth_effect_meta!(ASYMMETRIC_SOFT, ASYMMETRIC_SOFT_LAW);
    fn command(&self, _p: &[f64], thruster: &ThrusterParams, n: f64) -> f64 {
        // The catalogue's `soft_asymmetric` form has this law (the form is matched).
        ThrusterDeadbandSoftAsymmetric.command(&[self.d_fwd, self.d_rev], thruster, n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shoal_model::presets;

    #[test]
    fn asymmetric_soft_has_a_soft_knee_of_its_own_width_per_side() {
        let th = &presets::uauv2().thrusters[1];
        let form = forms().into_iter().find(|f| f.name == ASYMMETRIC_SOFT);
        let form = form.expect("registered");
        let Part::Effect(e) = form.part(&[5.0, 12.0]) else {
            panic!("an effect")
        };
        let c = |n: f64| e.command(&[], th, n);
        // tanh 2 = 0.964028, tanh 1 = 0.761594, tanh(5/12) = 0.394119.
        assert_eq!(c(0.0), 0.0);
        assert!((c(10.0) - (10.0 - 5.0 * 0.964_028)).abs() < 1e-5);
        assert!((c(-12.0) - (-12.0 + 12.0 * 0.761_594)).abs() < 1e-5);
        assert!((c(-5.0) - (-5.0 + 12.0 * 0.394_119)).abs() < 1e-5);
        // Far outside the band each side is shifted by its own width.
        assert!((c(80.0) - 75.0).abs() < 1e-9);
        assert!((c(-80.0) + 68.0).abs() < 1e-4);
        // Reverse loses more than forward.
        assert!(c(30.0) > -c(-30.0));
        // Zero widths: the baseline.
        let null = AsymmetricSoft {
            d_fwd: 0.0,
            d_rev: 0.0,
        };
        for n in [-100.0, -7.0, 0.0, 3.0, 100.0] {
            assert_eq!(null.command(&[], th, n), n);
        }
    }
}
