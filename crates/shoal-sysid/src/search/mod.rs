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
//! Levenberg–Marquardt ([`lm`](crate::evaluate::lm)) on the estimation residuals of all channels, each
//! channel weighted by the inverse of the fit's own residual variance, the weights updated and
//! the fit repeated until they settle. It starts from the best two of several points: the null
//! values, typical values, earlier fits, and a scan of the new effect's parameters — a line
//! from the null values towards the far bounds and a space-filling Halton design over their
//! whole box (`scan.rs`): threshold laws have no gradient where they do not bind, and
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
//!    reductions ([`heldout_t`](crate::evaluate::blocks::heldout_t)) is at least `t_threshold`
//!    (default 0: the mean block improvement must be positive; the t statistic is reported — a
//!    stricter threshold rejects effects that show only at a few events, such as a lag at
//!    command steps);
//! 4. the held-out RMSE falls by at least `min_material` (default 2 %) *of the baseline's*
//!    held-out RMSE: an extra effect that only trims what is left after the others — a form
//!    mismatch being soaked up — is not worth naming; unless it closes at least
//!    `min_closure` (default 50 %) of the gap between the held-out RMSE and the noise floor
//!    ([`measures::closure`]): an effect that explains most of what is left above the sensor
//!    noise is the rest of the story however small, where a soaking-up one trims a part;
//! 5. its parameters are jointly `z_threshold` (default 3) standard deviations from their null
//!    values (Wald test; shape parameters excluded).
//!
//! The gains of 2–4 are averaged over the channels the effect visibly changes: its held-out
//! prediction must move by at least one step of the channel's resolution (a quantised
//! sensor's step, read from the data; [`resolution`](crate::evaluate::stats::resolution)) — below that, a change
//! cannot be told from the quantisation itself.
//!
//! *Forward*: of the families that pass, the one whose model predicts the held-out data best
//! ([`measures::heldout_ratio`]: held-out RMSE relative to the current model's, averaged over every
//! channel) joins the model, then each promising remaining family is fitted together with the
//! chosen ones, and so on, until none passes or every channel's held-out residuals are white
//! (nothing is left to explain). When no family passes alone while structure is left, the round's
//! most promising families are fitted in pairs (`pairs.rs`): two effects hidden together can
//! each be a compromise that fails on the held-out part alone. *Backward*: every chosen effect
//! must still pass against the model without it (refitted); the weakest failing one is removed
//! and the test repeated; swaps of one effect for another that lower the BIC are tried.
//! *Forms again* (`refine.rs`): once the families are final, each family's forms are fitted
//! again beside all the others, and a form that lowers the model's BIC replaces the one chosen
//! when the family joined (then, a missing effect may have bent the choice). *Collapsed forms*
//! (`collapse.rs`): a named effect whose form's extra parameters end at their null values
//! (a depth-dependent buoyancy offset with a depth coefficient of 0) is the family's simpler
//! form, and is reported in it.
//!
//! **Identifiability** (`identify.rs`). For each chosen effect, the best alternative families
//! are fitted in its place. When an alternative explains the held-out data as well (the block
//! test cannot tell them apart) the log cannot separate the two: the verdict reports "A or B"
//! with the manoeuvre that would separate them, and names neither.
//!
//! **Stand-ins for a form** (`nuisance.rs`). A thrust-map family (gain, asymmetry, dead band,
//! saturation) beside another family, and any family beside a thrust-map family that explains
//! the most, is kept only where it fits better than a non-parametric thrust map in its place (a factor piecewise linear in the command, per direction, knots at
//! quantiles of the estimation commands): where the map fits better by the BIC over every
//! sample and by the effective ΔBIC, the family only soaks up the shape that the main
//! family's form misses, and the verdict lists it as *possible* (a stand-in) instead of
//! naming it.
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
//!
//! [`Effect::name`]: shoal_model::effects::Effect::name
//! [`Effect::form`]: shoal_model::effects::Effect::form

mod candidate;
mod collapse;
mod context;
mod fit;
mod fitted;
mod identify;
pub mod measures;
mod memo;
mod nuisance;
mod options;
mod orchestrate;
mod outcome;
mod pairs;
mod par;
mod refine;
mod rival;
pub mod rules;
mod scan;
mod stability;
mod step;
mod verdict;

pub use candidate::{Candidate, FormScore};
pub use fitted::{Fit, FittedEffect, ParamEstimate};
pub use identify::direct_channels;
pub use measures::{bic, delta_bic, gain};
pub use options::{PHYSICAL_RATIO, SearchOptions};
pub use orchestrate::search;
pub use outcome::Outcome;
pub use par::par_map;
pub use rival::Rival;
pub use step::Step;
pub use verdict::{Ambiguity, Possible, Unexplained, Verdict};
