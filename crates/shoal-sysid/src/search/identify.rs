//! Identifiability: can the log tell a chosen effect from another family?
//!
//! For each effect of the stepwise model, the most promising other families are fitted in its
//! place (the model without it, refitted, plus the alternative in its best form). If an
//! alternative would itself be selected there and explains the data about as well — its
//! held-out RMSE within `min_gain` of the chosen model's, the block test unable to prefer
//! either (|t| < 2) and the effective BIC of the two models within the selection
//! threshold — the log cannot separate the two: the verdict reports
//! "A or B" with the manoeuvre that would separate them.

use super::Step;
use super::context::Search;
use super::fitted::Fit;
use super::measures::{delta_bic_eff, gain};
use super::par::par_map;
use super::verdict::Ambiguity;
use crate::evaluate::blocks::heldout_t;
use crate::log::run::ChannelKind;

/// Block t below which the held-out data cannot prefer one of two models.
const AMBIGUOUS_T: f64 = 2.0;

/// How many alternatives are tried for each chosen effect.
const ALTERNATIVES: usize = 2;

/// The ambiguities of `stepwise`: pairs (chosen, alternative) the log cannot tell apart.
pub(super) fn ambiguities(
    s: &Search<'_>,
    stepwise: &Fit,
    progress: &(dyn Fn(Step<'_>) + Sync),
) -> Vec<Ambiguity> {
    let opts = s.ctx.opts;
    let names = stepwise.names();
    let mut tries: Vec<(String, Fit, String)> = Vec::new();
    for name in &names {
        let Some(reduced) = s.ctx.without(stepwise, name, &s.baseline) else {
            continue;
        };
        for alt in s.promising(&reduced, &names).into_iter().take(ALTERNATIVES) {
            tries.push((name.clone(), reduced.clone(), alt));
        }
    }
    let found: Vec<Option<Ambiguity>> = par_map(&tries, opts.threads, |(name, reduced, alt)| {
        let c = s.candidate(0, reduced, alt)?;
        progress(Step::Fit(&format!("{alt} in place of {name}")));
        if !c.significant {
            return None;
        }
        let fit = c.fit?;
        let g = gain(&stepwise.eval, &fit.eval);
        let t = heldout_t(&stepwise.eval, &fit.eval, opts.block_s, None);
        // The estimation data must not tell them apart either: the effective BIC of the two
        // models differs by less than the selection threshold.
        let d = delta_bic_eff(stepwise, &fit, None);
        (g >= -opts.min_gain && t.abs() < AMBIGUOUS_T && d.abs() < -opts.bic_threshold).then(|| {
            Ambiguity {
                effects: [name.clone(), alt.clone()],
                heldout_gain: g,
                heldout_t: t,
                manoeuvre: manoeuvre(name, alt),
            }
        })
    });
    let mut out: Vec<Ambiguity> = Vec::new();
    for a in found.into_iter().flatten() {
        if !out.iter().any(|b| b.effects[0] == a.effects[0]) {
            out.push(a);
        }
    }
    out
}

/// What excites an effect family most clearly, in words.
pub fn excitation(family: &str) -> &'static str {
    match family {
        "thruster_lag" => "short command steps (0.5–2 s) up and down",
        "thrust_gain" => "steps to several command levels in both directions",
        "thrust_asymmetry" => "equal forward and reverse commands",
        "thruster_deadband" => "slow ramps through zero and small commands (±5–15 %)",
        "battery_sag" => "the same command step repeated at the start and at the end of a long run",
        "inflow_thrust_loss" => {
            "the same command from rest and while already moving along the thrust axis"
        }
        "buoyancy_offset" => "idle phases (all thrusters off) at several depths",
        "ballast_mass" => "pump phases with the thrusters off",
        "damping_error" => "coasting down from several speeds",
        "added_mass_error" => "short, hard accelerations from rest",
        "water_current" => "holding station with the position tracked",
        "depth_sensor_bias" => {
            "a surface check (the reading at zero depth) at the start and at the end"
        }
        "sensor_delay" => "fast command reversals",
        "thrust_coupling" => "vertical thrust steps with the heading logged",
        "thrust_saturation" => "full-scale commands next to half-scale ones",
        "restoring_moment" => "resting at depth with roll and pitch logged (the resting tilt)",
        "tether_drag" => "travelling away from the anchor and back with the position tracked",
        _ => "an experiment that drives this effect alone",
    }
}

/// The channels a family shows in first, where it has such channels, and why the family is
/// not fitted on runs that log none of them. Without them only second-order marks remain (a
/// tilted hull's thrust pointing a little off), too easily taken for the direct marks of
/// other families (a thrust loss, a buoyancy offset) for a verdict to rest on.
pub fn direct_channels(family: &str) -> Option<(&'static [ChannelKind], &'static str)> {
    match family {
        "restoring_moment" => Some((
            &[
                ChannelKind::Roll,
                ChannelKind::Pitch,
                ChannelKind::P,
                ChannelKind::Q,
            ],
            "not fitted: these runs log neither roll nor pitch (nor their rates), where a \
             shifted centre of gravity shows first",
        )),
        // A tether's pull grows with the distance from its anchor: without the position (or
        // the horizontal velocity) a log cannot place the hull relative to the anchor, and
        // the cable's drag is just more drag, or less thrust, at speed — the damping-error and
        // inflow families' marks (on the BlueROV yaw runs it fitted C_d·d at its bound as a
        // stand-in for the damping error; in a mission the inflow loss won instead of it).
        "tether_drag" => Some((
            &[
                ChannelKind::X,
                ChannelKind::Y,
                ChannelKind::U,
                ChannelKind::V,
            ],
            "not fitted: these runs log neither the horizontal position nor the horizontal \
             velocity, which a tether's pull depends on (its distance from the anchor)",
        )),
        _ => None,
    }
}

/// The manoeuvre that would tell `a` from `b`.
pub fn manoeuvre(a: &str, b: &str) -> String {
    let pair = |x: &str, y: &str| (a == x && b == y) || (a == y && b == x);
    if pair("buoyancy_offset", "depth_sensor_bias") {
        return "surface at the start and at the end (a sensor bias reads ≠ 0 at the surface, a \
                buoyancy offset does not) and hold a depth with the thrusters off (a buoyancy \
                offset moves the vehicle, a sensor bias only the reading)"
            .into();
    }
    if pair("thrust_gain", "battery_sag") {
        return "repeat the same command step at the start and at the end of the run (a sag \
                changes the response over time, a gain does not)"
            .into();
    }
    format!(
        "to tell {a} from {b}: {} (excites {a}); {} (excites {b})",
        excitation(a),
        excitation(b)
    )
}
