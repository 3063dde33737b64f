//! The verdict: which effects the log shows with strong evidence, which are only possible
//! (unstable under resampling, or not separable from another family), and where residual
//! structure stays unexplained.

use super::context::Search;
use super::fitted::Fit;
use super::measures::{STRUCTURE_RATIO, moved, noise_floor};
use super::nuisance::StandIn;
use super::rival::Rival;
use crate::log::run::ChannelKind;
use std::collections::BTreeMap;

/// What the search concludes.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Verdict {
    /// Effect families with strong evidence (selected stepwise, stable under resampling,
    /// identifiable), in the order they were chosen.
    pub effects: Vec<String>,
    /// The best-fitting form of each named effect (same order as `effects`).
    pub forms: Vec<String>,
    /// Weaker or ambiguous candidates, with their evidence.
    pub possible: Vec<Possible>,
    /// Pairs of effects the log cannot tell apart ("A or B").
    pub ambiguous: Vec<Ambiguity>,
    /// Channels whose held-out residuals stay structured with no family to explain them.
    pub unexplained: Vec<Unexplained>,
    /// Selection frequency of each stepwise effect over the block-bootstrap resamples (0…1):
    /// the share of resamples on which it passes its backward test and no alternative fitted
    /// in its place fits better.
    pub stability: BTreeMap<String, f64>,
    /// Inclusion probability P(family) over the resamples (0…1) of each stepwise effect and of
    /// each family fitted in its place: the share of resamples on which it holds the place.
    pub inclusion: BTreeMap<String, f64>,
}

impl Verdict {
    /// [`Verdict::inclusion`] most included first (ties by name).
    pub fn inclusion_ranked(&self) -> Vec<(&str, f64)> {
        let mut rows: Vec<(&str, f64)> = self
            .inclusion
            .iter()
            .map(|(f, p)| (f.as_str(), *p))
            .collect();
        rows.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(b.0)));
        rows
    }
}

/// A candidate without strong evidence.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Possible {
    /// Effect family.
    pub effect: String,
    /// Its best-fitting form.
    pub form: String,
    /// Why it is not named.
    pub reason: String,
    /// Its selection frequency over resamples (0…1), where measured.
    pub stability: Option<f64>,
}

/// Two effects the log cannot tell apart.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Ambiguity {
    /// The effect chosen stepwise, then the alternative that explains the data as well.
    pub effects: [String; 2],
    /// Held-out gain of the alternative over the chosen model (fraction; ≈ 0: as good).
    pub heldout_gain: f64,
    /// Held-out block test of the alternative against the chosen model.
    pub heldout_t: f64,
    /// Inclusion probability of each of the two over the block-bootstrap resamples (0…1; the
    /// share of resamples on which it holds the place), where measured.
    pub inclusion: Option<[f64; 2]>,
    /// Whether the resamples found it: the full log prefers the first, but its segments
    /// disagree — each family holds the place on part of the resamples.
    pub across_resamples: bool,
    /// The manoeuvre that would separate them.
    pub manoeuvre: String,
}

impl Ambiguity {
    /// Why the first effect is not named, in words.
    pub fn why(&self) -> String {
        let [a, b] = &self.effects;
        match self.inclusion {
            Some([p, q]) if self.across_resamples => format!(
                "holds its place on only {:.0} % of the block-bootstrap resamples and {b} on \
                 {:.0} %: the log's segments disagree which of the two they show (on the whole \
                 log, {b} in {a}'s place: held-out block t {:.1}); {}",
                100.0 * p,
                100.0 * q,
                self.heldout_t,
                self.manoeuvre
            ),
            _ => format!(
                "cannot be told apart from {b} on this log (held-out block t {:.1}); {}",
                self.heldout_t, self.manoeuvre
            ),
        }
    }
}

/// Residual structure that no family explains.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Unexplained {
    /// The channel.
    pub channel: ChannelKind,
    /// Held-out RMSE of the final model (channel unit).
    pub rmse: f64,
    /// Noise floor estimated from sample-to-sample differences of the held-out residuals
    /// (channel unit).
    pub noise_floor: f64,
    /// Ljung–Box p-value of the held-out residuals.
    pub ljung_box_p: f64,
}

/// The verdict, the model of its named effects, and the questions it leaves open (each "A or
/// B" with the alternative's model, each effect left possible against the model refitted
/// without it), from the resamples' selection frequency of each stepwise effect (`stability`)
/// and P(family) (`inclusion`, [`super::stability`]).
pub(super) fn conclude(
    s: &Search<'_>,
    stepwise: &Fit,
    ambiguous: Vec<(Ambiguity, Fit)>,
    stand_ins: &[StandIn],
    stability: BTreeMap<String, f64>,
    inclusion: BTreeMap<String, f64>,
) -> (Fit, Verdict, Vec<Rival>) {
    let opts = s.ctx.opts;
    let mut possible = Vec::new();
    let mut drop: Vec<String> = Vec::new();
    let mut rivals: Vec<Rival> = Vec::new();
    for (a, fit_b) in &ambiguous {
        rivals.push(Rival {
            a: a.effects[0].clone(),
            b: a.effects[1].clone(),
            fit_a: stepwise.clone(),
            fit_b: fit_b.clone(),
        });
    }
    for e in &stepwise.effects {
        let name = e.effect.name().to_string();
        let form = e.effect.form().to_string();
        let freq = stability.get(&name).copied();
        if let Some((a, fit_b)) = ambiguous.iter().find(|(a, _)| a.effects[0] == name) {
            possible.push(Possible {
                effect: name.clone(),
                form: form.clone(),
                reason: a.why(),
                stability: freq,
            });
            let alt = &a.effects[1];
            let alt_form = fit_b
                .effects
                .iter()
                .find(|e| e.effect.name() == alt)
                .map(|e| e.effect.form().to_string())
                .unwrap_or_default();
            possible.push(Possible {
                effect: alt.clone(),
                form: alt_form,
                reason: if a.across_resamples {
                    format!("takes {name}'s place on part of the resamples")
                } else {
                    format!("explains the held-out data as well as {name}")
                },
                stability: inclusion.get(alt).copied(),
            });
            drop.push(name);
        } else if let Some(si) = stand_ins.iter().find(|si| si.effect == name) {
            possible.push(Possible {
                effect: name.clone(),
                form,
                reason: format!(
                    "a stand-in for the form of {}: a non-parametric thrust map in its place \
                     fits the log better (ΔBIC {:.0}, effective {:.0}), so what it explains is \
                     the shape of a thrust map that {}'s form misses, not a law of its own",
                    si.main, si.delta_bic, si.delta_bic_eff, si.main
                ),
                stability: freq,
            });
            drop.push(name);
        } else if let Some((k, size)) =
            physical_size(s, stepwise, &name).filter(|(_, size)| *size < opts.physical_ratio)
        {
            possible.push(Possible {
                effect: name.clone(),
                form,
                reason: format!(
                    "too small to matter physically: at its fitted size it moves no channel's \
                     held-out prediction by as much as {} × the channel's noise floor (most: \
                     y.{}, {size:.2} ×)",
                    opts.physical_ratio,
                    k.name()
                ),
                stability: freq,
            });
            drop.push(name);
        } else if let Some(f) = freq.filter(|f| *f < opts.stability_threshold) {
            possible.push(Possible {
                effect: name.clone(),
                form,
                reason: format!(
                    "selected in only {:.0} % of {} block-bootstrap resamples (needed: {:.0} %)",
                    100.0 * f,
                    opts.stability_draws,
                    100.0 * opts.stability_threshold
                ),
                stability: Some(f),
            });
            drop.push(name);
        }
    }
    // Each effect left possible for a reason of its own: the model with it against the model
    // refitted without it.
    let ambiguous: Vec<Ambiguity> = ambiguous.into_iter().map(|(a, _)| a).collect();
    for n in drop
        .iter()
        .filter(|n| !ambiguous.iter().any(|a| &a.effects[0] == *n))
    {
        if let Some(without) = s.ctx.without(stepwise, n, &s.baseline) {
            rivals.push(Rival {
                a: n.clone(),
                b: format!("no {n}"),
                fit_a: stepwise.clone(),
                fit_b: without,
            });
        }
    }
    let mut chosen = stepwise.clone();
    for n in &drop {
        if let Some(r) = s.ctx.without(&chosen, n, &s.baseline) {
            chosen = r;
        }
    }
    let chosen = super::collapse::collapsed(s, chosen);
    let unexplained = unexplained(&chosen);
    let verdict = Verdict {
        effects: chosen.names(),
        forms: chosen
            .effects
            .iter()
            .map(|e| e.effect.form().to_string())
            .collect(),
        possible,
        ambiguous,
        unexplained,
        stability,
        inclusion,
    };
    (chosen, verdict, rivals)
}

/// The physical size of effect `name` of `fit`: the channel its fitted values move most and
/// by how much — the RMS change of the held-out prediction when the effect alone is set to its
/// null values (its shape parameters kept), over the channel's noise floor. `None` when the
/// replay without it fails.
fn physical_size(s: &Search<'_>, fit: &Fit, name: &str) -> Option<(ChannelKind, f64)> {
    let effects: Vec<_> = fit.effects.iter().map(|e| e.effect.clone()).collect();
    let values: Vec<f64> = fit
        .effects
        .iter()
        .flat_map(|e| {
            let off = e.effect.name() == name;
            e.params
                .iter()
                .map(move |p| if off && !p.shape { p.null } else { p.value })
        })
        .collect();
    let nulled = s.ctx.eval(&effects, &values)?;
    fit.eval
        .metrics
        .keys()
        .map(|&k| {
            let floor = noise_floor(&fit.eval, k);
            let size = moved(&fit.eval, &nulled, k) / floor.max(1e-300);
            (k, size)
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
}

/// Channels of `fit` whose held-out residuals fail the Ljung–Box test and whose RMS is more
/// than [`STRUCTURE_RATIO`] times the noise floor.
pub(super) fn unexplained(fit: &Fit) -> Vec<Unexplained> {
    let mut out = Vec::new();
    for (k, m) in &fit.eval.metrics {
        let noise = noise_floor(&fit.eval, *k);
        if !m.ljung_box.white() && m.rmse > STRUCTURE_RATIO * noise.max(1e-12) {
            out.push(Unexplained {
                channel: *k,
                rmse: m.rmse,
                noise_floor: noise,
                ljung_box_p: m.ljung_box.p_value,
            });
        }
    }
    out
}
