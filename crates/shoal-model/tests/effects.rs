//! The model extensions of `shoal_model::effects` in a running vehicle, checked against closed
//! forms: terminal speeds from the damping law with the thrust or force an effect implies,
//! a first-order lag, a current carrying the hull, delayed and biased sensor readings.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use shoal_model::effects::{EffectInstance, Effects, by_name, catalogue, names};
use shoal_model::prelude::*;
use shoal_model::presets::{UAUV2_CT_NEG, UAUV2_CT_POS, UAUV2_ZW, UAUV2_ZWW};
use std::f64::consts::FRAC_PI_2;

const DT: f64 = 0.01;

fn with(effects: &[(&str, &[f64])]) -> VehicleModel {
    let list = effects
        .iter()
        .map(|(n, p)| EffectInstance {
            effect: by_name(n).unwrap(),
            params: p.to_vec(),
        })
        .collect();
    VehicleModel::with_effects(presets::uauv2(), Effects::new(list), 1000.0)
}

fn diving(n: f64) -> ActuatorCommands {
    ActuatorCommands {
        thrusters: vec![0.0, n, n],
        tilts: vec![0.0, -FRAC_PI_2],
        pump: Pump::Off,
    }
}

fn run(model: &VehicleModel, cmd: &ActuatorCommands, seconds: f64) -> VehicleState {
    let env = Environment::default();
    let mut st = VehicleState::new(
        model,
        RigidState::at_rest(Vec3::new(0.0, 0.0, 3.0), Quat::identity()),
        &env,
    );
    st.actuators.tilt.clone_from(&cmd.tilts);
    for _ in 0..(seconds / DT).round() as usize {
        step(model, &mut st, cmd, &env, Integrator::Rk4, DT);
    }
    st
}

/// Terminal heave speed for a net downward force `f` [N] (the damping law).
fn terminal(f: f64) -> f64 {
    let a = UAUV2_ZWW;
    let b = UAUV2_ZW;
    f.signum() * (-b + (b * b + 4.0 * a * f.abs()).sqrt()) / (2.0 * a)
}

#[test]
fn catalogue_is_complete_and_consistent() {
    let want = [
        "thruster_lag",
        "thrust_gain",
        "thrust_asymmetry",
        "thruster_deadband",
        "battery_sag",
        "inflow_thrust_loss",
        "buoyancy_offset",
        "ballast_mass",
        "damping_error",
        "added_mass_error",
        "water_current",
        "depth_sensor_bias",
        "sensor_delay",
        "thrust_coupling",
        "thrust_saturation",
    ];
    assert_eq!(names(), want);
    // Forms of one family have distinct names.
    for n in names() {
        let mut f = shoal_model::effects::forms(n);
        let k = f.len();
        f.sort();
        f.dedup();
        assert_eq!(f.len(), k, "{n}: duplicate forms");
    }
    let v = presets::uauv2();
    for e in catalogue() {
        assert!(!e.explanation().is_empty() && !e.summary().is_empty());
        for p in e.params(&v) {
            assert!(
                p.lo <= p.null && p.null <= p.hi && p.lo <= p.typical && p.typical <= p.hi,
                "{}: {p:?}",
                e.name()
            );
            // A shape parameter has no null of its own: its `null` is its neutral default.
            assert!(p.shape || p.typical != p.null, "{}.{}", e.name(), p.name);
        }
        // At the null values an effect changes nothing.
        let null = EffectInstance::null(e.clone(), &v);
        let m = VehicleModel::with_effects(v.clone(), Effects::new(vec![null]), 1000.0);
        let plain = VehicleModel::new(v.clone(), 1000.0);
        let a = run(&m, &diving(60.0), 3.0);
        let b = run(&plain, &diving(60.0), 3.0);
        assert!(
            (a.rigid.position - b.rigid.position).norm() < 1e-12,
            "{} at null",
            e.name()
        );
    }
}

#[test]
fn thrust_effects_set_terminal_heave_speeds() {
    let n = 70.0;
    let f0 = 2.0 * UAUV2_CT_POS * n * n;
    let cases: [(&str, &[f64], f64); 5] = [
        ("thrust_gain", &[1.3], 1.3 * f0),
        ("battery_sag", &[0.0], f0),
        (
            "thrust_saturation",
            &[0.4],
            2.0 * 0.4 * UAUV2_CT_POS * 100.0 * 100.0,
        ),
        // Dead band 10 %: 70 % acts like 100·(70 − 10)/90 = 66.7 %.
        (
            "thruster_deadband",
            &[10.0],
            2.0 * UAUV2_CT_POS * (100.0 * 60.0 / 90.0_f64).powi(2),
        ),
        ("thrust_asymmetry", &[0.5], f0),
    ];
    for (name, p, force) in cases {
        let st = run(&with(&[(name, p)]), &diving(n), 40.0);
        let w = st.rigid.nu[2];
        assert!(
            (w - terminal(force)).abs() < 1e-6,
            "{name}: {w} vs {}",
            terminal(force)
        );
    }
    // Reverse thrust is scaled by k_rev.
    let st = run(&with(&[("thrust_asymmetry", &[0.5])]), &diving(-70.0), 30.0);
    let f = -0.5 * 2.0 * UAUV2_CT_NEG * n * n;
    assert!((st.rigid.nu[2] - terminal(f)).abs() < 1e-6);
    // Below the dead band nothing happens.
    let st = run(&with(&[("thruster_deadband", &[10.0])]), &diving(8.0), 5.0);
    assert!(st.rigid.nu[2].abs() < 1e-12, "{}", st.rigid.nu[2]);
}

#[test]
fn inflow_loss_and_buoyancy_offset_follow_their_force_laws() {
    // Inflow: at terminal speed w, f = f0 − κ√f0·w per thruster, so
    // Z_w w + Z_w|w| w² = 2(f0 − κ√f0 w).
    let (n, kappa) = (70.0, 0.8);
    let f0 = UAUV2_CT_POS * n * n;
    let st = run(&with(&[("inflow_thrust_loss", &[kappa])]), &diving(n), 40.0);
    let w = st.rigid.nu[2];
    let b = UAUV2_ZW + 2.0 * kappa * f0.sqrt();
    let want = (-b + (b * b + 4.0 * UAUV2_ZWW * 2.0 * f0).sqrt()) / (2.0 * UAUV2_ZWW);
    assert!((w - want).abs() < 1e-6, "{w} vs {want}");
    // Buoyancy offset: the idle vehicle sinks (ΔF > 0) or rises at the damping-law speed.
    for df in [0.004, -0.003] {
        let st = run(&with(&[("buoyancy_offset", &[df])]), &diving(0.0), 60.0);
        assert!(
            (st.rigid.nu[2] - terminal(df)).abs() < 1e-6,
            "{df}: {}",
            st.rigid.nu[2]
        );
    }
}

#[test]
fn lag_damping_and_added_mass_change_the_response() {
    // Lag: the thrust reaches 1 − e⁻¹ of its static value after τ.
    let m = with(&[("thruster_lag", &[0.5])]);
    let st = run(&m, &diving(70.0), 0.5);
    let f0 = UAUV2_CT_POS * 70.0 * 70.0;
    assert!((st.actuators.thrust[1] / f0 - (1.0 - (-1.0f64).exp())).abs() < 1e-9);
    // Damping ×2 (both terms): terminal speed from the scaled law.
    let st = run(
        &with(&[("damping_error", &[2.0, 2.0])]),
        &diving(70.0),
        40.0,
    );
    let f = 2.0 * f0 / 2.0;
    assert!((st.rigid.nu[2] - terminal(f)).abs() < 1e-6);
    // Added mass ×2: same terminal speed, slower start (ẇ(0) = F/(m + 2A₃₃)).
    let m2 = with(&[("added_mass_error", &[2.0])]);
    let st = run(&m2, &diving(70.0), 0.01);
    let a0 = st.rigid.nu[2] / 0.01;
    let want = 2.0 * f0 / (presets::UAUV2_MASS + 2.0 * (presets::UAUV2_HEAVE_MASS - 1.2));
    assert!((a0 - want).abs() / want < 1e-3, "{a0} vs {want}");
    let st = run(&m2, &diving(70.0), 60.0);
    assert!((st.rigid.nu[2] - terminal(2.0 * f0)).abs() < 1e-6);
}

#[test]
fn coupling_turns_a_diving_vehicle_and_the_pump_flow_is_fitted() {
    // k_z = 0.02 m: yaw moment 0.02·F_z while diving; the yaw rate settles where the yaw
    // damping law balances it.
    let n = 70.0;
    let fz = 2.0 * UAUV2_CT_POS * n * n;
    let st = run(
        &with(&[("thrust_coupling", &[0.02, 0.0])]),
        &diving(n),
        60.0,
    );
    let moment = 0.02 * fz;
    let r = (-presets::UAUV2_NR
        + (presets::UAUV2_NR.powi(2) + 4.0 * presets::UAUV2_NRR * moment).sqrt())
        / (2.0 * presets::UAUV2_NRR);
    assert!(
        (st.rigid.nu[5] - r).abs() < 1e-6,
        "{} vs {r}",
        st.rigid.nu[5]
    );
    // Pump flow 0.2 ml/s for 10 s: 2 ml of water taken in.
    let m = with(&[("ballast_mass", &[0.2])]);
    let cmd = ActuatorCommands {
        pump: Pump::Fill,
        ..diving(0.0)
    };
    let st = run(&m, &cmd, 10.0);
    let v0 = presets::uauv2().ballast.unwrap().initial_volume;
    assert!((st.ballast_volume - v0 - 2e-6).abs() < 1e-12);
}

#[test]
fn a_current_carries_the_vehicle() {
    let m = with(&[("water_current", &[0.05, -0.02])]);
    let st = run(&m, &diving(0.0), 20.0);
    assert!((st.rigid.position.x - 1.0).abs() < 1e-9);
    assert!((st.rigid.position.y + 0.4).abs() < 1e-9);
    assert!(
        st.rigid.nu.norm() < 1e-12,
        "no motion relative to the water"
    );
}

#[test]
fn sensors_are_biased_and_delayed() {
    let mut p = presets::uauv2();
    p.pressure.noise_std = 0.0;
    p.imu.attitude_noise = 0.0;
    p.imu.gyro_noise = 0.0;
    p.imu.accel_noise = 0.0;
    let list = |e: &[(&str, &[f64])]| {
        Effects::new(
            e.iter()
                .map(|(n, v)| EffectInstance {
                    effect: by_name(n).unwrap(),
                    params: v.to_vec(),
                })
                .collect(),
        )
    };
    let env = Environment::default();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    // Bias: reading = depth + b₀ + b₁·t, quantised to 1.8 mm.
    let m = VehicleModel::with_effects(
        p.clone(),
        list(&[("depth_sensor_bias", &[0.05, 0.002])]),
        1000.0,
    );
    let cmd = diving(0.0);
    let mut st = VehicleState::new(
        &m,
        RigidState::at_rest(Vec3::new(0.0, 0.0, 1.091), Quat::identity()),
        &env,
    );
    st.actuators.tilt.clone_from(&cmd.tilts);
    for _ in 0..1000 {
        step(&m, &mut st, &cmd, &env, Integrator::Rk4, DT);
    }
    let mut r = SensorReadings::zeros(2);
    sense(&m, &mut st, &env, &mut rng, &mut r);
    assert!(
        (r.depth - (1.0 + 0.05 + 0.002 * 10.0)).abs() <= 0.9e-3 + 1e-9,
        "{}",
        r.depth
    );
    // Delay 0.3 s, sampled every 0.05 s while diving: the reading shows the depth of 0.3 s ago.
    let m = VehicleModel::with_effects(p.clone(), list(&[("sensor_delay", &[0.3])]), 1000.0);
    let cmd = diving(80.0);
    let mut st = VehicleState::new(
        &m,
        RigidState::at_rest(Vec3::new(0.0, 0.0, 1.091), Quat::identity()),
        &env,
    );
    st.actuators.tilt.clone_from(&cmd.tilts);
    let mut truth = Vec::new();
    for k in 0..200 {
        if k % 5 == 0 {
            sense(&m, &mut st, &env, &mut rng, &mut r);
            truth.push((st.time, st.depth_of(&p.pressure.position), r.depth));
        }
        step(&m, &mut st, &cmd, &env, Integrator::Rk4, DT);
    }
    for (i, &(t, _, read)) in truth.iter().enumerate().skip(20) {
        let then = truth[i - 6];
        assert!((then.0 - (t - 0.3)).abs() < 1e-9);
        assert!(
            (read - then.1).abs() <= 0.9e-3 + 1e-9,
            "t={t}: {read} vs {}",
            then.1
        );
        assert!(
            (truth[i].1 - then.1).abs() > 0.01,
            "the vehicle moved meanwhile: {:?} {then:?}",
            truth[i]
        );
    }
}
