//! `thrust_gain` truth forms — the thrust is off by a factor, but not by one factor for all
//! thrusters and commands as the fitting side assumes:
//!
//! * `thrust_gain/per_thruster` — each motor has its own gain (motors from different batches, a
//!   nicked propeller): port k(1 + r), starboard k(1 − r), top k. The catalogue's
//!   `per_thruster` form has this law: the form is matched.
//! * `thrust_gain/command_dependent` — the gain varies with the command, k(n) = k·(|n|/50 %)^e:
//!   the thrust curve's exponent differs from the baseline's 2 (an ESC whose output is not
//!   linear in its input). The catalogue's `curve` form has this law: the form is matched.
//! * `thrust_gain/two_slope` — the gain is k₁ up to a knee command n_k and changes linearly to
//!   k₂ at full command above it: an ESC whose throttle map has a breakpoint, so the thrust
//!   curve has two slopes. The catalogue's `knee` form has this law: the form is matched.
//! * `thrust_gain/smooth_step` — the gain moves from k₁ to k₂ along a logistic curve in the
//!   command, centred on n_c with width w: a throttle map that bends smoothly rather than at
//!   a breakpoint (an ESC's calibration curve interpolated through a few points).
//! * `thrust_gain/worn_propeller` — one propeller (port) is worn or fouled: it loses a share of
//!   its thrust that grows with its speed, k_port = 1 − w·(|n|/100 %)², the others are as
//!   measured — a gain of its own thruster *and* of the command, which no fitting form has.

use super::effect_meta::truth_effect_meta;
use super::exp_kind::ExpKind;
use super::form_param::FormParam;
use super::logistic::logistic;
use super::truth_form::{Part, TruthForm};
use shoal_model::effects::{Effect, ThrustContext, ThrustGainKnee};
use std::sync::Arc;

/// Command at which [`CommandDependent`]'s gain is k [%].
const N_REF: f64 = 50.0;

const PER_THRUSTER: &str = "thrust_gain/per_thruster";
const PER_THRUSTER_LAW: &str = "thrust × k(1 + r) on port, × k(1 − r) on starboard, × k on top";
const COMMAND_DEPENDENT: &str = "thrust_gain/command_dependent";
const COMMAND_DEPENDENT_LAW: &str = "thrust × k·(|n|/50 %)^e";
const TWO_SLOPE: &str = "thrust_gain/two_slope";
const TWO_SLOPE_LAW: &str =
    "thrust × k₁ for |n| ≤ n_k, × k₁ + (k₂ − k₁)·(|n| − n_k)/(n_max − n_k) above";

const WORN: &str = "thrust_gain/worn_propeller";
const WORN_LAW: &str = "port thrust × (1 − w·(|n|/100 %)²), the others as measured";

const SMOOTH_STEP: &str = "thrust_gain/smooth_step";
const SMOOTH_STEP_LAW: &str = "thrust × (k₁ + (k₂ − k₁)·σ((|n| − n_c)/w)), σ logistic";

pub(super) fn forms() -> Vec<TruthForm> {
    vec![
        TruthForm {
            name: PER_THRUSTER,
            family: "thrust_gain",
            law: PER_THRUSTER_LAW,
            params: vec![
                FormParam::signed("dk", "-", 0.15, 0.28, "mean gain minus one: k = 1 + dk"),
                FormParam::signed(
                    "r",
                    "-",
                    0.05,
                    0.15,
                    "relative imbalance between port and starboard",
                ),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Effect(Arc::new(PerThruster {
                    k: 1.0 + p[0],
                    r: p[1],
                }))
            },
        },
        TruthForm {
            name: COMMAND_DEPENDENT,
            family: "thrust_gain",
            law: COMMAND_DEPENDENT_LAW,
            params: vec![
                FormParam::signed(
                    "dk",
                    "-",
                    0.15,
                    0.28,
                    "gain at 50 % command minus one: k = 1 + dk",
                ),
                FormParam::signed(
                    "e",
                    "-",
                    0.06,
                    0.12,
                    "exponent of the gain's command dependence",
                ),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Effect(Arc::new(CommandDependent {
                    k: 1.0 + p[0],
                    e: p[1],
                }))
            },
        },
        TruthForm {
            name: TWO_SLOPE,
            family: "thrust_gain",
            law: TWO_SLOPE_LAW,
            params: vec![
                FormParam::signed("dk1", "-", 0.12, 0.22, "gain below the knee minus one"),
                FormParam::signed(
                    "dk2",
                    "-",
                    0.15,
                    0.3,
                    "change of the gain from the knee to full command: k₂ = k₁ + dk2",
                ),
                FormParam::shape("n_k_pct", "%", 40.0, 60.0, "knee command n_k"),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Effect(Arc::new(TwoSlope {
                    k1: 1.0 + p[0],
                    k2: 1.0 + p[0] + p[1],
                    knee: p[2],
                }))
            },
        },
        TruthForm {
            name: SMOOTH_STEP,
            family: "thrust_gain",
            law: SMOOTH_STEP_LAW,
            params: vec![
                FormParam::signed("dk1", "-", 0.12, 0.22, "gain at small commands minus one"),
                FormParam::signed(
                    "dk2",
                    "-",
                    0.15,
                    0.3,
                    "change of the gain across the step: k₂ = k₁ + dk2",
                ),
                FormParam::shape("n_c_pct", "%", 40.0, 65.0, "command at the step's middle"),
                FormParam::shape("w_pct", "%", 6.0, 12.0, "width of the step"),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Effect(Arc::new(SmoothStep {
                    k1: 1.0 + p[0],
                    k2: 1.0 + p[0] + p[1],
                    centre: p[2],
                    width: p[3],
                }))
            },
        },
        TruthForm {
            name: WORN,
            family: "thrust_gain",
            law: WORN_LAW,
            params: vec![FormParam::magnitude(
                "w",
                "-",
                0.2,
                0.4,
                "share of the port thrust lost at full command",
            )],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| Part::Effect(Arc::new(Worn { w: p[0] })),
        },
    ]
}

/// See the module documentation.
#[derive(Debug)]
struct SmoothStep {
    /// Gain at small commands \[-\].
    k1: f64,
    /// Gain at large commands \[-\].
    k2: f64,
    /// Command at the middle of the step [%].
    centre: f64,
    /// Width of the step [%].
    width: f64,
}

impl Effect for SmoothStep {
    truth_effect_meta!(SMOOTH_STEP, SMOOTH_STEP_LAW);
    fn thrust(&self, _p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        let s = logistic((ctx.command.abs() - self.centre) / self.width);
        (self.k1 + (self.k2 - self.k1) * s) * f
    }
}

/// See the module documentation.
#[derive(Debug)]
struct PerThruster {
    /// Mean gain \[-\].
    k: f64,
    /// Port/starboard imbalance \[-\].
    r: f64,
}

impl Effect for PerThruster {
    truth_effect_meta!(PER_THRUSTER, PER_THRUSTER_LAW);
    fn thrust(&self, _p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        let r = match ctx.thruster.name.as_str() {
            "port" => self.r,
            "stbd" => -self.r,
            _ => 0.0,
        };
        self.k * (1.0 + r) * f
    }
}

/// See the module documentation.
#[derive(Debug)]
struct Worn {
    /// Share of the port thrust lost at full command \[-\].
    w: f64,
}

impl Effect for Worn {
    truth_effect_meta!(WORN, WORN_LAW);
    fn thrust(&self, _p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        if ctx.thruster.name == "port" {
            (1.0 - self.w * (ctx.command / 100.0).powi(2)) * f
        } else {
            f
        }
    }
}

/// See the module documentation.
#[derive(Debug)]
struct CommandDependent {
    /// Gain at [`N_REF`] \[-\].
    k: f64,
    /// Exponent \[-\].
    e: f64,
}

impl Effect for CommandDependent {
    truth_effect_meta!(COMMAND_DEPENDENT, COMMAND_DEPENDENT_LAW);
    fn thrust(&self, _p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        // Below 1 % there is (almost) no thrust to scale; keep the factor finite.
        let n = ctx.command.abs().max(1.0);
        self.k * (n / N_REF).powf(self.e) * f
    }
}

/// See the module documentation.
#[derive(Debug)]
struct TwoSlope {
    /// Gain up to the knee \[-\].
    k1: f64,
    /// Gain at full command \[-\].
    k2: f64,
    /// Knee command [%].
    knee: f64,
}

impl Effect for TwoSlope {
    truth_effect_meta!(TWO_SLOPE, TWO_SLOPE_LAW);
    fn thrust(&self, _p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        // The catalogue's `knee` form has this law (the form is matched): k = k₁, s = k₂ − k₁.
        ThrustGainKnee.thrust(&[self.k1, self.k2 - self.k1, self.knee], ctx, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shoal_model::presets;

    fn thrust(e: &dyn Effect, n: f64) -> f64 {
        let th = &presets::uauv2().thrusters[1];
        let ctx = ThrustContext {
            t: 0.0,
            thruster: th,
            command: n,
            inflow: 0.0,
        };
        e.thrust(&[], &ctx, 2.0)
    }

    #[test]
    fn two_slope_gain_is_flat_to_the_knee_then_linear() {
        let form = forms().into_iter().find(|f| f.name == TWO_SLOPE);
        let form = form.expect("registered");
        let Part::Effect(e) = form.part(&[0.2, -0.3, 50.0]) else {
            panic!("an effect")
        };
        // k₁ = 1.2 up to 50 %, k₂ = 0.9 at 100 %; the baseline thrust is 2 N.
        for (n, k) in [
            (10.0, 1.2),
            (-50.0, 1.2),
            (75.0, 1.05),
            (-90.0, 0.96),
            (100.0, 0.9),
        ] {
            let f = thrust(e.as_ref(), n);
            assert!((f - 2.0 * k).abs() < 1e-12, "n = {n}: {f}");
        }
        // No gain error and no change at the knee: the baseline.
        let null = TwoSlope {
            k1: 1.0,
            k2: 1.0,
            knee: 40.0,
        };
        for n in [-100.0, -20.0, 0.0, 45.0, 100.0] {
            assert_eq!(thrust(&null, n), 2.0);
        }
    }

    #[test]
    fn smooth_step_gain_moves_from_k1_to_k2_around_the_centre() {
        let form = forms().into_iter().find(|f| f.name == SMOOTH_STEP);
        let Part::Effect(e) = form.expect("registered").part(&[0.2, -0.3, 50.0, 10.0]) else {
            panic!("an effect")
        };
        // k₁ = 1.2, k₂ = 0.9, centre 50 %, width 10 %; σ(−5) = 0.006693, σ(2.5) = 0.924142.
        for (n, k) in [
            (0.0, 1.2 - 0.3 * 0.006_693),
            (-50.0, 1.05),
            (75.0, 1.2 - 0.3 * 0.924_142),
        ] {
            let f = thrust(e.as_ref(), n);
            assert!((f - 2.0 * k).abs() < 1e-5, "n = {n}: {f}");
        }
        // Symmetric about the centre: k(50 + s) + k(50 − s) = 2·k(50).
        let sum = thrust(e.as_ref(), 62.0) + thrust(e.as_ref(), 38.0);
        assert!((sum - 2.0 * thrust(e.as_ref(), 50.0)).abs() < 1e-12);
    }
}
