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
//!
//! The catalogue's `curve` form (reverse factor k_rev·(|n|/50 %)^e) has since matched
//! `reverse_exponent`.

use super::{ExpKind, FormParam, Part, TruthForm, truth_effect_meta};
use shoal_model::effects::{Effect, ThrustContext};
use std::sync::Arc;

const REVERSE_EXPONENT: &str = "thrust_asymmetry/reverse_exponent";
const REVERSE_EXPONENT_LAW: &str = "reverse thrust −C⁻·n_max²·(|n|/n_max)^p, forward unchanged";
const HULL_WASH: &str = "thrust_asymmetry/reverse_hull_wash";
const HULL_WASH_LAW: &str = "reverse thrust f·(1 − a·|f|/f_max⁻), forward unchanged";
const PER_THRUSTER: &str = "thrust_asymmetry/reverse_per_thruster";
const PER_THRUSTER_LAW: &str =
    "reverse thrust × k_p on port, × k_s on starboard, × (k_p + k_s)/2 on top";

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
