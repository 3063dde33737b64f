//! `buoyancy_offset` truth forms — weight and buoyancy differ, but not by a constant ΔF, a
//! steady drift ΔF₀ + r·t, a change that settles ΔF₀ + ΔF₁·(1 − e^(−t/τ)) or a linear growth
//! with depth ΔF₀ + k·z as the fitting side assumes:
//!
//! * `buoyancy_offset/gas_compression` — the vehicle was trimmed neutral at the surface with
//!   air trapped in the hull; the air compresses with depth (Boyle), so the vehicle grows
//!   heavier as it dives: ΔF(z) = B_g·(1 − 1/(1 + z/H)), B_g the air's buoyancy at the surface,
//!   H = p_atm/(ρg) ≈ 10.33 m of fresh water. Close to the catalogue's `depth` form near the
//!   surface, it bends away from it with depth (at 2 m, 16 % below the tangent line).
//! * `buoyancy_offset/slow_leak` — a float or a seal leaks slowly: ΔF(t) = ΔF₀ + r·t, a trim
//!   error plus water seeping in at a steady rate. The catalogue's `drift` form has this law:
//!   the form is matched.
//! * `buoyancy_offset/venting_air` — air trapped under a free-flooding fairing escapes through
//!   a small vent after the dive starts, and water takes its place: the vehicle grows heavier
//!   and levels off, ΔF(t) = ΔF₀ + A·(1 − e^(−t/τ)). The catalogue's `settling` form has this
//!   law: the form is matched.
//! * `buoyancy_offset/leaking_bubble` — the vehicle was trimmed neutral at the surface with an
//!   air bubble in the hull that both compresses with depth (Boyle) and escapes through a
//!   leak: ΔF(z, t) = B_g·(1 − e^(−t/τ)/(1 + z/H)). Depth and time act together, which no
//!   single fitting form has.
//!
//! All act as the catalogue's force along the world vertical at the centre of buoyancy
//! (positive: heavier), with the value of the moment.

use super::effect_meta::truth_effect_meta;
use super::exp_kind::ExpKind;
use super::form_param::FormParam;
use super::truth_form::{Part, TruthForm};
use shoal_model::effects::{
    BuoyancyOffset, BuoyancyOffsetDrift, BuoyancyOffsetSettling, Effect, ForceContext,
};
use shoal_model::math::Vec6;
use std::sync::Arc;

/// Water column of one atmosphere in fresh water, p_atm/(ρg) \[m\].
const ATMOSPHERE_HEAD: f64 = 101_325.0 / (1000.0 * shoal_model::math::GRAVITY);

const GAS: &str = "buoyancy_offset/gas_compression";
const GAS_LAW: &str = "ΔF(z) = B_g·(1 − 1/(1 + z/10.33 m)), neutral at the surface";
const LEAK: &str = "buoyancy_offset/slow_leak";
const LEAK_LAW: &str = "ΔF(t) = ΔF₀ + r·t";
const VENT: &str = "buoyancy_offset/venting_air";
const VENT_LAW: &str = "ΔF(t) = ΔF₀ + A·(1 − e^(−t/τ))";
const BUBBLE: &str = "buoyancy_offset/leaking_bubble";
const BUBBLE_LAW: &str = "ΔF(z, t) = B_g·(1 − e^(−t/τ)/(1 + z/10.33 m)), neutral at the surface";

pub(super) fn forms() -> Vec<TruthForm> {
    vec![
        TruthForm {
            name: GAS,
            family: "buoyancy_offset",
            law: GAS_LAW,
            params: vec![FormParam::magnitude(
                "b_gas_n",
                "N",
                0.016,
                0.04,
                "buoyancy of the trapped air at the surface (1.6–4 ml; ΔF 1.5–3.8 mN at 1 m)",
            )],
            excites: &[ExpKind::Heave, ExpKind::Trim, ExpKind::Yaw],
            build: |p| Part::Effect(Arc::new(GasCompression { b_gas: p[0] })),
        },
        TruthForm {
            name: LEAK,
            family: "buoyancy_offset",
            law: LEAK_LAW,
            params: vec![
                FormParam::shape("delta_f0_n", "N", -0.001, 0.001, "trim error at the start"),
                FormParam::magnitude(
                    "rate_n_s",
                    "N/s",
                    1.5e-5,
                    3.0e-5,
                    "weight gained per second (1.5–3 µl/s of water seeping in)",
                ),
            ],
            excites: &[ExpKind::Heave, ExpKind::Trim, ExpKind::Yaw],
            build: |p| {
                Part::Effect(Arc::new(SlowLeak {
                    delta_f0: p[0],
                    rate: p[1],
                }))
            },
        },
        TruthForm {
            name: VENT,
            family: "buoyancy_offset",
            law: VENT_LAW,
            params: vec![
                FormParam::shape("delta_f0_n", "N", -0.001, 0.001, "trim error at the start"),
                FormParam::magnitude(
                    "a_n",
                    "N",
                    0.003,
                    0.006,
                    "weight gained once the air has vented (0.3–0.6 ml of air)",
                ),
                FormParam::shape("tau_s", "s", 20.0, 60.0, "time constant of the venting"),
            ],
            excites: &[ExpKind::Heave, ExpKind::Trim, ExpKind::Yaw],
            build: |p| {
                Part::Effect(Arc::new(VentingAir {
                    delta_f0: p[0],
                    a: p[1],
                    tau: p[2],
                }))
            },
        },
        TruthForm {
            name: BUBBLE,
            family: "buoyancy_offset",
            law: BUBBLE_LAW,
            params: vec![
                FormParam::magnitude(
                    "b_gas_n",
                    "N",
                    0.01,
                    0.025,
                    "buoyancy of the bubble at the surface (1–2.5 ml of air)",
                ),
                FormParam::shape("tau_s", "s", 40.0, 150.0, "time constant of the leak"),
            ],
            excites: &[ExpKind::Heave, ExpKind::Trim, ExpKind::Yaw],
            build: |p| {
                Part::Effect(Arc::new(LeakingBubble {
                    b_gas: p[0],
                    tau: p[1],
                }))
            },
        },
    ]
}

/// See the module documentation.
#[derive(Debug)]
struct GasCompression {
    /// Buoyancy of the trapped air at the surface \[N\].
    b_gas: f64,
}

impl Effect for GasCompression {
    truth_effect_meta!(GAS, GAS_LAW);
    fn force(&self, _p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        let z = ctx.rigid.position.z.max(0.0);
        let df = self.b_gas * (1.0 - 1.0 / (1.0 + z / ATMOSPHERE_HEAD));
        BuoyancyOffset.force(&[df], ctx)
    }
}

/// See the module documentation.
#[derive(Debug)]
struct SlowLeak {
    /// Net downward force at the start \[N\].
    delta_f0: f64,
    /// Weight gained per second [N/s].
    rate: f64,
}

impl Effect for SlowLeak {
    truth_effect_meta!(LEAK, LEAK_LAW);
    fn force(&self, _p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        // The catalogue's `drift` form has this law (the form is matched).
        BuoyancyOffsetDrift.force(&[self.delta_f0, self.rate], ctx)
    }
}

/// See the module documentation.
#[derive(Debug)]
struct VentingAir {
    /// Net downward force at the start \[N\].
    delta_f0: f64,
    /// Weight gained once the air has vented \[N\].
    a: f64,
    /// Time constant of the venting \[s\].
    tau: f64,
}

impl Effect for VentingAir {
    truth_effect_meta!(VENT, VENT_LAW);
    fn force(&self, _p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        // The catalogue's `settling` form has this law (the form is matched).
        BuoyancyOffsetSettling.force(&[self.delta_f0, self.a, self.tau], ctx)
    }
}

/// See the module documentation.
#[derive(Debug)]
struct LeakingBubble {
    /// Buoyancy of the bubble at the surface at the start \[N\].
    b_gas: f64,
    /// Time constant of the leak \[s\].
    tau: f64,
}

impl Effect for LeakingBubble {
    truth_effect_meta!(BUBBLE, BUBBLE_LAW);
    fn force(&self, _p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        let z = ctx.rigid.position.z.max(0.0);
        let left = (-ctx.t.max(0.0) / self.tau).exp() / (1.0 + z / ATMOSPHERE_HEAD);
        BuoyancyOffset.force(&[self.b_gas * (1.0 - left)], ctx)
    }
}
