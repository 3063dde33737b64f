//! The replay of the 6-DOF μAUV² model reduces exactly to the paper's 1-DOF laws: in diving
//! mode (β = −π/2, equal side commands) to the heave law
//! (m + A₃₃) ẇ = 2·f(n) − Z_w w − Z_w|w| |w| w, in turning mode (β = 0, side commands balanced
//! for zero surge force) to the yaw law (I_zz + A₆₆) ṙ = y·(f_port − f_stbd) − N_r r − N_r|r| |r| r.

use shoal_model::presets::{
    self, UAUV2_CT_NEG, UAUV2_CT_POS, UAUV2_HEAVE_MASS, UAUV2_NR, UAUV2_NRR, UAUV2_YAW_INERTIA,
    UAUV2_ZW, UAUV2_ZWW,
};
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::VehicleModel;
use shoal_sysid::evaluate::dataset::unwrap;
use shoal_sysid::evaluate::open_loop::{InitialState, InputMap, ReplayOptions, simulate};
use shoal_sysid::log::run::{Channel, ChannelKind, InputColumn, MeasuredRun};
use shoal_testkit::design::balanced_stbd;
use std::f64::consts::FRAC_PI_2;

fn thrust(n: f64) -> f64 {
    if n >= 0.0 {
        UAUV2_CT_POS * n * n
    } else {
        -UAUV2_CT_NEG * n * n
    }
}

/// A command profile with steps both ways, held for 2–5 s, on a 20 ms log.
fn profile(t: f64) -> f64 {
    let levels = [
        0.0, 60.0, 0.0, -70.0, 25.0, -25.0, 100.0, -100.0, 10.0, 0.0, 45.0,
    ];
    let k = ((t / 3.3) as usize).min(levels.len() - 1);
    levels[k]
}

fn run_with(inputs: Vec<(&str, &dyn Fn(f64) -> f64)>, duration: f64) -> MeasuredRun {
    let n = (duration / 0.02).round() as usize + 1;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 0.02).collect();
    let inputs = inputs
        .into_iter()
        .enumerate()
        .map(|(i, (name, f))| InputColumn {
            name: name.into(),
            column: i + 2,
            values: t.iter().map(|&t| f(t)).collect(),
            precision: Vec::new(),
            first_set: 0,
        })
        .collect();
    let mk = |kind, v: f64| Channel {
        kind,
        column: 0,
        rows: vec![0],
        values: vec![v],
    };
    MeasuredRun {
        path: "law.csv".into(),
        name: "law".into(),
        t,
        inputs,
        channels: vec![
            mk(ChannelKind::Depth, 1.0),
            mk(ChannelKind::Yaw, 0.4),
            mk(ChannelKind::R, 0.0),
        ],
        references: Vec::new(),
        extra: Vec::new(),
        header_line: 0,
        lines: Vec::new(),
        ingest: Default::default(),
    }
}

const KINDS: [ChannelKind; 7] = [
    ChannelKind::Depth,
    ChannelKind::Yaw,
    ChannelKind::R,
    ChannelKind::X,
    ChannelKind::Y,
    ChannelKind::Roll,
    ChannelKind::Pitch,
];

/// RK4 of a 1-DOF law ẋ = v, v̇ = a(v, force) with the force held per step.
fn one_dof(
    steps: usize,
    dt: f64,
    x0: f64,
    force: impl Fn(f64) -> f64,
    accel: impl Fn(f64, f64) -> f64,
) -> (Vec<f64>, Vec<f64>) {
    let (mut x, mut v) = (x0, 0.0);
    let mut xs = vec![x];
    let mut vs = vec![v];
    for s in 0..steps {
        let f = force(s as f64 * dt);
        let a = |v: f64| accel(v, f);
        let (k1x, k1v) = (v, a(v));
        let (k2x, k2v) = (v + 0.5 * dt * k1v, a(v + 0.5 * dt * k1v));
        let (k3x, k3v) = (v + 0.5 * dt * k2v, a(v + 0.5 * dt * k2v));
        let (k4x, k4v) = (v + dt * k3v, a(v + dt * k3v));
        x += dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        v += dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        xs.push(x);
        vs.push(v);
    }
    (xs, vs)
}

/// The command in force at `t` on the 20 ms log (zero-order hold).
fn held(f: impl Fn(f64) -> f64, t: f64) -> f64 {
    f(((t + 1e-9) / 0.02).floor() * 0.02)
}

#[test]
fn diving_mode_is_the_heave_law() {
    let params = presets::uauv2();
    let model = VehicleModel::new(params.clone(), 1000.0);
    let mut run = run_with(
        vec![
            ("beta", &|_| -FRAC_PI_2),
            ("alpha", &|_| 0.0),
            ("port", &profile),
            ("stbd", &profile),
        ],
        36.0,
    );
    let map = InputMap::new(&params, &mut run).unwrap();
    let init = InitialState::from_run(&params, &run, 0.5);
    let opts = ReplayOptions::default();
    let trace = simulate(
        &model,
        &Environment::default(),
        &run,
        &map,
        &init,
        &KINDS,
        &opts,
    );
    let steps = trace.len() - 1;
    // The law for the depth of the body origin; the pressure port sits 0.091 m above it.
    let (z, _) = one_dof(
        steps,
        opts.dt,
        1.0 + 0.091,
        |t| 2.0 * thrust(held(profile, t)),
        |w, f| (f - UAUV2_ZW * w - UAUV2_ZWW * w.abs() * w) / UAUV2_HEAVE_MASS,
    );
    let mut max_err: f64 = 0.0;
    let mut travel: f64 = 0.0;
    for k in 0..=steps {
        let row = &trace.values[k * KINDS.len()..(k + 1) * KINDS.len()];
        max_err = max_err.max((row[0] - (z[k] - 0.091)).abs());
        travel = travel.max((z[k] - z[0]).abs());
        // Nothing else moves.
        assert!((row[1] - 0.4).abs() < 1e-12 && row[2].abs() < 1e-12);
        assert!(row[3].abs() < 1e-12 && row[4].abs() < 1e-12);
        assert!(row[5].abs() < 1e-12 && row[6].abs() < 1e-12);
    }
    assert!(travel > 0.5, "the profile moves the vehicle: {travel} m");
    assert!(
        max_err < 1e-9,
        "6-DOF replay vs 1-DOF heave law: {max_err} m"
    );
}

#[test]
fn balanced_turning_mode_is_the_yaw_law_and_unbalanced_is_not() {
    let params = presets::uauv2();
    let model = VehicleModel::new(params.clone(), 1000.0);
    let port = |t: f64| (profile(t) * 0.75).clamp(-79.0, 79.0);
    let stbd = move |t: f64| balanced_stbd(port(t));
    let law = |stbd_cmd: &dyn Fn(f64) -> f64| {
        let mut run = run_with(
            vec![
                ("beta", &|_| 0.0),
                ("alpha", &|_| 0.0),
                ("port", &port),
                ("stbd", stbd_cmd),
            ],
            36.0,
        );
        let map = InputMap::new(&params, &mut run).unwrap();
        let init = InitialState::from_run(&params, &run, 0.5);
        let opts = ReplayOptions::default();
        let trace = simulate(
            &model,
            &Environment::default(),
            &run,
            &map,
            &init,
            &KINDS,
            &opts,
        );
        let steps = trace.len() - 1;
        // Side thrusters at y = ∓0.10 m pushing along body x: N = 0.1·(f_port − f_stbd).
        let (psi, r) = one_dof(
            steps,
            opts.dt,
            0.4,
            |t| 0.1 * (thrust(held(port, t)) - thrust(held(stbd_cmd, t))),
            |r, n| (n - UAUV2_NR * r - UAUV2_NRR * r.abs() * r) / UAUV2_YAW_INERTIA,
        );
        let mut yaw: Vec<f64> = (0..=steps)
            .map(|k| trace.values[k * KINDS.len() + 1])
            .collect();
        unwrap(&mut yaw);
        let mut err: f64 = 0.0;
        let mut drift: f64 = 0.0;
        for k in 0..=steps {
            let row = &trace.values[k * KINDS.len()..(k + 1) * KINDS.len()];
            err = err.max((yaw[k] - psi[k]).abs()).max((row[2] - r[k]).abs());
            drift = drift.max(row[3].abs()).max(row[4].abs());
        }
        let turned = psi.iter().map(|p| (p - psi[0]).abs()).fold(0.0, f64::max);
        (err, drift, turned)
    };
    let (err, drift, turned) = law(&stbd);
    assert!(turned > 6.0, "the profile turns the vehicle: {turned} rad");
    assert!(err < 1e-9, "6-DOF replay vs 1-DOF yaw law: {err}");
    assert!(
        drift < 1e-9,
        "balanced commands: no surge, no drift ({drift} m)"
    );
    // Equal commands instead: a net surge force, the vehicle moves while turning and the
    // Munk moment couples into yaw — the 1-DOF law no longer holds.
    let (err, drift, _) = law(&|t| -port(t));
    assert!(drift > 0.1, "{drift}");
    assert!(err > 1e-3, "{err}");
}
