//! The tether and the per-thruster forms checked by hand: the cable's force and moment for a
//! hull at a known place moving at a known velocity, the taut cable's spring, and the
//! per-thruster gains and lags — each on its own thruster only, and all equal the same as the
//! family's standard form.

use shoal_model::effects::{EffectInstance, Effects, ForceContext, by_name_form};
use shoal_model::prelude::*;
use shoal_model::presets::UAUV2_CT_POS;
use shoal_model::vehicle::VehicleParams;

/// The force hook of `tether_drag` in `form` with `p` for a hull at `position` with attitude
/// `attitude` moving at `nu` (body frame), in water of 1000 kg/m³.
fn tether(form: &str, p: &[f64], position: Vec3, attitude: Quat, nu: Vec6) -> Vec6 {
    let e = by_name_form("tether_drag", Some(form)).unwrap();
    let vehicle = presets::uauv2();
    let rigid = RigidState {
        position,
        attitude,
        nu,
    };
    e.force(
        p,
        &ForceContext::idle(0.0, &rigid, &vehicle, &Environment::default()),
    )
}

fn close(a: &Vec6, b: &Vec6) -> bool {
    (a - b).norm() < 1e-12
}

#[test]
fn the_cable_drags_across_its_length_in_proportion_to_it() {
    // The attachment point 3 m north and 4 m deep: the cable is 5 m long, along
    // (0.6, 0, 0.8).
    let at = Vec3::new(3.0, 0.0, 4.0);
    let level = Quat::identity();
    // Sway at 0.5 m/s, across the cable: F = −⅛ ρ C_d d L |v_n| v_n
    // = −0.125 · 1000 · 0.01 · 5 · 0.5 · 0.5 = −1.5625 N in y; at x_att = −0.2 m (aft, the
    // hull's origin 0.2 m further north) the moment about z is x F_y = −0.2 · −1.5625
    // = +0.3125 N·m.
    let sway = Vec6::new(0.0, 0.5, 0.0, 0.0, 0.0, 0.0);
    let hull = at + Vec3::new(0.2, 0.0, 0.0);
    let f = tether("drag", &[0.01, -0.2, 0.0, 0.0], hull, level, sway);
    assert!(
        close(&f, &Vec6::new(0.0, -1.5625, 0.0, 0.0, 0.0, 0.3125)),
        "{f}"
    );
    // Twice as far from the anchor, twice the drag.
    let f1 = tether("drag", &[0.01, 0.0, 0.0, 0.0], at, level, sway);
    let f2 = tether("drag", &[0.01, 0.0, 0.0, 0.0], 2.0 * at, level, sway);
    assert!(close(&f2, &(2.0 * f1)), "{f1} {f2}");
    // Moving along the cable drags nothing.
    let along = Vec6::new(0.3, 0.0, 0.4, 0.0, 0.0, 0.0);
    assert!(close(
        &tether("drag", &[0.01, -0.2, 0.0, 0.0], hull, level, along),
        &Vec6::zeros()
    ));
    // Surge at 0.5 m/s: the part across the cable is 0.5·(1 − 0.36, 0, −0.48) = (0.32, 0, −0.24),
    // 0.4 m/s; F = −6.25 · 0.4 · (0.32, 0, −0.24) = (−0.8, 0, 0.6) N, at the body origin.
    let surge = Vec6::new(0.5, 0.0, 0.0, 0.0, 0.0, 0.0);
    let f = tether("drag", &[0.01, 0.0, 0.0, 0.0], at, level, surge);
    assert!(close(&f, &Vec6::new(-0.8, 0.0, 0.6, 0.0, 0.0, 0.0)), "{f}");
    // Turning at 1 rad/s moves an attachment point 0.2 m aft at 0.2 m/s to port (−y): the same
    // cable drag as a sway of −0.2 m/s, −6.25 · 0.2 · (0, −0.2, 0) = (0, 0.25, 0) N, and its
    // moment −0.2 · 0.25 = −0.05 N·m opposes the turn.
    let turn = Vec6::new(0.0, 0.0, 0.0, 0.0, 0.0, 1.0);
    let f = tether("drag", &[0.01, -0.2, 0.0, 0.0], hull, level, turn);
    assert!(
        close(&f, &Vec6::new(0.0, 0.25, 0.0, 0.0, 0.0, -0.05)),
        "{f}"
    );
    // Headed east (yaw +90°), surging east across the cable: the world force
    // −6.25 · 0.5 · 0.5 = −1.5625 N east is −1.5625 N along the body's x.
    let east = Quat::from_euler_angles(0.0, 0.0, std::f64::consts::FRAC_PI_2);
    let f = tether("drag", &[0.01, 0.0, 0.0, 0.0], at, east, surge);
    assert!(
        close(&f, &Vec6::new(-1.5625, 0.0, 0.0, 0.0, 0.0, 0.0)),
        "{f}"
    );
}

#[test]
fn a_taut_cable_pulls_back_only_beyond_its_length() {
    let at = Vec3::new(3.0, 0.0, 4.0); // 3 m north of the anchor, 4 m deep
    let rest = Vec6::zeros();
    let level = Quat::identity();
    // Within its horizontal length: slack.
    let f = tether("taut", &[10.0, 3.5, 0.0, 0.0, 0.0], at, level, rest);
    assert!(close(&f, &Vec6::zeros()), "{f}");
    // 1 m beyond a 2-m cable at 10 N/m: 10 N back towards the anchor, horizontally (south).
    let f = tether("taut", &[10.0, 2.0, 0.0, 0.0, 0.0], at, level, rest);
    assert!(close(&f, &Vec6::new(-10.0, 0.0, 0.0, 0.0, 0.0, 0.0)), "{f}");
    // The anchor moved to (6, 4): the hull is 5 m from it horizontally, along (−0.6, −0.8);
    // 3 m beyond a 2-m cable: 30 N towards (0.6, 0.8); attached 0.1 m aft, the moment about
    // z is x F_y = −0.1 · 24 = −2.4 N·m.
    let f = tether(
        "taut",
        &[10.0, 2.0, -0.1, 6.0, 4.0],
        at + Vec3::new(0.1, 0.0, 0.0),
        level,
        rest,
    );
    assert!(
        close(&f, &Vec6::new(18.0, 24.0, 0.0, 0.0, 0.0, -2.4)),
        "{f}"
    );
    // Straight below the anchor, however deep: no pull (a vertical pull would be a buoyancy
    // that grows with depth).
    let f = tether(
        "taut",
        &[10.0, 0.5, 0.0, 0.0, 0.0],
        Vec3::new(0.0, 0.0, 30.0),
        level,
        rest,
    );
    assert!(close(&f, &Vec6::zeros()), "{f}");
}

/// The μAUV² with the thrust hooks of `effects`: its thrust curves and lags after configuring.
fn configured(form: (&str, &str), p: &[f64]) -> VehicleParams {
    let mut v = presets::uauv2();
    Effects::new(vec![EffectInstance {
        effect: by_name_form(form.0, Some(form.1)).unwrap(),
        params: p.to_vec(),
    }])
    .configure(&mut v);
    v
}

#[test]
fn per_thruster_gains_and_lags_act_on_their_own_thruster() {
    let v = configured(("thrust_gain", "per_thruster"), &[1.0, 1.3, 0.8]);
    let f50 = UAUV2_CT_POS * 50.0 * 50.0;
    let thrust: Vec<f64> = v.thrusters.iter().map(|t| t.curve.thrust(50.0)).collect();
    let want = [f50, 1.3 * f50, 0.8 * f50];
    for (got, want) in thrust.iter().zip(want) {
        assert!((got - want).abs() < 1e-12 * want, "{thrust:?}");
    }
    let v = configured(("thruster_lag", "per_thruster"), &[0.0, 0.4, 0.1]);
    let lags: Vec<f64> = v.thrusters.iter().map(|t| t.lag).collect();
    assert_eq!(lags, [0.0, 0.4, 0.1]);
}

/// The μAUV² in turning mode (side thrusters forward, β = 0) at 50 % on both sides, for
/// `seconds` with `effect`: its yaw rate at the end \[rad/s\].
fn turning(effect: (&str, &str), p: &[f64], seconds: f64) -> f64 {
    let list = vec![EffectInstance {
        effect: by_name_form(effect.0, Some(effect.1)).unwrap(),
        params: p.to_vec(),
    }];
    let m = VehicleModel::with_effects(presets::uauv2(), Effects::new(list), 1000.0);
    let env = Environment::default();
    let mut st = VehicleState::new(
        &m,
        RigidState::at_rest(Vec3::new(0.0, 0.0, 3.0), Quat::identity()),
        &env,
    );
    let cmd = ActuatorCommands {
        thrusters: vec![0.0, 50.0, 50.0].into(),
        tilts: vec![0.0, 0.0].into(),
        pump: Pump::Off,
    };
    st.actuators.tilt.clone_from(&cmd.tilts);
    for _ in 0..(seconds / 0.01).round() as usize {
        step(&m, &mut st, &cmd, &env, Integrator::Rk4, 0.01);
    }
    st.rigid.nu[5]
}

#[test]
fn unequal_side_gains_turn_the_hull_and_equal_ones_are_the_standard_gain() {
    // Port (y = −0.1 m) stronger: its surplus thrust turns the bow to starboard, r > 0 (NED).
    let port = turning(("thrust_gain", "per_thruster"), &[1.0, 1.2, 1.0], 5.0);
    let stbd = turning(("thrust_gain", "per_thruster"), &[1.0, 1.0, 1.2], 5.0);
    assert!(port > 0.05 && stbd < -0.05, "{port} {stbd}");
    assert!((port + stbd).abs() < 1e-9, "mirror images: {port} {stbd}");
    // All equal: the standard form's straight run (no turn at all).
    let equal = turning(("thrust_gain", "per_thruster"), &[1.2, 1.2, 1.2], 5.0);
    let standard = turning(("thrust_gain", "standard"), &[1.2], 5.0);
    assert!(
        equal.abs() < 1e-12 && standard.abs() < 1e-12,
        "{equal} {standard}"
    );
    // A lag on one side only: that side's thrust trails, so the other side turns the hull
    // (port lags: starboard pushes harder, r < 0); the same lag on both sides turns nothing.
    let one = turning(("thruster_lag", "per_thruster"), &[0.0, 0.5, 0.0], 0.5);
    let both = turning(("thruster_lag", "per_thruster"), &[0.0, 0.5, 0.5], 0.5);
    assert!(one < -0.01 && both.abs() < 1e-12, "{one} {both}");
}
