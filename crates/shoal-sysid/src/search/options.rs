//! The settings of a search: the effects it considers, the thresholds of its rules, the
//! stability check and the Levenberg–Marquardt settings.

use crate::evaluate::lm::LmOptions;
use shoal_model::effects::{Effect, EffectInstance, Effects};
use shoal_model::vehicle::{VehicleModel, VehicleParams};
use std::sync::Arc;

/// The default of [`SearchOptions::physical_ratio`]: how far an effect must move some
/// channel's held-out prediction (RMS) to be named, in units of that channel's noise floor
/// (`tests/null_and_pairs.rs` puts the threshold on each side of measured sizes): an effect
/// that changes every prediction by less than the sensor noise is physically nothing, however
/// much it lowers an RMSE statistically.
pub const PHYSICAL_RATIO: f64 = 1.0;

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
    /// correlation, see [`delta_bic_eff`](super::measures::delta_bic_eff)) with which an effect
    /// survives the backward checks of the model it is part of (default 0).
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
    /// How far an effect must move some channel's held-out prediction (RMS) to be named, in
    /// units of that channel's noise floor (default [`PHYSICAL_RATIO`], 1).
    pub physical_ratio: f64,
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
            block_s: crate::evaluate::blocks::DEFAULT_BLOCK_S,
            t_threshold: 0.0,
            min_material: 0.02,
            min_closure: 0.5,
            physical_ratio: PHYSICAL_RATIO,
            stability_draws: 8,
            stability_threshold: 0.8,
            seed: 0x5140a1,
        }
    }
}

impl SearchOptions {
    /// The baseline model every candidate is measured against: `base` with these options'
    /// own effects ([`SearchOptions::base_effects`]), in water of `density` [kg/m³].
    pub fn baseline_model(&self, base: &VehicleParams, density: f64) -> VehicleModel {
        VehicleModel::with_effects(
            base.clone(),
            Effects::new(self.base_effects.clone()),
            density,
        )
    }

    /// How many effect families [`SearchOptions::effects`] holds (each of one or more forms).
    pub fn family_count(&self) -> usize {
        families(&self.effects).len()
    }
}

/// The forms of each family among `effects`, families in first-appearance order.
pub(super) fn families(effects: &[Arc<dyn Effect>]) -> Vec<(String, Vec<Arc<dyn Effect>>)> {
    let mut out: Vec<(String, Vec<Arc<dyn Effect>>)> = Vec::new();
    for e in effects {
        match out.iter_mut().find(|(n, _)| n == e.name()) {
            Some((_, v)) => v.push(e.clone()),
            None => out.push((e.name().to_string(), vec![e.clone()])),
        }
    }
    out
}
