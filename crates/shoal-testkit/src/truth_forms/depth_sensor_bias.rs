//! `depth_sensor_bias` truth forms — the depth reading is off by a slowly changing amount, but
//! neither b₀ + b₁·t nor b₀ + Δ(1 − e^(−t/τ)) as the fitting side assumes:
//!
//! * `depth_sensor_bias/quadratic_drift` — b₀ + b₂·t²: a drift that accelerates (a sensor
//!   warming ever faster as the electronics heat up). The catalogue's `power_drift` form has
//!   this law (p = 2): the form is matched.
//! * `depth_sensor_bias/two_stage_thermal` — the sensor's temperature follows the electronics'
//!   warm-up through two thermal masses in series (time constants τ₁ > τ₂), so the bias rises
//!   along an S-curve with zero initial slope:
//!   b₀ + Δ·(1 − (τ₁e^(−t/τ₁) − τ₂e^(−t/τ₂))/(τ₁ − τ₂)).
//! * `depth_sensor_bias/thermocline_step` — b₀ + Δ·σ((t − t_c)/w), σ the logistic function:
//!   mid-run the sensor meets water of another temperature (a thermocline, an inflow of warmer
//!   water) and its reading follows its temperature coefficient through the housing's thermal
//!   lag, a step of a few centimetres w wide, flat before and after.
//!
//! All change only what the pressure sensor reports, not the motion.

use super::effect_meta::truth_effect_meta;
use super::exp_kind::ExpKind;
use super::form_param::FormParam;
use super::logistic::logistic;
use super::truth_form::{Part, TruthForm};
use shoal_model::effects::Effect;
use std::sync::Arc;

const QUADRATIC: &str = "depth_sensor_bias/quadratic_drift";
const QUADRATIC_LAW: &str = "depth reading + b₀ + b₂·t²";
const THERMAL: &str = "depth_sensor_bias/two_stage_thermal";
const THERMAL_LAW: &str = "depth reading + b₀ + Δ·(1 − (τ₁e^(−t/τ₁) − τ₂e^(−t/τ₂))/(τ₁ − τ₂))";
const STEP: &str = "depth_sensor_bias/thermocline_step";
const STEP_LAW: &str = "depth reading + b₀ + Δ·σ((t − t_c)/w), σ logistic";

pub(super) fn forms() -> Vec<TruthForm> {
    vec![
        TruthForm {
            name: QUADRATIC,
            family: "depth_sensor_bias",
            law: QUADRATIC_LAW,
            params: vec![
                FormParam::shape("b0_m", "m", -0.05, 0.05, "offset at the start"),
                FormParam::signed(
                    "b2_m_s2",
                    "m/s²",
                    5e-6,
                    1.2e-5,
                    "curvature of the drift (0.07–0.17 m after 120 s)",
                ),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| Part::Effect(Arc::new(QuadraticDrift { b0: p[0], b2: p[1] })),
        },
        TruthForm {
            name: THERMAL,
            family: "depth_sensor_bias",
            law: THERMAL_LAW,
            params: vec![
                FormParam::shape("b0_m", "m", -0.05, 0.05, "offset at the start"),
                FormParam::signed("delta_m", "m", 0.04, 0.1, "final change of the offset"),
                FormParam::shape("tau1_s", "s", 25.0, 50.0, "slow thermal time constant τ₁"),
                FormParam::shape("tau2_s", "s", 6.0, 15.0, "fast thermal time constant τ₂"),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Effect(Arc::new(TwoStageThermal {
                    b0: p[0],
                    delta: p[1],
                    tau1: p[2],
                    tau2: p[3],
                }))
            },
        },
        TruthForm {
            name: STEP,
            family: "depth_sensor_bias",
            law: STEP_LAW,
            params: vec![
                FormParam::shape("b0_m", "m", -0.05, 0.05, "offset at the start"),
                FormParam::signed("delta_m", "m", 0.04, 0.08, "height of the step Δ"),
                FormParam::shape("t_c_s", "s", 40.0, 80.0, "time of the step's middle t_c"),
                FormParam::shape("w_s", "s", 5.0, 15.0, "width of the step w"),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Effect(Arc::new(ThermoclineStep {
                    b0: p[0],
                    delta: p[1],
                    t_c: p[2],
                    w: p[3],
                }))
            },
        },
    ]
}

/// See the module documentation.
#[derive(Debug)]
struct QuadraticDrift {
    /// Offset \[m\].
    b0: f64,
    /// Curvature [m/s²].
    b2: f64,
}

impl Effect for QuadraticDrift {
    truth_effect_meta!(QUADRATIC, QUADRATIC_LAW);
    fn depth_offset(&self, _p: &[f64], t: f64) -> f64 {
        self.b0 + self.b2 * t * t
    }
}

/// See the module documentation.
#[derive(Debug)]
struct TwoStageThermal {
    /// Offset at the start \[m\].
    b0: f64,
    /// Final change \[m\].
    delta: f64,
    /// Slow time constant \[s\].
    tau1: f64,
    /// Fast time constant \[s\] (< `tau1`).
    tau2: f64,
}

impl Effect for TwoStageThermal {
    truth_effect_meta!(THERMAL, THERMAL_LAW);
    fn depth_offset(&self, _p: &[f64], t: f64) -> f64 {
        let (a, b) = (self.tau1, self.tau2);
        let s = 1.0 - (a * (-t / a).exp() - b * (-t / b).exp()) / (a - b);
        self.b0 + self.delta * s
    }
}

/// See the module documentation.
#[derive(Debug)]
struct ThermoclineStep {
    /// Offset at the start \[m\].
    b0: f64,
    /// Height of the step \[m\].
    delta: f64,
    /// Middle of the step \[s\].
    t_c: f64,
    /// Width of the step \[s\].
    w: f64,
}

impl Effect for ThermoclineStep {
    truth_effect_meta!(STEP, STEP_LAW);
    fn depth_offset(&self, _p: &[f64], t: f64) -> f64 {
        self.b0 + self.delta * logistic((t - self.t_c) / self.w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thermocline_step_is_a_logistic_step_of_delta_around_t_c() {
        let form = forms().into_iter().find(|f| f.name == STEP);
        let form = form.expect("registered");
        let Part::Effect(e) = form.part(&[0.01, -0.06, 60.0, 10.0]) else {
            panic!("an effect")
        };
        let b = |t: f64| e.depth_offset(&[], t);
        // σ(−6) = 0.002473, σ(0) = 1/2, σ(1) = 0.731059, σ(6) = 0.997527.
        assert!((b(0.0) - (0.01 - 0.06 * 0.002_473)).abs() < 1e-6);
        assert!((b(60.0) - (0.01 - 0.03)).abs() < 1e-12);
        assert!((b(70.0) - (0.01 - 0.06 * 0.731_059)).abs() < 1e-6);
        assert!((b(120.0) - (0.01 - 0.06 * 0.997_527)).abs() < 1e-6);
        // Symmetric about the middle: b(t_c + s) + b(t_c − s) = 2·b(t_c).
        assert!((b(75.0) + b(45.0) - 2.0 * b(60.0)).abs() < 1e-12);
        // Δ = 0: a constant offset.
        let null = ThermoclineStep {
            b0: 0.02,
            delta: 0.0,
            t_c: 60.0,
            w: 10.0,
        };
        assert!((0..=120).all(|t| null.depth_offset(&[], f64::from(t)) == 0.02));
    }
}
