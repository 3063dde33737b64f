//! The rules that decide whether an effect earns its place, from the measures of
//! `measures.rs`: ΔBIC, effective ΔBIC in the backward checks, held-out gain and its block
//! test, materiality or closure, and the Wald distance from null; and, of the forms of a
//! family, which one stands for it.

use super::candidate::{Candidate, FormScore};
use super::fitted::Fit;
use super::measures::{bic, closure, delta_bic, delta_bic_eff, gain, material, z_of};
use super::options::SearchOptions;
use crate::evaluate::blocks::heldout_t;
use crate::evaluate::evaluation::Evaluation;

/// A candidate that was not fitted.
pub fn skipped(round: usize, name: &str, note: String) -> Candidate {
    Candidate {
        round,
        backward: false,
        effect: name.to_string(),
        form: String::new(),
        forms: Vec::new(),
        fit: None,
        delta_bic: 0.0,
        delta_bic_eff: 0.0,
        gain: 0.0,
        heldout_t: 0.0,
        z: 0.0,
        significant: false,
        note,
    }
}

/// Tests whether `name` earns its place in `fit` against `base` (the model without it): the
/// same rules forward and backward (see the module docs of [`super`]).
pub fn judge(
    round: usize,
    name: &str,
    base: &Fit,
    fit: Fit,
    opts: &SearchOptions,
    backward: bool,
    baseline: &Evaluation,
) -> Candidate {
    judge_set(
        round,
        &[name.to_string()],
        base,
        fit,
        opts,
        backward,
        baseline,
    )
}

/// [`judge`] for the families `names` joining together (a pair, see `pairs.rs`): the same
/// rules for the model with all of them against `base`, and every one of them far from its
/// null values (the smallest Wald distance counts). The candidate's `effect` is the names
/// joined by ` + `.
pub fn judge_set(
    round: usize,
    names: &[String],
    base: &Fit,
    fit: Fit,
    opts: &SearchOptions,
    backward: bool,
    baseline: &Evaluation,
) -> Candidate {
    let name = names.join(" + ");
    let d = delta_bic(base, &fit);
    let de = delta_bic_eff(base, &fit, None);
    let g = gain(&base.eval, &fit.eval);
    let t = heldout_t(&base.eval, &fit.eval, opts.block_s, None);
    let z = names
        .iter()
        .map(|n| z_of(&fit, n, true))
        .fold(f64::INFINITY, f64::min);
    // The gate is the plain ΔBIC: while a second effect is still missing the residuals stay
    // smooth whatever the first explains, and the effective count would then refuse the first
    // effect of every pair. In a backward check the model is complete as far as the search
    // can tell, and the effective ΔBIC must not favour the model without the effect.
    let ok_eff = !backward || de < opts.backward_eff_bic_threshold;
    let ok_bic = d < opts.bic_threshold;
    let ok_gain = g >= opts.min_gain;
    let ok_t = t >= opts.t_threshold;
    let ok_z = z >= opts.z_threshold;
    let m = material(baseline, &base.eval, &fit.eval);
    let c = closure(&base.eval, &fit.eval);
    let ok_m = m >= opts.min_material || c >= opts.min_closure;
    let significant = ok_bic && ok_eff && ok_gain && ok_t && ok_z && ok_m;
    let mut why = Vec::new();
    if !ok_bic {
        why.push(format!(
            "ΔBIC {d:.1} ≥ {} (effective {de:.1})",
            opts.bic_threshold
        ));
    }
    if !ok_eff {
        why.push(format!(
            "effective ΔBIC {de:.1} ≥ {} in the backward check (plain {d:.1})",
            opts.backward_eff_bic_threshold
        ));
    }
    if !ok_gain {
        why.push(format!(
            "held-out gain {:.2} % < {:.1} %",
            100.0 * g,
            100.0 * opts.min_gain
        ));
    }
    if !ok_t {
        why.push(format!(
            "held-out block test t = {t:.1} < {}",
            opts.t_threshold
        ));
    }
    if !ok_m {
        why.push(format!(
            "held-out RMSE falls by only {:.2} % of the baseline's (< {:.1} %) and closes {:.0} % of the gap to the noise floor (< {:.0} %)",
            100.0 * m,
            100.0 * opts.min_material,
            100.0 * c,
            100.0 * opts.min_closure
        ));
    }
    if !ok_z {
        why.push(format!(
            "parameters within {:.1} σ of null (< {})",
            z, opts.z_threshold
        ));
    }
    let form = fit
        .effects
        .iter()
        .find(|e| e.effect.name() == name.as_str())
        .map(|e| e.effect.form().to_string())
        .unwrap_or_default();
    let note = if significant {
        format!(
            "significant: ΔBIC {d:.1} (effective {de:.1}), held-out gain {:.1} % (block t {t:.1}), {:.1} % of the baseline's RMSE, {:.0} % of the gap to the noise floor, {z:.1} σ from null",
            100.0 * g,
            100.0 * m,
            100.0 * c
        )
    } else {
        format!("not significant: {}", why.join("; "))
    };
    Candidate {
        round,
        backward,
        effect: name,
        form,
        forms: Vec::new(),
        fit: Some(fit),
        delta_bic: d,
        delta_bic_eff: de,
        gain: g,
        heldout_t: t,
        z,
        significant,
        note,
    }
}

/// The candidate of family `name` on top of `base`, given each of its forms' `fits`: the form
/// of lowest BIC among those that earn their place by the rules of [`judge`] (held-out gain,
/// block test, …), or the form of lowest BIC when none does. A form that fits the estimation
/// data best but fails on data the fit did not see must not hide a form of the same family
/// that holds there: the family is judged by its best form that generalises.
pub(super) fn choose(
    round: usize,
    name: &str,
    base: &Fit,
    fits: Vec<Fit>,
    scores: Vec<FormScore>,
    opts: &SearchOptions,
    baseline: &Evaluation,
) -> Candidate {
    let judged: Vec<Candidate> = fits
        .into_iter()
        .map(|f| judge(round, name, base, f, opts, false, baseline))
        .collect();
    let mut c = best_passing(judged).expect("choose is given at least one fit");
    c.forms = scores;
    c
}

/// Of `judged` (candidates of one family or one pair of families in different forms), the one
/// of lowest BIC among those that pass the rules, or the one of lowest BIC when none passes;
/// `None` when there is none.
pub(super) fn best_passing(judged: Vec<Candidate>) -> Option<Candidate> {
    let mut scored: Vec<(f64, Candidate)> = judged
        .into_iter()
        .map(|c| {
            let b = c.fit.as_ref().map_or(f64::INFINITY, |f| bic(&f.eval, f.k));
            (b, c)
        })
        .collect();
    scored.sort_by(|a, b| a.0.total_cmp(&b.0));
    let at = scored.iter().position(|(_, c)| c.significant).unwrap_or(0);
    (!scored.is_empty()).then(|| scored.swap_remove(at).1)
}
