//! What a search returns: the baseline, every candidate of every round, the stepwise and the
//! chosen model, and the verdict.

use super::candidate::Candidate;
use super::fitted::Fit;
use super::measures::gain;
use super::verdict::Verdict;
use crate::log::run::ChannelKind;
use std::collections::BTreeMap;

/// The search's result.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// The baseline, evaluated.
    pub baseline: Fit,
    /// Every candidate of every round.
    pub candidates: Vec<Candidate>,
    /// The model of the named effects (`verdict.effects`; the baseline when nothing is
    /// named).
    pub chosen: Fit,
    /// The stepwise selection's model, before the stability and identifiability checks.
    pub stepwise: Fit,
    /// What the search concludes.
    pub verdict: Verdict,
    /// Residual weights of the baseline (see
    /// [`Evaluation::ml_factors`](crate::evaluate::evaluation::Evaluation::ml_factors)).
    pub factors: BTreeMap<ChannelKind, f64>,
}

impl Outcome {
    /// Relative validation-RMSE reduction of the chosen model against the baseline, mean over
    /// channels [%].
    pub fn validation_gain_pct(&self) -> f64 {
        100.0 * gain(&self.baseline.eval, &self.chosen.eval)
    }
}
