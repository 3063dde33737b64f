//! The model search: fit every catalogue effect family on the estimation data, score it on the
//! held-out data and by information criteria, keep the best significant one, try adding each
//! further family to it (greedy forward selection), check every chosen effect by removing it
//! again, and then ask whether the choice is *stable* and *identifiable*.
//!
//! **Families and forms.** An effect family ([`Effect::name`]) may come in several forms
//! ([`Effect::form`]: a hard or soft dead band, a first- or second-order lag, …). Forms compete
//! as alternative shapes of one physical cause: each is fitted and the one with the lowest BIC
//! stands for the family; two forms of a family are never in one model. The report names the
//! family (the physics) and the form that fitted best.
//!
//! **Fitting** (`fit.rs`). Each candidate model is the baseline plus a set of effects. Its
//! parameters are fitted by maximum likelihood with unknown per-channel noise: bounded
//! Levenberg–Marquardt ([`crate::lm`]) on the estimation residuals of all channels, each
//! channel weighted by the inverse of the fit's own residual variance, the weights updated and
//! the fit repeated until they settle. It starts from the best two of several points: the null
//! values, typical values, earlier fits, and a scan of the new effect's parameters — a line
//! from the null values towards the far bounds and a space-filling Halton design over their
//! whole box (`fit.rs`): threshold laws have no gradient where they do not bind, and
//! an output-error cost has valleys far from the null values. Parameters that the data cannot
//! see are detected by a probe and kept at their null values.
//!
//! **Uncertainty.** From the Jacobian at the optimum: `sigma_white`, the Gauss–Newton value for
//! white residuals, and `sigma`, the honest one for a replay's smooth, correlated residuals
//! (each channel's information divided by κ = (1+ρ₁)/(1−ρ₁)).
//!
//! **Selection** ([`rules`]). An effect earns its place against the model without it when all
//! of these hold:
//! 1. ΔBIC < −10 on the estimation data. The *effective* ΔBIC — each channel's sample count
//!    replaced by n·(1−ρ₁)/(1+ρ₁), ρ₁ of the larger model's residuals — is reported beside it
//!    and used where two explanations are compared (identifiability). It is no gate for an
//!    effect *joining* a model, because while a second effect is still missing the residuals
//!    stay smooth whatever the first explains; in the *backward* checks, where the model is
//!    as complete as the search can make it, an effect must also have an effective ΔBIC
//!    below `backward_eff_bic_threshold` (default 0): counting only the independent
//!    information in its residuals, the log must not favour the model without it. (An effect
//!    that soaks up the form mismatch of another lowers the plain BIC by following the
//!    smooth residual, and fails this.)
//! 2. the *held-out* RMSE (validation blocks the fit never saw) falls by at least `min_gain`
//!    (default 3 %), averaged over channels;
//! 3. the held-out improvement is consistent over time blocks: the t statistic of the per-block
//!    reductions ([`crate::blocks::heldout_t`]) is at least `t_threshold` (default 0: the mean
//!    block improvement must be positive; the t statistic is reported — a stricter threshold
//!    rejects effects that show only at a few events, such as a lag at command steps);
//! 4. the held-out RMSE falls by at least `min_material` (default 2 %) *of the baseline's*
//!    held-out RMSE: an extra effect that only trims what is left after the others — a form
//!    mismatch being soaked up — is not worth naming; unless it closes at least
//!    `min_closure` (default 50 %) of the gap between the held-out RMSE and the noise floor
//!    ([`rules::closure`]): an effect that explains most of what is left above the sensor
//!    noise is the rest of the story however small, where a soaking-up one trims a part;
//! 5. its parameters are jointly `z_threshold` (default 3) standard deviations from their null
//!    values (Wald test; shape parameters excluded).
//!
//! The gains of 2–4 are averaged over the channels the effect visibly changes: its held-out
//! prediction must move by at least one step of the channel's resolution (a quantised
//! sensor's step, read from the data; [`crate::stats::resolution`]) — below that, a change
//! cannot be told from the quantisation itself.
//!
//! *Forward*: of the families that pass, the one whose model predicts the held-out data best
//! ([`rules::heldout_ratio`]: held-out RMSE relative to the current model's, averaged over every
//! channel) joins the model, then each promising remaining family is fitted together with the
//! chosen ones, and so on, until none passes or every channel's held-out residuals are white
//! (nothing is left to explain). When no family passes alone while structure is left, the round's
//! most promising families are fitted in pairs (`pairs.rs`): two effects hidden together can
//! each be a compromise that fails on the held-out part alone. *Backward*: every chosen effect
//! must still pass against the model without it (refitted); the weakest failing one is removed
//! and the test repeated; swaps of one effect for another that lower the BIC are tried.
//! *Forms again* (`refine.rs`): once the families are final, each family's forms are fitted
//! again beside all the others, and a form that lowers the model's BIC replaces the one chosen
//! when the family joined (then, a missing effect may have bent the choice).
//!
//! **Identifiability** (`identify.rs`). For each chosen effect, the best alternative families
//! are fitted in its place. When an alternative explains the held-out data as well (the block
//! test cannot tell them apart) the log cannot separate the two: the verdict reports "A or B"
//! with the manoeuvre that would separate them, and names neither.
//!
//! **Stability selection** (`stability.rs`). The chosen model is refitted on block-bootstrap
//! resamples of the log (estimation and validation blocks drawn with replacement), and on each
//! the backward test is repeated — ΔBIC, held-out gain, block test and materiality, on the
//! resample's blocks. An effect is named in `verdict.effects` only if it is selected in at
//! least `stability_threshold` (default 80 %: 7 of the 8 resamples) of the resamples;
//! otherwise it is listed as *possible* with its evidence. (An effect that only soaks up
//! another's form mismatch tends to sit near the materiality limit and fails it on some
//! resamples.)
//!
//! **Unexplained structure.** When the final model's held-out residuals stay structured
//! (Ljung–Box fails and their RMS is well above the noise floor estimated from sample-to-sample
//! differences) and no family explains them, the verdict says so for that channel instead of
//! forcing a name.
//!
//! A run the baseline already explains therefore yields an empty verdict: nothing fitted to
//! noise generalises to the held-out data.

mod fit;
mod identify;
mod memo;
mod orchestrate;
mod pairs;
mod par;
mod refine;
pub mod rules;
mod stability;
mod verdict;

pub use orchestrate::search;
pub use par::par_map;
pub use rules::{bic, delta_bic, gain};
pub use verdict::{Ambiguity, Possible, Unexplained, Verdict};

use crate::evaluation::Evaluation;
use crate::lm::LmOptions;
use crate::run::ChannelKind;
use nalgebra::DMatrix;
use shoal_model::effects::{Effect, EffectInstance, Effects};
use shoal_model::vehicle::{VehicleModel, VehicleParams};
use std::collections::BTreeMap;
use std::sync::Arc;

/// Settings of a search.
#[derive(Clone, Debug)]
pub struct SearchOptions {
    /// The effects to consider (default: the built-in catalogue).
    pub effects: Vec<Arc<dyn Effect>>,
    /// Smallest relative validation-RMSE reduction that counts (fraction, default 0.03).
    pub min_gain: f64,
    /// Largest ΔBIC that counts as an improvement (default −10).
    pub bic_threshold: f64,
    /// Largest *effective* ΔBIC (each channel's sample count reduced for the residuals'
    /// correlation, see [`rules::delta_bic_eff`]) with which an effect survives the backward
    /// checks of the model it is part of (default 0).
    pub backward_eff_bic_threshold: f64,
    /// Smallest distance of a parameter from its null value in standard deviations
    /// (default 3).
    pub z_threshold: f64,
    /// Most effects in the verdict (default 4).
    pub max_effects: usize,
    /// After the first round, how many of the best first-round candidates are tried as
    /// additions (default 6).
    pub candidates_per_round: usize,
    /// Worker threads for candidate fits (results do not depend on it).
    pub threads: usize,
    /// Levenberg–Marquardt settings.
    pub lm: LmOptions,
    /// Effects that are part of the baseline itself (from the vehicle file), fixed.
    pub base_effects: Vec<EffectInstance>,
    /// Length of the time blocks of the held-out test and the bootstrap \[s\] (default 4).
    pub block_s: f64,
    /// Smallest reduction of the held-out RMSE, as a fraction of the baseline's, that an
    /// effect must bring to the model it joins (default 0.02).
    pub min_material: f64,
    /// Fraction of the gap between the held-out RMSE and the noise floor that makes an
    /// effect material however small its share of the baseline's error (default 0.5).
    pub min_closure: f64,
    /// Smallest held-out block t statistic that counts (default 0).
    pub t_threshold: f64,
    /// Block-bootstrap resamples for stability selection (default 8; 0: no stability check).
    pub stability_draws: usize,
    /// Smallest selection frequency over the resamples for an effect to be named (fraction,
    /// default 0.8: with 8 resamples, an effect must survive 7; see docs/validation.md for
    /// the measurement behind it).
    pub stability_threshold: f64,
    /// Seed of the resamples.
    pub seed: u64,
}

impl Default for SearchOptions {
    fn default() -> Self {
        Self {
            effects: shoal_model::effects::catalogue(),
            min_gain: 0.03,
            bic_threshold: -10.0,
            backward_eff_bic_threshold: 0.0,
            z_threshold: 3.0,
            max_effects: 4,
            candidates_per_round: 6,
            threads: 1,
            lm: LmOptions::default(),
            base_effects: Vec::new(),
            block_s: crate::blocks::DEFAULT_BLOCK_S,
            t_threshold: 0.0,
            min_material: 0.02,
            min_closure: 0.5,
            stability_draws: 8,
            stability_threshold: 0.8,
            seed: 0x5140a1,
        }
    }
}

/// A fitted parameter.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ParamEstimate {
    /// Parameter name.
    pub name: String,
    /// Unit.
    pub unit: String,
    /// Estimate (unit as above).
    pub value: f64,
    /// Standard deviation allowing for autocorrelated residuals (unit as above); `None` where
    /// not excited or not determined.
    pub sigma: Option<f64>,
    /// Gauss–Newton standard deviation for white residuals (unit as above).
    pub sigma_white: Option<f64>,
    /// The value at which the effect vanishes.
    pub null: f64,
    /// Whether the data excite it (otherwise it is held at `null`).
    pub excited: bool,
    /// A shape parameter (never tested against `null`).
    pub shape: bool,
}

/// An effect with fitted parameters.
#[derive(Clone, Debug)]
pub struct FittedEffect {
    /// The effect.
    pub effect: Arc<dyn Effect>,
    /// Its parameters.
    pub params: Vec<ParamEstimate>,
}

impl FittedEffect {
    /// As an instance for a model.
    pub fn instance(&self) -> EffectInstance {
        EffectInstance {
            effect: self.effect.clone(),
            params: self.params.iter().map(|p| p.value).collect(),
        }
    }
}

/// A candidate model (baseline + effects) fitted and evaluated.
#[derive(Clone, Debug)]
pub struct Fit {
    /// Its effects.
    pub effects: Vec<FittedEffect>,
    /// Number of fitted (free) parameters.
    pub k: usize,
    /// Comparison with the data.
    pub eval: Evaluation,
    /// Model replays spent on the fit.
    pub evaluations: usize,
    /// (effect index, parameter index) of each free parameter, in the order of the
    /// covariance matrices.
    pub free: Vec<(usize, usize)>,
    /// Covariance of the free parameters allowing for autocorrelated residuals.
    pub cov: Option<DMatrix<f64>>,
    /// Gauss–Newton covariance of the free parameters for white residuals.
    pub cov_white: Option<DMatrix<f64>>,
}

impl Fit {
    /// Names of its effects with their forms, e.g. `thruster_lag (second_order)`.
    pub fn labels(&self) -> Vec<String> {
        self.effects
            .iter()
            .map(|e| format!("{} ({})", e.effect.name(), e.effect.form()))
            .collect()
    }

    /// Names of its effects.
    pub fn names(&self) -> Vec<String> {
        self.effects
            .iter()
            .map(|e| e.effect.name().to_string())
            .collect()
    }

    /// The model: `base` with `base_effects` and this fit's effects.
    pub fn model(
        &self,
        base: &VehicleParams,
        base_effects: &[EffectInstance],
        density: f64,
    ) -> VehicleModel {
        let mut list = base_effects.to_vec();
        list.extend(self.effects.iter().map(FittedEffect::instance));
        VehicleModel::with_effects(base.clone(), Effects::new(list), density)
    }
}

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
    fn of(form: &str, base: &Fit, fit: &Fit) -> Self {
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
    /// ΔBIC with effective sample counts (see [`rules::delta_bic_eff`]).
    pub delta_bic_eff: f64,
    /// Held-out block test t statistic (see [`crate::blocks::heldout_t`]).
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
    /// Residual weights of the baseline (see [`Evaluation::ml_factors`]).
    pub factors: BTreeMap<ChannelKind, f64>,
}

impl Outcome {
    /// Relative validation-RMSE reduction of the chosen model against the baseline, mean over
    /// channels [%].
    pub fn validation_gain_pct(&self) -> f64 {
        100.0 * gain(&self.baseline.eval, &self.chosen.eval)
    }
}
