//! What a search returns: the baseline, every candidate of every round, the stepwise and the
//! chosen model, and the verdict.

use super::candidate::Candidate;
use super::fitted::Fit;
use super::measures::{changed, channel_gains_pct, gain, mean_channel_gain_pct};
use super::rival::Rival;
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
    /// The questions the log leaves open, each as two fitted models: every "A or B" and every
    /// effect left possible (the model with it against the model without it). What a next
    /// experiment is chosen to answer ([`crate::experiment`]).
    pub rivals: Vec<Rival>,
}

impl Outcome {
    /// The report's headline: the relative validation-RMSE reduction of the chosen model
    /// against the baseline, the mean over every measured channel of the per-channel gains
    /// (each channel's pooled validation RMSE through
    /// [`rmse_gain_pct`](crate::evaluate::evaluation::rmse_gain_pct): the table's `gain`
    /// column) [%]. 0 when nothing is named.
    pub fn validation_gain_pct(&self) -> f64 {
        mean_channel_gain_pct(&self.baseline.eval, &self.chosen.eval)
    }

    /// The channels the chosen model changes (its held-out prediction moves by at least the
    /// channel's sensor resolution, RMS) and the mean relative validation-RMSE reduction over
    /// them [%] — the figure the search compares with its `min_gain` (see
    /// [`gain`](super::measures::gain)).
    pub fn changed_channels_gain_pct(&self) -> (Vec<ChannelKind>, f64) {
        let (b, c) = (&self.baseline.eval, &self.chosen.eval);
        (changed(b, c), 100.0 * gain(b, c))
    }

    /// The channels the chosen model makes worse: those whose validation RMSE it raises, each
    /// with its (negative) gain [%] as the table's `gain` column shows it, in channel order.
    /// The headline's mean can hide them.
    pub fn worsened_channels(&self) -> Vec<(ChannelKind, f64)> {
        channel_gains_pct(&self.baseline.eval, &self.chosen.eval)
            .into_iter()
            .filter(|g| g.1 < 0.0)
            .collect()
    }
}
