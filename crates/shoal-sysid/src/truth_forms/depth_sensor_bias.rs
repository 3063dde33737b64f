//! `depth_sensor_bias` truth forms — the depth reading is off by a slowly changing amount, but
//! neither b₀ + b₁·t nor b₀ + Δ(1 − e^(−t/τ)) as the fitting side assumes:
//!
//! * `depth_sensor_bias/quadratic_drift` — b₀ + b₂·t²: a drift that accelerates (a sensor
//!   warming ever faster as the electronics heat up).
//! * `depth_sensor_bias/two_stage_thermal` — the sensor's temperature follows the electronics'
//!   warm-up through two thermal masses in series (time constants τ₁ > τ₂), so the bias rises
//!   along an S-curve with zero initial slope:
//!   b₀ + Δ·(1 − (τ₁e^(−t/τ₁) − τ₂e^(−t/τ₂))/(τ₁ − τ₂)).
//!
//! Both change only what the pressure sensor reports, not the motion.

use super::{ExpKind, FormParam, Part, TruthForm, truth_effect_meta};
use shoal_model::effects::Effect;
use std::sync::Arc;

const QUADRATIC: &str = "depth_sensor_bias/quadratic_drift";
const QUADRATIC_LAW: &str = "depth reading + b₀ + b₂·t²";
const THERMAL: &str = "depth_sensor_bias/two_stage_thermal";
const THERMAL_LAW: &str = "depth reading + b₀ + Δ·(1 − (τ₁e^(−t/τ₁) − τ₂e^(−t/τ₂))/(τ₁ − τ₂))";

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
