//! Synthetic measured runs: a vehicle model (with any hidden effects) driven by an input
//! schedule through the full sensor models — noise, ADC quantisation, IMU errors, sensor
//! delay — sampled like a logger would. This is how the search is tested ("hide an effect in
//! data and find it") and how experiments are designed before going to the pool.
//!
//! Independent of [`shoal_sysid::evaluate::open_loop`]: it steps the model with the run-time path of
//! `shoal run` (`actuate_vehicle`, `integrate_vehicle`, `sense` with its delay line) on its own
//! time step, and adds measurement noise from a seeded RNG.
//!
//! [`synthesize_with`] adds a [`TruthHook`]: per-step access for simulated truths whose state
//! the effect hooks cannot carry (a motor's speed response, a pump's start-up, a sensor's
//! filter; see [`crate::truth_forms`]). [`synthesize`] is the same without a hook.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use shoal_model::ballast::Pump;
use shoal_model::control::{ActuatorCommands, SensorReadings};
use shoal_model::dynamics::{Integrator, RigidState};
use shoal_model::math::{Vec3, quat_from_rpy};
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::{VehicleModel, VehicleState, actuate_vehicle, integrate_vehicle, sense};
use shoal_sysid::log::run::{Channel, ChannelKind, InputColumn, MeasuredRun};
use std::collections::VecDeque;
use std::path::PathBuf;

/// An experiment to simulate.
#[derive(Clone, Debug, PartialEq)]
pub struct Experiment {
    /// Name (becomes the run's name and file stem).
    pub name: String,
    /// Length \[s\].
    pub duration: f64,
    /// Logger sample period \[s\].
    pub sample_period: f64,
    /// Input changes (time \[s\], actuator name, value), in time order. Values hold until the
    /// next change of the same actuator (thrusters in %, tilts in rad, pump −1/0/+1).
    pub inputs: Vec<(f64, String, f64)>,
    /// What is logged.
    pub channels: Vec<ChannelKind>,
    /// Initial position of the body origin, world frame \[m\].
    pub position: Vec3,
    /// Initial heading \[rad\].
    pub yaw: f64,
    /// Standard deviation of tracked positions `y.x`, `y.y` \[m\].
    pub tracking_noise: f64,
}

impl Experiment {
    /// Names of the actuators the experiment drives, in first-use order.
    pub fn actuators(&self) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        for (_, n, _) in &self.inputs {
            if !out.contains(n) {
                out.push(n.clone());
            }
        }
        out
    }

    /// The value of actuator `name` in force at time `t` \[s\] (0 before its first change).
    pub fn input_at(&self, name: &str, t: f64) -> f64 {
        self.inputs
            .iter()
            .rfind(|(ti, n, _)| n == name && *ti <= t + 1e-9)
            .map_or(0.0, |(_, _, v)| *v)
    }
}

/// Per-step access to a simulated truth, for behaviour with state of its own. Every method
/// defaults to doing nothing; `()` is the hook that changes nothing.
pub trait TruthHook {
    /// Before the actuators act over a physics step of `dt` \[s\]: may change what the actuators
    /// receive (`cmd`; the log keeps the experiment's commands), the water (`env`, for this
    /// step and the samples that follow it) and the vehicle's state (e.g. its tank volume).
    fn before_actuate(
        &mut self,
        _model: &VehicleModel,
        _state: &mut VehicleState,
        _cmd: &mut ActuatorCommands,
        _env: &mut Environment,
        _dt: f64,
    ) {
    }
    /// After the actuators, before the rigid body is integrated over `dt` \[s\]: may change the
    /// force `state.tau` and the mass properties `state.mass`.
    fn before_integrate(
        &mut self,
        _model: &VehicleModel,
        _state: &mut VehicleState,
        _env: &Environment,
        _dt: f64,
    ) {
    }
    /// At a logger sample: the hull state the sensors see, if not the true one (a sensor that
    /// filters or holds its input).
    fn sensed(&mut self, _state: &VehicleState) -> Option<RigidState> {
        None
    }
}

impl TruthHook for () {}

/// Simulates `exp` on `model` in water `env` with physics step `dt` \[s\] and measurement
/// noise from `seed`.
pub fn synthesize(
    model: &VehicleModel,
    env: &Environment,
    exp: &Experiment,
    dt: f64,
    seed: u64,
) -> MeasuredRun {
    synthesize_with(model, env, exp, dt, seed, &mut ())
}

/// [`synthesize`] with a [`TruthHook`] called around every physics step and at every sample.
pub fn synthesize_with(
    model: &VehicleModel,
    env: &Environment,
    exp: &Experiment,
    dt: f64,
    seed: u64,
    hook: &mut dyn TruthHook,
) -> MeasuredRun {
    let p = &model.params;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let rigid = RigidState::at_rest(exp.position, quat_from_rpy(0.0, 0.0, exp.yaw));
    let mut state = VehicleState::new(model, rigid, env);
    let actuators = exp.actuators();
    let mut cmd = ActuatorCommands::zeros(p.thrusters.len(), p.tilts.len());
    let mut readings = SensorReadings::zeros(p.tilts.len());
    let n_samples = (exp.duration / exp.sample_period).round() as usize + 1;
    let sub = (exp.sample_period / dt).round().max(1.0) as usize;
    let h = exp.sample_period / sub as f64;
    let mut log = Recorder::new(
        model,
        &actuators,
        &exp.channels,
        n_samples,
        exp.tracking_noise,
    );
    let apply = |t: f64, cmd: &mut ActuatorCommands, state: &mut VehicleState| {
        for name in &actuators {
            set_actuator(model, cmd, state, name, exp.input_at(name, t));
        }
    };
    let mut stepper = Stepper::new(&cmd, env);
    let mut values = vec![0.0; actuators.len()];
    for k in 0..n_samples {
        let t = k as f64 * exp.sample_period;
        apply(t, &mut cmd, &mut state);
        for (v, name) in values.iter_mut().zip(&actuators) {
            *v = exp.input_at(name, t);
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
        log.push_inputs(&values);
        if k + 1 == n_samples {
            break;
        }
        for s in 0..sub {
            apply(t + s as f64 * h, &mut cmd, &mut state);
            stepper.step(model, env, &mut state, &cmd, hook, h);
        }
    }
    log.finish(&exp.name)
}

/// Sets actuator `name` of `model` to `v` in `cmd` (thrusters in %, tilts in rad — a tilt is
/// where the log says it is, so the state's angle is set too —, the pump by its sign).
pub(crate) fn set_actuator(
    model: &VehicleModel,
    cmd: &mut ActuatorCommands,
    state: &mut VehicleState,
    name: &str,
    v: f64,
) {
    let p = &model.params;
    if let Some(i) = p.thrusters.iter().position(|th| th.name == name) {
        cmd.thrusters[i] = v;
    } else if let Some(i) = p.tilts.iter().position(|tl| tl.name == name) {
        cmd.tilts[i] = v;
        state.actuators.tilt[i] = v;
    } else if name == "pump" {
        cmd.pump = Pump::from_sign(v);
    }
}

/// One physics step of the simulated truth, with the hook around it: the water the hook saw
/// last is kept for the next sample.
pub(crate) struct Stepper {
    /// The water of the last step, as the hook left it (the next sample is read in it).
    pub(crate) water: Environment,
    hooked: ActuatorCommands,
}

impl Stepper {
    /// A stepper for commands shaped like `cmd`, in water `env` until the first step.
    pub(crate) fn new(cmd: &ActuatorCommands, env: &Environment) -> Self {
        Self {
            water: *env,
            hooked: cmd.clone(),
        }
    }

    /// Actuates and integrates `state` over `h` \[s\] in water `env` with commands `cmd`.
    pub(crate) fn step(
        &mut self,
        model: &VehicleModel,
        env: &Environment,
        state: &mut VehicleState,
        cmd: &ActuatorCommands,
        hook: &mut dyn TruthHook,
        h: f64,
    ) {
        self.hooked.clone_from(cmd);
        self.water = *env;
        hook.before_actuate(model, state, &mut self.hooked, &mut self.water, h);
        actuate_vehicle(model, state, &self.hooked, &self.water, h);
        hook.before_integrate(model, state, &self.water, h);
        integrate_vehicle(model, state, &self.water, Integrator::Rk4, h);
    }
}

/// The logger: one row per sample with the inputs in force and every logged channel, as the
/// vehicle's sensors read them (tracked positions with the sensor delay and their own noise).
pub(crate) struct Recorder {
    t: Vec<f64>,
    inputs: Vec<InputColumn>,
    channels: Vec<Channel>,
    track: Option<Normal<f64>>,
    delay: f64,
    positions: VecDeque<(f64, Vec3)>,
}

impl Recorder {
    /// A logger of inputs `actuators` and channels `kinds` for `n` samples, tracked positions
    /// with noise `tracking_noise` \[m\] (standard deviation).
    pub(crate) fn new(
        model: &VehicleModel,
        actuators: &[String],
        kinds: &[ChannelKind],
        n: usize,
        tracking_noise: f64,
    ) -> Self {
        let inputs = actuators
            .iter()
            .enumerate()
            .map(|(i, name)| InputColumn {
                values: Vec::with_capacity(n),
                ..InputColumn::held(name, 2 + i)
            })
            .collect();
        let channels = kinds
            .iter()
            .enumerate()
            .map(|(i, &kind)| Channel {
                kind,
                column: 2 + actuators.len() + i,
                rows: Vec::with_capacity(n),
                values: Vec::with_capacity(n),
            })
            .collect();
        Self {
            t: Vec::with_capacity(n),
            inputs,
            channels,
            track: Normal::new(0.0, tracking_noise.max(0.0)).ok(),
            delay: model.effects.delay(),
            positions: VecDeque::new(),
        }
    }

    /// Samples the sensors into `readings` (through the hook's view of the hull, if it has
    /// one) and logs the channels at time `t` \[s\]. The inputs of the row follow with
    /// [`Self::push_inputs`].
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn observe(
        &mut self,
        t: f64,
        model: &VehicleModel,
        state: &mut VehicleState,
        water: &Environment,
        hook: &mut dyn TruthHook,
        rng: &mut ChaCha8Rng,
        readings: &mut SensorReadings,
    ) {
        let seen = hook.sensed(state);
        let truth = seen.map(|r| std::mem::replace(&mut state.rigid, r));
        sense(model, state, water, rng, readings);
        // Tracked positions share the sensor delay.
        let delay = self.delay;
        self.positions.push_back((state.time, state.rigid.position));
        while self.positions.len() > 1 && self.positions[1].0 <= state.time - delay + 1e-9 {
            self.positions.pop_front();
        }
        let pos = match self.positions.front() {
            Some((t, p)) if *t <= state.time - delay + 1e-9 => *p,
            _ => state.rigid.position,
        };
        self.t.push(t);
        let k = self.t.len() - 1;
        let (roll, pitch, yaw) = readings.attitude.euler_angles();
        let track = self.track;
        for c in &mut self.channels {
            let noise = |rng: &mut ChaCha8Rng| track.map_or(0.0, |d| d.sample(rng));
            let v = match c.kind {
                ChannelKind::Depth => readings.depth,
                ChannelKind::Roll => roll,
                ChannelKind::Pitch => pitch,
                ChannelKind::Yaw => yaw,
                ChannelKind::P => readings.gyro.x,
                ChannelKind::Q => readings.gyro.y,
                ChannelKind::R => readings.gyro.z,
                ChannelKind::X => pos.x + noise(rng),
                ChannelKind::Y => pos.y + noise(rng),
                // Commands are logged as inputs (`push_inputs`).
                ChannelKind::Command(_) => continue,
                ChannelKind::U | ChannelKind::V | ChannelKind::W => {
                    let v = state.rigid.nu.fixed_rows::<3>(0).into_owned()
                        + state
                            .rigid
                            .attitude
                            .inverse_transform_vector(&model.environment(water).current);
                    match c.kind {
                        ChannelKind::U => v.x,
                        ChannelKind::V => v.y,
                        _ => v.z,
                    }
                }
            };
            c.rows.push(k);
            c.values.push(v);
        }
        if let Some(r) = truth {
            state.rigid = r;
        }
    }

    /// The row's input values, in the order of the logger's actuators.
    pub(crate) fn push_inputs(&mut self, values: &[f64]) {
        for (inp, v) in self.inputs.iter_mut().zip(values) {
            inp.values.push(*v);
        }
    }

    /// The log as a run named `name`.
    pub(crate) fn finish(self, name: &str) -> MeasuredRun {
        MeasuredRun {
            path: PathBuf::from(format!("{name}.csv")),
            name: name.to_string(),
            t: self.t,
            inputs: self.inputs,
            channels: self.channels,
            references: Vec::new(),
            extra: Vec::new(),
            header_line: 0,
            lines: Vec::new(),
            ingest: Default::default(),
        }
    }
}
