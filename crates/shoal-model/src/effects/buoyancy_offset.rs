//! `buoyancy_offset`: a constant net vertical force ΔF.
//!
//! A vehicle trimmed "neutral" rarely is: a few grams of lead, an air bubble in the hull, a
//! different water density. The difference between weight and buoyancy is a constant force
//! along the world vertical that makes the vehicle drift up or down whenever the thrusters
//! are idle (the BlueROV logs show it: depth drifts 0.47 → 0.80 m with every thruster off).
//!
//! Modelled as a force of ΔF along world z (down, NED) acting at the centre of buoyancy:
//! ΔF > 0 makes the vehicle heavier (it sinks), ΔF < 0 lighter.

use super::{Effect, ForceContext, ParamInfo};
use crate::math::{Vec6, join6};
use crate::vehicle::VehicleParams;

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct BuoyancyOffset;

/// Default gravitational acceleration used to scale the bounds [m/s²].
const G: f64 = crate::math::GRAVITY;

impl Effect for BuoyancyOffset {
    fn name(&self) -> &'static str {
        "buoyancy_offset"
    }
    fn summary(&self) -> &'static str {
        "constant net vertical force ΔF (positive: heavier)"
    }
    fn explanation(&self) -> &'static str {
        "Trim not neutral: weight and buoyancy differ by ΔF, a constant force along the \
         world vertical that makes the idle vehicle sink (ΔF > 0) or rise (ΔF < 0)."
    }
    fn params(&self, vehicle: &VehicleParams) -> Vec<ParamInfo> {
        // Up to a tenth of the vehicle's weight either way.
        let w = vehicle.body.mass * G;
        vec![ParamInfo {
            name: "delta_f_n",
            unit: "N",
            lo: -0.1 * w,
            hi: 0.1 * w,
            null: 0.0,
            typical: 0.002 * w,
            doc: "net downward force (weight minus buoyancy error)",
            shape: false,
        }]
    }
    fn force(&self, p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        let f = ctx
            .rigid
            .attitude
            .inverse_transform_vector(&crate::math::Vec3::new(0.0, 0.0, p[0]));
        let m = ctx.vehicle.body.cob.cross(&f);
        join6(&f, &m)
    }
}
