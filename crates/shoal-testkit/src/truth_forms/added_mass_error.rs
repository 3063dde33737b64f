//! `added_mass_error` truth forms — the vehicle is more sluggish than the baseline believes, but
//! not by one constant scale on its added mass and inertia as the fitting side assumes:
//!
//! * `added_mass_error/entrained_water` — water in flooded spaces of the hull is coupled to it
//!   by a soft spring and a damper (natural frequency ω_f, damping ratio ζ_f), in heave and in
//!   yaw: slow motions carry it along (the effective mass grows by μ·M), quick ones leave it
//!   behind, and it rings after a step. The water is neutrally buoyant: no weight change.
//! * `added_mass_error/speed_dependent` — the wake a moving hull drags along adds to its
//!   effective mass: M_eff = M·(1 + c·min(|ν|/ν_ref, 2)) in heave and yaw (ν_ref as in
//!   [`super::NU_REF`]), the baseline's at rest. Quasi-static: the momentum change of the
//!   growing wake itself is left out.
//!
//! M is the effective mass or inertia of the axis, M_RB + M_A, of the baseline.

use super::exp_kind::ExpKind;
use super::form_param::FormParam;
use super::truth_form::{Part, TruthForm};
use crate::synth::TruthHook;
use shoal_model::effects::NU_REF;
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::{VehicleModel, VehicleState};

/// The axes the forms act on: heave (w) and yaw (r).
const AXES: [usize; 2] = [2, 5];

pub(super) fn forms() -> Vec<TruthForm> {
    vec![
        TruthForm {
            name: "added_mass_error/entrained_water",
            family: "added_mass_error",
            law: "internal water μ·M on a spring-damper (ω_f, ζ_f) in heave and yaw",
            params: vec![
                FormParam::magnitude("mu", "-", 0.3, 0.6, "entrained water per effective mass"),
                FormParam::shape("omega_rad_s", "rad/s", 2.0, 5.0, "coupling frequency ω_f"),
                FormParam::shape("zeta", "-", 0.2, 0.5, "coupling damping ratio ζ_f"),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Hook(Box::new(EntrainedWater {
                    mu: p[0],
                    omega: p[1],
                    zeta: p[2],
                    water: None,
                }))
            },
        },
        TruthForm {
            name: "added_mass_error/speed_dependent",
            family: "added_mass_error",
            law: "M_eff = M·(1 + c·min(|ν|/ν_ref, 2)) in heave and yaw",
            params: vec![FormParam::magnitude(
                "c",
                "-",
                0.3,
                0.6,
                "effective mass gained at the reference speed, per effective mass",
            )],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| Part::Hook(Box::new(SpeedDependent { c: p[0] })),
        },
    ]
}

/// See the module documentation.
struct EntrainedWater {
    /// Internal water per effective mass \[-\].
    mu: f64,
    /// Coupling frequency \[rad/s\].
    omega: f64,
    /// Coupling damping ratio \[-\].
    zeta: f64,
    /// Per axis of [`AXES`]: (mass [kg or kg·m²], displacement relative to the hull [m or rad],
    /// velocity [m/s or rad/s]), once started.
    water: Option<[(f64, f64, f64); 2]>,
}

impl TruthHook for EntrainedWater {
    fn before_integrate(
        &mut self,
        _model: &VehicleModel,
        state: &mut VehicleState,
        _env: &Environment,
        dt: f64,
    ) {
        // The run starts at rest: the water moves with the hull.
        let mass = &state.mass.m_total;
        let water = self
            .water
            .get_or_insert_with(|| AXES.map(|i| (self.mu * mass[(i, i)], 0.0, 0.0)));
        for (k, &i) in AXES.iter().enumerate() {
            let (m, x, u) = &mut water[k];
            let hull = state.rigid.nu[i];
            // Force of the water on the hull, held over the step like every other force.
            let f =
                *m * (self.omega * self.omega * *x + 2.0 * self.zeta * self.omega * (*u - hull));
            state.tau[i] += f;
            // Semi-implicit Euler: ω_f·dt ≤ 0.025 at the simulation's 5 ms step.
            *u -= dt * f / *m;
            *x += dt * (*u - hull);
        }
    }
}

/// See the module documentation.
struct SpeedDependent {
    /// Effective mass gained at the reference speed, per effective mass \[-\].
    c: f64,
}

impl TruthHook for SpeedDependent {
    fn before_integrate(
        &mut self,
        model: &VehicleModel,
        state: &mut VehicleState,
        env: &Environment,
        _dt: f64,
    ) {
        let mut mp = model
            .params
            .mass_properties(state.ballast_volume, env.density);
        for i in AXES {
            let s = (state.rigid.nu[i] / NU_REF[i]).abs().min(2.0);
            mp.m_total[(i, i)] *= 1.0 + self.c * s;
        }
        if let Some(inv) = mp.m_total.try_inverse() {
            mp.m_inv = inv;
            state.set_mass(mp);
        }
    }
}
