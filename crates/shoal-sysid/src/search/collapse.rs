//! Forms that collapse: a named effect fitted in a form whose extra parameters all sit at
//! their null values is the family's simpler form — a buoyancy offset in its `depth` form with
//! a depth coefficient of 0 is the `standard` offset. Reporting it in the richer form would
//! tell a user that the buoyancy changes with depth, at a rate of zero; and which of two equal
//! models the search ends with would hang on numerical noise. So the chosen model's effect
//! is refitted in the simpler form (from the same values) and reported in it when it fits at
//! least as well (BIC no higher, to rounding).

use super::context::Search;
use super::fitted::Fit;
use super::measures::bic;
use shoal_model::effects::Effect;
use std::sync::Arc;

/// How close a parameter must be to its null value to count as there (relative to
/// max(1, |null|)): a fit stopped at a bound equal to the null sits there exactly.
const AT_NULL: f64 = 1e-9;

/// BIC slack of a refit in the simpler form (relative): the same model refitted may differ
/// by rounding.
const BIC_SLACK: f64 = 1e-9;

/// `chosen` with every effect whose form collapses to a simpler form of its family (among the
/// forms the search considered) refitted in that form (see the module doc).
pub(super) fn collapsed(s: &Search<'_>, mut chosen: Fit) -> Fit {
    for i in 0..chosen.effects.len() {
        let e = &chosen.effects[i];
        let family = e.effect.name();
        let considered: Vec<Arc<dyn Effect>> = s
            .forms
            .get(family)
            .map(|f| f.iter().map(|fi| fi.effect.clone()).collect())
            .unwrap_or_default();
        for simpler in considered {
            if simpler.form() == e.effect.form() {
                continue;
            }
            let Some(fit) = refit_in(s, &chosen, i, &simpler) else {
                continue;
            };
            let (was, now) = (bic(&chosen.eval, chosen.k), bic(&fit.eval, fit.k));
            if now <= was + BIC_SLACK * was.abs() {
                chosen = fit;
                break;
            }
        }
    }
    chosen
}

/// `chosen` with its `i`-th effect in the form `simpler`, refitted from the same values —
/// `None` unless `simpler`'s parameters are some of the effect's (by name) and every one it
/// lacks is a non-shape parameter at its null value.
fn refit_in(s: &Search<'_>, chosen: &Fit, i: usize, simpler: &Arc<dyn Effect>) -> Option<Fit> {
    let e = &chosen.effects[i];
    let infos = simpler.params(s.ctx.base);
    let by_name = |n: &str| e.params.iter().find(|p| p.name == n);
    if infos.iter().any(|p| by_name(p.name).is_none()) {
        return None;
    }
    let extra_at_null = e
        .params
        .iter()
        .filter(|p| !infos.iter().any(|q| q.name == p.name))
        .all(|p| !p.shape && (p.value - p.null).abs() <= AT_NULL * p.null.abs().max(1.0));
    if !extra_at_null || infos.len() == e.params.len() {
        return None;
    }
    let mut effects = Vec::new();
    let (mut excited, mut held) = (Vec::new(), Vec::new());
    for (j, f) in chosen.effects.iter().enumerate() {
        if j == i {
            effects.push(simpler.clone());
            for q in &infos {
                let p = by_name(q.name)?;
                excited.push(p.excited);
                held.push(p.value);
            }
        } else {
            effects.push(f.effect.clone());
            excited.extend(f.params.iter().map(|p| p.excited));
            held.extend(f.params.iter().map(|p| p.value));
        }
    }
    s.ctx.fit(&effects, &excited, &[held], None)
}
