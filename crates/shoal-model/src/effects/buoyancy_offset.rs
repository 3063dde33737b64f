//! `buoyancy_offset`: a constant net vertical force ΔF.
//!
//! A vehicle trimmed "neutral" rarely is: a few grams of lead, an air bubble in the hull, a
//! different water density. The difference between weight and buoyancy is a constant force
//! along the world vertical that makes the vehicle drift up or down whenever the thrusters
//! are idle (the BlueROV logs show it: depth drifts 0.47 → 0.80 m with every thruster off).
//!
//! Modelled as a force of ΔF along world z (down, NED) acting at the centre of buoyancy:
//! ΔF > 0 makes the vehicle heavier (it sinks), ΔF < 0 lighter.

//!
//! A `depth_dependent` form competes: ΔF(z) = ΔF₀ + k·z (a compressible hull).
use super::{Effect, ForceContext, ParamInfo};
use crate::math::{Vec6, join6};
use crate::vehicle::VehicleParams;

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct BuoyancyOffset;

/// Default gravitational acceleration used to scale the bounds [m/s²].
const G: f64 = crate::math::GRAVITY;

impl Effect for BuoyancyOffset {
    fn form(&self) -> &'static str {
        "constant"
    }
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

/// The `depth_dependent` form: the net vertical force changes with depth,
/// ΔF(z) = ΔF₀ + k·z — a hull or an air pocket compressed by the water pressure.
#[derive(Clone, Copy, Debug, Default)]
pub struct BuoyancyOffsetDepth;

impl Effect for BuoyancyOffsetDepth {
    fn name(&self) -> &'static str {
        "buoyancy_offset"
    }
    fn form(&self) -> &'static str {
        "depth_dependent"
    }
    fn summary(&self) -> &'static str {
        "net vertical force ΔF₀ + k·depth (positive: heavier)"
    }
    fn explanation(&self) -> &'static str {
        "Trim not neutral and a compressible hull or air pocket: the net downward force is \
         ΔF₀ at the surface and changes by k per metre of depth."
    }
    fn params(&self, vehicle: &VehicleParams) -> Vec<ParamInfo> {
        let w = vehicle.body.mass * G;
        vec![
            ParamInfo {
                name: "delta_f_n",
                unit: "N",
                lo: -0.1 * w,
                hi: 0.1 * w,
                null: 0.0,
                typical: 0.002 * w,
                doc: "net downward force at the surface",
                shape: false,
            },
            ParamInfo {
                name: "k_n_m",
                unit: "N/m",
                lo: 0.0,
                hi: 0.05 * w,
                null: 0.0,
                typical: 0.002 * w,
                doc: "growth of the net downward force per metre of depth (compression only \
                      makes a hull heavier)",
                shape: false,
            },
        ]
    }
    fn force(&self, p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        let df = p[0] + p[1] * ctx.rigid.position.z;
        let f = ctx
            .rigid
            .attitude
            .inverse_transform_vector(&crate::math::Vec3::new(0.0, 0.0, df));
        let m = ctx.vehicle.body.cob.cross(&f);
        join6(&f, &m)
    }
}
