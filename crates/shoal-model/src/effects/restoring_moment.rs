//! `restoring_moment`: the centre of gravity is not where the model puts it.
//!
//! The first thing a trim error does is tilt the vehicle: a battery mounted a few millimetres
//! off, a sensor added at the nose, lead placed to one side, a foam block that is lighter on
//! one end. Weight and buoyancy then no longer act on one vertical line and the hull settles
//! at a roll and pitch where their moments balance — θ ≈ atan(Δx / BG) for a shift Δx along
//! the hull over a metacentric height BG, so that a millimetre tilts the μAUV² (BG = 15 mm)
//! by almost 4°. A tilted hull also points its thrusters off their nominal directions.
//!
//! Modelled as the moment of the weight W = m·g about a centre of gravity displaced by
//! Δr = (Δx, Δy, 0) in the body frame: M = Δr × Rᵀ·(0, 0, W). (A centre of buoyancy
//! displaced by −Δr has the same moment for a neutral vehicle, so this one family stands for
//! both; the vertical component, which changes the metacentric height, is not fitted: it shows
//! only in roll and pitch oscillations that few logs excite.)
//!
//! A `drift` form competes: Δr(t) = Δr₀ + ṙ·t — a compartment at one end slowly flooding,
//! a battery or a loose weight working its way along the hull; the tilt grows during the run.
//! A `settling` form Δr(t) = Δr₀ + Δr₁·(1 − e^(−t/τ)) is a change that levels off (a
//! compartment that floods until it is full): the same three time laws — constant, drifting,
//! settling — as the buoyancy offset's.
//!
//! Roll and pitch show it directly; logs without them see it only through the tilted thrust.

use super::effect::{Effect, ForceContext, ParamInfo};
use super::family::{DirectChannels, Family, FamilyFacts, Regressor};
use super::laws::{settled, settling_tau_param};
use crate::math::{Vec3, Vec6, join6};
use crate::vehicle_params::VehicleParams;
use std::sync::Arc;

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct RestoringMoment;

/// The largest shift of the centre of gravity a fit may try [m]: twice the metacentric height
/// (a tilt of 63°), at least 2 cm.
fn bound(vehicle: &VehicleParams) -> f64 {
    2.0 * (vehicle.body.cog.z - vehicle.body.cob.z).max(0.01)
}

/// A shift of the centre of gravity along body `axis` (`x` or `y`).
fn shift(vehicle: &VehicleParams, name: &'static str, doc: &'static str) -> ParamInfo {
    let b = bound(vehicle);
    ParamInfo {
        name,
        unit: "m",
        lo: -b,
        hi: b,
        null: 0.0,
        typical: 0.05 * b,
        doc,
        shape: false,
    }
}

/// The moment of the weight about a centre of gravity displaced by `dr` (body frame, m), as a
/// body-frame wrench.
fn weight_moment(dr: Vec3, ctx: &ForceContext<'_>) -> Vec6 {
    let w = ctx.vehicle.body.mass * ctx.gravity;
    let f = ctx
        .rigid
        .attitude
        .inverse_transform_vector(&Vec3::new(0.0, 0.0, w));
    join6(&Vec3::zeros(), &dr.cross(&f))
}

impl Effect for RestoringMoment {
    fn name(&self) -> &'static str {
        "restoring_moment"
    }
    fn summary(&self) -> &'static str {
        "centre of gravity shifted by (Δx, Δy): the hull trims at a roll and pitch"
    }
    fn explanation(&self) -> &'static str {
        "Trim error: the centre of gravity sits Δx forward and Δy to starboard of the \
         model's, so weight and buoyancy make a moment that tilts the resting hull \
         (pitch ≈ −atan(Δx/BG), roll ≈ atan(Δy/BG)) and its thrusters with it."
    }
    fn params(&self, vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![
            shift(
                vehicle,
                "dx_m",
                "shift of the centre of gravity forward (body x)",
            ),
            shift(
                vehicle,
                "dy_m",
                "shift of the centre of gravity to starboard (body y)",
            ),
        ]
    }
    fn force(&self, p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        weight_moment(Vec3::new(p[0], p[1], 0.0), ctx)
    }
}

/// The `drift` form: the shift grows during the run, Δr(t) = Δr₀ + ṙ·t.
#[derive(Clone, Copy, Debug, Default)]
pub struct RestoringMomentDrift;

impl Effect for RestoringMomentDrift {
    fn name(&self) -> &'static str {
        "restoring_moment"
    }
    fn form(&self) -> &'static str {
        "drift"
    }
    fn summary(&self) -> &'static str {
        "centre of gravity that moves during the run, Δr(t) = Δr₀ + ṙ·t"
    }
    fn explanation(&self) -> &'static str {
        "Trim that changes during the run: a compartment at one end flooding, a loose weight \
         working its way along the hull; the resting tilt grows steadily."
    }
    fn params(&self, vehicle: &VehicleParams) -> Vec<ParamInfo> {
        let mut p = RestoringMoment.params(vehicle);
        // Up to the whole bound in 100 s.
        let r = 0.01 * bound(vehicle);
        for (name, doc) in [
            ("dx_rate_m_s", "forward shift per second"),
            ("dy_rate_m_s", "starboard shift per second"),
        ] {
            p.push(ParamInfo {
                name,
                unit: "m/s",
                lo: -r,
                hi: r,
                null: 0.0,
                typical: 0.05 * r,
                doc,
                shape: false,
            });
        }
        p
    }
    fn force(&self, p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        weight_moment(
            Vec3::new(p[0] + p[2] * ctx.t, p[1] + p[3] * ctx.t, 0.0),
            ctx,
        )
    }
}

/// The `settling` form: the shift moves by Δr₁ and levels off,
/// Δr(t) = Δr₀ + Δr₁·(1 − e^(−t/τ)).
#[derive(Clone, Copy, Debug, Default)]
pub struct RestoringMomentSettling;

impl Effect for RestoringMomentSettling {
    fn name(&self) -> &'static str {
        "restoring_moment"
    }
    fn form(&self) -> &'static str {
        "settling"
    }
    fn summary(&self) -> &'static str {
        "centre of gravity that moves and levels off, Δr(t) = Δr₀ + Δr₁·(1 − e^(−t/τ))"
    }
    fn explanation(&self) -> &'static str {
        "Trim that changes during the run and then holds: a compartment at one end flooding \
         until it is full; the resting tilt changes and settles."
    }
    fn params(&self, vehicle: &VehicleParams) -> Vec<ParamInfo> {
        let mut p = RestoringMoment.params(vehicle);
        p.push(shift(vehicle, "dx1_m", "forward shift added once settled"));
        p.push(shift(
            vehicle,
            "dy1_m",
            "starboard shift added once settled",
        ));
        p.push(settling_tau_param(
            5.0,
            1000.0,
            "time constant of the change",
        ));
        p
    }
    fn force(&self, p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        let k = settled(ctx.t, p[4]);
        weight_moment(Vec3::new(p[0] + p[2] * k, p[1] + p[3] * k, 0.0), ctx)
    }
}

/// The family: its forms, default first, and its facts.
pub(super) fn family() -> Family {
    Family {
        forms: vec![
            Arc::new(RestoringMoment),
            Arc::new(RestoringMomentDrift),
            Arc::new(RestoringMomentSettling),
        ],
        facts: FamilyFacts {
            excitation: "resting at depth with roll and pitch logged (the resting tilt)",
            direct: Some(DirectChannels {
                channels: &["roll", "pitch", "p", "q"],
                why_not_fitted: "not fitted: these runs log neither roll nor pitch (nor their rates), where a \
             shifted centre of gravity shows first",
            }),
            regressor: Regressor::Time,
            thrust_map: false,
            separations: &[],
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Quat;
    use crate::presets;
    use crate::rigid_body::RigidState;

    fn ctx<'a>(rigid: &'a RigidState, vehicle: &'a VehicleParams, t: f64) -> ForceContext<'a> {
        ForceContext::idle(
            t,
            rigid,
            vehicle,
            &crate::rigid_body::Environment::default(),
        )
    }

    #[test]
    fn a_forward_shift_pitches_the_level_hull_nose_down_and_null_does_nothing() {
        let v = presets::uauv2();
        let level = RigidState {
            position: Vec3::new(0.0, 0.0, 1.0),
            attitude: Quat::identity(),
            nu: Vec6::zeros(),
        };
        let w = v.body.mass * 9.81;
        // Δx = 2 mm forward: M_y = Δz·F_x − Δx·F_z = −0.002·W (nose down in NED: negative
        // pitch moment); Δy = 1 mm: M_x = Δy·F_z = 0.001·W (starboard side down).
        let m = RestoringMoment.force(&[0.002, 0.001], &ctx(&level, &v, 0.0));
        assert!(m.fixed_rows::<3>(0).norm() == 0.0);
        assert!((m[3] - 0.001 * w).abs() < 1e-12, "{m}");
        assert!((m[4] + 0.002 * w).abs() < 1e-12, "{m}");
        assert!(m[5].abs() < 1e-12);
        assert_eq!(
            RestoringMoment.force(&[0.0, 0.0], &ctx(&level, &v, 5.0)),
            Vec6::zeros()
        );
        // The drift form: at t = 10 s a rate of 0.1 mm/s has added 1 mm.
        let d = RestoringMomentDrift.force(&[0.001, 0.0, 1e-4, 0.0], &ctx(&level, &v, 10.0));
        assert!((d[4] + 0.002 * w).abs() < 1e-12, "{d}");
        // The settling form: after one time constant 63.2 % of Δr₁ = 1 mm has been added.
        let s =
            RestoringMomentSettling.force(&[0.001, 0.0, 0.001, 0.0, 20.0], &ctx(&level, &v, 20.0));
        let dx = 0.001 + 0.001 * (1.0 - (-1f64).exp());
        assert!((s[4] + dx * w).abs() < 1e-12, "{s}");
        // Pitched nose down by the balancing angle, the weight's moment about the shifted
        // centre and the baseline's righting moment (BG·W·sin θ) cancel: tan θ = Δx / BG.
        let bg = v.body.cog.z - v.body.cob.z;
        let theta = -(0.002f64 / bg).atan();
        let tilted = RigidState {
            attitude: Quat::from_euler_angles(0.0, theta, 0.0),
            ..level
        };
        let extra = RestoringMoment.force(&[0.002, 0.0], &ctx(&tilted, &v, 0.0))[4];
        // Righting moment of weight at cog below buoyancy at cob: −BG·W·sin θ about y.
        let righting = -bg * w * theta.sin();
        assert!(
            (extra + righting).abs() < 1e-3 * w * 0.002,
            "{extra} vs {righting}"
        );
    }
}
