//! `water_current`: a constant horizontal current in the world frame.
//!
//! Pools circulate (filters, inlets) and open water flows. A constant, irrotational current
//! carries the vehicle along without changing its motion relative to the water, so it shows
//! only in tracked positions: a steady drift of x and y.
//!
//! Modelled as a current (v_x, v_y) added to the world's (the dynamics use the velocity
//! relative to the water, [`crate::dynamics`]). Vertical currents are left out: they are
//! negligible in pools and, in a depth-only log, indistinguishable from a depth-sensor drift.

use super::effect::{Effect, ParamInfo};
use super::family::{Family, FamilyFacts, Regressor};
use crate::math::Vec3;
use crate::vehicle_params::VehicleParams;
use std::sync::Arc;

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct WaterCurrent;

impl Effect for WaterCurrent {
    fn name(&self) -> &'static str {
        "water_current"
    }
    fn summary(&self) -> &'static str {
        "constant horizontal current in the world frame"
    }
    fn explanation(&self) -> &'static str {
        "Pool circulation or open-water flow: the water, and the vehicle with it, moves at a \
         constant velocity; seen as a steady drift of the tracked position."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        let p = |name, doc| ParamInfo {
            name,
            unit: "m/s",
            lo: -1.0,
            hi: 1.0,
            null: 0.0,
            typical: 0.05,
            doc,
            shape: false,
        };
        vec![
            p("vx_m_s", "current towards world x (north)"),
            p("vy_m_s", "current towards world y (east)"),
        ]
    }
    fn current(&self, p: &[f64]) -> Vec3 {
        Vec3::new(p[0], p[1], 0.0)
    }
}

/// The family: its forms, default first, and its facts.
pub(super) fn family() -> Family {
    Family {
        forms: vec![Arc::new(WaterCurrent)],
        facts: FamilyFacts {
            excitation: "holding station with the position tracked",
            direct: None,
            regressor: Regressor::Time,
            thrust_map: false,
            separations: &[],
        },
    }
}
