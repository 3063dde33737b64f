//! The μAUV² paper's Section 5 experiments, run from the world files in `worlds/` through the
//! whole simulator (sensors with noise and quantisation, controllers, filters, 6-DOF dynamics)
//! and compared with what the paper reports. docs/paper-comparison.md has the full table.
//!
//! The paper's bands are wide (a turn rate of 28–45°/s passes a yaw inertia 25 % off), so each
//! run is also compared with what the paper's 1-DOF laws (identified inertia, mass and damping,
//! the controllers' gains designed on them, the pump's flow) predict for it, within what the
//! sensors, filters and the 6-DOF hull add: the segments of each run are counted, and every
//! band a run must reach is required.

use shoal::model::presets;
use shoal::model::rigid_body::Environment;
use shoal::model::vehicle::VehicleModel;
use shoal::record::analysis::{Segment, point_depth, record_run, segments};
use shoal::sim::recorder::col;
use shoal::world::load::load_file;
use std::path::Path;
use std::sync::Arc;

/// Recorded rows of every vehicle of a world file, run to its end.
fn run(file: &str) -> (Vec<Vec<Vec<f64>>>, Vec<Arc<VehicleModel>>) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("worlds")
        .join(file);
    let desc = load_file(&path).unwrap_or_else(|e| panic!("{e}"));
    (
        record_run(&desc),
        desc.vehicles.iter().map(|v| v.model.clone()).collect(),
    )
}

fn sensor_depth(row: &[f64], port_z: f64) -> f64 {
    point_depth(row, port_z)
}

fn depth_segments(rows: &[Vec<f64>], port_z: f64, band: f64) -> Vec<Segment> {
    let s: Vec<(f64, f64, f64)> = rows
        .iter()
        .map(|r| (r[col::T], sensor_depth(r, port_z), r[col::DEPTH_SP]))
        .collect();
    segments(&s, band, false)
}

fn yaw_segments(rows: &[Vec<f64>], band: f64) -> Vec<Segment> {
    let s: Vec<(f64, f64, f64)> = rows
        .iter()
        .map(|r| (r[col::T], r[col::YAW], r[col::YAW_SP]))
        .collect();
    segments(&s, band, true)
}

fn port_z(m: &VehicleModel) -> f64 {
    m.params.pressure.position.z
}

const QUANTUM: f64 = 1.8e-3;

#[test]
fn diving_has_no_overshoot_and_reaches_every_setpoint() {
    let (rows, m) = run("paper_diving.toml");
    let segs = depth_segments(&rows[0], port_z(&m[0]), 0.01);
    assert_eq!(segs.len(), 4, "0 → 0.4 → 0.2 → 0");
    for s in &segs[1..] {
        // ζ = 1: no overshoot beyond one quantisation step of the true depth.
        assert!(
            s.overshoot < QUANTUM,
            "overshoot {} m in {s:?}",
            s.overshoot
        );
        // Paper: setpoints reached after ≈ 15 s in simulation.
        let t = s.time_to_band.expect("enters ±1 cm");
        assert!(t < 15.0, "took {t} s: {s:?}");
        assert!(s.final_error.abs() < 0.006, "{s:?}");
    }
}

/// One axis of the paper's 1-DOF model (Sec. 4, identified in Tables 3 and 4):
/// `inertia · ẍ = u − linear · ẋ − quadratic · |ẋ| ẋ`, with `u` the controller's force or
/// torque plus whatever else acts on the axis.
#[derive(Clone, Copy, Debug)]
struct Axis {
    inertia: f64,
    linear: f64,
    quadratic: f64,
}

/// Yaw: I_zz + A₆₆, N_r, N_r|r|.
const YAW: Axis = Axis {
    inertia: presets::UAUV2_YAW_INERTIA,
    linear: presets::UAUV2_NR,
    quadratic: presets::UAUV2_NRR,
};
/// Heave: m + A₃₃, Z_w, Z_w|w|.
const HEAVE: Axis = Axis {
    inertia: presets::UAUV2_HEAVE_MASS,
    linear: presets::UAUV2_ZW,
    quadratic: presets::UAUV2_ZWW,
};

/// Step of the 1-DOF integration [s].
const IDEAL_DT: f64 = 1e-3;

impl Axis {
    /// The axis from `x0` moving at `v0`, for `seconds`, under `u(t, x, ẋ)` (semi-implicit
    /// Euler in [`IDEAL_DT`] steps): the samples `(t, x, ẋ)`, the first at t = 0.
    fn response(
        &self,
        x0: f64,
        v0: f64,
        seconds: f64,
        mut u: impl FnMut(f64, f64, f64) -> f64,
    ) -> Vec<(f64, f64, f64)> {
        let (mut x, mut v) = (x0, v0);
        let mut out = vec![(0.0, x, v)];
        for k in 0..(seconds / IDEAL_DT).round() as usize {
            let t = k as f64 * IDEAL_DT;
            let a = (u(t, x, v) - self.linear * v - self.quadratic * v.abs() * v) / self.inertia;
            v += a * IDEAL_DT;
            x += v * IDEAL_DT;
            out.push((t + IDEAL_DT, x, v));
        }
        out
    }
}

/// The ideal yaw response under the yaw PD `(K_P, K_D)` towards `target`, from heading `psi0`
/// turning at `r0`, for `seconds`: samples `(t, ψ, r)`.
fn ideal_yaw(
    (kp, kd): (f64, f64),
    target: f64,
    psi0: f64,
    r0: f64,
    seconds: f64,
) -> Vec<(f64, f64, f64)> {
    YAW.response(psi0, r0, seconds, |_, psi, r| kp * (target - psi) - kd * r)
}

/// The yaw PD of the world's design (ω, ζ, explicit gains) for the identified yaw inertia: the
/// gains the simulated controller has when the vehicle's inertia is the paper's.
fn paper_yaw_gains(m: &VehicleModel) -> (f64, f64) {
    m.params.control.yaw.gains(presets::UAUV2_YAW_INERTIA)
}

/// Recorded (unwrapped heading, yaw rate) of the row at the start of a yaw segment.
fn yaw_state_at(rows: &[Vec<f64>], s: &Segment) -> (f64, f64) {
    let r = rows.iter().find(|r| r[col::T] >= s.t0).expect("sample");
    (s.from, r[col::R])
}

/// Each yaw segment after the first, against the ideal 1-DOF yaw law (gains of the vehicle's
/// design for the identified inertia) started from the recorded heading and rate: the final
/// error must agree within [`YAW_TOL_DEG`] + [`YAW_REL`] of the move. Returns the ideal
/// responses.
fn check_yaw_law(
    rows: &[Vec<f64>],
    segs: &[Segment],
    m: &VehicleModel,
) -> Vec<Vec<(f64, f64, f64)>> {
    let gains = paper_yaw_gains(m);
    segs[1..]
        .iter()
        .map(|s| {
            let (psi0, r0) = yaw_state_at(rows, s);
            let ideal = ideal_yaw(gains, s.target, psi0, r0, s.t1 - s.t0);
            let predicted = (s.target - ideal.last().unwrap().1).to_degrees();
            let got = s.final_error.to_degrees();
            let tol = YAW_TOL_DEG + YAW_REL * (s.target - psi0).abs().to_degrees();
            println!(
                "yaw {:.0}° → {:.0}°: error at the end sim {got:.2}°, ideal {predicted:.2}° (± {tol:.2}°)",
                psi0.to_degrees(),
                s.target.to_degrees()
            );
            assert!(
                (got - predicted).abs() <= tol,
                "sim {got}° vs ideal {predicted}° (± {tol}°) in {s:?}"
            );
            ideal
        })
        .collect()
}

/// The ideal buoyancy calibration: the pressure port's depth from `x0` under the buoyancy-mode
/// heave PD `(K_P, K_D)` (within the side thrusters' `limits`, forward and reverse [N]) towards
/// `target`, with a net downward force of `net_weight` [N] at the start that the pump raises
/// at [`presets::UAUV2_PUMP_FLOW`] while the error exceeds `dead_zone`. Returns the samples
/// `(t, depth, rate)` and the time the pump first stops.
fn ideal_buoyancy(
    (kp, kd): (f64, f64),
    limits: (f64, f64),
    target: f64,
    x0: f64,
    net_weight: f64,
    dead_zone: f64,
    seconds: f64,
) -> (Vec<(f64, f64, f64)>, f64) {
    let env = Environment::default();
    let mut weight = net_weight;
    let mut stop = f64::INFINITY;
    let response = HEAVE.response(x0, 0.0, seconds, |t, x, v| {
        let e = target - x;
        if e > dead_zone {
            weight += env.density * env.gravity * presets::UAUV2_PUMP_FLOW * IDEAL_DT;
        } else if stop.is_infinite() {
            stop = t;
        }
        (kp * e - kd * v).clamp(-2.0 * limits.1, 2.0 * limits.0) + weight
    });
    (response, stop)
}

#[test]
fn buoyancy_calibration_ends_inside_the_dead_zone() {
    let (rows, m) = run("paper_buoyancy.toml");
    let pz = port_z(&m[0]);
    let at = |t: f64| rows[0].iter().find(|r| r[col::T] >= t).expect("sample");
    let d16 = sensor_depth(at(16.0), pz);
    // The pump stops when the heave error is inside the 8 mm dead zone.
    let stop = rows[0]
        .iter()
        .find(|r| r[col::T] > 1.0 && r[col::PUMP] == 0.0)
        .expect("pump stops")[col::T];
    // The 1-DOF heave law with the identified mass and damping, the pump's flow and the
    // starting buoyancy predicts both.
    let u = m[0].uauv2.as_ref().unwrap();
    let (ideal, ideal_stop) = ideal_buoyancy(
        m[0].params
            .control
            .heave_buoyancy
            .gains(presets::UAUV2_HEAVE_MASS),
        u.side_limits,
        0.2,
        sensor_depth(&rows[0][0], pz),
        m[0].params.net_weight(&Environment::default()),
        m[0].params.control.dead_zone,
        120.0,
    );
    let ideal16 = ideal.iter().find(|s| s.0 >= 16.0).unwrap().1;
    println!(
        "depth at 16 s: sim {d16:.4} m, ideal {ideal16:.4} m; pump stops: sim {stop:.2} s, ideal {ideal_stop:.2} s"
    );
    // (Measured: 1.7 mm shallower and 0.55 s later than the ideal law; a pump 10 % slower
    // or faster moves the stop by 4 s, 25 % by 15 s, and the depth by 3 to 6 mm.)
    assert!(
        (d16 - ideal16).abs() < 0.0025,
        "depth at 16 s {d16} m, ideal {ideal16} m"
    );
    assert!(
        (stop - ideal_stop).abs() < 1.5,
        "pump stopped at {stop} s, ideal {ideal_stop} s"
    );
    // Paper: 0.15 m after 16 s, held short of 0.2 m by the positive buoyancy; the pump stops
    // at 51 s.
    assert!((0.12..0.17).contains(&d16), "depth at 16 s: {d16}");
    assert!((40.0..62.0).contains(&stop), "pump stopped at {stop} s");
    // Paper: then holds within the dead zone for ≥ 30 s; here until the end (120 s).
    for r in rows[0].iter().filter(|r| r[col::T] >= stop + 10.0) {
        let e = 0.2 - sensor_depth(r, pz);
        assert!(
            e.abs() < 0.008,
            "left the dead zone at t = {}: error {e}",
            r[col::T]
        );
    }
    // Water was taken in: the ballast ends near the neutral 10 ml.
    let last = rows[0].last().unwrap();
    assert!(
        (last[col::BALLAST] * 1e6 - 10.0).abs() < 0.3,
        "ballast {} ml",
        last[col::BALLAST] * 1e6
    );
}

#[test]
fn turning_with_the_papers_gains_does_not_overshoot_and_follows_the_yaw_law() {
    let (rows, m) = run("paper_turning.toml");
    let segs = yaw_segments(&rows[0], 2f64.to_radians());
    assert_eq!(segs.len(), 5, "0 → 180° → 45° → 90° → 0: {segs:?}");
    for s in &segs {
        // Paper: maximum overshoot 10°.
        assert!(s.overshoot.to_degrees() <= 10.0, "{s:?}");
    }
    // With K_Dψ = 0.016 the loop is overdamped: the 180° turn is still short after 15 s, by
    // what the ideal 1-DOF yaw law predicts for these gains (sensors, filters and the 6-DOF
    // hull change it by little), and so is every later turn.
    let ideal = check_yaw_law(&rows[0], &segs, &m[0]);
    let left = (segs[1].target - ideal[0].last().unwrap().1).to_degrees();
    assert!(left > 20.0, "the paper's gains leave {left}° after 15 s");
}

/// The simulated turns may differ from the ideal 1-DOF yaw law by this much of the move plus
/// [`YAW_TOL_DEG`]: the sensors' noise, the command filters and the 6-DOF hull. (A yaw inertia
/// 25 % off the identified one changes the 180° turns by several degrees.)
const YAW_REL: f64 = 0.01;
/// See [`YAW_REL`] [°].
const YAW_TOL_DEG: f64 = 0.5;

/// Largest rate towards the target of an ideal response, sampled at the recording rate
/// (as [`Segment::peak_rate`] measures the recorded one).
fn ideal_peak_rate(ideal: &[(f64, f64, f64)], record_dt: f64, dir: f64) -> f64 {
    let every = (record_dt / IDEAL_DT).round() as usize;
    let sampled: Vec<&(f64, f64, f64)> = ideal.iter().step_by(every).collect();
    sampled
        .windows(2)
        .map(|w| (w[1].1 - w[0].1) / (w[1].0 - w[0].0) * dir)
        .fold(0.0, f64::max)
}

#[test]
fn turning_with_nominal_gains_turns_at_the_papers_rate() {
    let (rows, m) = run("paper_turning_zeta1.toml");
    let segs = yaw_segments(&rows[0], 2f64.to_radians());
    assert_eq!(segs.len(), 5, "0 → 180° → 45° → 90° → 0: {segs:?}");
    for s in &segs[1..] {
        assert!(s.overshoot.to_degrees() <= 10.0, "{s:?}");
        assert!(
            s.final_error.to_degrees().abs() < 2.0,
            "reaches the setpoint: {s:?}"
        );
        assert!(s.time_to_band.is_some(), "enters ±2°: {s:?}");
    }
    let ideal = check_yaw_law(&rows[0], &segs, &m[0]);
    // The peak rate of every turn as the 1-DOF law has it, sampled as recorded (20 Hz).
    let record_dt = rows[0][1][col::T] - rows[0][0][col::T];
    for (s, ideal) in segs[1..].iter().zip(&ideal) {
        let dir = (s.target - s.from).signum();
        let (got, want) = (
            s.peak_rate.to_degrees(),
            ideal_peak_rate(ideal, record_dt, dir).to_degrees(),
        );
        println!("peak rate sim {got:.2}°/s, ideal {want:.2}°/s");
        assert!(
            (got - want).abs() <= PEAK_RATE_REL * want,
            "peak turn rate {got}°/s, ideal {want}°/s: {s:?}"
        );
    }
    // Paper: 34°/s on the big turn.
    let peak = segs[1].peak_rate.to_degrees();
    assert!((28.0..45.0).contains(&peak), "peak turn rate {peak}°/s");
}

/// Largest relative difference between a simulated and the ideal peak turn rate. (Measured:
/// the simulated turns peak 3–5 % above the ideal law; a yaw inertia 25 % above the identified
/// one gives 19 %.)
const PEAK_RATE_REL: f64 = 0.06;

#[test]
fn auto_mode_controls_heave_and_yaw_and_barely_drifts() {
    let (rows, m) = run("paper_auto.toml");
    let heave = depth_segments(&rows[0], port_z(&m[0]), 0.01);
    let dive = {
        let (r, m) = run("paper_diving.toml");
        depth_segments(&r[0], port_z(&m[0]), 0.01)
    };
    assert_eq!(heave.len(), 4, "0 → 0.4 → 0.2 → 0: {heave:?}");
    assert_eq!(dive.len(), 4, "0 → 0.4 → 0.2 → 0: {dive:?}");
    for (a, d) in heave[1..].iter().zip(&dive[1..]) {
        // Paper (real vehicle): steady error ≤ 0.018 m.
        assert!(a.final_error.abs() < 0.018, "{a:?}");
        // The side thrust available for heave is capped by what the top thruster can cancel,
        // so auto mode is never faster than diving mode; both reach ±1 cm.
        let (ta, td) = (
            a.time_to_band.expect("auto mode enters ±1 cm"),
            d.time_to_band.expect("diving mode enters ±1 cm"),
        );
        assert!(ta >= td - 0.5, "{a:?} vs {d:?}");
    }
    // Yaw as in turning mode (priority on yaw): the same overdamped response, as the ideal
    // 1-DOF yaw law has it for the paper's gains.
    let yaw = yaw_segments(&rows[1], 2f64.to_radians());
    assert_eq!(yaw.len(), 5, "0 → 180° → 45° → 90° → 0: {yaw:?}");
    assert!(yaw.iter().all(|s| s.overshoot.to_degrees() <= 10.0));
    let ideal = check_yaw_law(&rows[1], &yaw, &m[1]);
    // It turned: the 180° turn covered most of its way in 15 s, as the ideal one did.
    let covered = (yaw[1].target - yaw[1].final_error - yaw[1].from).to_degrees();
    let ideal_covered = (ideal[0].last().unwrap().1 - yaw[1].from).to_degrees();
    assert!(
        covered > 120.0 && ideal_covered > 120.0,
        "the turn covered {covered}°, the ideal one {ideal_covered}°"
    );
    // The top thruster cancels the side thrusters' surge: both vehicles stay within 0.25 m.
    for v in &rows {
        let (x0, y0) = (v[0][col::X], v[0][col::Y]);
        let drift = v
            .iter()
            .map(|r| (r[col::X] - x0).hypot(r[col::Y] - y0))
            .fold(0.0, f64::max);
        assert!(drift < 0.25, "horizontal drift {drift} m");
    }
}
