//! The candidates of a search's rounds: a family (or pair) tried on top of a model, with the
//! scores of its forms, its fit and the measures the rules judged it by.

use super::fitted::Fit;
use super::measures::{bic, gain};

/// One form of a family as fitted in a round.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct FormScore {
    /// The form.
    pub form: String,
    /// BIC of the model with this form (estimation data).
    pub bic: f64,
    /// Held-out gain against the model it was added to (fraction).
    pub gain: f64,
    /// Free parameters of the form.
    pub k: usize,
}

impl FormScore {
    /// The score of `form`, fitted on top of `base` as `fit`.
    pub(super) fn of(form: &str, base: &Fit, fit: &Fit) -> Self {
        Self {
            form: form.to_string(),
            bic: bic(&fit.eval, fit.k),
            gain: gain(&base.eval, &fit.eval),
            k: fit.k - base.k,
        }
    }
}

/// One candidate of one round.
#[derive(Clone, Debug)]
pub struct Candidate {
    /// Round (1 = each effect alone on the baseline).
    pub round: usize,
    /// Whether this is the backward check of an effect in the final model (`delta_bic`,
    /// `gain` and `z` then compare the model with and without it).
    pub backward: bool,
    /// The effect family tried in this round.
    pub effect: String,
    /// The form of the family that fitted best.
    pub form: String,
    /// Every form of the family that was fitted in this round, with its score.
    pub forms: Vec<FormScore>,
    /// The fit (none if the effect does not apply or is not excited).
    pub fit: Option<Fit>,
    /// ΔBIC against the model it was added to.
    pub delta_bic: f64,
    /// ΔBIC with effective sample counts (see [`super::measures::delta_bic_eff`]).
    pub delta_bic_eff: f64,
    /// Held-out block test t statistic (see [`crate::evaluate::blocks::heldout_t`]).
    pub heldout_t: f64,
    /// Relative validation-RMSE reduction against the model it was added to (fraction,
    /// mean over channels).
    pub gain: f64,
    /// Joint distance of its parameters from their null values: the Wald test with the
    /// white-residual covariance, as the normal deviate of the same tail probability
    /// [standard deviations].
    pub z: f64,
    /// Whether it passed every significance test.
    pub significant: bool,
    /// Why it was skipped or rejected, or what it achieved.
    pub note: String,
}
