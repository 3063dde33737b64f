//! The open-loop simulation of a replay: one model ([`simulate_with`]) or up to
//! [`LANES`] models of one run together ([`simulate_many`], one lane of the RK4 kernel
//! each), stepped with the run's inputs and recorded through the sensor models (see the
//! parent module).

use super::anchors::Anchor;
use super::control::{Controlling, depth_reading};
use super::setup::{InitialState, InputMap, ReplayOptions, replay_steps};
use super::trace::Trace;
use crate::evaluate::masses::{BodyMasses, MassTable};
use crate::log::run::{ChannelKind, MeasuredRun};
use shoal_model::ballast::Pump;
use shoal_model::control::ActuatorCommands;
use shoal_model::dynamics::{Integrator, RigidState};
use shoal_model::lanes::{DynConsts, LANES, LaneConsts, Lanes, rk4_group};
use shoal_model::math::{Quat, quat_from_rpy, split6};
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::{
    VehicleModel, VehicleState, actuate_thrusters, integrate_vehicle, integrate_vehicle_rk4,
    run_pump,
};

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
    // The filter for the horizontal velocities at each anchor: the same model, anchored densely.
    let mut f = (!init.filter.is_empty())
        .then(|| Replaying::new(model, env, run, map, init, &[], dt, masses, max_steps))
        .map(|f| f.into_filter(init));
    // The controller's twin, whose commands the recording shows.
    let mut w = init
        .control
        .is_some()
        .then(|| Replaying::new(model, env, run, map, init, &[], dt, masses, max_steps))
        .map(|w| w.into_twin(init));
    // The constants of the equation of motion, while the ballast does not change.
    let mut consts = v.consts();
    let mut f_consts = f.as_ref().map(Replaying::consts);
    let mut w_consts = w.as_ref().map(Replaying::consts);
    let mut row = 0usize;
    for s in 0..v.steps {
        row = row_at(run, row, s, dt);
        if let Some(f) = &mut f {
            f.anchor_at(s);
        }
        // (The twin is never re-anchored.)
        if v.anchor_at(s)
            && let Some(f) = &f
        {
            v.take_horizontal(f);
        }
        if let (Some(w), Some(wc)) = (&mut w, &mut w_consts) {
            if let Some(c) = w.actuate(run, map, row, env, dt) {
                *wc = c;
            }
            v.patch_commands(&w.cmd.thrusters);
            step(w, wc, env, opts);
        }
        if let Some(c) = v.actuate(run, map, row, env, dt) {
            consts = c;
        }
        step(&mut v, &consts, env, opts);
        if let (Some(f), Some(fc)) = (&mut f, &mut f_consts) {
            if let Some(c) = f.actuate(run, map, row, env, dt) {
                *fc = c;
            }
            step(f, fc, env, opts);
        }
        if let Some(w) = &mut w {
            w.record(&[]);
        }
        v.record(kinds);
        if let Some(w) = &w {
            v.patch_commands(&w.cmd.thrusters);
        }
    }
    v.trace(run, dt, kinds)
}

/// Integrates `v` over one physics step with its constants of motion `consts`.
fn step(v: &mut Replaying, consts: &DynConsts, env: &Environment, opts: &ReplayOptions) {
    match opts.integrator {
        Integrator::Rk4 => integrate_vehicle_rk4(&mut v.state, consts, opts.dt),
        other => integrate_vehicle(v.model, &mut v.state, env, other, opts.dt),
    }
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
    // Each model takes a lane for its replay, then one for its filter (with a filter), then
    // one for its controller's twin (in a closed-loop replay).
    let filtered = !init.filter.is_empty();
    let twinned = init.control.is_some();
    let k = 1 + usize::from(filtered) + usize::from(twinned);
    let per = LANES / k;
    for (group, bounds) in models.chunks(per).zip(max_steps.chunks(per)) {
        // A model alone goes one hull after another — except with a twin, where its three
        // hulls share one step of the lane kernel (the same numbers either way).
        if (group.len() == 1 && k < 3) || opts.integrator != Integrator::Rk4 {
            out.extend(
                group
                    .iter()
                    .zip(bounds)
                    .map(|(m, &n)| simulate_with(m, env, run, map, init, kinds, opts, masses, n)),
            );
            continue;
        }
        let dt = opts.dt;
        let mut lanes: Vec<Replaying> = Vec::with_capacity(LANES);
        for (m, &n) in group.iter().zip(bounds) {
            lanes.push(Replaying::new(m, env, run, map, init, kinds, dt, masses, n));
            let alone = || Replaying::new(m, env, run, map, init, &[], dt, masses, n);
            if filtered {
                lanes.push(alone().into_filter(init));
            }
            if twinned {
                lanes.push(alone().into_twin(init));
            }
        }
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
            // Filters first: a replay anchored now takes its filter's velocities of now.
            for v in lanes.iter_mut().filter(|v| s < v.steps && v.is_filter) {
                v.anchor_at(s);
            }
            for l in 0..lanes.len() {
                if !lanes[l].is_filter && s < lanes[l].steps && lanes[l].anchor_at(s) && filtered {
                    // The model's filter is the lane after its replay.
                    let f = l - l % k + 1;
                    let uv = lanes[f].horizontal();
                    lanes[l].set_horizontal(uv);
                }
            }
            // A model whose replay has ended leaves its lanes unread.
            for (l, v) in lanes.iter_mut().enumerate().filter(|(_, v)| s < v.steps) {
                if let Some(c) = v.actuate(run, map, row, env, dt) {
                    consts.set(l, &c);
                }
                x.load(l, &v.state.rigid, &v.state.tau);
            }
            if twinned {
                patch_from_twins(&mut lanes, k, s);
            }
            rk4_group(&consts, &mut x, dt);
            for (l, v) in lanes.iter_mut().enumerate().filter(|(_, v)| s < v.steps) {
                let nu0 = v.state.rigid.nu;
                x.store(l, &mut v.state.rigid);
                v.state.finish_step(&nu0, dt);
                v.record(if l % k == 0 { kinds } else { &[] });
            }
            if twinned {
                patch_from_twins(&mut lanes, k, s);
            }
        }
        out.extend(
            lanes
                .into_iter()
                .enumerate()
                .filter(|(l, _)| l % k == 0)
                .map(|(_, v)| v.trace(run, dt, kinds)),
        );
    }
    out
}

/// Writes each twin's commands into its replay's last recorded point (lanes of `k` per model,
/// the twin last), for the models still replaying at step `s`.
fn patch_from_twins(lanes: &mut [Replaying], k: usize, s: usize) {
    for model in lanes.chunks_mut(k) {
        let (main, rest) = model.split_first_mut().expect("a replay per model");
        let twin = rest.last().expect("a twin per model");
        if s < main.steps {
            main.patch_commands(&twin.cmd.thrusters);
        }
    }
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
    /// The recording so far, as [`Trace::values`] (empty for a filter).
    values: Vec<f64>,
    /// Where it is re-anchored (the run's anchors, or a filter's dense ones).
    anchors: &'a [Anchor],
    /// The next of `anchors` not yet applied.
    next: usize,
    /// Whether it is the filter of another replay (it records nothing).
    is_filter: bool,
    /// The controller, in a closed-loop replay.
    control: Option<Controlling<'a>>,
    /// (column in the recording, thruster index) of each recorded command channel.
    cmd_cols: Vec<(usize, usize)>,
    /// Recorded columns per point.
    stride: usize,
}

impl<'a> Replaying<'a> {
    /// At the start of `run`, from `init`, with the first inputs set and recorded.
    fn new(
        model: &'a VehicleModel,
        env: &Environment,
        run: &MeasuredRun,
        map: &InputMap,
        init: &'a InitialState,
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
            anchors: &init.anchors,
            next: 0,
            is_filter: false,
            control: None,
            cmd_cols: kinds
                .iter()
                .enumerate()
                .filter_map(|(col, k)| match k {
                    ChannelKind::Command(name) => p
                        .thrusters
                        .iter()
                        .position(|t| t.name == *name)
                        .map(|i| (col, i)),
                    _ => None,
                })
                .collect(),
            stride: kinds.len(),
        };
        v.set_inputs(run, map, 0);
        v.record(kinds);
        v
    }

    /// This replay (made with no recorded kinds) as the filter of a replay of the same model
    /// from the same start: anchored at `init.filter`, recording nothing.
    fn into_filter(mut self, init: &'a InitialState) -> Self {
        self.anchors = &init.filter;
        self.is_filter = true;
        self
    }

    /// This replay (made with no recorded kinds) as the closed-loop twin of a replay of the
    /// same model from the same start: the controller of `init.control` in the loop, never
    /// re-anchored, recording nothing (its commands go into the replay's recording).
    fn into_twin(mut self, init: &'a InitialState) -> Self {
        self.anchors = &[];
        let (model, state) = (self.model, &self.state);
        self.control = init.control.as_deref().map(|c| {
            let mut c = Controlling::new(c, model);
            // What the sensors read at the start, for a delayed reading later.
            c.observe(model, state);
            c
        });
        self
    }

    /// Applies its anchor at physics step `s`, if it has one there (see [`Anchor::apply`]);
    /// whether it had.
    fn anchor_at(&mut self, s: usize) -> bool {
        match self.anchors.get(self.next) {
            Some(a) if a.step == s => {
                a.apply(self.model, self.state.time, &mut self.state.rigid);
                self.next += 1;
                true
            }
            _ => false,
        }
    }

    /// Takes the horizontal body velocities u, v of its filter `f`.
    fn take_horizontal(&mut self, f: &Replaying) {
        self.set_horizontal(f.horizontal());
    }

    /// Its horizontal body velocities u, v \[m/s\].
    fn horizontal(&self) -> [f64; 2] {
        [self.state.rigid.nu[0], self.state.rigid.nu[1]]
    }

    /// Sets its horizontal body velocities u, v \[m/s\].
    fn set_horizontal(&mut self, uv: [f64; 2]) {
        self.state.rigid.nu[0] = uv[0];
        self.state.rigid.nu[1] = uv[1];
    }

    /// The constants of its equation of motion in its present ballast.
    fn consts(&self) -> DynConsts {
        DynConsts::new(&self.model.params.body, &self.state.mass, &self.env)
    }

    /// The inputs of row `row` (in a closed-loop replay the controller's thruster commands
    /// stay).
    fn set_inputs(&mut self, run: &MeasuredRun, map: &InputMap, row: usize) {
        if self.control.is_none() {
            for &(i, k) in &map.thrusters {
                self.cmd.thrusters[i] = run.inputs[k].values[row];
            }
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
        // The controller reads the tilt drives where they stood before this row moves them.
        if let Some(c) = &mut self.control {
            let logged = map
                .thrusters
                .iter()
                .map(|&(i, k)| (i, run.inputs[k].values[row]));
            c.tick(self.model, &self.state, run, row, logged, &mut self.cmd);
        }
        self.set_inputs(run, map, row);
        let consts = run_pump(self.model, &mut self.state, self.cmd.pump, dt).map(|v| {
            self.state.mass = self.body.at(v);
            self.consts()
        });
        actuate_thrusters(self.model, &mut self.state, &self.cmd, env, dt);
        consts
    }

    /// Records the present state (and keeps it for the controller's delayed readings).
    fn record(&mut self, kinds: &[ChannelKind]) {
        record(self.model, &self.state, &self.env, kinds, &mut self.values);
        if let Some(c) = &mut self.control {
            c.observe(self.model, &self.state);
        }
    }

    /// Writes `thrusters`, the commands its twin's controller has in force \[%\], into the
    /// command columns of the last recorded point (the recording of now shows the command of
    /// now).
    fn patch_commands(&mut self, thrusters: &[f64]) {
        let Some(last) = self.values.len().checked_sub(self.stride) else {
            return;
        };
        for &(col, i) in &self.cmd_cols {
            self.values[last + col] = thrusters[i];
        }
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
    // Computed once per record, at the first angle channel.
    let mut angles: Option<(f64, f64, f64)> = None;
    let mut rpy = || {
        *angles.get_or_insert_with(|| {
            if tilted {
                rigid.attitude.euler_angles()
            } else {
                (0.0, 0.0, yaw_of(&rigid.attitude))
            }
        })
    };
    for k in kinds {
        let x = match k {
            ChannelKind::Depth => depth_reading(model, state),
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
            // Written by `Replaying::patch_commands`, which knows each column's thruster.
            ChannelKind::Command(_) => 0.0,
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
}
