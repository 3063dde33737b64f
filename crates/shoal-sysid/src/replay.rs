//! Replay: the vehicle model driven open-loop by a run's measured inputs.
//!
//! The inputs are held between their samples (zero-order hold). Thruster commands go through
//! the thrust model (curve, lag, effects); tilt angles are the measured angles and are set
//! directly (a log records where the drives stood, not where they were asked to go); the pump
//! command is −1/0/+1. The replay starts from the measured initial state (attitude, position
//! and rates from the first samples; a vehicle whose velocity is not measured starts at rest
//! relative to the water, as the experiments start at rest) and is sampled at the measurement times through the
//! deterministic part of the sensor models: the pressure port's depth (clamped at the
//! surface) plus any depth-sensor effect, attitude, gyro rates plus the gyro bias, tracked
//! position, velocity over ground, all delayed by any sensor delay.
//!
//! Quantisation and noise are not simulated: they are what the residual of a perfect model
//! consists of.

use crate::ingest::short;
use crate::limits::{ClampNote, Limits};
use crate::masses::{BodyMasses, MassTable};
use crate::run::{ChannelKind, MeasuredRun, RunError};
use shoal_model::ballast::Pump;
use shoal_model::control::ActuatorCommands;
use shoal_model::dynamics::{Integrator, RigidState};
use shoal_model::lanes::{DynConsts, LANES, LaneConsts, Lanes, rk4_group};
use shoal_model::math::{Quat, Vec3, quat_from_rpy, split6, wrap_pi};
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::{
    VehicleModel, VehicleParams, VehicleState, actuate_thrusters, integrate_vehicle,
    integrate_vehicle_rk4, run_pump,
};

/// Which input column drives which actuator.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct InputMap {
    /// (thruster index, input column index) [command %].
    pub thrusters: Vec<(usize, usize)>,
    /// (tilt index, input column index) \[rad\].
    pub tilts: Vec<(usize, usize)>,
    /// Input column of the pump (−1 empty, 0 off, +1 fill).
    pub pump: Option<usize>,
    /// Input values that lay within rounding of an actuator limit and were clamped to it
    /// (see [`crate::limits`]).
    pub clamped: Vec<ClampNote>,
}

impl InputMap {
    /// Maps the run's `u.` columns onto the vehicle's actuators by name: `u.<thruster>`
    /// [%], `u.<tilt drive>` \[rad\], `u.pump`. Actuators without a column stay at zero.
    ///
    /// Checks every input value against its actuator's limits ([`crate::limits`]): values
    /// within rounding of a limit are clamped to it in `run` and counted in
    /// [`InputMap::clamped`]; a value clearly out of range, a pump command that is not −1, 0
    /// or +1, or an unknown actuator is an error naming the line and column (and `run` is
    /// left unchanged).
    pub fn new(params: &VehicleParams, run: &mut MeasuredRun) -> Result<InputMap, RunError> {
        let mut map = InputMap::default();
        let mut limits = Vec::with_capacity(run.inputs.len());
        for (k, inp) in run.inputs.iter().enumerate() {
            let lim = if let Some(i) = params.thrusters.iter().position(|t| t.name == inp.name) {
                map.thrusters.push((i, k));
                Limits::thruster(params.thrusters[i].max_command)
            } else if let Some(i) = params.tilts.iter().position(|t| t.name == inp.name) {
                map.tilts.push((i, k));
                Limits::tilt(params.tilts[i].min, params.tilts[i].max)
            } else if inp.name == "pump" && params.ballast.is_some() {
                map.pump = Some(k);
                Limits::Pump
            } else {
                let mut names: Vec<String> = params
                    .thrusters
                    .iter()
                    .map(|t| format!("u.{}", t.name))
                    .chain(params.tilts.iter().map(|t| format!("u.{}", t.name)))
                    .collect();
                if params.ballast.is_some() {
                    names.push("u.pump".into());
                }
                return Err(RunError {
                    file: run.path.clone(),
                    line: run.header_line,
                    column: Some((inp.column, format!("u.{}", inp.name))),
                    message: format!(
                        "vehicle `{}` has no actuator `{}` (its inputs: {})",
                        params.name,
                        inp.name,
                        names.join(", ")
                    ),
                });
            };
            map.clamped.extend(lim.check(run, k)?);
            limits.push(lim);
        }
        for (inp, lim) in run.inputs.iter_mut().zip(&limits) {
            lim.apply(&mut inp.values);
        }
        Ok(map)
    }
}

/// The most physics steps one replay may take: 10⁷, i.e. 27.8 h of log at the default 10 ms
/// step (the trace then holds 80 MB per recorded channel). Longer replays are refused by
/// [`ReplayOptions::steps`] (and cut there by [`simulate`]) instead of allocating by the time
/// span.
pub const MAX_REPLAY_STEPS: usize = 10_000_000;

/// Settings of a replay.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReplayOptions {
    /// Physics step \[s\].
    pub dt: f64,
    /// Integrator.
    pub integrator: Integrator,
}

impl ReplayOptions {
    /// Smallest physics step allowed \[s\].
    pub const DT_MIN: f64 = 1e-4;
    /// Largest physics step allowed \[s\].
    pub const DT_MAX: f64 = 0.1;

    /// The physics steps a replay of `run` takes, or an error naming the run when the step is
    /// outside [`Self::DT_MIN`]…[`Self::DT_MAX`] or the replay would need more than
    /// [`MAX_REPLAY_STEPS`].
    pub fn steps(&self, run: &MeasuredRun) -> Result<usize, RunError> {
        let err = |message: String| RunError {
            file: run.path.clone(),
            line: 0,
            column: None,
            message,
        };
        if !(self.dt >= Self::DT_MIN && self.dt <= Self::DT_MAX) {
            return Err(err(format!(
                "replay step {} s is out of range; allowed: {} … {} s",
                self.dt,
                Self::DT_MIN,
                Self::DT_MAX
            )));
        }
        let span = run.duration();
        let steps = (span / self.dt).ceil();
        if steps.is_nan() || steps > MAX_REPLAY_STEPS as f64 {
            return Err(err(format!(
                "run `{}`: replaying its {} s at a {} s step needs {:.3e} steps; at most {:.0e} \
                 are allowed (use a larger --dt, or split the run at its gaps with --max-gap)",
                run.name,
                short(span),
                self.dt,
                steps,
                MAX_REPLAY_STEPS as f64
            )));
        }
        Ok(steps.max(0.0) as usize)
    }
}

impl Default for ReplayOptions {
    fn default() -> Self {
        Self {
            dt: 0.01,
            integrator: Integrator::Rk4,
        }
    }
}

/// The state a replay starts from.
#[derive(Clone, Debug, PartialEq)]
pub struct InitialState {
    /// Roll, pitch, yaw \[rad\].
    pub rpy: Vec3,
    /// World position of the body origin \[m\] (depth from the first depth reading).
    pub position: Vec3,
    /// Body velocity over ground (u, v, w) [m/s], if measured; otherwise the vehicle starts
    /// at rest relative to the water.
    pub velocity: Option<Vec3>,
    /// Body rates (p, q, r) [rad/s].
    pub rates: Vec3,
}

impl InitialState {
    /// The state the run's first samples show: angles, positions and depth from the first
    /// sample of each channel; rates and velocities from the mean of the samples in the first
    /// `window` seconds where that mean differs from zero by more than three standard errors
    /// (a slowly damped yaw would otherwise integrate the gyro noise of the first samples
    /// into a heading drift); zero where nothing is measured.
    pub fn from_run(params: &VehicleParams, run: &MeasuredRun, window: f64) -> InitialState {
        let t0 = run.t[0];
        let first = |k: ChannelKind| run.channel(k).map(|c| c.values[0]);
        let mean = |k: ChannelKind| {
            run.channel(k).map_or(0.0, |c| {
                let v: Vec<f64> = c
                    .rows
                    .iter()
                    .zip(&c.values)
                    .filter(|(r, _)| run.t[**r] <= t0 + window)
                    .map(|(_, v)| *v)
                    .collect();
                let n = v.len() as f64;
                if v.len() < 3 {
                    return c.values[0];
                }
                let m = v.iter().sum::<f64>() / n;
                let sd = (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
                if m.abs() > 3.0 * sd / n.sqrt() {
                    m
                } else {
                    0.0
                }
            })
        };
        let rpy = Vec3::new(
            first(ChannelKind::Roll).unwrap_or(0.0),
            first(ChannelKind::Pitch).unwrap_or(0.0),
            first(ChannelKind::Yaw).unwrap_or(0.0),
        );
        let att = quat_from_rpy(rpy.x, rpy.y, rpy.z);
        let port = att.transform_vector(&params.pressure.position).z;
        let depth = first(ChannelKind::Depth).map_or(1.0, |d| d - port);
        InitialState {
            rpy,
            position: Vec3::new(
                first(ChannelKind::X).unwrap_or(0.0),
                first(ChannelKind::Y).unwrap_or(0.0),
                depth,
            ),
            velocity: [ChannelKind::U, ChannelKind::V, ChannelKind::W]
                .iter()
                .any(|k| run.channel(*k).is_some())
                .then(|| {
                    Vec3::new(
                        mean(ChannelKind::U),
                        mean(ChannelKind::V),
                        mean(ChannelKind::W),
                    )
                }),
            rates: Vec3::new(
                mean(ChannelKind::P),
                mean(ChannelKind::Q),
                mean(ChannelKind::R),
            ),
        }
    }
}

/// A replayed run: the model's outputs on a uniform time grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Trace {
    /// Time of the first grid point (the run's first time) \[s\].
    pub t0: f64,
    /// Grid step \[s\].
    pub dt: f64,
    /// The recorded kinds, in column order of `values`.
    pub kinds: Vec<ChannelKind>,
    /// Row-major: grid point × kind (units of [`ChannelKind::unit`]).
    pub values: Vec<f64>,
}

impl Trace {
    /// Number of grid points.
    pub fn len(&self) -> usize {
        self.values.len() / self.kinds.len().max(1)
    }

    /// Whether the trace is empty.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The value of column `col` at time `t` \[s\] (linear interpolation, angles along the
    /// shorter arc; held constant outside the grid).
    pub fn at(&self, col: usize, t: f64) -> f64 {
        self.at_position(col, grid_position(self.t0, self.dt, self.len(), t))
    }

    /// The value of column `col` at a grid position from [`grid_position`] for this trace's
    /// grid (as [`Trace::at`], with the position computed once for many replays).
    #[inline]
    pub fn at_position(&self, col: usize, (k, f): (usize, f64)) -> f64 {
        let n = self.len();
        let stride = self.kinds.len();
        let a = self.values[k * stride + col];
        if k + 1 >= n {
            return a;
        }
        let b = self.values[(k + 1) * stride + col];
        if self.kinds[col].is_angle() {
            wrap_pi(a + wrap_pi(b - a) * f)
        } else {
            a + (b - a) * f
        }
    }
}

/// Where time `t` \[s\] falls on a grid of `n` (≥ 1) points `t0 + i·dt`: the index of the
/// point at or before it (clamped to the grid) and the fraction of the step beyond it.
#[inline]
pub fn grid_position(t0: f64, dt: f64, n: usize, t: f64) -> (usize, f64) {
    let x = ((t - t0) / dt).max(0.0);
    let k = (x.floor() as usize).min(n - 1);
    (k, x - k as f64)
}

/// The physics steps a replay of `run` takes at `dt` \[s\] (its trace has one point more),
/// bounded by [`MAX_REPLAY_STEPS`] whatever the run (callers check with
/// [`ReplayOptions::steps`] first).
pub fn replay_steps(run: &MeasuredRun, dt: f64) -> usize {
    let t0 = run.t[0];
    let t_end = *run.t.last().unwrap_or(&t0);
    ((t_end - t0) / dt)
        .ceil()
        .clamp(0.0, MAX_REPLAY_STEPS as f64) as usize
}

/// Replays `run` on `model` in water `env` from `init` and records the `kinds`.
pub fn simulate(
    model: &VehicleModel,
    env: &Environment,
    run: &MeasuredRun,
    map: &InputMap,
    init: &InitialState,
    kinds: &[ChannelKind],
    opts: &ReplayOptions,
) -> Trace {
    simulate_with(
        model,
        env,
        run,
        map,
        init,
        kinds,
        opts,
        &MassTable::default(),
        usize::MAX,
    )
}

/// [`simulate`] for at most `max_steps` physics steps (the trace then ends early, and is the
/// same as far as it goes), taking the mass properties of each ballast volume from `masses`
/// (and keeping there those it computes): the same numbers, without a matrix factorisation
/// per pumping step when the table already holds the volume.
pub fn simulate_with(
    model: &VehicleModel,
    env: &Environment,
    run: &MeasuredRun,
    map: &InputMap,
    init: &InitialState,
    kinds: &[ChannelKind],
    opts: &ReplayOptions,
    masses: &MassTable,
    max_steps: usize,
) -> Trace {
    let dt = opts.dt;
    let mut v = Replaying::new(model, env, run, map, init, kinds, dt, masses, max_steps);
    // The constants of the equation of motion, while the ballast does not change.
    let mut consts = v.consts();
    let mut row = 0usize;
    for s in 0..v.steps {
        row = row_at(run, row, s, dt);
        if let Some(c) = v.actuate(run, map, row, env, dt) {
            consts = c;
        }
        match opts.integrator {
            Integrator::Rk4 => integrate_vehicle_rk4(&mut v.state, &consts, dt),
            other => integrate_vehicle(model, &mut v.state, env, other, dt),
        }
        v.record(kinds);
    }
    v.trace(run, dt, kinds)
}

/// [`simulate_with`] for each of `models` (with at most `max_steps[i]` physics steps for
/// `models[i]`), the same traces bit for bit, made [`LANES`] models at a time: per physics
/// step each model's actuation as in [`simulate_with`], then one RK4 step of the lane kernel
/// for all of them (one lane each, with its own constants of motion), then each model's
/// recording. Every lane does the same floating-point operations as a hull integrated alone,
/// so this is a faster way to the same numbers. (Other integrators: one model after another.)
pub fn simulate_many(
    models: &[&VehicleModel],
    max_steps: &[usize],
    env: &Environment,
    run: &MeasuredRun,
    map: &InputMap,
    init: &InitialState,
    kinds: &[ChannelKind],
    opts: &ReplayOptions,
    masses: &MassTable,
) -> Vec<Trace> {
    assert_eq!(models.len(), max_steps.len(), "one step bound per model");
    let mut out = Vec::with_capacity(models.len());
    for (group, bounds) in models.chunks(LANES).zip(max_steps.chunks(LANES)) {
        if group.len() == 1 || opts.integrator != Integrator::Rk4 {
            out.extend(
                group
                    .iter()
                    .zip(bounds)
                    .map(|(m, &n)| simulate_with(m, env, run, map, init, kinds, opts, masses, n)),
            );
            continue;
        }
        let dt = opts.dt;
        let mut lanes: Vec<Replaying> = group
            .iter()
            .zip(bounds)
            .map(|(m, &n)| Replaying::new(m, env, run, map, init, kinds, dt, masses, n))
            .collect();
        let mut consts = LaneConsts::<LANES>::splat(&lanes[0].consts());
        let mut x = Lanes::<LANES>::default();
        for (l, v) in lanes.iter().enumerate() {
            consts.set(l, &v.consts());
            x.load(l, &v.state.rigid, &v.state.tau);
        }
        // Lanes without a model integrate a copy of the first one's start, unread.
        for l in lanes.len()..LANES {
            x.load(l, &lanes[0].state.rigid, &lanes[0].state.tau);
        }
        let steps = lanes.iter().map(|v| v.steps).max().unwrap_or(0);
        let mut row = 0usize;
        for s in 0..steps {
            row = row_at(run, row, s, dt);
            // A model whose replay has ended leaves its lane unread.
            for (l, v) in lanes.iter_mut().enumerate().filter(|(_, v)| s < v.steps) {
                if let Some(c) = v.actuate(run, map, row, env, dt) {
                    consts.set(l, &c);
                }
                x.load(l, &v.state.rigid, &v.state.tau);
            }
            rk4_group(&consts, &mut x, dt);
            for (l, v) in lanes.iter_mut().enumerate().filter(|(_, v)| s < v.steps) {
                let nu0 = v.state.rigid.nu;
                x.store(l, &mut v.state.rigid);
                v.state.finish_step(&nu0, dt);
                v.record(kinds);
            }
        }
        out.extend(lanes.into_iter().map(|v| v.trace(run, dt, kinds)));
    }
    out
}

/// The input row in effect at physics step `s` of `dt` \[s\], from `row` (the row of an
/// earlier step) on.
fn row_at(run: &MeasuredRun, mut row: usize, s: usize, dt: f64) -> usize {
    let t = run.t[0] + s as f64 * dt;
    while row + 1 < run.t.len() && run.t[row + 1] <= t + 1e-9 {
        row += 1;
    }
    row
}

/// One model being replayed: its state, commands and recording.
struct Replaying<'a> {
    model: &'a VehicleModel,
    /// The water as the model's dynamics see it.
    env: Environment,
    state: VehicleState,
    cmd: ActuatorCommands,
    /// Mass properties by ballast volume.
    body: BodyMasses,
    /// The physics steps it takes.
    steps: usize,
    /// The recording so far, as [`Trace::values`].
    values: Vec<f64>,
}

impl<'a> Replaying<'a> {
    /// At the start of `run`, from `init`, with the first inputs set and recorded.
    fn new(
        model: &'a VehicleModel,
        env: &Environment,
        run: &MeasuredRun,
        map: &InputMap,
        init: &InitialState,
        kinds: &[ChannelKind],
        dt: f64,
        masses: &MassTable,
        max_steps: usize,
    ) -> Self {
        let p = &model.params;
        let steps = replay_steps(run, dt).min(max_steps);
        let env_vehicle = model.environment(env);
        let mut rigid = RigidState::at_rest(
            init.position,
            quat_from_rpy(init.rpy.x, init.rpy.y, init.rpy.z),
        );
        rigid.nu.fixed_rows_mut::<3>(3).copy_from(&init.rates);
        // A measured velocity is over ground; without one, the vehicle drifts with the water.
        if let Some(v) = init.velocity {
            let v_rel = v - rigid
                .attitude
                .inverse_transform_vector(&env_vehicle.current);
            rigid.nu.fixed_rows_mut::<3>(0).copy_from(&v_rel);
        }
        let mut v = Self {
            model,
            env: env_vehicle,
            state: VehicleState::new(model, rigid, env),
            cmd: ActuatorCommands::zeros(p.thrusters.len(), p.tilts.len()),
            body: masses.body(p, env.density),
            steps,
            values: Vec::with_capacity((steps + 1) * kinds.len()),
        };
        v.set_inputs(run, map, 0);
        v.record(kinds);
        v
    }

    /// The constants of its equation of motion in its present ballast.
    fn consts(&self) -> DynConsts {
        DynConsts::new(&self.model.params.body, &self.state.mass, &self.env)
    }

    /// The inputs of row `row`.
    fn set_inputs(&mut self, run: &MeasuredRun, map: &InputMap, row: usize) {
        for &(i, k) in &map.thrusters {
            self.cmd.thrusters[i] = run.inputs[k].values[row];
        }
        for &(i, k) in &map.tilts {
            let a = run.inputs[k].values[row];
            self.cmd.tilts[i] = a;
            self.state.actuators.tilt[i] = a;
        }
        if let Some(k) = map.pump {
            self.cmd.pump = Pump::from_sign(run.inputs[k].values[row]);
        }
    }

    /// Sets the inputs of row `row` and actuates for a step of `dt` \[s\] in the world's
    /// water `env` (`actuate_vehicle`, with the mass properties of a new volume from the
    /// table); the new constants of motion when the ballast changed.
    fn actuate(
        &mut self,
        run: &MeasuredRun,
        map: &InputMap,
        row: usize,
        env: &Environment,
        dt: f64,
    ) -> Option<DynConsts> {
        self.set_inputs(run, map, row);
        let consts = run_pump(self.model, &mut self.state, self.cmd.pump, dt).map(|v| {
            self.state.mass = self.body.at(v);
            self.consts()
        });
        actuate_thrusters(self.model, &mut self.state, &self.cmd, env, dt);
        consts
    }

    /// Records the present state.
    fn record(&mut self, kinds: &[ChannelKind]) {
        record(self.model, &self.state, &self.env, kinds, &mut self.values);
    }

    /// The recording as a trace of `run` at `dt` \[s\].
    fn trace(self, run: &MeasuredRun, dt: f64, kinds: &[ChannelKind]) -> Trace {
        Trace {
            t0: run.t[0],
            dt,
            kinds: kinds.to_vec(),
            values: self.values,
        }
    }
}

fn record(
    model: &VehicleModel,
    state: &VehicleState,
    env: &Environment,
    kinds: &[ChannelKind],
    out: &mut Vec<f64>,
) {
    let p = &model.params;
    let rigid = &state.rigid;
    let (v, w) = split6(&rigid.nu);
    // Roll and pitch only when recorded (yaw alone needs less).
    let tilted = kinds
        .iter()
        .any(|k| matches!(k, ChannelKind::Roll | ChannelKind::Pitch));
    let rpy = || {
        if tilted {
            rigid.attitude.euler_angles()
        } else {
            (0.0, 0.0, yaw_of(&rigid.attitude))
        }
    };
    for k in kinds {
        let x = match k {
            ChannelKind::Depth => {
                state.depth_of(&p.pressure.position).max(0.0)
                    + model.effects.depth_offset(state.time)
            }
            ChannelKind::Roll => rpy().0,
            ChannelKind::Pitch => rpy().1,
            ChannelKind::Yaw => rpy().2,
            ChannelKind::P => w.x + p.imu.gyro_bias.x,
            ChannelKind::Q => w.y + p.imu.gyro_bias.y,
            ChannelKind::R => w.z + p.imu.gyro_bias.z,
            ChannelKind::X => rigid.position.x,
            ChannelKind::Y => rigid.position.y,
            ChannelKind::U | ChannelKind::V | ChannelKind::W => {
                let vg = v + rigid.attitude.inverse_transform_vector(&env.current);
                match k {
                    ChannelKind::U => vg.x,
                    ChannelKind::V => vg.y,
                    _ => vg.z,
                }
            }
        };
        out.push(x);
    }
}

/// The yaw of `q`'s Euler angles, bit for bit as `q.euler_angles().2` (nalgebra's rotation
/// matrix formula) without computing the roll.
fn yaw_of(q: &Quat) -> f64 {
    let m = q.to_rotation_matrix();
    if m[(2, 0)].abs() < 1.0 {
        let c = (-m[(2, 0)].asin()).cos();
        (m[(1, 0)] / c).atan2(m[(0, 0)] / c)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn input_errors_name_the_file_line_after_comments() {
        let text = "# a comment\n# another\nt,u.port,y.depth\n0,10,1\n0.1,,1\n0.2,120,1\n";
        let mut run = MeasuredRun::parse(text, Path::new("r.csv")).unwrap();
        assert_eq!(run.header_line, 3);
        assert_eq!(run.lines, vec![4, 5, 6]);
        let params = shoal_model::presets::uauv2();
        // A command beyond ±100 % is reported on the row where it is set.
        let e = InputMap::new(&params, &mut run).unwrap_err();
        assert_eq!((e.line, e.column.clone()), (6, Some((2, "u.port".into()))));
        assert!(e.message.contains("−100 … 100 %"), "{}", e.message);
        // An unknown actuator is reported on the header line.
        let text = text.replace("u.port", "u.rudder");
        let mut run = MeasuredRun::parse(&text, Path::new("r.csv")).unwrap();
        let e = InputMap::new(&params, &mut run).unwrap_err();
        assert_eq!(
            (e.line, e.column.clone()),
            (3, Some((2, "u.rudder".into())))
        );
        assert!(e.message.contains("u.port"), "{}", e.message);
    }

    #[test]
    fn a_diving_log_at_the_tilt_limit_is_clamped_and_counted() {
        let mut text = String::from("t,u.top,u.port,u.stbd,u.alpha,u.beta,u.pump,y.depth\n");
        for i in 0..50 {
            let t = f64::from(i) * 0.02;
            text.push_str(&format!("{t},0,40,40,0,-1.5708,0,0.8\n"));
        }
        let mut run = MeasuredRun::parse(&text, Path::new("dive.csv")).unwrap();
        let params = shoal_model::presets::uauv2();
        let map = InputMap::new(&params, &mut run).unwrap();
        assert_eq!(map.clamped.len(), 1, "{:?}", map.clamped);
        let note = &map.clamped[0];
        assert_eq!(
            (note.name.as_str(), note.column, note.count),
            ("u.beta", 6, 50)
        );
        assert_eq!(note.limit, -std::f64::consts::FRAC_PI_2);
        assert!(note.to_string().contains("50 value(s)"), "{note}");
        let beta = run.input("beta").unwrap();
        assert!(
            beta.values
                .iter()
                .all(|&v| v == -std::f64::consts::FRAC_PI_2)
        );
        // The pump takes −1, 0, +1 only, and a failed check leaves the run as it was.
        for bad in ["0.5", "1e9"] {
            let text = text.replacen(
                ",-1.5708,0,0.8\n0.02,",
                &format!(",-1.5708,{bad},0.8\n0.02,"),
                1,
            );
            let mut run = MeasuredRun::parse(&text, Path::new("dive.csv")).unwrap();
            let before = run.clone();
            let e = InputMap::new(&params, &mut run).unwrap_err();
            assert_eq!(
                (e.line, e.column.clone()),
                (2, Some((7, "u.pump".into()))),
                "{e}"
            );
            assert!(
                e.message
                    .contains("allowed: −1 (empty), 0 (off), +1 (fill)"),
                "{e}"
            );
            assert_eq!(run, before);
        }
    }

    #[test]
    fn yaw_alone_is_the_euler_yaw() {
        let mut n = 0;
        for i in 0..2000 {
            let f = i as f64;
            let (r, p, y) = (
                (f * 0.37).sin() * 3.2,
                (f * 0.11).cos() * 1.58,
                f * 0.013 - 13.0,
            );
            let q = quat_from_rpy(r, p, y);
            assert_eq!(yaw_of(&q).to_bits(), q.euler_angles().2.to_bits(), "{q:?}");
            n += 1;
        }
        // At the poles (pitch ±90°) too.
        for p in [std::f64::consts::FRAC_PI_2, -std::f64::consts::FRAC_PI_2] {
            let q = quat_from_rpy(0.3, p, 1.1);
            assert_eq!(yaw_of(&q).to_bits(), q.euler_angles().2.to_bits());
        }
        assert_eq!(n, 2000);
    }

    #[test]
    fn replay_steps_are_bounded() {
        let mut run =
            MeasuredRun::parse("t,u.port,y.depth\n0,1,1\n1000,1,1\n", Path::new("long.csv"))
                .unwrap();
        let opts = ReplayOptions::default();
        assert_eq!(opts.steps(&run).unwrap(), 100_000);
        for dt in [0.0, -1.0, f64::NAN, 1e-9, 0.5] {
            let e = ReplayOptions { dt, ..opts }.steps(&run).unwrap_err();
            assert!(e.message.contains("allowed: 0.0001 … 0.1 s"), "{dt}: {e}");
        }
        run.t[1] = 1e9;
        let e = opts.steps(&run).unwrap_err();
        assert!(e.message.starts_with("run `long`"), "{e}");
        assert!(e.message.contains("at most 1e7"), "{e}");
        // Even unchecked, a replay never runs past the bound.
        let model = VehicleModel::new(shoal_model::presets::uauv2(), 1000.0);
        let map = InputMap::new(&model.params, &mut run).unwrap();
        let init = InitialState::from_run(&model.params, &run, 0.5);
        let trace = simulate(
            &model,
            &Environment::default(),
            &run,
            &map,
            &init,
            &[ChannelKind::Depth],
            &ReplayOptions {
                dt: f64::NAN,
                ..opts
            },
        );
        assert_eq!(trace.len(), 1);
    }
}
