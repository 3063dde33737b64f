//! A truth form: one law of one catalogue family's physics, its parameters and how it enters
//! the simulation.

use super::exp_kind::ExpKind;
use super::form_param::{Draw, FormParam};
use crate::synth::TruthHook;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use shoal_model::effects::Effect;
use std::fmt;
use std::sync::Arc;

/// How a truth form enters the simulation.
pub enum Part {
    /// Through the model's effect hooks (stateless laws). The effect carries its own values;
    /// its [`Effect::params`] is empty.
    Effect(Arc<dyn Effect>),
    /// Around every physics step and sample (laws with state of their own).
    Hook(Box<dyn TruthHook>),
}

impl fmt::Debug for Part {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Part::Effect(e) => write!(f, "Effect({})", e.name()),
            Part::Hook(_) => write!(f, "Hook"),
        }
    }
}

/// A truth form: one law of one catalogue family's physics.
#[derive(Clone, Debug)]
pub struct TruthForm {
    /// `family/form`, e.g. `thruster_lag/slew_rate`.
    pub name: &'static str,
    /// The catalogue effect whose physics this is (`Effect::name()`), the expected verdict.
    pub family: &'static str,
    /// The law in one line.
    pub law: &'static str,
    /// The parameters, in the order [`TruthForm::part`] takes them.
    pub params: Vec<FormParam>,
    /// The designed experiments whose logs show it. Empty for a form none shows — a tether
    /// needs the hull to travel, which the designed experiments do not (and an open-loop
    /// surge leg cannot: the μAUV² is directionally unstable and spins within seconds); such
    /// forms are hidden only in the closed-loop missions ([`crate::closed_loop`]).
    pub excites: &'static [ExpKind],
    /// Builds the part from parameter values.
    pub(super) build: fn(&[f64]) -> Part,
}

impl TruthForm {
    /// The form's own name (after the `/`).
    pub fn form(&self) -> &'static str {
        self.name.split_once('/').map_or(self.name, |(_, f)| f)
    }

    /// Draws parameter values: magnitudes uniformly within `band`, a sub-interval of 0 … 1 from
    /// the weak to the strong end of each magnitude's range ((0, 1) is the whole range,
    /// (0.5, 1) its stronger half); shapes over their whole range.
    pub fn draw(&self, rng: &mut ChaCha8Rng, band: (f64, f64)) -> Vec<f64> {
        let (b0, b1) = (band.0.clamp(0.0, 1.0), band.1.clamp(0.0, 1.0));
        self.params
            .iter()
            .map(|p| {
                let u = match p.draw {
                    Draw::Shape => rng.random_range(0.0..1.0),
                    _ => b0 + (b1 - b0) * rng.random_range(0.0..1.0),
                };
                let v = match p.draw {
                    Draw::Deficit => p.hi - (p.hi - p.lo) * u,
                    _ => p.lo + (p.hi - p.lo) * u,
                };
                if p.draw == Draw::Signed && rng.random_bool(0.5) {
                    -v
                } else {
                    v
                }
            })
            .collect()
    }

    /// The part for parameter `values` (in the order of [`TruthForm::params`]).
    ///
    /// # Panics
    /// If `values` has the wrong length.
    pub fn part(&self, values: &[f64]) -> Part {
        assert_eq!(
            values.len(),
            self.params.len(),
            "{} takes {} parameters",
            self.name,
            self.params.len()
        );
        (self.build)(values)
    }
}
