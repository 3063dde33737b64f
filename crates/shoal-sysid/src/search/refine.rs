//! Forms chosen again once the set of families is final.
//!
//! A family's form is chosen when the family joins the model, on top of the effects chosen
//! before it. With a second effect still missing, the form that fits best is the one that also
//! bends towards the missing effect's signature: a first-order lag hidden beside a buoyancy
//! offset, fitted before the offset is in the model, comes out as a second-order lag, and the
//! offset, fitted beside that lag, as a settling one. Once the families are settled, each
//! family's forms are therefore fitted again against the model of all the *other* families
//! (each refitted without it), and the form of lowest BIC among those that pass the rules of
//! [`super::rules::judge`] there replaces the chosen one when it lowers the whole model's BIC.
//! The best such change is made and the others are tried again on the new model, until none
//! helps (at most one pass per family and one more).

use super::orchestrate::{Search, choose};
use super::rules::bic;
use super::{Candidate, Fit, par_map};

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
    progress: &(dyn Fn(&str) + Sync),
) -> (Fit, Vec<Candidate>) {
    let mut made = Vec::new();
    if current.effects.len() < 2 {
        return (current, made);
    }
    let mut without: Vec<(String, Option<Fit>)> = reduced;
    for _ in 0..=current.effects.len() {
        let cur_bic = bic(&current.eval, current.k);
        let names = current.names();
        let forms: Vec<String> = current
            .effects
            .iter()
            .map(|e| e.effect.form().to_string())
            .collect();
        let cur = &current;
        let tries: Vec<Option<(Candidate, f64)>> = par_map(&names, s.ctx.opts.threads, |name| {
            let r = match without.iter().find(|(n, _)| n == name) {
                Some((_, Some(r))) => r.clone(),
                _ => s.ctx.without(cur, name, &s.baseline)?,
            };
            let (fits, scores) = s.add_forms(&r, name)?;
            let c = choose(
                round + 1,
                name,
                &r,
                fits,
                scores,
                s.ctx.opts,
                &s.baseline.eval,
            );
            progress(name);
            let b = c.fit.as_ref().map_or(f64::INFINITY, |f| bic(&f.eval, f.k));
            Some((c, b))
        });
        let best = tries
            .into_iter()
            .flatten()
            .filter(|(c, b)| {
                let i = names.iter().position(|n| *n == c.effect);
                c.significant
                    && i.is_some_and(|i| forms[i] != c.form)
                    && *b < cur_bic - MIN_IMPROVEMENT
            })
            .min_by(|a, b| a.1.total_cmp(&b.1));
        let Some((mut c, b)) = best else { break };
        let Some(fit) = c.fit.clone() else { break };
        let old = &forms[names.iter().position(|n| *n == c.effect).unwrap_or(0)];
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
