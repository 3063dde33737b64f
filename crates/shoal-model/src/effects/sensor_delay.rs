//! `sensor_delay`: every measurement lags the truth by δ.
//!
//! On-board filters, averaging ADCs, serial links and logging on receipt delay what a log
//! says about the vehicle. Against an undelayed replay the measurement trails every change of
//! motion by the same time, whatever the command.
//!
//! Modelled as `y(t) = y_true(t − δ)` for every sensor (in a running world: each sample is
//! held back by δ).

use super::effect::{Effect, ParamInfo};
use super::family::{Family, FamilyFacts, Regressor};
use crate::vehicle_params::VehicleParams;
use std::sync::Arc;

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct SensorDelay;

impl Effect for SensorDelay {
    fn name(&self) -> &'static str {
        "sensor_delay"
    }
    fn summary(&self) -> &'static str {
        "measurements lag the truth by δ"
    }
    fn explanation(&self) -> &'static str {
        "Filtering and transport delay: every measurement shows the vehicle as it was δ \
         seconds earlier."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![ParamInfo {
            name: "delay_s",
            unit: "s",
            lo: 0.0,
            hi: 1.0,
            null: 0.0,
            typical: 0.1,
            doc: "measurement delay",
            shape: false,
        }]
    }
    fn delay(&self, p: &[f64]) -> f64 {
        p[0]
    }
}

/// The family: its forms, default first, and its facts.
pub(super) fn family() -> Family {
    Family {
        forms: vec![Arc::new(SensorDelay)],
        facts: FamilyFacts {
            excitation: "fast command reversals",
            direct: None,
            regressor: Regressor::Time,
            thrust_map: false,
            separations: &[],
        },
    }
}
