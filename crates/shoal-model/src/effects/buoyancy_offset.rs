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
//! A `drift` form competes: ΔF(t) = ΔF₀ + r·t, a trim that changes during the run — water
//! seeping into the hull, air escaping from a foam or a cable gland, a pump compartment that
//! slowly floods. A constant offset fitted to the first part of such a log mispredicts the
//! rest by more and more. A `depth` form ΔF(z) = ΔF₀ + k·z stands for a compressible hull,
//! foam or air pocket that the water pressure squeezes: heavier the deeper it dives. A
//! `settling` form ΔF(t) = ΔF₀ + ΔF₁·(1 − e^(−t/τ)) is a change that levels off (air that
//! escapes until it is gone): the same three time laws — constant, drifting, settling — as
//! the depth sensor's bias and the battery's sag.

use super::effect::{Effect, ForceContext, ParamInfo};
use super::family::{Family, FamilyFacts, Regressor};
use super::laws::{settled, settling_tau_param};
use crate::math::{Vec6, join6};
use crate::vehicle_params::VehicleParams;
use std::sync::Arc;

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
        vertical_force(p[0], ctx)
    }
}

/// A force `df` along the world vertical (down, NED), acting at the centre of buoyancy, as a
/// body-frame wrench.
fn vertical_force(df: f64, ctx: &ForceContext<'_>) -> Vec6 {
    let f = ctx
        .rigid
        .attitude
        .inverse_transform_vector(&crate::math::Vec3::new(0.0, 0.0, df));
    let m = ctx.vehicle.body.cob.cross(&f);
    join6(&f, &m)
}

/// The `drift` form: the net vertical force changes linearly during the run,
/// ΔF(t) = ΔF₀ + r·t (t from the start of the run).
#[derive(Clone, Copy, Debug, Default)]
pub struct BuoyancyOffsetDrift;

impl Effect for BuoyancyOffsetDrift {
    fn name(&self) -> &'static str {
        "buoyancy_offset"
    }
    fn form(&self) -> &'static str {
        "drift"
    }
    fn summary(&self) -> &'static str {
        "net vertical force that changes during the run, ΔF(t) = ΔF₀ + r·t"
    }
    fn explanation(&self) -> &'static str {
        "Trim that changes during the run: water seeping in, air escaping, a compartment \
         slowly flooding; the idle vehicle sinks or rises faster and faster."
    }
    fn params(&self, vehicle: &VehicleParams) -> Vec<ParamInfo> {
        let mut p = BuoyancyOffset.params(vehicle);
        // Up to a tenth of the weight gained or lost in 100 s.
        let w = vehicle.body.mass * G;
        p.push(ParamInfo {
            name: "rate_n_s",
            unit: "N/s",
            lo: -1e-3 * w,
            hi: 1e-3 * w,
            null: 0.0,
            typical: 2e-6 * w,
            doc: "change of the net downward force per second",
            shape: false,
        });
        p
    }
    fn force(&self, p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        vertical_force(p[0] + p[1] * ctx.t, ctx)
    }
}

/// The `depth` form: the net vertical force grows with depth, ΔF(z) = ΔF₀ + k·z — a hull,
/// a foam or an air pocket compressed by the water pressure (z below the surface).
#[derive(Clone, Copy, Debug, Default)]
pub struct BuoyancyOffsetDepth;

impl Effect for BuoyancyOffsetDepth {
    fn name(&self) -> &'static str {
        "buoyancy_offset"
    }
    fn form(&self) -> &'static str {
        "depth"
    }
    fn summary(&self) -> &'static str {
        "net vertical force that grows with depth, ΔF(z) = ΔF₀ + k·z"
    }
    fn explanation(&self) -> &'static str {
        "A compressible hull, foam or air pocket squeezed by the water pressure: the vehicle \
         grows heavier the deeper it dives."
    }
    fn params(&self, vehicle: &VehicleParams) -> Vec<ParamInfo> {
        let mut p = BuoyancyOffset.params(vehicle);
        let w = vehicle.body.mass * G;
        p.push(ParamInfo {
            name: "k_n_m",
            unit: "N/m",
            lo: 0.0,
            hi: 0.05 * w,
            null: 0.0,
            typical: 0.0005 * w,
            doc: "growth of the net downward force per metre of depth (compression only makes \
                  a hull heavier)",
            shape: false,
        });
        p
    }
    fn force(&self, p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        vertical_force(p[0] + p[1] * ctx.rigid.position.z.max(0.0), ctx)
    }
}

/// The `settling` form: the net vertical force moves by ΔF₁ towards a new value with time
/// constant τ and levels off, ΔF(t) = ΔF₀ + ΔF₁·(1 − e^(−t/τ)) — air escaping from a
/// free-flooding fairing or a foam until it is gone, a hull taking up water until it is
/// soaked. (For τ much longer than the run it is the `drift` form's straight line.)
#[derive(Clone, Copy, Debug, Default)]
pub struct BuoyancyOffsetSettling;

impl Effect for BuoyancyOffsetSettling {
    fn name(&self) -> &'static str {
        "buoyancy_offset"
    }
    fn form(&self) -> &'static str {
        "settling"
    }
    fn summary(&self) -> &'static str {
        "net vertical force that changes and levels off, ΔF(t) = ΔF₀ + ΔF₁·(1 − e^(−t/τ))"
    }
    fn explanation(&self) -> &'static str {
        "Trim that changes during the run and then holds: air escaping from a fairing or a \
         foam, a hull soaking up water; the idle vehicle's drift changes and settles."
    }
    fn params(&self, vehicle: &VehicleParams) -> Vec<ParamInfo> {
        let mut p = BuoyancyOffset.params(vehicle);
        let w = vehicle.body.mass * G;
        p.push(ParamInfo {
            name: "delta_f1_n",
            unit: "N",
            lo: -0.1 * w,
            hi: 0.1 * w,
            null: 0.0,
            typical: 0.002 * w,
            doc: "change of the net downward force once settled",
            shape: false,
        });
        p.push(settling_tau_param(
            5.0,
            1000.0,
            "time constant of the change",
        ));
        p
    }
    fn force(&self, p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        vertical_force(p[0] + p[1] * settled(ctx.t, p[2]), ctx)
    }
}

/// The family: its forms, default first, and its facts.
pub(super) fn family() -> Family {
    Family {
        forms: vec![
            Arc::new(BuoyancyOffset),
            Arc::new(BuoyancyOffsetDrift),
            Arc::new(BuoyancyOffsetDepth),
            Arc::new(BuoyancyOffsetSettling),
        ],
        facts: FamilyFacts {
            excitation: "idle phases (all thrusters off) at several depths",
            direct: None,
            regressor: Regressor::Time,
            thrust_map: false,
            separations: &[],
        },
    }
}
