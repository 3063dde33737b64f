//! Stability selection and inclusion probabilities: which family holds each place of the model
//! when the log is resampled?
//!
//! The stepwise model is refitted on block-bootstrap resamples of the log
//! ([`crate::evaluate::blocks::Resample`]: estimation and validation blocks drawn with replacement, a
//! warm start from the full-data fit with a few Levenberg–Marquardt iterations), and so is each
//! [`Swap`] (the model with another family in a chosen effect's place). On each resample a place
//! goes to the best swap that beats the stepwise model there on both halves (lower BIC on the
//! resampled estimation blocks, lower error on the resampled validation blocks); otherwise to the
//! chosen effect if it passes its backward test with the resample's statistics: ΔBIC on the
//! resampled estimation blocks; held-out gain, block test and materiality (share of the baseline's
//! held-out error, or of the gap to the noise floor, that the effect removes) on the resampled
//! validation blocks; otherwise to none. A family's inclusion probability P(family) is the share
//! of resamples on which it holds a place; a chosen effect's is its selection frequency. (The
//! backward checks' effective-ΔBIC rule is not repeated: a resample duplicates blocks, and its
//! count of independent samples is not defined.)
//!
//! Two families that share a place across the resamples — neither held it often enough to be
//! named, together they did — are an "A or B" ([`substitutes`]): the log's segments disagree on
//! which of the two it shows.

use super::context::Search;
use super::fit::Ctx;
use super::fitted::Fit;
use super::identify::Swap;
use super::measures::{bic_resampled, closure_resampled, gain_resampled, material_resampled};
use super::par::par_map;
use super::step::Step;
use super::verdict::Ambiguity;
use crate::evaluate::blocks::{Resample, heldout_t};
use crate::evaluate::lm::LmOptions;
use std::collections::BTreeMap;

/// Levenberg–Marquardt iterations of a warm refit on a resample.
const REFIT_ITERATIONS: usize = 6;

/// The least inclusion probability of each family of an "A or B" found across resamples: two
/// resamples of the default eight.
pub const SUBSTITUTE_SHARE: f64 = 0.25;

/// What the resamples say.
#[derive(Clone, Debug, Default)]
pub(super) struct Inclusion {
    /// Selection frequency (0…1) of each stepwise effect.
    pub chosen: BTreeMap<String, f64>,
    /// Inclusion probability (0…1) of each stepwise effect and each swap's alternative.
    pub all: BTreeMap<String, f64>,
}

/// Who holds a place on one resample.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Holder {
    /// The chosen effect.
    Chosen,
    /// The alternative of the swap with this index.
    Swap(usize),
    /// Nobody: the effect fails its backward test and no swap beats the model.
    None,
}

/// Inclusion probabilities of the effects of `stepwise` and of the alternatives of `swaps`
/// over the resamples; empty when `stepwise` has no effect or no resamples are asked for.
pub(super) fn inclusion(
    s: &Search<'_>,
    stepwise: &Fit,
    swaps: &[Swap],
    progress: &(dyn Fn(Step<'_>) + Sync),
) -> Inclusion {
    let opts = s.ctx.opts;
    let names = stepwise.names();
    if names.is_empty() || opts.stability_draws == 0 {
        return Inclusion::default();
    }
    progress(Step::Stage {
        stage: "stability over resamples",
        fits: Some(opts.stability_draws),
    });
    let draws: Vec<u64> = (0..opts.stability_draws as u64).collect();
    let holders: Vec<Vec<Holder>> = par_map(&draws, opts.threads, |&d| {
        let rs = Resample::draw(
            &stepwise.eval,
            opts.block_s,
            opts.seed.wrapping_add(d.wrapping_mul(0x9e37_79b9)),
        );
        let ctx = Ctx {
            ds: s.ctx.ds,
            base: s.ctx.base,
            factors: s.ctx.factors.clone(),
            opts,
            resample: Some(&rs),
            lm: LmOptions {
                max_iterations: REFIT_ITERATIONS,
                ..opts.lm
            },
            memo: s.ctx.memo,
        };
        // Refit everything (no effect is named "")…
        let Some(full) = ctx.without(stepwise, "", &s.baseline) else {
            return vec![Holder::None; names.len()];
        };
        progress(Step::Fit(&format!("resample {}", d + 1)));
        let bic_full = bic_resampled(&full.eval, full.k, Some(&rs));
        // …each swap, scored where it beats the model on both halves of the resample…
        let beats: Vec<Option<f64>> = swaps
            .iter()
            .map(|sw| {
                let f = ctx.without(&sw.fit, "", &s.baseline)?;
                let b = bic_resampled(&f.eval, f.k, Some(&rs));
                (b < bic_full && gain_resampled(&full.eval, &f.eval, Some(&rs)) > 0.0).then_some(b)
            })
            .collect();
        // …and each effect's backward test on this resample.
        names
            .iter()
            .map(|n| {
                let best_swap = swaps
                    .iter()
                    .enumerate()
                    .filter(|(_, sw)| &sw.chosen == n)
                    .filter_map(|(i, _)| beats[i].map(|b| (i, b)))
                    .min_by(|a, b| a.1.total_cmp(&b.1));
                if let Some((i, _)) = best_swap {
                    return Holder::Swap(i);
                }
                let passes = ctx.without(&full, n, &s.baseline).is_some_and(|red| {
                    bic_full - bic_resampled(&red.eval, red.k, Some(&rs)) < opts.bic_threshold
                        && gain_resampled(&red.eval, &full.eval, Some(&rs)) >= opts.min_gain
                        && heldout_t(&red.eval, &full.eval, opts.block_s, Some(&rs))
                            >= opts.t_threshold
                        && (material_resampled(&s.baseline.eval, &red.eval, &full.eval, Some(&rs))
                            >= opts.min_material
                            || closure_resampled(&red.eval, &full.eval, Some(&rs))
                                >= opts.min_closure)
                });
                if passes { Holder::Chosen } else { Holder::None }
            })
            .collect()
    });
    tally(&names, swaps, &holders)
}

/// The shares of `holders` (per resample, the holder of each place of `names`).
fn tally(names: &[String], swaps: &[Swap], holders: &[Vec<Holder>]) -> Inclusion {
    let share = |held: &dyn Fn(&[Holder]) -> bool| {
        holders.iter().filter(|h| held(h)).count() as f64 / holders.len().max(1) as f64
    };
    let mut out = Inclusion::default();
    for (i, n) in names.iter().enumerate() {
        let p = share(&|h| h[i] == Holder::Chosen);
        out.chosen.insert(n.clone(), p);
        out.all.insert(n.clone(), p);
    }
    for sw in swaps {
        if out.all.contains_key(&sw.alt) {
            continue;
        }
        let alt = &sw.alt;
        let p = share(&|h| {
            h.iter()
                .any(|x| matches!(x, Holder::Swap(j) if &swaps[*j].alt == alt))
        });
        out.all.insert(alt.clone(), p);
    }
    out
}

/// The "A or B"s of the whole log (`ambiguous`), each with its two families' inclusion
/// probabilities, then those the resamples show ([`substitutes`]).
pub(super) fn with_inclusion(
    mut ambiguous: Vec<(Ambiguity, Fit)>,
    swaps: &[Swap],
    inc: &Inclusion,
    threshold: f64,
) -> Vec<(Ambiguity, Fit)> {
    for (a, _) in &mut ambiguous {
        let [x, y] = &a.effects;
        a.inclusion = inc.all.get(x).zip(inc.all.get(y)).map(|(p, q)| [*p, *q]);
    }
    let known: Vec<String> = ambiguous
        .iter()
        .map(|(a, _)| a.effects[0].clone())
        .collect();
    ambiguous.extend(substitutes(swaps, inc, threshold, &known));
    ambiguous
}

/// The "A or B"s the resamples show: a chosen effect not named for its selection frequency
/// (below `threshold`) and the alternative that most often took its place, where each held the
/// place on at least [`SUBSTITUTE_SHARE`] of the resamples and the two together on at least
/// `threshold` — each with the alternative's model. Effects in `known` (already an "A or B" on
/// the full log) are left out.
pub(super) fn substitutes(
    swaps: &[Swap],
    inc: &Inclusion,
    threshold: f64,
    known: &[String],
) -> Vec<(Ambiguity, Fit)> {
    let mut out: Vec<(Ambiguity, Fit)> = Vec::new();
    for (name, &p) in &inc.chosen {
        if p >= threshold || known.contains(name) {
            continue;
        }
        let best = swaps
            .iter()
            .filter(|sw| &sw.chosen == name)
            .filter_map(|sw| inc.all.get(&sw.alt).map(|q| (sw, *q)))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        if let Some((sw, q)) = best
            && p >= SUBSTITUTE_SHARE
            && q >= SUBSTITUTE_SHARE
            && p + q >= threshold
        {
            out.push((sw.ambiguity(Some([p, q]), true), sw.fit.clone()));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluate::evaluation::Evaluation;

    fn fit() -> Fit {
        Fit {
            effects: Vec::new(),
            k: 0,
            eval: Evaluation {
                runs: Vec::new(),
                metrics: BTreeMap::new(),
            },
            evaluations: 0,
            free: Vec::new(),
            cov: None,
            cov_white: None,
        }
    }

    fn swap(chosen: &str, alt: &str) -> Swap {
        Swap {
            chosen: chosen.into(),
            alt: alt.into(),
            fit: fit(),
            heldout_gain: 0.0,
            heldout_t: -2.5,
            ambiguous: false,
        }
    }

    /// Eight resamples: the gain holds its place on 4, the saturation takes it on 3, one has
    /// neither; the lag is chosen on all. P: 0.5, 0.375, 1; the gain and the saturation are an
    /// "A or B" (together 7 of 8 ≥ 0.8), the lag is named.
    #[test]
    fn two_families_sharing_a_place_are_an_a_or_b() {
        use Holder::*;
        let names = vec!["thrust_gain".to_string(), "thruster_lag".to_string()];
        let swaps = vec![
            swap("thrust_gain", "thrust_saturation"),
            swap("thrust_gain", "battery_sag"),
        ];
        let h = |a: Holder| vec![a, Chosen];
        let holders = vec![
            h(Chosen),
            h(Swap(0)),
            h(Chosen),
            h(Swap(0)),
            h(None),
            h(Chosen),
            h(Swap(0)),
            h(Chosen),
        ];
        let inc = tally(&names, &swaps, &holders);
        assert_eq!(inc.chosen["thrust_gain"], 0.5);
        assert_eq!(inc.chosen["thruster_lag"], 1.0);
        assert_eq!(inc.all["thrust_saturation"], 0.375);
        assert_eq!(inc.all["battery_sag"], 0.0);
        let ab = substitutes(&swaps, &inc, 0.8, &[]);
        assert_eq!(ab.len(), 1);
        assert_eq!(ab[0].0.effects, ["thrust_gain", "thrust_saturation"]);
        assert_eq!(ab[0].0.inclusion, Some([0.5, 0.375]));
        // Already an "A or B" on the full log: not repeated.
        assert!(substitutes(&swaps, &inc, 0.8, &names[..1]).is_empty());
    }

    /// An unstable effect whose place is mostly left empty is not an "A or B": 3 of 8 for the
    /// gain, 2 of 8 for the saturation (together 5 of 8 < 0.8); nor is a rare substitute
    /// beside a nearly stable effect (6 of 8 and 1 of 8).
    #[test]
    fn an_empty_place_or_a_rare_substitute_is_no_a_or_b() {
        use Holder::*;
        let names = vec!["thrust_gain".to_string()];
        let swaps = vec![swap("thrust_gain", "thrust_saturation")];
        let of = |v: &[Holder]| v.iter().map(|h| vec![*h]).collect::<Vec<_>>();
        let sparse = of(&[Chosen, None, Swap(0), None, Chosen, None, Swap(0), Chosen]);
        let inc = tally(&names, &swaps, &sparse);
        assert_eq!(
            (inc.chosen["thrust_gain"], inc.all["thrust_saturation"]),
            (0.375, 0.25)
        );
        assert!(substitutes(&swaps, &inc, 0.8, &[]).is_empty());
        let rare = of(&[
            Chosen,
            Chosen,
            Swap(0),
            Chosen,
            Chosen,
            None,
            Chosen,
            Chosen,
        ]);
        let inc = tally(&names, &swaps, &rare);
        assert_eq!(
            (inc.chosen["thrust_gain"], inc.all["thrust_saturation"]),
            (0.75, 0.125)
        );
        assert!(substitutes(&swaps, &inc, 0.8, &[]).is_empty());
    }
}
