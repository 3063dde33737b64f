//! `battery_sag`: the thrust scale falls during the run, k(t) = 1 − s·t.
//!
//! A discharging battery's voltage drops, and with it the motor speed and the thrust at a
//! given command (T200 maximum thrust grows roughly as V^1.2). Over a long run the same
//! command pushes less and less: residuals that grow with time.
//!
//! Modelled as `f = max(1 − s·t, 0) · f_static`, t from the start of the run.

//!
//! An `exponential` form competes with the linear one: k(t) = 1 − a·(1 − e^(−t/τ)), a sag
//! that levels off; a `power` form k(t) = 1 − a·(t/100 s)^p has a shape exponent p for a sag
//! that accelerates (p > 1: a cell nearing the knee of its discharge curve) or slows (p < 1).
use super::effect::{Effect, ParamInfo, ThrustContext};
use super::family::{Family, FamilyFacts, Regressor};
use super::laws::{POWER_T_REF, settled, settling_tau_param, time_exponent_param};
use crate::vehicle_params::VehicleParams;
use std::sync::Arc;

/// The fraction a of the thrust a sag takes (the exponential and power forms).
fn fraction_param(doc: &'static str) -> ParamInfo {
    ParamInfo {
        name: "a",
        unit: "-",
        lo: 0.0,
        hi: 0.6,
        null: 0.0,
        typical: 0.1,
        doc,
        shape: false,
    }
}

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct BatterySag;

impl Effect for BatterySag {
    fn form(&self) -> &'static str {
        "linear"
    }
    fn name(&self) -> &'static str {
        "battery_sag"
    }
    fn summary(&self) -> &'static str {
        "thrust scale falls during the run, k(t) = 1 − s·t"
    }
    fn explanation(&self) -> &'static str {
        "Battery discharge: the voltage, and with it the thrust at a given command, falls \
         steadily over the run."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![ParamInfo {
            name: "s_per_s",
            unit: "1/s",
            lo: 0.0,
            hi: 0.01,
            null: 0.0,
            typical: 0.001,
            doc: "relative thrust lost per second",
            shape: false,
        }]
    }
    fn thrust(&self, p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        (1.0 - p[0] * ctx.t).max(0.0) * f
    }
}

/// The `exponential` form: the thrust scale falls by a fraction a with time constant τ and
/// levels off, k(t) = 1 − a·(1 − e^(−t/τ)) — a battery whose voltage drops quickly under load
/// and then holds.
#[derive(Clone, Copy, Debug, Default)]
pub struct BatterySagExponential;

impl Effect for BatterySagExponential {
    fn name(&self) -> &'static str {
        "battery_sag"
    }
    fn form(&self) -> &'static str {
        "exponential"
    }
    fn summary(&self) -> &'static str {
        "thrust scale falls and levels off, k(t) = 1 − a·(1 − e^(−t/τ))"
    }
    fn explanation(&self) -> &'static str {
        "Battery discharge under load: the voltage, and with it the thrust, drops by a \
         fraction a with time constant τ and then holds."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![
            fraction_param("fraction of thrust lost in the end"),
            settling_tau_param(5.0, 1000.0, "time constant of the sag"),
        ]
    }
    fn thrust(&self, p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        (1.0 - p[0] * settled(ctx.t, p[1])).max(0.0) * f
    }
}

/// The `power` form: k(t) = 1 − a·(t/100 s)^p. The exponent p is the family's shape
/// parameter: 1 is the linear sag, 2 a sag that accelerates as the cells near the knee of
/// their discharge curve, below 1 one that slows.
#[derive(Clone, Copy, Debug, Default)]
pub struct BatterySagPower;

impl Effect for BatterySagPower {
    fn name(&self) -> &'static str {
        "battery_sag"
    }
    fn form(&self) -> &'static str {
        "power"
    }
    fn summary(&self) -> &'static str {
        "thrust scale falls as a power of time, k(t) = 1 − a·(t/100 s)^p"
    }
    fn explanation(&self) -> &'static str {
        "Battery discharge whose voltage falls faster (p > 1) or slower (p < 1) than linearly \
         in time: the thrust at a given command drops by a fraction a after 100 s."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![
            fraction_param("fraction of thrust lost after 100 s"),
            time_exponent_param("exponent of the sag's growth in time"),
        ]
    }
    fn thrust(&self, p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        let x = (ctx.t.max(0.0) / POWER_T_REF).powf(p[1]);
        (1.0 - p[0] * x).max(0.0) * f
    }
}

/// The family: its forms, default first, and its facts.
pub(super) fn family() -> Family {
    Family {
        forms: vec![
            Arc::new(BatterySag),
            Arc::new(BatterySagExponential),
            Arc::new(BatterySagPower),
        ],
        facts: FamilyFacts {
            excitation: "the same command step repeated at the start and at the end of a long run",
            direct: None,
            regressor: Regressor::Time,
            thrust_map: false,
            separations: &[(
                "thrust_gain",
                "repeat the same command step at the start and at the end of the run (a sag \
             changes the response over time, a gain does not)",
            )],
        },
    }
}
