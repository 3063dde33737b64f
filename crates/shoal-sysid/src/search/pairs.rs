//! Pairs: two families that explain a log only together.
//!
//! Forward selection adds one family at a time, and a family joins only when the model with it
//! predicts the held-out part better. With two effects hidden in a log, each family fitted
//! alone is a compromise: on the estimation part it also bends towards the other effect's
//! signature, and on the held-out part — a free run that continues from it — that compromise
//! drifts away, so neither passes on its own and the search would stop with the structure
//! unexplained. So when no single family passes while the residuals stay structured
//! ([`super::verdict::unexplained`]), the families that explained most of the estimation data
//! in that round (largest ΔBIC, whatever their held-out result) are fitted in pairs, each in the
//! form it fitted best there; a pair joins when it passes every rule of
//! [`super::rules::judge`] as a unit and both its members are far from their null values. The
//! backward check then tests each member against the model with the other, and stability
//! selection each on its own, as for any chosen effect.

use super::orchestrate::Search;
use super::rules::judge_set;
use super::{Candidate, Fit, par_map};
use std::sync::Arc;

/// A family and one of its forms.
type FamilyForm<'a> = (&'a str, &'a str);

/// How many of a round's families are paired (the pairs among them are tried).
const PAIRED_FAMILIES: usize = 4;

/// The pair candidates on top of `cur` for round `round`, from that round's single-family
/// candidates `round_candidates` (families already in `cur` are left out).
pub(super) fn pair_candidates(
    s: &Search<'_>,
    round: usize,
    cur: &Fit,
    round_candidates: &[&Candidate],
    progress: &(dyn Fn(&str) + Sync),
) -> Vec<Candidate> {
    let opts = s.ctx.opts;
    let names = cur.names();
    let mut ranked: Vec<(&str, &str, f64)> = round_candidates
        .iter()
        .filter(|c| !c.backward && c.fit.is_some() && !names.contains(&c.effect))
        .filter(|c| c.delta_bic < opts.bic_threshold)
        .map(|c| (c.effect.as_str(), c.form.as_str(), c.delta_bic))
        .collect();
    ranked.sort_by(|a, b| a.2.total_cmp(&b.2));
    ranked.truncate(PAIRED_FAMILIES);
    let mut pairs: Vec<(FamilyForm, FamilyForm)> = Vec::new();
    for i in 0..ranked.len() {
        for j in i + 1..ranked.len() {
            pairs.push(((ranked[i].0, ranked[i].1), (ranked[j].0, ranked[j].1)));
        }
    }
    let fitted: Vec<Option<Candidate>> = par_map(&pairs, opts.threads, |&(a, b)| {
        let fa = s.forms.get(a.0)?.iter().find(|f| f.effect.form() == a.1)?;
        let fb = s.forms.get(b.0)?.iter().find(|f| f.effect.form() == b.1)?;
        let mut effects: Vec<Arc<dyn shoal_model::effects::Effect>> =
            cur.effects.iter().map(|e| e.effect.clone()).collect();
        let mut excited: Vec<bool> = cur
            .effects
            .iter()
            .flat_map(|e| e.params.iter().map(|p| p.excited))
            .collect();
        let held: Vec<f64> = cur
            .effects
            .iter()
            .flat_map(|e| e.params.iter().map(|p| p.value))
            .collect();
        let mut starts = vec![held.clone(), held.clone(), held];
        for (k, fi) in [fa, fb].into_iter().enumerate() {
            effects.push(fi.effect.clone());
            excited.extend_from_slice(&fi.excited);
            let infos = fi.effect.params(s.ctx.base);
            let null: Vec<f64> = infos.iter().map(|p| p.null).collect();
            let first = fi
                .first
                .clone()
                .unwrap_or_else(|| infos.iter().map(|p| p.typical).collect());
            // Both from their own fits alone, and each from null beside the other's.
            starts[0].extend_from_slice(&first);
            starts[1].extend_from_slice(if k == 0 { &null } else { &first });
            starts[2].extend_from_slice(if k == 0 { &first } else { &null });
        }
        let from = cur.effects.iter().map(|e| e.params.len()).sum();
        let fit = s.ctx.fit(&effects, &excited, &starts, Some(from))?;
        progress(&format!("{} + {}", a.0, b.0));
        let set = [a.0.to_string(), b.0.to_string()];
        let mut c = judge_set(round, &set, cur, fit, opts, false, &s.baseline.eval);
        c.form = format!("{} + {}", a.1, b.1);
        c.note = format!("pair (neither passes alone): {}", c.note);
        Some(c)
    });
    fitted.into_iter().flatten().collect()
}
