//! `thrust_gain` truth forms — the thrust is off by a factor, but not by one factor for all
//! thrusters and commands as the fitting side assumes:
//!
//! * `thrust_gain/per_thruster` — each motor has its own gain (motors from different batches, a
//!   nicked propeller): port k(1 + r), starboard k(1 − r), top k.
//! * `thrust_gain/command_dependent` — the gain varies with the command, k(n) = k·(|n|/50 %)^e:
//!   the thrust curve's exponent differs from the baseline's 2 (an ESC whose output is not
//!   linear in its input).

use super::{ExpKind, FormParam, Part, TruthForm, truth_effect_meta};
use shoal_model::effects::{Effect, ThrustContext};
use std::sync::Arc;

/// Command at which [`CommandDependent`]'s gain is k [%].
const N_REF: f64 = 50.0;

const PER_THRUSTER: &str = "thrust_gain/per_thruster";
const PER_THRUSTER_LAW: &str = "thrust × k(1 + r) on port, × k(1 − r) on starboard, × k on top";
const COMMAND_DEPENDENT: &str = "thrust_gain/command_dependent";
const COMMAND_DEPENDENT_LAW: &str = "thrust × k·(|n|/50 %)^e";

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
    ]
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
