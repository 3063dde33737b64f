//! Forms chosen again once the set of families is final.
//!
//! A family's form is chosen when the family joins the model, on top of the effects chosen
//! before it. With a second effect still missing, the form that fits best is the one that also
//! bends towards the missing effect's signature: a first-order lag hidden beside a buoyancy
//! offset, fitted before the offset is in the model, comes out as a second-order lag, and the
//! offset, fitted beside that lag, as a settling one. Once the families are settled, each
//! family's forms are therefore fitted again against the model of all the *other* families
//! (each refitted without it), and the form of lowest BIC among those that pass the rules of
//! [`super::rules::judge`] there ([`Search::candidate`]) replaces the chosen one when it
//! lowers the whole model's BIC. The best such change is made and the others are tried again
//! on the new model, until none helps (at most one pass per family and one more).

use super::candidate::Candidate;
use super::context::Search;
use super::fitted::Fit;
use super::measures::bic;
use super::par::par_map;
use super::step::Step;

/// Smallest BIC reduction for which a form replaces the chosen one (the BIC threshold of a
/// swap: two forms that fit equally well keep the one chosen first).
const MIN_IMPROVEMENT: f64 = 2.0;

/// `current` with each family's form chosen again against the others (see the module
/// documentation). `reduced` holds `current` refitted without each of its families, as the
/// last backward check left them (`None`: that refit failed; it is redone). Returns the
/// refined model and the candidates of the changes made, numbered from `round`.
pub(super) fn refine_forms(
    s: &Search<'_>,
    mut current: Fit,
    reduced: Vec<(String, Option<Fit>)>,
    mut round: usize,
    progress: &(dyn Fn(Step<'_>) + Sync),
) -> (Fit, Vec<Candidate>) {
    let mut made = Vec::new();
    if current.effects.len() < 2 {
        return (current, made);
    }
    let mut without: Vec<(String, Option<Fit>)> = reduced;
    for _ in 0..=current.effects.len() {
        let cur_bic = bic(&current.eval, current.k);
        // Each family with the form it has now.
        let chosen: Vec<(String, String)> = current
            .effects
            .iter()
            .map(|e| (e.effect.name().to_string(), e.effect.form().to_string()))
            .collect();
        let cur = &current;
        let tries: Vec<Option<(Candidate, f64, String)>> =
            par_map(&chosen, s.ctx.opts.threads, |(name, form)| {
                let r = match without.iter().find(|(n, _)| n == name) {
                    Some((_, Some(r))) => r.clone(),
                    _ => s.ctx.without(cur, name, &s.baseline)?,
                };
                let c = s.candidate(round + 1, &r, name)?;
                progress(Step::Fit(name));
                let b = c.fit.as_ref().map_or(f64::INFINITY, |f| bic(&f.eval, f.k));
                Some((c, b, form.clone()))
            });
        let best = tries
            .into_iter()
            .flatten()
            .filter(|(c, b, old)| c.significant && c.form != *old && *b < cur_bic - MIN_IMPROVEMENT)
            .min_by(|a, b| a.1.total_cmp(&b.1));
        let Some((mut c, b, old)) = best else { break };
        let Some(fit) = c.fit.clone() else { break };
        round += 1;
        c.round = round;
        c.note = format!(
            "form {} for {old} beside the others (model ΔBIC {:.1}): {}",
            c.form,
            b - cur_bic,
            c.note
        );
        made.push(c);
        current = fit;
        // The refits without each family belonged to the old model.
        without = Vec::new();
    }
    (current, made)
}
