//! `ballast_mass`: the pump changes mass and weight at flow q.
//!
//! The μAUV² paper's model assumes a constant mass while its buoyancy tank takes in and
//! pushes out water. shoal's baseline already carries the tank as variable mass (weight and
//! centre of gravity change, [`crate::ballast`]); this effect fits the pump's real volume
//! flow q, which sets how fast the weight changes while the pump runs: drift that starts and
//! stops with the pump command.
//!
//! Modelled by replacing the tank's flow with q. Its null value is the baseline's flow.
//! Applies only to vehicles with a buoyancy tank.

use super::effect::{Effect, ParamInfo};
use super::family::{Family, FamilyFacts, Regressor};
use crate::vehicle_params::VehicleParams;
use std::sync::Arc;

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct BallastMass;

impl Effect for BallastMass {
    fn name(&self) -> &'static str {
        "ballast_mass"
    }
    fn summary(&self) -> &'static str {
        "the pump changes mass and weight at flow q"
    }
    fn explanation(&self) -> &'static str {
        "Buoyancy tank: while the pump runs, water enters or leaves at the volume flow q and \
         the vehicle's mass and weight change with it (variable mass)."
    }
    fn not_applicable(&self, vehicle: &VehicleParams) -> Option<String> {
        vehicle
            .ballast
            .is_none()
            .then(|| "the vehicle has no buoyancy tank".to_string())
    }
    fn params(&self, vehicle: &VehicleParams) -> Vec<ParamInfo> {
        let base = vehicle.ballast.as_ref().map_or(0.0, |b| b.flow * 1e6);
        vec![ParamInfo {
            name: "flow_ml_s",
            unit: "ml/s",
            lo: 0.0,
            hi: 20.0_f64.max(10.0 * base),
            null: base,
            typical: if base > 0.0 { 2.0 * base } else { 0.1 },
            doc: "pump volume flow (both directions)",
            shape: false,
        }]
    }
    fn configure(&self, p: &[f64], vehicle: &mut VehicleParams) {
        if let Some(b) = &mut vehicle.ballast {
            b.flow = p[0] * 1e-6;
        }
    }
}

/// The family: its forms, default first, and its facts.
pub(super) fn family() -> Family {
    Family {
        forms: vec![Arc::new(BallastMass)],
        facts: FamilyFacts {
            excitation: "pump phases with the thrusters off",
            direct: None,
            regressor: Regressor::Time,
            thrust_map: false,
            separations: &[],
        },
    }
}
