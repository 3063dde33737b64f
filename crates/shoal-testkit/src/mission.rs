//! Long closed-loop missions: the μAUV² flown by its own controllers
//! ([`shoal_model::control`]) through a seeded schedule of the paper's modes and setpoints, in
//! water that gusts, with a hull whose parameters differ by a few per cent from the ones its
//! controller was designed on — the kind of log a real mission leaves, which an open-loop
//! replay from the first sample cannot follow.
//!
//! * [`uauv2_mission`] — the schedule: legs of 15–60 s in diving, buoyancy, turning, drift
//!   and auto mode with random depths, headings and forces, for as long as asked.
//! * [`Disturbance`] — what the model does not know: a current that wanders (an
//!   Ornstein–Uhlenbeck process per axis, mean zero) and per-parameter noise on damping, added
//!   mass, inertia and thrust coefficients ([`perturb`]).
//! * [`fly`] — the closed loop: at every control tick the sensors are read (through the full
//!   sensor models, as [`crate::synth`] reads them), the controller computes the commands, and
//!   the logger writes the commands it sent (thrusters %, tilt angles, pump) and the
//!   references it followed ([`REFERENCES`]) beside the readings; then the truth is stepped at its own time step with any hidden forms' hooks.

use crate::synth::{Recorder, Stepper, TruthHook};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use shoal_model::control::{Mission, MissionCursor, MissionStep, Mode, SensorReadings, Setpoints};
use shoal_model::dynamics::RigidState;
use shoal_model::math::{Vec3, quat_from_rpy};
use shoal_model::rigid_body::Environment;
use shoal_model::thruster::ThrustCurve;
use shoal_model::vehicle::{VehicleModel, VehicleParams, VehicleState};
use shoal_sysid::log::run::{ChannelKind, InputColumn, MeasuredRun, ReferenceKind};
use std::f64::consts::PI;

/// A mission to fly.
#[derive(Clone, Debug, PartialEq)]
pub struct MissionPlan {
    /// Name (becomes the run's name and file stem).
    pub name: String,
    /// Length \[s\].
    pub duration: f64,
    /// The schedule of modes and setpoints.
    pub mission: Mission,
    /// What is logged (at every control tick).
    pub channels: Vec<ChannelKind>,
    /// Standard deviation of the tracked positions `y.x`, `y.y` where they are logged \[m\].
    pub tracking_noise: f64,
    /// Initial position of the body origin, world frame \[m\].
    pub position: Vec3,
    /// Initial heading \[rad\].
    pub yaw: f64,
}

/// A random heading in (−π, π] \[rad\].
fn heading(rng: &mut ChaCha8Rng) -> f64 {
    rng.random_range(-PI..PI)
}

/// One leg of the schedule starting at `t` \[s\]; returns its length \[s\].
fn leg(rng: &mut ChaCha8Rng, kind: u32, t: f64, steps: &mut Vec<MissionStep>) -> f64 {
    let mut step = MissionStep {
        t,
        ..Default::default()
    };
    let hold: f64 = match kind {
        // Diving: a depth step, held.
        0 => {
            step.mode = Some(Mode::Diving);
            step.depth = Some(rng.random_range(0.6..2.2));
            rng.random_range(20.0..40.0)
        }
        // Buoyancy: a depth step reached with the pump's help.
        1 => {
            step.mode = Some(Mode::Buoyancy);
            step.depth = Some(rng.random_range(0.6..2.2));
            rng.random_range(40.0..60.0)
        }
        // Turning: a heading step (depth is not controlled).
        2 => {
            step.mode = Some(Mode::Turning);
            step.yaw = Some(heading(rng));
            rng.random_range(25.0..40.0)
        }
        // Drift: heading held, pushed forward or back and sideways.
        3 => {
            step.mode = Some(Mode::Drift);
            step.yaw = Some(heading(rng));
            step.surge = Some(rng.random_range(-0.06..0.08));
            step.sway = Some(rng.random_range(-0.04..0.04));
            rng.random_range(25.0..40.0)
        }
        // Auto: depth, heading and surge together.
        _ => {
            step.mode = Some(Mode::Auto);
            step.depth = Some(rng.random_range(0.6..2.2));
            step.yaw = Some(heading(rng));
            step.surge = Some(rng.random_range(0.0..0.08));
            rng.random_range(30.0..60.0)
        }
    };
    steps.push(step);
    // Whole tenths of a second: setpoints change on control ticks.
    (hold * 10.0).round() / 10.0
}

/// The μAUV² mission for `seed`, `duration` \[s\] long: 20 s diving to 1 m from rest, then
/// legs in every mode (each mode once per five legs, in a seeded order), logging depth, roll,
/// pitch, heading and yaw rate.
pub fn uauv2_mission(seed: u64, duration: f64) -> MissionPlan {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x6d15_5104);
    let yaw = heading(&mut rng);
    let mut steps = vec![MissionStep {
        t: 0.0,
        mode: Some(Mode::Diving),
        depth: Some(1.0),
        yaw: Some(yaw),
        surge: Some(0.0),
        sway: Some(0.0),
        ..Default::default()
    }];
    let mut t = 20.0;
    'legs: loop {
        let mut order = [0u32, 1, 2, 3, 4];
        for i in (1..order.len()).rev() {
            order.swap(i, rng.random_range(0..=i));
        }
        for kind in order {
            if t >= duration {
                break 'legs;
            }
            t += leg(&mut rng, kind, t, &mut steps);
        }
    }
    MissionPlan {
        name: format!("uauv2_mission_{seed}"),
        duration,
        mission: Mission { steps },
        channels: vec![
            ChannelKind::Depth,
            ChannelKind::Roll,
            ChannelKind::Pitch,
            ChannelKind::Yaw,
            ChannelKind::R,
        ],
        tracking_noise: 0.0,
        position: Vec3::new(0.0, 0.0, 0.3),
        yaw,
    }
}

/// What the model of a mission log does not know.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disturbance {
    /// Standard deviation of the wandering current, horizontal axes \[m/s\].
    pub gust_horizontal: f64,
    /// Standard deviation of the wandering current, vertical axis \[m/s\].
    pub gust_vertical: f64,
    /// Correlation time of the wandering current \[s\].
    pub gust_time: f64,
    /// Largest relative error of each perturbed parameter (uniform in ±this) \[-\].
    pub param_noise: f64,
}

impl Default for Disturbance {
    /// A pool with a pump running: 2 cm/s horizontal and 5 mm/s vertical gusts over 15 s;
    /// parameters within ±3 %.
    fn default() -> Self {
        Self {
            gust_horizontal: 0.02,
            gust_vertical: 0.005,
            gust_time: 15.0,
            param_noise: 0.03,
        }
    }
}

impl Disturbance {
    /// None at all.
    pub const NONE: Disturbance = Disturbance {
        gust_horizontal: 0.0,
        gust_vertical: 0.0,
        gust_time: 15.0,
        param_noise: 0.0,
    };
}

/// Multiplies every damping coefficient, the added-mass and inertia diagonals and each
/// thruster's thrust coefficients of `params` by its own factor 1 + U(−`frac`, `frac`). Mass,
/// volume and centres stay: a trimmed vehicle is weighed and balanced, its hydrodynamics and
/// motors are only estimated.
pub fn perturb(params: &mut VehicleParams, frac: f64, rng: &mut ChaCha8Rng) {
    if frac <= 0.0 {
        return;
    }
    let mut f = || 1.0 + rng.random_range(-frac..frac);
    let b = &mut params.body;
    for i in 0..6 {
        b.damping_linear[i] *= f();
        b.damping_quadratic[i] *= f();
        b.added_mass[(i, i)] *= f();
    }
    for i in 0..3 {
        b.inertia_cg[(i, i)] *= f();
    }
    for th in &mut params.thrusters {
        match &mut th.curve {
            ThrustCurve::Quadratic { ct_pos, ct_neg } => {
                *ct_pos *= f();
                *ct_neg *= f();
            }
            ThrustCurve::Table { points } => {
                let k = f();
                points.iter_mut().for_each(|(_, thrust)| *thrust *= k);
            }
        }
    }
}

/// A current that wanders: per axis an Ornstein–Uhlenbeck process of standard deviation σ
/// and correlation time τ, sampled exactly at every step.
struct Gusts {
    current: Vec3,
    sigma: Vec3,
    tau: f64,
    rng: ChaCha8Rng,
}

impl Gusts {
    fn new(d: &Disturbance, seed: u64) -> Self {
        let sigma = Vec3::new(d.gust_horizontal, d.gust_horizontal, d.gust_vertical);
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x6775_5374);
        // Start in the process's stationary distribution.
        let current = sigma.map(|s| {
            let z: f64 = StandardNormal.sample(&mut rng);
            s * z
        });
        Self {
            current,
            sigma,
            tau: d.gust_time.max(1e-3),
            rng,
        }
    }

    /// Advances by `h` \[s\] and returns the current \[m/s\].
    fn step(&mut self, h: f64) -> Vec3 {
        let a = (-h / self.tau).exp();
        let b = (1.0 - a * a).sqrt();
        for i in 0..3 {
            let z: f64 = StandardNormal.sample(&mut self.rng);
            self.current[i] = a * self.current[i] + b * self.sigma[i] * z;
        }
        self.current
    }
}

/// Flies `plan` with the truth `model` (hidden effects, perturbed parameters) under the
/// controller `designed` for (the model its designer believes in) in water `env` with the
/// wandering current of `dist`, physics step `dt` \[s\], noise from `seed`, `hook` around
/// every step. Logs at every control tick of the designed controller.
#[allow(clippy::too_many_arguments)]
pub fn fly(
    model: &VehicleModel,
    designed: &VehicleModel,
    env: &Environment,
    plan: &MissionPlan,
    dist: &Disturbance,
    dt: f64,
    seed: u64,
    hook: &mut dyn TruthHook,
) -> MeasuredRun {
    let ctrl = &designed.params.control;
    let period = ctrl.period;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut gusts = Gusts::new(dist, seed);
    let rigid = RigidState::at_rest(plan.position, quat_from_rpy(0.0, 0.0, plan.yaw));
    let mut state = VehicleState::new(model, rigid, env);
    let mut controller = designed.controller();
    let mut cmd = designed.zero_commands();
    let mut readings = SensorReadings::zeros(cmd.tilts.len());
    let mut sp = Setpoints {
        raw: designed.zero_commands(),
        ..Default::default()
    };
    let mut cursor = MissionCursor::default();
    // Logged: every thruster [%], every tilt drive [rad], the pump (−1, 0, +1) if it has one.
    let p = &model.params;
    let pump = p.ballast.is_some();
    let names: Vec<String> = (p.thrusters.iter().map(|th| th.name.clone()))
        .chain(p.tilts.iter().map(|tl| tl.name.clone()))
        .chain(pump.then(|| "pump".to_string()))
        .collect();
    let n_samples = (plan.duration / period).round() as usize + 1;
    let sub = (period / dt).round().max(1.0) as usize;
    let h = period / sub as f64;
    let mut log = Recorder::new(
        model,
        &names,
        &plan.channels,
        n_samples,
        plan.tracking_noise,
    );
    let mut stepper = Stepper::new(&cmd, env);
    let mut water = *env;
    let mut values = Vec::with_capacity(names.len());
    // The references in force at each tick, as REFERENCES lists them.
    let mut refs: [Vec<f64>; 5] = std::array::from_fn(|_| Vec::with_capacity(n_samples));
    for k in 0..n_samples {
        let t = k as f64 * period;
        cursor.advance(&plan.mission, t, &mut sp);
        for (col, kind) in refs.iter_mut().zip(REFERENCES) {
            col.push(match kind {
                ReferenceKind::Mode => sp.mode.code() as f64,
                ReferenceKind::Depth => sp.depth,
                ReferenceKind::Yaw => sp.yaw,
                ReferenceKind::Surge => sp.surge,
                ReferenceKind::Sway => sp.sway,
            });
        }
        log.observe(
            t,
            model,
            &mut state,
            &stepper.water,
            hook,
            &mut rng,
            &mut readings,
        );
        controller.update(
            ctrl,
            designed.uauv2.as_ref(),
            &designed.params.thrusters,
            &readings,
            &sp,
            &mut cmd,
        );
        values.clear();
        values.extend(cmd.thrusters.iter().chain(&cmd.tilts));
        values.extend(pump.then(|| cmd.pump.sign()));
        log.push_inputs(&values);
        if k + 1 == n_samples {
            break;
        }
        // A tilt is where the log says it is (the replay sets it so).
        state.actuators.tilt.clone_from(&cmd.tilts);
        for _ in 0..sub {
            water.current = env.current + gusts.step(h);
            stepper.step(model, &water, &mut state, &cmd, hook, h);
        }
    }
    let mut run = log.finish(&plan.name);
    let first_column = 2 + run.inputs.len() + run.channels.len();
    run.references = REFERENCES
        .iter()
        .zip(refs)
        .enumerate()
        .map(|(i, (kind, values))| InputColumn {
            name: kind.name().to_string(),
            column: first_column + i,
            values,
            precision: Vec::new(),
            first_set: 0,
        })
        .collect();
    run
}

/// The references a mission log carries (`r.<name>`), in column order: the controller's mode
/// (its code), depth \[m\], heading \[rad\], surge and sway forces \[N\].
pub const REFERENCES: [ReferenceKind; 5] = [
    ReferenceKind::Mode,
    ReferenceKind::Depth,
    ReferenceKind::Yaw,
    ReferenceKind::Surge,
    ReferenceKind::Sway,
];

#[cfg(test)]
mod tests {
    use super::*;
    use shoal_model::control::heading_error;
    use shoal_model::presets;

    fn series(run: &MeasuredRun, kind: ChannelKind) -> &[f64] {
        &run.channels.iter().find(|c| c.kind == kind).unwrap().values
    }

    /// Without disturbances the μAUV² flies its own mission: over every leg that controls
    /// depth the depth error shrinks to a quarter or less (and ends within 3 cm), over every
    /// leg that controls heading the heading error does — except in drift mode, where the
    /// top thruster's sway force turns the hull and the PD (no integral) holds it off by
    /// N/K_P, as on the real vehicle.
    #[test]
    fn the_controllers_drive_every_leg_towards_its_setpoint() {
        let model = VehicleModel::new(presets::uauv2(), 1000.0);
        let plan = uauv2_mission(7, 600.0);
        let env = Environment::default();
        let run = fly(
            &model,
            &model,
            &env,
            &plan,
            &Disturbance::NONE,
            0.005,
            1,
            &mut (),
        );
        let (depth, yaw) = (
            series(&run, ChannelKind::Depth),
            series(&run, ChannelKind::Yaw),
        );
        let steps = &plan.mission.steps;
        let mut sp = Setpoints::default();
        let mut cursor = MissionCursor::default();
        let (mut depth_legs, mut yaw_legs) = (0, 0);
        let at = |t: f64| ((t / 0.05).round() as usize).min(depth.len() - 1);
        for (i, s) in steps.iter().enumerate() {
            cursor.advance(&plan.mission, s.t, &mut sp);
            let end = steps.get(i + 1).map_or(plan.duration, |n| n.t);
            if end - s.t < 20.0 {
                continue; // the mission's last leg, cut short
            }
            let (k0, k1) = (at(s.t), at(end) - 1);
            if sp.mode.holds_depth() {
                let (e0, e1) = (depth[k0] - sp.depth, depth[k1] - sp.depth);
                let ok = e1.abs() < 0.03 && (e1.abs() <= 0.25 * e0.abs() || e0.abs() < 0.05);
                assert!(ok, "leg {i} ({:?}): depth error {e0} → {e1} m", sp.mode);
                depth_legs += 1;
            }
            if matches!(sp.mode, Mode::Turning | Mode::Auto) {
                let (e0, e1) = (
                    heading_error(sp.yaw, yaw[k0]),
                    heading_error(sp.yaw, yaw[k1]),
                );
                let ok = e1.abs() <= 0.25 * e0.abs() || e1.abs() < 0.03;
                assert!(ok, "leg {i} ({:?}): heading error {e0} → {e1} rad", sp.mode);
                yaw_legs += 1;
            }
        }
        assert!(depth_legs >= 5 && yaw_legs >= 4, "{depth_legs} {yaw_legs}");
    }

    /// The wandering current has the asked spread and correlation time: over 20 000 s its
    /// standard deviation is within 10 % of σ and its autocorrelation after τ is e⁻¹ ± 0.1.
    #[test]
    fn gusts_have_their_spread_and_correlation_time() {
        let d = Disturbance {
            gust_horizontal: 0.02,
            gust_vertical: 0.005,
            gust_time: 10.0,
            param_noise: 0.0,
        };
        let mut g = Gusts::new(&d, 3);
        let h = 0.5;
        let xs: Vec<Vec3> = (0..40_000).map(|_| g.step(h)).collect();
        for (axis, sigma) in [(0, 0.02), (1, 0.02), (2, 0.005)] {
            let v: Vec<f64> = xs.iter().map(|c| c[axis]).collect();
            let n = v.len() as f64;
            let var = v.iter().map(|x| x * x).sum::<f64>() / n;
            assert!(
                (var.sqrt() / sigma - 1.0).abs() < 0.1,
                "axis {axis}: σ = {}",
                var.sqrt()
            );
            let lag = (d.gust_time / h) as usize;
            let cov = v.iter().zip(&v[lag..]).map(|(a, b)| a * b).sum::<f64>() / (n - lag as f64);
            let rho = cov / var;
            assert!(
                (rho - (-1.0f64).exp()).abs() < 0.1,
                "axis {axis}: ρ(τ) = {rho}"
            );
        }
    }

    /// Parameter noise changes the hydrodynamic and thrust coefficients within the asked
    /// fraction and leaves what a trimmed vehicle is weighed for alone.
    #[test]
    fn perturbation_stays_within_its_fraction_and_spares_mass_and_volume() {
        let base = presets::uauv2();
        let mut p = base.clone();
        perturb(&mut p, 0.03, &mut ChaCha8Rng::seed_from_u64(5));
        let ratio = |a: f64, b: f64| if b == 0.0 { 1.0 } else { a / b };
        let mut changed = 0;
        for i in 0..6 {
            for (a, b) in [
                (p.body.damping_linear[i], base.body.damping_linear[i]),
                (p.body.damping_quadratic[i], base.body.damping_quadratic[i]),
                (p.body.added_mass[(i, i)], base.body.added_mass[(i, i)]),
            ] {
                let r = ratio(a, b);
                assert!((r - 1.0).abs() <= 0.03 + 1e-12, "{r}");
                changed += usize::from(r != 1.0);
            }
        }
        assert!(changed >= 10, "only {changed} coefficients changed");
        assert_eq!(p.body.mass, base.body.mass);
        assert_eq!(p.body.volume, base.body.volume);
        assert_eq!(p.body.cog, base.body.cog);
        assert_eq!(p.body.cob, base.body.cob);
        assert_ne!(p.thrusters[0].curve, base.thrusters[0].curve);
    }
}
