//! `depth_sensor_bias`: the depth reading has an offset and a linear drift.
//!
//! Pressure sensors drift with temperature and need a zero at the surface that is easily
//! off (atmospheric pressure changes, a zero taken with the port out of the water). The
//! reading is `depth + b₀ + b₁·t`: the motion is unchanged, only what the sensor says about
//! it. In a log the drift looks like a slow sinking or rising that no force explains.
//!
//! Note: with the initial depth taken from the first reading, b₀ is observable only where the
//! physics depends on absolute depth (at the surface).

//!
//! A `settling` form competes: `b₀ + Δ·(1 − e^(−t/τ))`, a drift that levels off; and a
//! `power_drift` form `b₀ + d·(t/100 s)^p` whose exponent p shapes a drift that accelerates
//! (p > 1, a sensor warming ever faster) or slows (p < 1); and an `s_curve` form
//! `b₀ + Δ·(1 − e^(−(t/τ)^k))`, a settling whose start is slow (k > 1: the sensor warms through
//! more than one thermal mass, or the vehicle crosses a thermocline).
use super::effect::{Effect, ParamInfo};
use super::family::{Family, FamilyFacts, Regressor};
use super::laws::{POWER_T_REF, settled, settling_tau_param, time_exponent_param};
use crate::vehicle_params::VehicleParams;
use std::sync::Arc;

/// The reading's constant offset b₀ \[m\], shared by both forms.
fn b0_param() -> ParamInfo {
    ParamInfo {
        name: "b0_m",
        unit: "m",
        lo: -0.5,
        hi: 0.5,
        null: 0.0,
        typical: 0.02,
        doc: "constant offset of the depth reading",
        shape: false,
    }
}

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct DepthSensorBias;

impl Effect for DepthSensorBias {
    fn form(&self) -> &'static str {
        "linear_drift"
    }
    fn name(&self) -> &'static str {
        "depth_sensor_bias"
    }
    fn summary(&self) -> &'static str {
        "depth reading offset b₀ plus linear drift b₁·t"
    }
    fn explanation(&self) -> &'static str {
        "Pressure-sensor zero and temperature drift: the reading is depth + b₀ + b₁·t while \
         the vehicle's motion is unchanged."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![
            b0_param(),
            ParamInfo {
                name: "b1_m_s",
                unit: "m/s",
                lo: -0.02,
                hi: 0.02,
                null: 0.0,
                typical: 5e-4,
                doc: "drift of the depth reading per second",
                shape: false,
            },
        ]
    }
    fn depth_offset(&self, p: &[f64], t: f64) -> f64 {
        p[0] + p[1] * t
    }
}

/// The `settling` form: the reading's offset moves by Δ towards a new value with time
/// constant τ, `b₀ + Δ·(1 − e^(−t/τ))` — a sensor warming up to the water's temperature.
#[derive(Clone, Copy, Debug, Default)]
pub struct DepthSensorBiasSettling;

impl Effect for DepthSensorBiasSettling {
    fn name(&self) -> &'static str {
        "depth_sensor_bias"
    }
    fn form(&self) -> &'static str {
        "settling"
    }
    fn summary(&self) -> &'static str {
        "depth reading offset b₀ that settles by Δ with time constant τ"
    }
    fn explanation(&self) -> &'static str {
        "Pressure-sensor zero that drifts while the sensor reaches the water's temperature: \
         the reading is depth + b₀ + Δ·(1 − e^(−t/τ)) while the motion is unchanged."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![
            b0_param(),
            ParamInfo {
                name: "delta_m",
                unit: "m",
                lo: -0.5,
                hi: 0.5,
                null: 0.0,
                typical: 0.03,
                doc: "change of the offset once settled",
                shape: false,
            },
            settling_tau_param(20.0, 1000.0, "time constant of the settling"),
        ]
    }
    fn depth_offset(&self, p: &[f64], t: f64) -> f64 {
        p[0] + p[1] * settled(t, p[2])
    }
}

/// The `power_drift` form: `b₀ + d·(t/100 s)^p` — a drift of d after 100 s whose exponent p
/// (the family's shape parameter; 1 is the linear drift) bends it.
#[derive(Clone, Copy, Debug, Default)]
pub struct DepthSensorBiasPower;

impl Effect for DepthSensorBiasPower {
    fn name(&self) -> &'static str {
        "depth_sensor_bias"
    }
    fn form(&self) -> &'static str {
        "power_drift"
    }
    fn summary(&self) -> &'static str {
        "depth reading offset b₀ plus a drift d·(t/100 s)^p"
    }
    fn explanation(&self) -> &'static str {
        "Pressure-sensor zero and a temperature drift that accelerates or slows: the reading \
         is depth + b₀ + d·(t/100 s)^p while the vehicle's motion is unchanged."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![
            b0_param(),
            ParamInfo {
                name: "d_m",
                unit: "m",
                lo: -0.5,
                hi: 0.5,
                null: 0.0,
                typical: 0.02,
                doc: "drift of the depth reading after 100 s",
                shape: false,
            },
            time_exponent_param("exponent of the drift's growth in time"),
        ]
    }
    fn depth_offset(&self, p: &[f64], t: f64) -> f64 {
        p[0] + p[1] * (t.max(0.0) / POWER_T_REF).powf(p[2])
    }
}

/// The `s_curve` form: `b₀ + Δ·(1 − e^(−(t/τ)^k))` — a settling that starts slowly and levels
/// off (a Weibull law; k = 1 is the `settling` form, k > 1 an S-curve): a sensor that warms
/// through more than one thermal mass (housing, then membrane), or a reading that changes as
/// the vehicle passes into a water layer of another temperature.
#[derive(Clone, Copy, Debug, Default)]
pub struct DepthSensorBiasSCurve;

impl Effect for DepthSensorBiasSCurve {
    fn name(&self) -> &'static str {
        "depth_sensor_bias"
    }
    fn form(&self) -> &'static str {
        "s_curve"
    }
    fn summary(&self) -> &'static str {
        "depth reading offset b₀ that moves by Δ along an S-curve, 1 − e^(−(t/τ)^k)"
    }
    fn explanation(&self) -> &'static str {
        "Pressure-sensor zero that drifts slowly at first, then faster, then levels off (the \
         sensor warms through more than one thermal mass, or the water's temperature changes): \
         the reading is depth + b₀ + Δ·(1 − e^(−(t/τ)^k)) while the motion is unchanged."
    }
    fn params(&self, vehicle: &VehicleParams) -> Vec<ParamInfo> {
        let mut p = DepthSensorBiasSettling.params(vehicle);
        p[2].doc = "time at which the offset has moved by 63 % of Δ";
        p.push(ParamInfo {
            name: "k",
            unit: "-",
            lo: 1.0,
            hi: 6.0,
            null: 2.0,
            typical: 2.0,
            doc: "steepness of the S-curve (1: the settling form's exponential)",
            shape: true,
        });
        p
    }
    fn depth_offset(&self, p: &[f64], t: f64) -> f64 {
        // The settling law in the time variable (t/τ)^k.
        let x = t.max(0.0) / p[2].max(1e-3);
        p[0] + p[1] * settled(x.powf(p[3]), 1.0)
    }
}

/// The family: its forms, default first, and its facts.
pub(super) fn family() -> Family {
    Family {
        forms: vec![
            Arc::new(DepthSensorBias),
            Arc::new(DepthSensorBiasSettling),
            Arc::new(DepthSensorBiasPower),
            Arc::new(DepthSensorBiasSCurve),
        ],
        facts: FamilyFacts {
            excitation: "a surface check (the reading at zero depth) at the start and at the end",
            direct: None,
            regressor: Regressor::Time,
            thrust_map: false,
            separations: &[(
                "buoyancy_offset",
                "surface at the start and at the end (a sensor bias reads ≠ 0 at the surface, a \
             buoyancy offset does not) and hold a depth with the thrusters off (a buoyancy \
             offset moves the vehicle, a sensor bias only the reading)",
            )],
        },
    }
}
