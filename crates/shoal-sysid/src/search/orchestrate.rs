//! The search from start to verdict: round 1 (every family alone, forms competing), forward
//! rounds, backward checks and swaps, then identifiability, stability and the verdict.

use super::candidate::{Candidate, FormScore};
use super::context::{FormInfo, Search};
use super::fit::Ctx;
use super::fitted::Fit;
use super::measures::{bic, heldout_ratio};
use super::memo::Memo;
use super::options::{SearchOptions, families};
use super::outcome::Outcome;
use super::par::par_map;
use super::rules::{choose, judge, skipped};
use super::step::Step;
use super::{identify, nuisance, pairs, refine, stability, verdict};
use crate::evaluate::dataset::Dataset;
use shoal_model::effects::Effect;
use shoal_model::vehicle::VehicleParams;
use std::collections::BTreeMap;
use std::sync::Arc;

/// One round-1 fit: (family index, form, the fit with its excitation or why there is none).
type RoundOne = (usize, Arc<dyn Effect>, Result<(Fit, Vec<bool>), String>);

/// The model refitted without each of its families, as the last backward check left it.
type Reduced = Vec<(String, Option<Fit>)>;

/// Searches the effects of `opts` for the ones that explain `ds` better than `base`.
/// `progress` hears each stage as it begins and each candidate fit as it ends.
pub fn search(
    ds: &Dataset,
    base: &VehicleParams,
    opts: &SearchOptions,
    progress: &(dyn Fn(Step<'_>) + Sync),
) -> Outcome {
    let baseline = baseline_fit(ds, base, opts);
    let factors = baseline.eval.ml_factors();
    let memo = Memo::new(Memo::BUDGET);
    let ctx = Ctx {
        ds,
        base,
        factors: factors.clone(),
        opts,
        resample: None,
        lm: opts.lm,
        memo: &memo,
    };
    let fams = families(&opts.effects);
    // Round 1: every form of every family alone on the baseline.
    progress(Step::Stage {
        stage: "round 1: every form of every family alone",
        fits: Some(fams.iter().map(|(_, forms)| forms.len()).sum()),
    });
    let fitted = round_one_fits(&ctx, &fams, progress);
    let (forms, mut candidates) = round_one(&fams, &fitted, &baseline, opts);
    let s = Search {
        ctx,
        baseline: baseline.clone(),
        forms,
    };
    progress(Step::Stage {
        stage: "forward rounds",
        fits: None,
    });
    let (current, first, round) = forward(&s, &baseline, &mut candidates, progress);
    progress(Step::Stage {
        stage: "backward checks and swaps",
        fits: None,
    });
    let (current, reduced, round) = backward_and_swaps(
        &s,
        &baseline,
        current,
        first,
        round,
        &mut candidates,
        progress,
    );
    // Each family's form chosen again beside the final others (see `refine.rs`).
    let (current, changes) = refine::refine_forms(&s, current, reduced, round, progress);
    candidates.extend(changes);
    let stepwise = current.clone();
    // Identifiability, stability, verdict.
    progress(Step::Stage {
        stage: "identifiability",
        fits: None,
    });
    let swaps = identify::swaps(&s, &stepwise, progress);
    let ambiguous = identify::ambiguities(&swaps);
    let stand_ins = nuisance::stand_ins(&s, &stepwise, progress);
    let inclusion = stability::inclusion(&s, &stepwise, &swaps, progress);
    let ambiguous =
        stability::with_inclusion(ambiguous, &swaps, &inclusion, opts.stability_threshold);
    let (chosen, verdict, rivals) = verdict::conclude(
        &s,
        &stepwise,
        ambiguous,
        &stand_ins,
        inclusion.chosen,
        inclusion.all,
    );
    Outcome {
        baseline,
        candidates,
        chosen,
        stepwise,
        verdict,
        factors,
        rivals,
    }
}

/// The baseline (`base` with the options' own effects), evaluated: the model every candidate
/// is measured against.
fn baseline_fit(ds: &Dataset, base: &VehicleParams, opts: &SearchOptions) -> Fit {
    let base_eval = ds.evaluate(&opts.baseline_model(base, ds.env.density));
    Fit {
        effects: Vec::new(),
        k: 0,
        eval: base_eval,
        evaluations: 1,
        free: Vec::new(),
        cov: None,
        cov_white: None,
    }
}

/// Round 1's fits: every form of every family of `fams` alone on the baseline, each with the
/// parameters the data excite, from the null and the typical values and a scan.
fn round_one_fits(
    ctx: &Ctx<'_>,
    fams: &[(String, Vec<Arc<dyn Effect>>)],
    progress: &(dyn Fn(Step<'_>) + Sync),
) -> Vec<RoundOne> {
    let base = ctx.base;
    let items: Vec<(usize, Arc<dyn Effect>)> = fams
        .iter()
        .enumerate()
        .flat_map(|(i, (_, forms))| forms.iter().map(move |e| (i, e.clone())))
        .collect();
    par_map(&items, ctx.opts.threads, |(i, e)| {
        let unseen = identify::direct_channels(e.name())
            .filter(|(kinds, _)| !kinds.iter().any(|k| ctx.factors.contains_key(k)));
        let r = if let Some(why) = e.not_applicable(base) {
            Err(format!("does not apply: {why}"))
        } else if let Some((_, why)) = unseen {
            Err(why.to_string())
        } else {
            let excited = ctx.excited(e);
            if !excited.iter().any(|&x| x) {
                Err("not excited: no input or measurement of these runs shows it".into())
            } else {
                let infos = e.params(base);
                let starts = vec![
                    infos.iter().map(|p| p.null).collect(),
                    infos.iter().map(|p| p.typical).collect(),
                ];
                ctx.fit(std::slice::from_ref(e), &excited, &starts, Some(0))
                    .map(|f| (f, excited))
                    .ok_or_else(|| "the replay failed for every start".to_string())
            }
        };
        progress(Step::Fit(&format!("{} ({})", e.name(), e.form())));
        (*i, e.clone(), r)
    })
}

/// What round 1 learnt: per family, its forms that fitted (with their excitation and round-1
/// values), and the family's round-1 candidate (its forms judged, or why none was fitted).
fn round_one(
    fams: &[(String, Vec<Arc<dyn Effect>>)],
    fitted: &[RoundOne],
    baseline: &Fit,
    opts: &SearchOptions,
) -> (BTreeMap<String, Vec<FormInfo>>, Vec<Candidate>) {
    let mut candidates = Vec::new();
    let mut forms: BTreeMap<String, Vec<FormInfo>> = BTreeMap::new();
    for (fi, (name, _)) in fams.iter().enumerate() {
        let mine: Vec<&RoundOne> = fitted.iter().filter(|(i, _, _)| *i == fi).collect();
        let mut fits: Vec<Fit> = Vec::new();
        let mut scores = Vec::new();
        let mut why = None;
        for (_, e, r) in &mine {
            match r {
                Ok((fit, excited)) => {
                    let score = FormScore::of(e.form(), baseline, fit);
                    forms.entry(name.clone()).or_default().push(FormInfo {
                        effect: e.clone(),
                        excited: excited.clone(),
                        first: Some(fit.effects[0].params.iter().map(|p| p.value).collect()),
                    });
                    scores.push(score);
                    fits.push(fit.clone());
                }
                Err(w) => why = why.or(Some(w.clone())),
            }
        }
        let c = if fits.is_empty() {
            skipped(1, name, why.unwrap_or_else(|| "no form applies".into()))
        } else {
            choose(1, name, baseline, fits, scores, opts, &baseline.eval)
        };
        candidates.push(c);
    }
    (forms, candidates)
}

/// The forward rounds from the baseline: the best passing family of each round joins, the
/// families promising on top of it are tried in the next round, pairs where none passes alone
/// while structure is left. Returns the model, the family that joined alone in round 1 (if
/// one did) and the last round.
fn forward(
    s: &Search<'_>,
    baseline: &Fit,
    candidates: &mut Vec<Candidate>,
    progress: &(dyn Fn(Step<'_>) + Sync),
) -> (Fit, Option<String>, usize) {
    let opts = s.ctx.opts;
    let mut current = baseline.clone();
    let mut round = 1;
    let mut paired = 0;
    // The family that joined alone in round 1, if one did.
    let mut first: Option<String> = None;
    loop {
        // Of the families that pass, the one that predicts the held-out data best joins (the
        // estimation data's BIC already gated each; ranking by it prefers a flexible law that
        // follows the fitted stretch over the physics that carries on beyond it). Judged over
        // every channel, so a family that improves four channels is not ranked below one
        // that improves only the two it touches.
        let base = &current;
        let best = candidates
            .iter()
            .filter(|c| c.round == round && !c.backward && c.significant)
            .filter_map(|c| {
                c.fit
                    .as_ref()
                    .map(|f| (c, heldout_ratio(&base.eval, &f.eval)))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(c, _)| c);
        let Some(fit) = best.and_then(|c| c.fit.clone()) else {
            // No family passes alone: while structure is left and there is room for two,
            // the round's most promising families are tried in pairs (see `pairs.rs`).
            if paired < round
                && current.effects.len() + 2 <= opts.max_effects
                && !verdict::unexplained(&current).is_empty()
            {
                paired = round;
                let this: Vec<&Candidate> = candidates
                    .iter()
                    .filter(|c| c.round == round && !c.backward)
                    .collect();
                let found = pairs::pair_candidates(s, round, &current, &this, progress);
                candidates.extend(found);
                continue;
            }
            break;
        };
        if round == 1 && fit.effects.len() == 1 {
            first = fit.names().pop();
        }
        current = fit;
        if current.effects.len() >= opts.max_effects {
            break;
        }
        // Nothing left to explain: every channel's held-out residuals are white (Ljung–Box at
        // 5 %), so a further family could only fit noise; the rounds it would take are skipped.
        if current.eval.metrics.values().all(|m| m.ljung_box.white()) {
            break;
        }
        round += 1;
        let tries = s.promising(&current, &[]);
        if tries.is_empty() {
            break;
        }
        let cur = &current;
        let next: Vec<Candidate> = par_map(&tries, opts.threads, |name| {
            let c = s.candidate(round, cur, name).unwrap_or_else(|| {
                skipped(round, name, "the replay failed for every start".into())
            });
            progress(Step::Fit(name));
            c
        });
        candidates.extend(next);
    }
    (current, first, round)
}

/// Backward checks, then swaps of one effect for another where that lowers the BIC
/// (equivalent explanations with fewer parameters), then backward checks again.
/// A single effect left by the backward checks is swapped too, for a family that alone
/// beats it on both counts, BIC and held-out prediction: the forward rounds may have
/// started from a family that only stood in for the true one (a saturation for an inflow
/// loss) and the backward checks then removed both, leaving a third. (The held-out
/// condition: the forward rounds rank families by held-out prediction, and a swap of the
/// only effect must not overturn that ranking by the BIC alone.) Returns the model, its
/// refits without each family as the last backward check left them, and the last round.
fn backward_and_swaps(
    s: &Search<'_>,
    baseline: &Fit,
    mut current: Fit,
    first: Option<String>,
    mut round: usize,
    candidates: &mut Vec<Candidate>,
    progress: &(dyn Fn(Step<'_>) + Sync),
) -> (Fit, Reduced, usize) {
    let mut swaps = 0;
    // The model refitted without each of its families, as the last backward check left it.
    let mut reduced: Reduced = Vec::new();
    loop {
        backward(
            s,
            baseline,
            &mut current,
            &mut round,
            &mut reduced,
            candidates,
            progress,
        );
        // A single effect that round 1 chose is not swapped: round 1 compared every family
        // alone by the same measures already.
        let chosen_alone = current.effects.len() == 1 && first == current.names().pop();
        if current.effects.is_empty() || chosen_alone || swaps >= 2 {
            break;
        }
        let Some(c) = best_swap(s, &current, &reduced, round, progress) else {
            break;
        };
        round += 1;
        swaps += 1;
        if let Some(f) = &c.fit {
            current = f.clone();
        }
        candidates.push(c);
    }
    (current, reduced, round)
}

/// The backward checks: every effect of `current` judged against the model refitted without
/// it, the weakest failing one removed, until every one passes. `reduced` becomes the refits
/// of the last check (it is left as it was when `current` has no effect).
fn backward(
    s: &Search<'_>,
    baseline: &Fit,
    current: &mut Fit,
    round: &mut usize,
    reduced: &mut Reduced,
    candidates: &mut Vec<Candidate>,
    progress: &(dyn Fn(Step<'_>) + Sync),
) {
    let opts = s.ctx.opts;
    while !current.effects.is_empty() {
        *round += 1;
        let round = *round;
        let names = current.names();
        let cur = &*current;
        let checks: Vec<(Candidate, Option<Fit>)> = par_map(&names, opts.threads, |name| {
            let r = s.ctx.without(cur, name, baseline);
            let c = match &r {
                Some(r) => judge(round, name, r, cur.clone(), opts, true, &baseline.eval),
                None => Candidate {
                    significant: true,
                    backward: true,
                    ..skipped(
                        round,
                        name,
                        "kept: the model without it could not be replayed".into(),
                    )
                },
            };
            progress(Step::Fit(name));
            (c, r)
        });
        let weakest = checks
            .iter()
            .filter(|(c, r)| !c.significant && r.is_some())
            .max_by(|a, b| a.0.delta_bic_eff.total_cmp(&b.0.delta_bic_eff))
            .and_then(|(_, r)| r.clone());
        *reduced = checks
            .iter()
            .map(|(c, r)| (c.effect.clone(), r.clone()))
            .collect();
        candidates.extend(checks.into_iter().map(|(c, _)| c));
        match weakest {
            Some(r) => *current = r,
            None => break,
        }
    }
}

/// The best swap of one family of `current` for another: for each family, the model without
/// it (`reduced`) with each of the three most promising other families added, as candidates
/// of round `round + 1`; the one of lowest BIC among those that pass and lower the BIC of
/// `current` by more than 2 (and, replacing the only effect, also predict the held-out data
/// better). `None` when no swap helps.
fn best_swap(
    s: &Search<'_>,
    current: &Fit,
    reduced: &Reduced,
    round: usize,
    progress: &(dyn Fn(Step<'_>) + Sync),
) -> Option<Candidate> {
    let opts = s.ctx.opts;
    let cur_bic = bic(&current.eval, current.k);
    let names = current.names();
    let options: Vec<(String, Fit)> = reduced
        .iter()
        .filter_map(|(n, r)| r.clone().map(|r| (n.clone(), r)))
        .collect();
    let pairs: Vec<(String, Fit, String)> = options
        .iter()
        .flat_map(|(out, r)| {
            s.promising(r, &names)
                .into_iter()
                .take(3)
                .map(|alt| (out.clone(), r.clone(), alt))
        })
        .collect();
    let swapped: Vec<Option<(Candidate, f64)>> = par_map(&pairs, opts.threads, |(out, r, alt)| {
        let mut c = s.candidate(round + 1, r, alt)?;
        let b = c.fit.as_ref().map_or(f64::INFINITY, |f| bic(&f.eval, f.k));
        c.note = format!("swap for {out}: {}", c.note);
        progress(Step::Fit(alt));
        Some((c, b))
    });
    let best = swapped
        .into_iter()
        .flatten()
        .filter(|(c, b)| {
            c.significant
                && *b < cur_bic - 2.0
                && (names.len() > 1
                    || c.fit
                        .as_ref()
                        .is_some_and(|f| heldout_ratio(&current.eval, &f.eval) < 1.0))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1));
    best.map(|(c, _)| c)
}
