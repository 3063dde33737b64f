//! Identifiability: can the log tell a chosen effect from another family?
//!
//! For each effect of the stepwise model, the most promising other families are fitted in its
//! place (the model without it, refitted, plus the alternative in its best form). If an
//! alternative would itself be selected there and explains the data about as well — its
//! held-out RMSE within `min_gain` of the chosen model's, the block test unable to prefer
//! either (|t| < 2) and the effective BIC of the two models within the selection
//! threshold — the log cannot separate the two: the verdict reports
//! "A or B" with the manoeuvre that would separate them. Every alternative that would be
//! selected in a chosen effect's place is kept as a [`Swap`]: on the resamples of the log,
//! stability selection asks which of the two each resample prefers.

use super::context::Search;
use super::fitted::Fit;
use super::measures::{delta_bic_eff, gain};
use super::par::par_map;
use super::step::Step;
use super::verdict::Ambiguity;
use crate::evaluate::blocks::heldout_t;
use crate::log::run::ChannelKind;
use shoal_model::effects::{self, FamilyFacts};

/// Block t below which the held-out data cannot prefer one of two models.
const AMBIGUOUS_T: f64 = 2.0;

/// How many alternatives are tried for each chosen effect.
const ALTERNATIVES: usize = 2;

/// A chosen effect with another family fitted in its place (the model without it, refitted,
/// plus the alternative in its best form), where the alternative would itself be selected
/// there: the rival a resample may prefer ([`super::stability`]).
#[derive(Clone, Debug)]
pub(super) struct Swap {
    /// The effect of the stepwise model.
    pub chosen: String,
    /// The family fitted in its place.
    pub alt: String,
    /// The model with the alternative in place of the chosen effect.
    pub fit: Fit,
    /// Held-out gain of the swapped model over the stepwise one (fraction; ≈ 0: as good).
    pub heldout_gain: f64,
    /// Held-out block test of the swapped model against the stepwise one.
    pub heldout_t: f64,
    /// Whether the full log cannot tell the two apart (see the module doc).
    pub ambiguous: bool,
}

impl Swap {
    /// The "A or B" this swap stands for, with the inclusion probabilities of its two families
    /// where measured.
    pub fn ambiguity(&self, inclusion: Option<[f64; 2]>, across_resamples: bool) -> Ambiguity {
        Ambiguity {
            effects: [self.chosen.clone(), self.alt.clone()],
            heldout_gain: self.heldout_gain,
            heldout_t: self.heldout_t,
            inclusion,
            across_resamples,
            manoeuvre: manoeuvre(&self.chosen, &self.alt),
        }
    }
}

/// The swaps of `stepwise`: for each of its effects, the [`ALTERNATIVES`] most promising other
/// families fitted in its place, kept where the alternative would itself be selected there;
/// each marked ambiguous where the log cannot tell it from the chosen effect.
pub(super) fn swaps(
    s: &Search<'_>,
    stepwise: &Fit,
    progress: &(dyn Fn(Step<'_>) + Sync),
) -> Vec<Swap> {
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
    let found: Vec<Option<Swap>> = par_map(&tries, opts.threads, |(name, reduced, alt)| {
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
        Some(Swap {
            chosen: name.clone(),
            alt: alt.clone(),
            fit,
            heldout_gain: g,
            heldout_t: t,
            ambiguous: g >= -opts.min_gain
                && t.abs() < AMBIGUOUS_T
                && d.abs() < -opts.bic_threshold,
        })
    });
    found.into_iter().flatten().collect()
}

/// The ambiguities among `swaps`: at most one per chosen effect (the first alternative the log
/// cannot tell from it), each with the alternative's model.
pub(super) fn ambiguities(swaps: &[Swap]) -> Vec<(Ambiguity, Fit)> {
    let mut out: Vec<(Ambiguity, Fit)> = Vec::new();
    for sw in swaps.iter().filter(|sw| sw.ambiguous) {
        if !out.iter().any(|(b, _)| b.effects[0] == sw.chosen) {
            out.push((sw.ambiguity(None, false), sw.fit.clone()));
        }
    }
    out
}

/// The channels the family shows in first, where it has such channels, and why the family is
/// not fitted on runs that log none of them (its
/// [`FamilyFacts::direct`](shoal_model::effects::FamilyFacts::direct)).
pub fn direct_channels(family: &str) -> Option<(Vec<ChannelKind>, &'static str)> {
    let direct = effects::facts(family)?.direct?;
    let kinds = direct
        .channels
        .iter()
        .filter_map(|c| ChannelKind::from_name(c))
        .collect();
    Some((kinds, direct.why_not_fitted))
}

/// The manoeuvre that would tell `a` from `b`: the one either family's facts name for the
/// other, else what excites each.
pub fn manoeuvre(a: &str, b: &str) -> String {
    let (fa, fb) = (effects::facts(a), effects::facts(b));
    let named = |f: Option<FamilyFacts>, other: &str| {
        f.and_then(|f| f.separations.iter().find(|s| s.0 == other).map(|s| s.1))
    };
    if let Some(m) = named(fa, b).or_else(|| named(fb, a)) {
        return m.into();
    }
    let excites = |f: Option<FamilyFacts>, name: &str| {
        f.map_or_else(
            || format!("an experiment that drives {name} alone"),
            |f| f.excitation.to_string(),
        )
    };
    format!(
        "to tell {a} from {b}: {} (excites {a}); {} (excites {b})",
        excites(fa, a),
        excites(fb, b)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every family's facts name log channels the log reader knows: a misspelt channel would
    /// silently make the family's direct channels empty.
    #[test]
    fn direct_channels_are_log_channels() {
        for f in effects::families() {
            if let Some(d) = f.facts.direct {
                let kinds = direct_channels(f.name()).unwrap().0;
                assert_eq!(
                    kinds.len(),
                    d.channels.len(),
                    "{}: {:?}",
                    f.name(),
                    d.channels
                );
            }
        }
        let (kinds, _) = direct_channels("restoring_moment").unwrap();
        use ChannelKind::*;
        assert_eq!(kinds, vec![Roll, Pitch, P, Q]);
        assert!(direct_channels("thrust_gain").is_none());
    }

    /// A pair with a manoeuvre of its own gets it in either order; others get what excites each.
    #[test]
    fn manoeuvres_come_from_the_families_facts() {
        let m = manoeuvre("buoyancy_offset", "depth_sensor_bias");
        assert_eq!(m, manoeuvre("depth_sensor_bias", "buoyancy_offset"));
        assert!(m.starts_with("surface at the start and at the end"), "{m}");
        assert!(
            manoeuvre("thrust_gain", "battery_sag").starts_with("repeat the same command step")
        );
        assert_eq!(
            manoeuvre("thruster_lag", "sensor_delay"),
            "to tell thruster_lag from sensor_delay: short command steps (0.5–2 s) up and down \
             (excites thruster_lag); fast command reversals (excites sensor_delay)"
        );
    }
}
