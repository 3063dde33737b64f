//! Pairs: two families that explain a log only together.
//!
//! Forward selection adds one family at a time, and a family joins only when the model with it
//! predicts the held-out part better. With two effects hidden in a log, each family fitted
//! alone is a compromise: on the estimation part it also bends towards the other effect's
//! signature, and on the held-out part — a free run that continues from it — that compromise
//! drifts away, so neither passes on its own and the search would stop with the structure
//! unexplained. So when no single family passes while the residuals stay structured
//! ([`super::verdict::unexplained`]), the families that explained most of the estimation data
//! in that round (largest ΔBIC, whatever their held-out result) are fitted in pairs. A family's
//! best form alone is a compromise too, so each pair is fitted in the combinations of its
//! families' leading forms of that round (the chosen one and the next by BIC,
//! [`PAIRED_FORMS`] in all) and, as for a single family ([`best_passing`]), the combination
//! of lowest BIC among those that pass stands for the pair. A pair joins when it passes every rule of
//! [`super::rules::judge`] as a unit and both its members are far from their null values. The
//! backward check then tests each member against the model with the other, and stability
//! selection each on its own, as for any chosen effect.

use super::candidate::Candidate;
use super::context::Search;
use super::fitted::Fit;
use super::par::par_map;
use super::rules::{best_passing, judge_set};
use super::step::Step;

/// A family and one of its forms.
type FamilyForm<'a> = (&'a str, &'a str);

/// How many of a round's families are paired (the pairs among them are tried).
const PAIRED_FAMILIES: usize = 4;

/// How many forms of each paired family are tried (its best ones alone in the round, by BIC).
const PAIRED_FORMS: usize = 2;

/// The forms of round candidate `c` to pair: the form it chose first, then its other forms by
/// BIC, [`PAIRED_FORMS`] in all.
fn paired_forms(c: &Candidate) -> Vec<&str> {
    let mut others: Vec<_> = c.forms.iter().filter(|f| f.form != c.form).collect();
    others.sort_by(|a, b| a.bic.total_cmp(&b.bic));
    std::iter::once(c.form.as_str())
        .chain(others.into_iter().map(|f| f.form.as_str()))
        .take(PAIRED_FORMS)
        .collect()
}

/// The pair candidates on top of `cur` for round `round`, from that round's single-family
/// candidates `round_candidates` (families already in `cur` are left out): one per pair of
/// families, in its best combination of forms.
pub(super) fn pair_candidates(
    s: &Search<'_>,
    round: usize,
    cur: &Fit,
    round_candidates: &[&Candidate],
    progress: &(dyn Fn(Step<'_>) + Sync),
) -> Vec<Candidate> {
    let opts = s.ctx.opts;
    let names = cur.names();
    let mut ranked: Vec<&Candidate> = round_candidates
        .iter()
        .copied()
        .filter(|c| !c.backward && c.fit.is_some() && !names.contains(&c.effect))
        .filter(|c| c.delta_bic < opts.bic_threshold)
        .collect();
    ranked.sort_by(|a, b| a.delta_bic.total_cmp(&b.delta_bic));
    ranked.truncate(PAIRED_FAMILIES);
    // (index of the family pair, form of the first, form of the second).
    let mut combos: Vec<(usize, FamilyForm, FamilyForm)> = Vec::new();
    let mut pair_index = 0;
    for i in 0..ranked.len() {
        for j in i + 1..ranked.len() {
            let (ca, cb) = (ranked[i], ranked[j]);
            for fa in paired_forms(ca) {
                for fb in paired_forms(cb) {
                    combos.push((pair_index, (&ca.effect, fa), (&cb.effect, fb)));
                }
            }
            pair_index += 1;
        }
    }
    let fitted: Vec<Option<(usize, Candidate)>> = par_map(&combos, opts.threads, |&(p, a, b)| {
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
        progress(Step::Fit(&format!("{} + {}", a.0, b.0)));
        let set = [a.0.to_string(), b.0.to_string()];
        let mut c = judge_set(round, &set, cur, fit, opts, false, &s.baseline.eval);
        c.form = format!("{} + {}", a.1, b.1);
        c.note = format!("pair (neither passes alone): {}", c.note);
        Some((p, c))
    });
    let mut per_pair: Vec<Vec<Candidate>> = vec![Vec::new(); pair_index];
    for (p, c) in fitted.into_iter().flatten() {
        per_pair[p].push(c);
    }
    per_pair.into_iter().filter_map(best_passing).collect()
}
