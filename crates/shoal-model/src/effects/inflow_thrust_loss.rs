//! `inflow_thrust_loss`: thrust falls with the axial inflow speed (dynamic ≠ static thrust).
//!
//! A thrust curve measured on a bench is *static*: the propeller works in still water. When
//! the vehicle moves along the thrust direction, the water enters the propeller at the
//! advance speed u_a, the advance ratio J = u_a/(nD) grows and the thrust coefficient falls,
//! K_T ≈ K_T0 (1 − J/J₀) — the μAUV² paper suspects exactly this (static ≠ dynamic thrust).
//! With the propeller speed n ∝ √|f_static| this gives
//!
//! ```text
//! f = f_static − κ · √|f_static| · u_a
//! ```
//!
//! (and the thrust never changes sign by it). The loss grows with speed and vanishes at rest,
//! so it looks like extra damping that only acts while the thruster runs.

//!
//! A `linear` form competes, `f = f_static − k·|f_static|·u_a`.
use super::effect::{Effect, ParamInfo, ThrustContext};
use super::family::{Family, FamilyFacts, Regressor};
use crate::vehicle_params::VehicleParams;
use std::sync::Arc;

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct InflowThrustLoss;

impl Effect for InflowThrustLoss {
    fn form(&self) -> &'static str {
        "advance_ratio"
    }
    fn name(&self) -> &'static str {
        "inflow_thrust_loss"
    }
    fn summary(&self) -> &'static str {
        "thrust falls with the axial inflow speed (dynamic ≠ static thrust)"
    }
    fn explanation(&self) -> &'static str {
        "Propeller advance ratio: moving along the thrust direction lowers the thrust \
         coefficient, f = f_static − κ·√|f_static|·u_a with u_a the axial inflow speed."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![ParamInfo {
            name: "kappa",
            unit: "√N·s/m",
            lo: 0.0,
            hi: 5.0,
            null: 0.0,
            typical: 0.5,
            doc: "thrust loss per √N of static thrust and m/s of inflow",
            shape: false,
        }]
    }
    fn thrust(&self, p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        reduced(f, p[0] * f.abs().sqrt() * ctx.inflow)
    }
}

/// The `linear` form: thrust lost in proportion to thrust and inflow speed,
/// `f = f_static − k·|f_static|·u_a` (momentum theory at small inflow).
#[derive(Clone, Copy, Debug, Default)]
pub struct InflowThrustLossLinear;

impl Effect for InflowThrustLossLinear {
    fn name(&self) -> &'static str {
        "inflow_thrust_loss"
    }
    fn form(&self) -> &'static str {
        "linear"
    }
    fn summary(&self) -> &'static str {
        "thrust falls in proportion to thrust and axial inflow speed"
    }
    fn explanation(&self) -> &'static str {
        "Propeller inflow: moving along the thrust direction lowers the thrust by a fraction \
         k·u_a of itself, f = f_static − k·|f_static|·u_a."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![ParamInfo {
            name: "k_s_m",
            unit: "s/m",
            lo: 0.0,
            hi: 10.0,
            null: 0.0,
            typical: 1.0,
            doc: "relative thrust loss per m/s of inflow",
            shape: false,
        }]
    }
    fn thrust(&self, p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        reduced(f, p[0] * f.abs() * ctx.inflow)
    }
}

/// Static thrust `f` \[N\] less the inflow loss `loss` \[N\] (signed along `f`: negative
/// when the vehicle moves against its thrust, a gain): an inflow slows the propeller's thrust
/// to zero at most, never reverses it. Shared by every form of the family (and by the test
/// set's truth forms).
pub fn reduced(f: f64, loss: f64) -> f64 {
    let g = f - loss;
    if g * f < 0.0 { 0.0 } else { g }
}

/// Inflow speed the `power` form's loss is quoted at \[m/s\]: a typical μAUV² heave or surge
/// speed.
pub const INFLOW_REF: f64 = 0.1;

/// The `power` form: the relative loss grows as a power of the inflow speed,
/// `f = f_static − k·|f_static|·sign(u_a)·(|u_a|/u_ref)^p` with u_ref = [`INFLOW_REF`]; the
/// shape `p` spans a loss that sets in with the first cm/s and then hardly grows (p ≪ 1),
/// the `linear` form (p = 1) and a loss growing with the square of the inflow (p = 2).
#[derive(Clone, Copy, Debug, Default)]
pub struct InflowThrustLossPower;

impl Effect for InflowThrustLossPower {
    fn name(&self) -> &'static str {
        "inflow_thrust_loss"
    }
    fn form(&self) -> &'static str {
        "power"
    }
    fn summary(&self) -> &'static str {
        "thrust falls by a fraction of itself growing as a power of the inflow speed"
    }
    fn explanation(&self) -> &'static str {
        "Propeller inflow whose loss is not linear in the speed: moving along the thrust \
         direction lowers the thrust by k·(u_a/u_ref)^p of itself (u_ref = 0.1 m/s)."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![
            ParamInfo {
                name: "k",
                unit: "-",
                lo: 0.0,
                hi: 2.0,
                null: 0.0,
                typical: 0.2,
                doc: "fraction of the thrust lost at 0.1 m/s of inflow",
                shape: false,
            },
            ParamInfo {
                name: "p",
                unit: "-",
                lo: 0.1,
                hi: 3.0,
                null: 1.0,
                typical: 1.0,
                doc: "exponent of the inflow speed",
                shape: true,
            },
        ]
    }
    fn thrust(&self, p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        let u = ctx.inflow;
        let rel = p[0] * u.signum() * (u.abs() / INFLOW_REF).powf(p[1]);
        reduced(f, rel * f.abs())
    }
}

/// The family: its forms, default first, and its facts.
pub(super) fn family() -> Family {
    Family {
        forms: vec![
            Arc::new(InflowThrustLoss),
            Arc::new(InflowThrustLossLinear),
            Arc::new(InflowThrustLossPower),
        ],
        facts: FamilyFacts {
            excitation: "the same command from rest and while already moving along the thrust axis",
            direct: None,
            regressor: Regressor::Command,
            thrust_map: false,
            separations: &[],
        },
    }
}
