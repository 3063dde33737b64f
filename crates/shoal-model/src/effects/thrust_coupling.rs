//! `thrust_coupling`: thrust of one group leaks into the yaw axis.
//!
//! The jet of a thruster does not leave the hull alone: wash hits the frame or the other
//! thrusters, and a mounting that is a little off-centre or skewed turns a force into a
//! moment the allocation does not know about. The μAUV² paper sees the vehicle turn while it
//! only dives; on the BlueROV, a differential yaw command with a net surge force turns faster
//! one way than the other.
//!
//! Modelled as a yaw moment proportional to the thrusters' body-frame force:
//! `N = k_z · F_z + k_x · F_x` (effective lever arms in metres).

use super::{Effect, ForceContext, ParamInfo};
use crate::math::Vec6;
use crate::vehicle::VehicleParams;

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrustCoupling;

impl Effect for ThrustCoupling {
    fn name(&self) -> &'static str {
        "thrust_coupling"
    }
    fn summary(&self) -> &'static str {
        "vertical and surge thrust leak into a yaw moment"
    }
    fn explanation(&self) -> &'static str {
        "Thruster wash and mounting errors: the thrusters' vertical force F_z and surge force \
         F_x produce a yaw moment N = k_z·F_z + k_x·F_x that the allocation does not expect."
    }
    fn params(&self, vehicle: &VehicleParams) -> Vec<ParamInfo> {
        let l = vehicle.body.hull_size.x.max(0.05);
        let p = |name, doc| ParamInfo {
            name,
            unit: "m",
            lo: -l,
            hi: l,
            null: 0.0,
            typical: 0.02 * l,
            doc,
            shape: false,
        };
        vec![
            p("k_z_m", "yaw moment per newton of vertical (body z) thrust"),
            p("k_x_m", "yaw moment per newton of surge (body x) thrust"),
        ]
    }
    fn force(&self, p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        let mut f = Vec6::zeros();
        f[5] = p[0] * ctx.thrust_force.z + p[1] * ctx.thrust_force.x;
        f
    }
}
