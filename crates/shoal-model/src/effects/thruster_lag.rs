//! `thruster_lag`: thrust follows the command through a first-order lag.
//!
//! A propeller cannot change its speed instantly: the motor and propeller inertia and the
//! water the propeller drags along make the thrust settle with a time constant τ after a step
//! of the command (Yoerger's one-state thruster model, linearised:
//! τ ḟ = f_static(n) − f). The μAUV² paper neglects thruster dynamics (Sec. 4.2); a lag shows
//! as measured motion trailing the replay after every command step.
//!
//! Modelled by adding τ to every thruster's lag time constant ([`ThrusterParams::lag`]), which
//! the actuator model integrates exactly over each step.
//!
//! [`ThrusterParams::lag`]: crate::thruster::ThrusterParams::lag

use super::{Effect, ParamInfo};
use crate::vehicle::VehicleParams;

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrusterLag;

impl Effect for ThrusterLag {
    fn name(&self) -> &'static str {
        "thruster_lag"
    }
    fn summary(&self) -> &'static str {
        "thrust follows the command through a first-order lag τ"
    }
    fn explanation(&self) -> &'static str {
        "Motor and propeller inertia: after a command step the thrust settles with a time \
         constant τ instead of jumping (one-state thruster model, linearised)."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![ParamInfo {
            name: "tau_s",
            unit: "s",
            lo: 0.0,
            hi: 2.0,
            null: 0.0,
            typical: 0.3,
            doc: "time constant added to each thruster's lag",
        }]
    }
    fn configure(&self, p: &[f64], vehicle: &mut VehicleParams) {
        for th in &mut vehicle.thrusters {
            th.lag += p[0];
        }
    }
}
