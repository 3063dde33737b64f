//! `added_mass_error`: effective mass and inertia differ from the baseline.
//!
//! Added mass is hard to identify (the μAUV² paper's heave fit has R² = 0.80) and the
//! rotational inertia of a small vehicle is usually estimated, not measured. A wrong value
//! shows in the transients — how fast the vehicle picks up and loses speed — not in the
//! terminal speeds.
//!
//! Modelled by scaling the added-mass matrix M_A and the rigid-body rotational inertia by k.
//! The rigid mass itself is fixed by the weight and stays.

use super::effect::{Effect, ParamInfo};
use super::family::{Family, FamilyFacts, Regressor};
use crate::vehicle_params::VehicleParams;
use std::sync::Arc;

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct AddedMassError;

impl Effect for AddedMassError {
    fn name(&self) -> &'static str {
        "added_mass_error"
    }
    fn summary(&self) -> &'static str {
        "effective mass and inertia differ (scale factor on M_A and rotational inertia)"
    }
    fn explanation(&self) -> &'static str {
        "Poor identification of the added mass and inertia: the vehicle speeds up and slows \
         down more sluggishly (k > 1) or more briskly (k < 1) than the model."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![ParamInfo {
            name: "scale",
            unit: "-",
            lo: 0.1,
            hi: 5.0,
            null: 1.0,
            typical: 1.5,
            doc: "factor on M_A and on the rigid-body inertia",
            shape: false,
        }]
    }
    fn configure(&self, p: &[f64], vehicle: &mut VehicleParams) {
        vehicle.body.added_mass *= p[0];
        vehicle.body.inertia_cg *= p[0];
    }
}

/// The family: its forms, default first, and its facts.
pub(super) fn family() -> Family {
    Family {
        forms: vec![Arc::new(AddedMassError)],
        facts: FamilyFacts {
            excitation: "short, hard accelerations from rest",
            direct: None,
            regressor: Regressor::Time,
            thrust_map: false,
            separations: &[],
        },
    }
}
