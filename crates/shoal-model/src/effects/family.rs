//! What an effect family is: its forms (catalogue entries sharing one [`Effect::name`]) and
//! the facts about it that the model search and its report need — what excites it, the
//! channels it shows in first, what its residual signature is plotted against and the
//! manoeuvres that tell it from a look-alike. Every family file builds one [`Family`]; its
//! facts are required fields, so a new family cannot be listed without them.

use super::effect::Effect;
use std::sync::Arc;

/// One effect family of the catalogue.
#[derive(Clone, Debug)]
pub struct Family {
    /// Its forms, default first; all share one [`Effect::name`].
    pub forms: Vec<Arc<dyn Effect>>,
    /// What the search and the report know of it.
    pub facts: FamilyFacts,
}

impl Family {
    /// The family's name (its default form's [`Effect::name`]).
    pub fn name(&self) -> &'static str {
        self.forms[0].name()
    }
}

/// What the search and the report know of one family.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FamilyFacts {
    /// The experiment that excites the family most clearly, in words.
    pub excitation: &'static str,
    /// The channels it shows in first, where it has such channels (`None`: every channel
    /// the family touches will do).
    pub direct: Option<DirectChannels>,
    /// What its residual signature is plotted against.
    pub regressor: Regressor,
    /// Whether the family is a static map from command to thrust (a gain, an asymmetry, a
    /// dead band, a saturation): a form mismatch of another such family leaves a residual it
    /// can soak up, so the search keeps it beside another family only where it fits better
    /// than a non-parametric thrust map ([`super::ThrustMap`]) in its place.
    pub thrust_map: bool,
    /// Manoeuvres that tell it from particular other families, each (other family's name,
    /// manoeuvre in words); against families not listed here (nor listing it) the two
    /// families' [`FamilyFacts::excitation`]s are the manoeuvre.
    pub separations: &'static [(&'static str, &'static str)],
}

/// The channels a family shows in first and why the family is not fitted on runs that log
/// none of them. Without them only second-order marks remain (a tilted hull's thrust pointing
/// a little off), too easily taken for the direct marks of other families for a verdict to
/// rest on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DirectChannels {
    /// Log channel names (as after `y.` in a log's columns: `roll`, `x`, …).
    pub channels: &'static [&'static str],
    /// Why the family is not fitted without any of them, in words.
    pub why_not_fitted: &'static str,
}

/// What a family's residual signature is plotted against.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Regressor {
    /// The command of the most active thruster input [%].
    Command,
    /// Time since the run's start \[s\].
    Time,
    /// The rate of the channel: the measured value itself for rates and velocities, else the
    /// measured value differenced over 0.2 s (channel unit per second).
    Rate,
}
