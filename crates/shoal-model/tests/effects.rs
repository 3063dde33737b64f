//! The model extensions of `shoal_model::effects` in a running vehicle, checked against closed
//! forms: terminal speeds from the damping law with the thrust or force an effect implies,
//! a first-order lag, a current carrying the hull, delayed and biased sensor readings. And
//! for every form of every family: at its null values a run that would show it is exactly
//! the baseline's, at its typical values it is measurably not.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use shoal_model::effects::{
    EffectInstance, Effects, ForceContext, by_name, by_name_form, catalogue, names,
};
use shoal_model::prelude::*;
use shoal_model::presets::{UAUV2_CT_NEG, UAUV2_CT_POS, UAUV2_ZW, UAUV2_ZWW};
use shoal_model::vehicle::VehicleParams;
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
        thrusters: vec![0.0, n, n].into(),
        tilts: vec![0.0, -FRAC_PI_2].into(),
        pump: Pump::Off,
    }
}

fn run(model: &VehicleModel, cmd: &ActuatorCommands, seconds: f64) -> VehicleState {
    run_from(model, cmd, seconds, 3.0)
}

/// As [`run`], starting at rest `z` metres deep.
fn run_from(model: &VehicleModel, cmd: &ActuatorCommands, seconds: f64, z: f64) -> VehicleState {
    let env = Environment::default();
    let mut st = VehicleState::new(
        model,
        RigidState::at_rest(Vec3::new(0.0, 0.0, z), Quat::identity()),
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

/// Asserts that the run `st` ended under water (more than 0.5 m deep: a rise from 3 m stopped
/// short of the surface) at the terminal heave speed for the net downward force `f` [N].
fn assert_terminal(st: &VehicleState, f: f64) {
    assert!(st.rigid.position.z > 0.5, "{}", st.rigid.position.z);
    assert!(
        (st.rigid.nu[2] - terminal(f)).abs() < 1e-6,
        "{} vs {}",
        st.rigid.nu[2],
        terminal(f)
    );
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
        "restoring_moment",
        "water_current",
        "depth_sensor_bias",
        "sensor_delay",
        "thrust_coupling",
        "thrust_saturation",
        "tether_drag",
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
                "{} ({}): {p:?}",
                e.name(),
                e.form()
            );
            // A shape parameter's `null` is only a neutral default; every other parameter's
            // typical value must switch the effect on.
            assert!(
                p.shape || p.typical != p.null,
                "{} ({}).{}",
                e.name(),
                e.form(),
                p.name
            );
        }
    }
}

/// Each family carries its facts once: its forms share its name, no family is listed twice
/// (two entries would be two sets of facts for one family), and the manoeuvres that separate
/// it name other catalogue families.
#[test]
fn families_carry_their_facts() {
    let fams = shoal_model::effects::families();
    let all = names();
    assert_eq!(fams.len(), all.len(), "a family listed twice");
    for f in &fams {
        let name = f.name();
        for e in &f.forms {
            assert_eq!(e.name(), name, "form {} in family {name}", e.form());
        }
        assert!(!f.facts.excitation.is_empty(), "{name}");
        for (other, how) in f.facts.separations {
            assert!(
                all.contains(other) && *other != name && !how.is_empty(),
                "{name}: separation from {other}"
            );
        }
        if let Some(d) = f.facts.direct {
            assert!(
                !d.channels.is_empty() && !d.why_not_fitted.is_empty(),
                "{name}"
            );
        }
        assert_eq!(shoal_model::effects::facts(name), Some(f.facts));
    }
    assert_eq!(shoal_model::effects::facts("no_such_family"), None);
}

// ---------------------------------------------------------------------------------------
// Null values change nothing — in a scenario that would show the effect.

/// One phase of a scenario: how long \[s\], the tilt of the side thrusters β \[rad\]
/// (−π/2: diving, 0: surge/turning), the commands of top, port and starboard thruster [%],
/// the pump.
#[derive(Clone, Copy, Debug)]
struct Phase {
    seconds: f64,
    beta: f64,
    n: [f64; 3],
    pump: Pump,
}

fn dive(seconds: f64, n: f64) -> Phase {
    Phase {
        seconds,
        beta: -FRAC_PI_2,
        n: [0.0, n, n],
        pump: Pump::Off,
    }
}

/// A phase with only the top thruster running (at tilt 0, pushing forward): what shows a
/// per-thruster form's parameter of the top thruster.
fn top(seconds: f64, n: f64) -> Phase {
    Phase {
        beta: 0.0,
        n: [n, 0.0, 0.0],
        ..dive(seconds, 0.0)
    }
}

/// The scenario in which the family `name` shows if it is on; it starts at rest 3 m deep.
fn scenario(name: &str) -> Vec<Phase> {
    match name {
        // Command steps up and down: lags and inertia act on every change.
        // The top thruster stepped too: the per-thruster forms have a lag of its own.
        "thruster_lag" | "added_mass_error" => {
            vec![
                dive(3.0, 70.0),
                dive(3.0, 0.0),
                dive(3.0, -70.0),
                dive(3.0, 0.0),
                top(3.0, 70.0),
                top(3.0, 0.0),
            ]
        }
        // Moving under thrust: scale, inflow and drag (the top thruster alone as well, for
        // the per-thruster gain).
        "thrust_gain" | "inflow_thrust_loss" => vec![dive(10.0, 70.0), top(10.0, 70.0)],
        // Surging away from below the anchor: the cable drags, then runs out.
        "tether_drag" => vec![Phase {
            beta: 0.0,
            ..dive(40.0, 80.0)
        }],
        // Moving both ways: drag that differs with the direction.
        "damping_error" => vec![dive(10.0, 70.0), dive(10.0, -70.0)],
        // Reverse thrust.
        "thrust_asymmetry" => vec![dive(10.0, -70.0)],
        // Small commands, inside a typical dead band and just outside it.
        "thruster_deadband" => vec![dive(5.0, 5.0), dive(5.0, -6.0), dive(5.0, 12.0)],
        // Full commands both ways.
        "thrust_saturation" => vec![dive(5.0, 100.0), dive(5.0, -100.0)],
        // A long run under thrust.
        "battery_sag" => vec![dive(90.0, 40.0)],
        // The pump filling, then emptying.
        "ballast_mass" => vec![
            Phase {
                pump: Pump::Fill,
                ..dive(10.0, 0.0)
            },
            Phase {
                pump: Pump::Empty,
                ..dive(10.0, 0.0)
            },
        ],
        // Idle at depth: an offset force moves it, the current carries it, a shifted weight
        // tilts it.
        "buoyancy_offset" | "water_current" | "restoring_moment" => vec![dive(20.0, 0.0)],
        // Depth readings over a while (bias and drift) and while moving (delay).
        "depth_sensor_bias" | "sensor_delay" => vec![dive(10.0, 0.0), dive(10.0, 70.0)],
        // Vertical thrust down and up, then surge thrust.
        "thrust_coupling" => vec![
            dive(5.0, 70.0),
            dive(5.0, -70.0),
            Phase {
                beta: 0.0,
                ..dive(5.0, 60.0)
            },
        ],
        _ => panic!("no scenario for the effect family `{name}`: add one here"),
    }
}

/// What a run records every 0.05 s, by quantity.
#[derive(Clone, Debug, Default, PartialEq)]
struct Trace {
    /// Position, Euler angles and velocities (m, rad, m/s, rad/s).
    motion: Vec<f64>,
    /// Thrust of each thruster \[N\].
    thrust: Vec<f64>,
    /// Volume of water in the tank [m³].
    ballast: Vec<f64>,
    /// Depth reading, attitude reading, gyro reading (m, rad, rad/s).
    readings: Vec<f64>,
}

impl Trace {
    /// Largest difference to `o`, per quantity, each relative to its threshold of a
    /// measurable change: 1 mm / 1 mrad / 1 mm/s of motion and readings, 1 mN of thrust,
    /// 0.01 ml in the tank.
    fn difference(&self, o: &Trace) -> f64 {
        let max = |a: &[f64], b: &[f64], unit: f64| {
            a.iter()
                .zip(b)
                .map(|(x, y)| (x - y).abs() / unit)
                .fold(0.0, f64::max)
        };
        max(&self.motion, &o.motion, 1e-3)
            .max(max(&self.thrust, &o.thrust, 1e-3))
            .max(max(&self.ballast, &o.ballast, 1e-8))
            .max(max(&self.readings, &o.readings, 1e-3))
    }

    /// The first entry that differs from `o` at all.
    fn first_change(&self, o: &Trace) -> Option<String> {
        for (what, a, b) in [
            ("motion", &self.motion, &o.motion),
            ("thrust", &self.thrust, &o.thrust),
            ("ballast", &self.ballast, &o.ballast),
            ("readings", &self.readings, &o.readings),
        ] {
            if a.len() != b.len() {
                return Some(format!("{what}: {} vs {} entries", a.len(), b.len()));
            }
            if let Some(i) = (0..a.len()).find(|&i| a[i].to_bits() != b[i].to_bits()) {
                return Some(format!("{what}[{i}]: {} vs {}", a[i], b[i]));
            }
        }
        None
    }
}

/// The μAUV² with noise-free sensors; `lag` \[s\] on every thruster (a baseline may already
/// model a lag).
fn vehicle(lag: f64) -> VehicleParams {
    let mut p = presets::uauv2();
    p.pressure.noise_std = 0.0;
    p.imu.attitude_noise = 0.0;
    p.imu.gyro_noise = 0.0;
    p.imu.accel_noise = 0.0;
    for th in &mut p.thrusters {
        th.lag = lag;
    }
    p
}

/// Runs `phases` on `v` with `effects` and records the trace.
fn record(v: &VehicleParams, effects: Vec<EffectInstance>, phases: &[Phase]) -> Trace {
    let m = VehicleModel::with_effects(v.clone(), Effects::new(effects), 1000.0);
    let env = Environment::default();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut st = VehicleState::new(
        &m,
        RigidState::at_rest(Vec3::new(0.0, 0.0, 3.0), Quat::identity()),
        &env,
    );
    let mut r = SensorReadings::zeros(v.tilts.len());
    let mut tr = Trace::default();
    let mut k = 0usize;
    for ph in phases {
        let cmd = ActuatorCommands {
            thrusters: ph.n.to_vec().into(),
            tilts: vec![0.0, ph.beta].into(),
            pump: ph.pump,
        };
        st.actuators.tilt.clone_from(&cmd.tilts);
        for _ in 0..(ph.seconds / DT).round() as usize {
            if k.is_multiple_of(5) {
                sense(&m, &mut st, &env, &mut rng, &mut r);
                let p = st.rigid.position;
                let (roll, pitch, yaw) = st.rigid.attitude.euler_angles();
                tr.motion.extend([p.x, p.y, p.z, roll, pitch, yaw]);
                tr.motion.extend(st.rigid.nu.iter());
                tr.thrust.extend(st.actuators.thrust.iter());
                tr.ballast.push(st.ballast_volume);
                let (rr, rp, ry) = r.attitude.euler_angles();
                tr.readings
                    .extend([r.depth, rr, rp, ry, r.gyro.x, r.gyro.y, r.gyro.z]);
            }
            step(&m, &mut st, &cmd, &env, Integrator::Rk4, DT);
            k += 1;
        }
    }
    tr
}

/// Every form of every catalogue family on the vehicle `v`, in a scenario that shows it: at
/// its null values the run must be bit for bit the baseline's — whatever the value of a shape
/// parameter — and at its typical values (each non-shape parameter alone, and all together)
/// measurably different. Returns what failed.
fn check_nulls(v: &VehicleParams) -> Vec<String> {
    let lag = v.thrusters[0].lag;
    let mut checked = 0;
    let mut failures: Vec<String> = Vec::new();
    for e in catalogue() {
        let ctx = format!(
            "{} ({}) on a vehicle with thruster lag {lag} s",
            e.name(),
            e.form()
        );
        if let Some(why) = e.not_applicable(v) {
            panic!("{ctx}: does not apply to the μAUV²: {why}");
        }
        let phases = scenario(e.name());
        let base = record(v, Vec::new(), &phases);
        let infos = e.params(v);
        let null: Vec<f64> = infos.iter().map(|p| p.null).collect();
        let with = |params: Vec<f64>| {
            record(
                v,
                vec![EffectInstance {
                    effect: e.clone(),
                    params,
                }],
                &phases,
            )
        };
        // Null: exactly the baseline, for every value a shape parameter may take.
        let mut nulls = vec![null.clone()];
        for (i, p) in infos.iter().enumerate().filter(|(_, p)| p.shape) {
            for s in [p.lo, p.typical, p.hi] {
                let mut q = null.clone();
                q[i] = s;
                nulls.push(q);
            }
        }
        for q in nulls {
            let t = with(q.clone());
            if t != base {
                failures.push(format!(
                    "{ctx}: at null {q:?} the run differs from the baseline, first at {}, \
                         by up to {:.1} thresholds of a measurable change",
                    t.first_change(&base).unwrap_or_default(),
                    t.difference(&base)
                ));
            }
        }
        // Typical: measurably different — each non-shape parameter alone (the others at
        // null, shapes typical), and all together.
        let shapes_typical: Vec<f64> = infos
            .iter()
            .map(|p| if p.shape { p.typical } else { p.null })
            .collect();
        let mut typical = vec![infos.iter().map(|p| p.typical).collect::<Vec<f64>>()];
        for (i, p) in infos.iter().enumerate().filter(|(_, p)| !p.shape) {
            let mut q = shapes_typical.clone();
            q[i] = p.typical;
            typical.push(q);
        }
        for q in typical {
            let d = with(q.clone()).difference(&base);
            if d <= 1.0 {
                failures.push(format!(
                    "{ctx}: at {q:?} the run is only {d:.3} thresholds from the baseline — \
                         the scenario does not show it"
                ));
            }
        }
        checked += 1;
    }
    assert_eq!(checked, catalogue().len());
    failures
}

/// On the plain μAUV² (no thruster lag of its own).
#[test]
fn null_values_change_nothing_where_the_effect_would_show() {
    let failures = check_nulls(&vehicle(0.0));
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// On a vehicle whose thrusters already lag by 0.1 s, as a vehicle file may say: an effect at
/// null must leave the baseline's own lag as it is. (Fails while the second-order lag form
/// turns every lag into two stages even at τ = 0.)
#[test]
fn null_values_keep_a_lag_the_baseline_already_has() {
    let failures = check_nulls(&vehicle(0.1));
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn thrust_effects_set_terminal_heave_speeds() {
    let n = 70.0;
    let f0 = 2.0 * UAUV2_CT_POS * n * n;
    let cases: [(&str, &[f64], f64); 4] = [
        ("thrust_gain", &[1.3], 1.3 * f0),
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
    // Battery sag: after 40 s the thrust is 1 − s·t of the static thrust (t the start of the
    // last step).
    let sag = 0.002;
    let st = run(&with(&[("battery_sag", &[sag])]), &diving(n), 40.0);
    let f1 = UAUV2_CT_POS * n * n;
    let k = st.actuators.thrust[1] / f1;
    assert!(
        (k - (1.0 - sag * (st.time - DT))).abs() < 1e-9,
        "thrust scale {k} after {} s",
        st.time
    );
    // Reverse thrust is scaled by k_rev.
    let st = run(&with(&[("thrust_asymmetry", &[0.5])]), &diving(-70.0), 30.0);
    let f = -0.5 * 2.0 * UAUV2_CT_NEG * n * n;
    assert_terminal(&st, f);
    // Below the dead band nothing happens.
    let st = run(&with(&[("thruster_deadband", &[10.0])]), &diving(8.0), 5.0);
    assert!(st.rigid.nu[2].abs() < 1e-12, "{}", st.rigid.nu[2]);
}

/// A model with one effect in a named form.
fn with_form(name: &str, form: &str, params: &[f64]) -> VehicleModel {
    let effect = by_name_form(name, Some(form)).unwrap_or_else(|| panic!("{name}/{form}"));
    let list = vec![EffectInstance {
        effect,
        params: params.to_vec(),
    }];
    VehicleModel::with_effects(presets::uauv2(), Effects::new(list), 1000.0)
}

/// The forms with an exponent or a direction set the terminal heave speed their laws imply.
#[test]
fn shaped_forms_follow_their_laws() {
    let n = 70.0;
    let f0 = 2.0 * UAUV2_CT_POS * n * n;
    // Gain curve: k·(|n|/50 %)^e.
    let st = run(
        &with_form("thrust_gain", "curve", &[1.2, 0.3]),
        &diving(n),
        40.0,
    );
    let f = 1.2 * (70.0_f64 / 50.0).powf(0.3) * f0;
    assert_terminal(&st, f);
    // Direction-dependent drag, diving (w > 0): the drag law × k₊, so the terminal speed is
    // the baseline's for the force / k₊; rising (w < 0) it is × k₋.
    // (Rising from 3 m, the run stops well before the surface.)
    let m = with_form("damping_error", "direction", &[1.5, 2.0]);
    let st = run(&m, &diving(n), 40.0);
    assert_terminal(&st, f0 / 1.5);
    let st = run(&m, &diving(-n), 12.0);
    let fr = -2.0 * UAUV2_CT_NEG * n * n;
    assert_terminal(&st, fr / 2.0);
    // Asymmetric dead band (4 % forward, 12 % reverse): 8 % pushes, −8 % does nothing, and
    // −40 % acts like −100·(40 − 12)/88.
    let m = with_form("thruster_deadband", "asymmetric", &[4.0, 12.0]);
    let st = run(&m, &diving(-8.0), 5.0);
    assert!(st.rigid.nu[2].abs() < 1e-12, "{}", st.rigid.nu[2]);
    let st = run(&m, &diving(8.0), 5.0);
    assert!(st.rigid.nu[2] > 1e-4, "{}", st.rigid.nu[2]);
    let st = run(&m, &diving(-40.0), 60.0);
    let fr = -2.0 * UAUV2_CT_NEG * (100.0 * 28.0 / 88.0_f64).powi(2);
    assert_terminal(&st, fr);
    // Asymmetric saturation (40 % of the forward maximum, 60 % of the reverse one): full
    // command dives at the speed of 0.4 · the forward maximum and rises at that of 0.6 · the
    // reverse maximum.
    let m = with_form("thrust_saturation", "asymmetric", &[0.4, 0.6]);
    let st = run(&m, &diving(100.0), 40.0);
    let f = 2.0 * 0.4 * UAUV2_CT_POS * 100.0 * 100.0;
    assert_terminal(&st, f);
    let st = run(&m, &diving(-100.0), 20.0);
    let fr = -2.0 * 0.6 * UAUV2_CT_NEG * 100.0 * 100.0;
    assert_terminal(&st, fr);
    // Inflow loss as a power of the speed: at the terminal speed w each thruster gives
    // f0·(1 − k·(w/0.1 m/s)^p), which the drag Z_w·w + Z_w|w|·w² balances.
    for (k, p) in [(0.3, 0.5), (0.2, 2.0)] {
        let st = run(
            &with_form("inflow_thrust_loss", "power", &[k, p]),
            &diving(n),
            40.0,
        );
        let w = st.rigid.nu[2];
        let f1 = UAUV2_CT_POS * n * n;
        let thrust = 2.0 * f1 * (1.0 - k * (w / 0.1).powf(p));
        let drag = UAUV2_ZW * w + UAUV2_ZWW * w * w;
        assert!(w > 0.0 && w < terminal(f0), "{w}");
        assert!(
            (thrust - drag).abs() < 1e-6 * f0,
            "k {k}, p {p}: {thrust} vs {drag}"
        );
    }
    // Power sag: after t the thrust is 1 − a·(t/100 s)^p of the static thrust (t the start
    // of the last step).
    let st = run(
        &with_form("battery_sag", "power", &[0.2, 2.5]),
        &diving(n),
        60.0,
    );
    let k = st.actuators.thrust[1] / (UAUV2_CT_POS * n * n);
    let t = st.time - DT;
    assert!(
        (k - (1.0 - 0.2 * (t / 100.0).powf(2.5))).abs() < 1e-9,
        "{k} at {t} s"
    );
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
    assert_terminal(&st, f);
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
    // Power drift: reading = depth + b₀ + d·(t/100 s)^p.
    let e = by_name_form("depth_sensor_bias", Some("power_drift")).unwrap();
    let m = VehicleModel::with_effects(
        p.clone(),
        Effects::new(vec![EffectInstance {
            effect: e,
            params: vec![0.05, 0.1, 2.0],
        }]),
        1000.0,
    );
    let mut st = VehicleState::new(
        &m,
        RigidState::at_rest(Vec3::new(0.0, 0.0, 1.091), Quat::identity()),
        &env,
    );
    st.actuators.tilt.clone_from(&cmd.tilts);
    for _ in 0..3000 {
        step(&m, &mut st, &cmd, &env, Integrator::Rk4, DT);
    }
    sense(&m, &mut st, &env, &mut rng, &mut r);
    assert!(
        (r.depth - (1.0 + 0.05 + 0.1 * 0.3_f64.powi(2))).abs() <= 0.9e-3 + 1e-9,
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

/// The force of one form on a hull level at depth `z` [m], moving with `nu`, `t` seconds into
/// the run, under a thruster force `thrust` (body frame) [N].
fn form_force(name: &str, form: &str, p: &[f64], t: f64, z: f64, nu: Vec6, thrust: Vec3) -> Vec6 {
    let effect = by_name_form(name, Some(form)).unwrap_or_else(|| panic!("{name}/{form}"));
    let mut rigid = RigidState::at_rest(Vec3::new(0.0, 0.0, z), Quat::identity());
    rigid.nu = nu;
    let vehicle = presets::uauv2();
    let ctx = ForceContext {
        t,
        rigid: &rigid,
        thrust_force: thrust,
        thrust_moment: Vec3::zeros(),
        vehicle: &vehicle,
        gravity: shoal_model::math::GRAVITY,
        density: 1000.0,
    };
    effect.force(p, &ctx)
}

/// The buoyancy forms that vary (in time, with depth), the power-law drag and the
/// direction-dependent coupling: their forces by hand, and the states they lead to.
#[test]
fn varying_buoyancy_power_drag_and_directional_coupling_follow_their_laws() {
    let zero = Vec6::zeros();
    // Drift: ΔF₀ + r·t along the vertical of a level hull, at any depth.
    let f = form_force(
        "buoyancy_offset",
        "drift",
        &[0.002, 1e-4],
        50.0,
        2.0,
        zero,
        Vec3::zeros(),
    );
    assert!((f[2] - (0.002 + 1e-4 * 50.0)).abs() < 1e-15, "{f}");
    // Depth: ΔF₀ + k·z, and no extra force above the surface.
    let f = form_force(
        "buoyancy_offset",
        "depth",
        &[-0.01, 0.004],
        80.0,
        2.5,
        zero,
        Vec3::zeros(),
    );
    assert!((f[2] - (-0.01 + 0.004 * 2.5)).abs() < 1e-15, "{f}");
    // With ΔF₀ = −0.1 N and k = 0.05 N/m the idle vehicle is neutral at 2 m only, and that
    // trim is unstable (a compressible hull): a centimetre deeper it sinks, a centimetre
    // higher it rises.
    let m = with_form("buoyancy_offset", "depth", &[-0.1, 0.05]);
    let from = |z: f64| run_from(&m, &diving(0.0), 30.0, z);
    let st = from(2.0);
    assert!(
        (st.rigid.position.z - 2.0).abs() < 1e-9,
        "{}",
        st.rigid.position.z
    );
    let (deeper, higher) = (from(2.01), from(1.99));
    assert!(deeper.rigid.position.z > 2.05 && deeper.rigid.nu[2] > 0.0);
    assert!(higher.rigid.position.z < 1.95 && higher.rigid.nu[2] < 0.0);
    // Power drag: diving at 70 %, the terminal speed balances thrust with the baseline's drag
    // plus s·Z_w|w|·ν_ref²·(w/ν_ref)^p (ν_ref = 0.1 m/s in heave).
    let (s, p) = (0.6, 3.0);
    let n = 70.0;
    let thrust = 2.0 * UAUV2_CT_POS * n * n;
    let st = run(
        &with_form("damping_error", "power", &[s, p]),
        &diving(n),
        60.0,
    );
    let w = st.rigid.nu[2];
    let drag = UAUV2_ZW * w + UAUV2_ZWW * w * w + s * UAUV2_ZWW * 0.01 * (w / 0.1).powf(p);
    assert!(w > 0.0 && w < terminal(thrust), "{w}");
    assert!((drag - thrust).abs() < 1e-6 * thrust, "{drag} vs {thrust}");
    // Direction-dependent coupling: the vertical arm k₊ pushing down, k₋ pushing up, plus
    // k_x·F_x.
    let k = [0.02, -0.005, 0.01];
    for (fz, arm) in [(0.3, k[0]), (-0.2, k[1])] {
        let f = form_force(
            "thrust_coupling",
            "direction",
            &k,
            0.0,
            2.0,
            zero,
            Vec3::new(0.1, 0.0, fz),
        );
        assert!((f[5] - (arm * fz + k[2] * 0.1)).abs() < 1e-15, "{f}");
        assert!(f.rows(0, 5).iter().all(|x| *x == 0.0), "{f}");
    }
}

/// The knee gain, the sided reverse factor and the S-curve depth bias follow their laws at the
/// hooks, and the knee gain sets the terminal heave speed its law implies.
#[test]
fn knee_sided_and_s_curve_forms_follow_their_laws() {
    let v = presets::uauv2();
    let one = |name: &str, form: &str, params: &[f64]| {
        let effect = by_name_form(name, Some(form)).unwrap_or_else(|| panic!("{name}/{form}"));
        Effects::new(vec![EffectInstance {
            effect,
            params: params.to_vec(),
        }])
    };
    let by = |name: &str| v.thrusters.iter().find(|t| t.name == name).unwrap();
    let (top, port, stbd) = (by("top"), by("port"), by("stbd"));
    // Knee gain k = 0.8 up to 40 %, rising by s = 0.3 to full command (100 %).
    let knee = one("thrust_gain", "knee", &[0.8, 0.3, 40.0]);
    for (n, k) in [(20.0, 0.8), (-40.0, 0.8), (70.0, 0.95), (-100.0, 1.1)] {
        let f0 = top.curve.thrust(n);
        let f = knee.thrust(top, n, 0.0, 0.0);
        assert!(
            (f - k * f0).abs() < 1e-12 * f0.abs().max(1.0),
            "n {n}: {f} vs {k}·{f0}"
        );
    }
    let n = 70.0;
    let st = run(
        &with_form("thrust_gain", "knee", &[0.8, 0.3, 40.0]),
        &diving(n),
        40.0,
    );
    assert_terminal(&st, 0.95 * 2.0 * UAUV2_CT_POS * n * n);
    // Sided reverse factor k_rev = 0.8, d = 0.1: reverse thrust × 0.72 on the port side
    // (y < 0), × 0.88 on the starboard side, × 0.8 on the centre line; forward unchanged.
    let sided = one("thrust_asymmetry", "sided", &[0.8, 0.1]);
    assert!(port.position.y < 0.0 && stbd.position.y > 0.0 && top.position.y == 0.0);
    for (th, k) in [(port, 0.72), (stbd, 0.88), (top, 0.8)] {
        let f0 = th.curve.thrust(-60.0);
        assert!(
            (sided.thrust(th, -60.0, 0.0, 0.0) - k * f0).abs() < 1e-12,
            "{}",
            th.name
        );
        assert_eq!(sided.thrust(th, 60.0, 0.0, 0.0), th.curve.thrust(60.0));
    }
    // S-curve bias b₀ + Δ·(1 − e^(−(t/τ)^k)): flat at the start (k > 1), 63 % of Δ at τ,
    // levelled off long after; k = 1 is the settling form.
    let s = one("depth_sensor_bias", "s_curve", &[0.01, 0.08, 50.0, 3.0]);
    assert!((s.depth_offset(0.0) - 0.01).abs() < 1e-15);
    assert!((s.depth_offset(10.0) - (0.01 + 0.08 * (1.0 - (-0.008_f64).exp()))).abs() < 1e-12);
    assert!((s.depth_offset(50.0) - (0.01 + 0.08 * (1.0 - (-1.0_f64).exp()))).abs() < 1e-12);
    assert!((s.depth_offset(500.0) - 0.09).abs() < 1e-12);
    let exp = one("depth_sensor_bias", "s_curve", &[0.0, 0.05, 40.0, 1.0]);
    let settling = one("depth_sensor_bias", "settling", &[0.0, 0.05, 40.0]);
    for t in [0.0, 7.0, 40.0, 123.0] {
        assert!((exp.depth_offset(t) - settling.depth_offset(t)).abs() < 1e-15);
    }
}
