//! A question a verdict leaves open, as two fitted models: an "A or B" (the chosen model and
//! the alternative's), or an effect only possible (the model with it and the model refitted
//! without it). What a next experiment is chosen to answer ([`crate::experiment`]).

use super::fitted::Fit;

/// Two fitted models the log cannot decide between.
#[derive(Clone, Debug)]
pub struct Rival {
    /// The first explanation, as the report names it (an effect family).
    pub a: String,
    /// The second (another family, or `no <family>`).
    pub b: String,
    /// The model of the first.
    pub fit_a: Fit,
    /// The model of the second.
    pub fit_b: Fit,
}
