//! A fitted candidate model: its effects with their parameter estimates and covariances, and
//! its comparison with the data.

use crate::evaluate::evaluation::Evaluation;
use nalgebra::DMatrix;
use shoal_model::effects::{Effect, EffectInstance, Effects};
use shoal_model::vehicle::{VehicleModel, VehicleParams};
use std::sync::Arc;

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
