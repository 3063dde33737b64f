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
        let [first_a, null_a] = fa.starts(s.ctx.base);
        let [first_b, null_b] = fb.starts(s.ctx.base);
        // Both from their own fits alone, and each from null beside the other's.
        let starts = [
            [first_a.clone(), first_b.clone()].concat(),
            [null_a, first_b].concat(),
            [first_a, null_b].concat(),
        ];
        let adds = [
            (&fa.effect, fa.excited.as_slice()),
            (&fb.effect, fb.excited.as_slice()),
        ];
        let fit = s.ctx.extend_with(cur, &adds, &starts)?;
        progress(&format!("{} + {}", a.0, b.0));
        let set = [a.0.to_string(), b.0.to_string()];
        let mut c = judge_set(round, &set, cur, fit, opts, false, &s.baseline.eval);
        c.form = format!("{} + {}", a.1, b.1);
        c.note = format!("pair (neither passes alone): {}", c.note);
        Some(c)
    });
    fitted.into_iter().flatten().collect()
}
