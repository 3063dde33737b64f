//! `thrust_asymmetry` truth forms — reverse thrust differs from the baseline's, but not by one
//! factor k_rev on every thruster as the fitting side assumes:
//!
//! * `thrust_asymmetry/reverse_exponent` — the reverse thrust curve has another exponent:
//!   f = −C⁻·n_max²·(|n|/n_max)^p with p > 2, right at full reverse and ever weaker below it
//!   (a propeller pitched for forward thrust stalls in reverse at low speed).
//! * `thrust_asymmetry/reverse_per_thruster` — each propeller's reverse thrust is scaled by its
//!   own factor (port k_p, starboard k_s, top their mean): propellers of one type but
//!   mounted with different clearances to the hull.
//! * `thrust_asymmetry/reverse_hull_wash` — in reverse the propeller's jet washes along the
//!   hull and drags on it: the reverse thrust loses a share growing with itself,
//!   f·(1 − a·|f|/f_max⁻), forward unchanged.
//! * `thrust_asymmetry/reverse_separation` — in reverse the flow separates from the blades as
//!   the propeller speeds up: the reverse thrust loses a share that grows with the command and
//!   levels off, f·(1 − a·(1 − e^(−|n|/n₀))), forward unchanged.
//!
//! The catalogue's `curve` form (reverse factor k_rev·(|n|/50 %)^e) has since matched
//! `reverse_exponent`, its `sided` form (reverse factor k_rev·(1 ± d) port/starboard, k_rev on
//! the centre line) `reverse_per_thruster`.

use super::effect_meta::truth_effect_meta;
use super::exp_kind::ExpKind;
use super::form_param::FormParam;
use super::truth_form::{Part, TruthForm};
use shoal_model::effects::{Effect, ThrustContext};
use std::sync::Arc;

const REVERSE_EXPONENT: &str = "thrust_asymmetry/reverse_exponent";
const REVERSE_EXPONENT_LAW: &str = "reverse thrust −C⁻·n_max²·(|n|/n_max)^p, forward unchanged";
const HULL_WASH: &str = "thrust_asymmetry/reverse_hull_wash";
const HULL_WASH_LAW: &str = "reverse thrust f·(1 − a·|f|/f_max⁻), forward unchanged";
const PER_THRUSTER: &str = "thrust_asymmetry/reverse_per_thruster";
const PER_THRUSTER_LAW: &str =
    "reverse thrust × k_p on port, × k_s on starboard, × (k_p + k_s)/2 on top";

const SEPARATION: &str = "thrust_asymmetry/reverse_separation";
const SEPARATION_LAW: &str = "reverse thrust f·(1 − a·(1 − e^(−|n|/n₀))), forward unchanged";

pub(super) fn forms() -> Vec<TruthForm> {
    vec![
        TruthForm {
            name: REVERSE_EXPONENT,
            family: "thrust_asymmetry",
            law: REVERSE_EXPONENT_LAW,
            params: vec![FormParam::magnitude(
                "p",
                "-",
                2.35,
                2.7,
                "exponent of the reverse thrust curve (baseline 2)",
            )],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| Part::Effect(Arc::new(ReverseExponent { p: p[0] })),
        },
        TruthForm {
            name: PER_THRUSTER,
            family: "thrust_asymmetry",
            law: PER_THRUSTER_LAW,
            params: vec![
                FormParam::deficit("k_port", "-", 0.6, 0.8, "reverse-thrust factor, port"),
                FormParam::shape(
                    "gap",
                    "-",
                    0.05,
                    0.12,
                    "starboard factor minus port factor, k_s − k_p",
                ),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Effect(Arc::new(ReversePerThruster {
                    k_port: p[0],
                    k_stbd: p[0] + p[1],
                }))
            },
        },
        TruthForm {
            name: HULL_WASH,
            family: "thrust_asymmetry",
            law: HULL_WASH_LAW,
            params: vec![FormParam::magnitude(
                "a",
                "-",
                0.25,
                0.45,
                "share of the full reverse thrust lost to the jet's drag on the hull",
            )],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| Part::Effect(Arc::new(ReverseHullWash { a: p[0] })),
        },
        TruthForm {
            name: SEPARATION,
            family: "thrust_asymmetry",
            law: SEPARATION_LAW,
            params: vec![
                FormParam::magnitude(
                    "a",
                    "-",
                    0.2,
                    0.35,
                    "share of the reverse thrust lost once the flow has separated",
                ),
                FormParam::shape(
                    "n0_pct",
                    "%",
                    20.0,
                    40.0,
                    "command scale of the separation n₀",
                ),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| Part::Effect(Arc::new(ReverseSeparation { a: p[0], n0: p[1] })),
        },
    ]
}

/// See the module documentation.
#[derive(Debug)]
struct ReverseHullWash {
    /// Share of the full reverse thrust lost \[-\].
    a: f64,
}

impl Effect for ReverseHullWash {
    truth_effect_meta!(HULL_WASH, HULL_WASH_LAW);
    fn thrust(&self, _p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        if f >= 0.0 {
            return f;
        }
        let rev = ctx.thruster.max_thrust_towards(f);
        if rev <= 0.0 {
            return f;
        }
        f * (1.0 - self.a * (f.abs() / rev).min(1.0))
    }
}

/// See the module documentation.
#[derive(Debug)]
struct ReverseSeparation {
    /// Share of the reverse thrust lost at large commands \[-\].
    a: f64,
    /// Command scale [%].
    n0: f64,
}

impl Effect for ReverseSeparation {
    truth_effect_meta!(SEPARATION, SEPARATION_LAW);
    fn thrust(&self, _p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        if f >= 0.0 {
            return f;
        }
        f * (1.0 - self.a * (1.0 - (-ctx.command.abs() / self.n0).exp()))
    }
}

/// See the module documentation.
#[derive(Debug)]
struct ReverseExponent {
    /// Exponent of the reverse curve \[-\].
    p: f64,
}

impl Effect for ReverseExponent {
    truth_effect_meta!(REVERSE_EXPONENT, REVERSE_EXPONENT_LAW);
    fn thrust(&self, _p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        if f >= 0.0 || ctx.thruster.max_command <= 0.0 {
            return f;
        }
        // The baseline's reverse curve is ∝ n²: rescale it to ∝ |n|^p, equal at n_max.
        let x = (ctx.command.abs() / ctx.thruster.max_command).min(1.0);
        f * x.powf(self.p - 2.0)
    }
}

/// See the module documentation.
#[derive(Debug)]
struct ReversePerThruster {
    /// Reverse-thrust factor of the port thruster \[-\].
    k_port: f64,
    /// Reverse-thrust factor of the starboard thruster \[-\].
    k_stbd: f64,
}

impl Effect for ReversePerThruster {
    truth_effect_meta!(PER_THRUSTER, PER_THRUSTER_LAW);
    fn thrust(&self, _p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        if f >= 0.0 {
            return f;
        }
        let k = match ctx.thruster.name.as_str() {
            "port" => self.k_port,
            "stbd" => self.k_stbd,
            _ => 0.5 * (self.k_port + self.k_stbd),
        };
        k * f
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shoal_model::presets;

    #[test]
    fn separation_loses_a_share_of_reverse_thrust_that_levels_off() {
        let form = forms().into_iter().find(|f| f.name == SEPARATION);
        let Part::Effect(e) = form.expect("registered").part(&[0.3, 25.0]) else {
            panic!("an effect")
        };
        let th = &presets::uauv2().thrusters[1];
        let at = |n: f64, f: f64| {
            let ctx = ThrustContext {
                t: 0.0,
                thruster: th,
                command: n,
                inflow: 0.0,
            };
            e.thrust(&[], &ctx, f)
        };
        // Reverse: f·(1 − 0.3·(1 − e^(−|n|/25 %))); at 25 % e^−1 = 0.367879, at 100 % e^−4.
        assert!((at(-25.0, -1.0) + (1.0 - 0.3 * (1.0 - 0.367_879))).abs() < 1e-6);
        assert!((at(-100.0, -2.0) + 2.0 * (1.0 - 0.3 * (1.0 - (-4.0_f64).exp()))).abs() < 1e-12);
        // Forward thrust is unchanged.
        assert_eq!(at(60.0, 1.5), 1.5);
    }
}
