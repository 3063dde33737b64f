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
//!
//! A `direction` form competes: the vertical arm differs with the sense of the vertical
//! thrust, k_z₊ pushing down and k_z₋ pushing up — the wash meets a fin, a skid or a cable on
//! one side of the hull only.

use super::effect::{Effect, ForceContext, ParamInfo};
use super::family::{Family, FamilyFacts, Regressor};
use crate::math::Vec6;
use crate::vehicle_params::VehicleParams;
use std::sync::Arc;

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
        vec![
            arm(
                vehicle,
                "k_z_m",
                "yaw moment per newton of vertical (body z) thrust",
            ),
            arm(
                vehicle,
                "k_x_m",
                "yaw moment per newton of surge (body x) thrust",
            ),
        ]
    }
    fn force(&self, p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        yaw_moment(p[0] * ctx.thrust_force.z + p[1] * ctx.thrust_force.x)
    }
}

/// An effective lever arm \[m\], bounded by the hull's length.
fn arm(vehicle: &VehicleParams, name: &'static str, doc: &'static str) -> ParamInfo {
    let l = vehicle.body.hull_size.x.max(0.05);
    ParamInfo {
        name,
        unit: "m",
        lo: -l,
        hi: l,
        null: 0.0,
        typical: 0.02 * l,
        doc,
        shape: false,
    }
}

/// A pure yaw moment `n` \[N·m\] as a body-frame wrench.
fn yaw_moment(n: f64) -> Vec6 {
    let mut f = Vec6::zeros();
    f[5] = n;
    f
}

/// The `direction` form: N = k_z±·F_z + k_x·F_x with the arm k_z₊ while the thrusters push
/// down (F_z ≥ 0, body z down) and k_z₋ while they push up.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrustCouplingDirection;

impl Effect for ThrustCouplingDirection {
    fn name(&self) -> &'static str {
        "thrust_coupling"
    }
    fn form(&self) -> &'static str {
        "direction"
    }
    fn summary(&self) -> &'static str {
        "vertical thrust leaks into a yaw moment with an arm of its own in each direction"
    }
    fn explanation(&self) -> &'static str {
        "Thruster wash meeting a fin, a skid or a cable on one side of the hull: pushing down \
         and pushing up turn the vehicle by different amounts."
    }
    fn params(&self, vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![
            arm(
                vehicle,
                "k_down_m",
                "yaw moment per newton of downward (body +z) thrust",
            ),
            arm(
                vehicle,
                "k_up_m",
                "yaw moment per newton of upward (body −z) thrust",
            ),
            arm(
                vehicle,
                "k_x_m",
                "yaw moment per newton of surge (body x) thrust",
            ),
        ]
    }
    fn force(&self, p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        let fz = ctx.thrust_force.z;
        let k_z = if fz >= 0.0 { p[0] } else { p[1] };
        yaw_moment(k_z * fz + p[2] * ctx.thrust_force.x)
    }
}

/// The family: its forms, default first, and its facts.
pub(super) fn family() -> Family {
    Family {
        forms: vec![Arc::new(ThrustCoupling), Arc::new(ThrustCouplingDirection)],
        facts: FamilyFacts {
            excitation: "vertical thrust steps with the heading logged",
            direct: None,
            regressor: Regressor::Command,
            thrust_map: false,
            separations: &[],
        },
    }
}
