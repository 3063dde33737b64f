//! What the stages of a search after round 1 share: the fitting context, the baseline, and
//! what round 1 learnt about each family's forms ([`Search`]), with the steps every stage
//! takes — a family's forms fitted on top of a model and judged, and the families worth
//! trying next. The driver (`orchestrate.rs`) builds it; identifiability, pairs, forms
//! refined, stability and the verdict use it.

use super::candidate::{Candidate, FormScore};
use super::fit::Ctx;
use super::fitted::Fit;
use super::par::par_map;
use super::rules::choose;
use shoal_model::effects::Effect;
use shoal_model::vehicle::VehicleParams;
use std::collections::BTreeMap;
use std::sync::Arc;

/// What round 1 learnt about one form: whether the data excite each parameter and its fit
/// alone on the baseline.
#[derive(Clone)]
pub(super) struct FormInfo {
    pub effect: Arc<dyn Effect>,
    pub excited: Vec<bool>,
    pub first: Option<Vec<f64>>,
}

impl FormInfo {
    /// The form's starting values on top of another model: its round-1 fit (its typical values
    /// where round 1 did not fit it), and its null values.
    pub fn starts(&self, base: &VehicleParams) -> [Vec<f64>; 2] {
        let params = self.effect.params(base);
        let first = self
            .first
            .clone()
            .unwrap_or_else(|| params.iter().map(|p| p.typical).collect());
        [first, params.iter().map(|p| p.null).collect()]
    }
}

/// Everything the later stages of a search share.
pub(super) struct Search<'a> {
    pub ctx: Ctx<'a>,
    pub baseline: Fit,
    /// Per family: its forms that apply and are excited, with their round-1 fits.
    pub forms: BTreeMap<String, Vec<FormInfo>>,
}

impl Search<'_> {
    /// `cur` with the family `name` added: every excited form fitted on top (from its round-1
    /// values and from null). Returns every form's fit and score (`None`: no form could be
    /// replayed); [`choose`](super::rules::choose) picks the form.
    fn add_forms(&self, cur: &Fit, name: &str) -> Option<(Vec<Fit>, Vec<FormScore>)> {
        let infos = self.forms.get(name)?;
        let mut fits: Vec<Fit> = Vec::new();
        let mut scores = Vec::new();
        for fi in infos {
            let starts = fi.starts(self.ctx.base);
            let Some(fit) = self.ctx.extend(cur, &fi.effect, &fi.excited, &starts) else {
                continue;
            };
            scores.push(FormScore::of(fi.effect.form(), cur, &fit));
            fits.push(fit);
        }
        (!fits.is_empty()).then_some((fits, scores))
    }

    /// The candidate of family `name` added to `base` ([`choose`](super::rules::choose) over
    /// [`Search::add_forms`]).
    pub fn candidate(&self, round: usize, base: &Fit, name: &str) -> Option<Candidate> {
        let (fits, scores) = self.add_forms(base, name)?;
        let opts = self.ctx.opts;
        Some(choose(
            round,
            name,
            base,
            fits,
            scores,
            opts,
            &self.baseline.eval,
        ))
    }

    /// Families worth adding to `cur` (not in it, not excluded), best score first, at most
    /// `candidates_per_round`.
    pub fn promising(&self, cur: &Fit, exclude: &[String]) -> Vec<String> {
        let names: Vec<String> = self
            .forms
            .keys()
            .filter(|n| !cur.names().contains(n) && !exclude.contains(n))
            .cloned()
            .collect();
        let opts = self.ctx.opts;
        let scores = par_map(&names, opts.threads, |n| {
            // Score each family by its most promising form on top of `cur` (the form that
            // fitted best alone need not be the one that fits best beside others).
            self.forms[n]
                .iter()
                .map(|fi| self.ctx.score(cur, &fi.effect, &fi.excited))
                .fold(0.0, f64::max)
        });
        let mut ranked: Vec<(f64, String)> = scores.into_iter().zip(names).collect();
        ranked.sort_by(|a, b| b.0.total_cmp(&a.0));
        ranked
            .into_iter()
            .filter(|(s, _)| *s > 0.0)
            .take(opts.candidates_per_round)
            .map(|(_, n)| n)
            .collect()
    }
}
