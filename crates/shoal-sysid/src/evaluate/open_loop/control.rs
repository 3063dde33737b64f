//! The controller in the replay: the closed-loop twin of the replay of a log that carries the
//! references its controller followed (`r.mode`, `r.depth`, `r.yaw`, `r.surge`, `r.sway`).
//!
//! Under feedback a model error hides from the states: the controller pushes the hull back to
//! its setpoint, and only the commands it sent carry the effect (a battery that sags is
//! answered by larger commands, the depth stays where it was asked to be). Replaying the
//! logged commands open loop, the model drifts off; re-anchored, the error is compensated in
//! the data and invisible in the replay. Closed-loop identification (DIDIM, Forssell & Ljung)
//! replays the model *with its controller*: the vehicle's own controller — for the μAUV² the
//! paper's modes (`shoal_model::control`), designed on the vehicle as given, not on the model
//! being tested — reads the replay's sensors at its control period and follows the logged
//! references; its thruster commands drive the replayed hull and are compared with the logged
//! ones as channels of their own ([`ChannelKind::Command`]).
//!
//! That simulation runs as a *twin* beside the replay proper: the same model from the same
//! start, never re-anchored, recording only its commands, while the replay proper is driven
//! by the logged commands (re-anchored or open loop as chosen) and its states are compared as
//! before. One fit sees both views: from command to state, where a lag or a damping shows its
//! shape, and from reference to command, where what the controller compensates shows. (Alone,
//! the closed-loop view lost what the re-anchored one found: roll, pitch, surge and sway,
//! which the controller does not hold, ran off for the whole mission, and a thruster lag was
//! named a sensor delay; docs/validation.md.)
//!
//! What the controller reads is what the model's sensors would read — the deterministic part:
//! the pressure port's depth plus any depth-sensor effect, the attitude, the gyro rates plus
//! their bias, the tilt drives where the log says they stood, the tank's full switch — and it
//! reads it late by the model's sensor delay, as the real controller did. To the depth, the
//! heading and the yaw rate it adds the *fast part* of the replay's residual at the tick —
//! measured less read, less the residual's mean over the last [`NOISE_WINDOW_S`] —: the
//! sensor noise the real controller answered (its derivative terms amplify it into command
//! jitter of several per cent that no model predicts), while the slow part of the residual,
//! what the model gets wrong, stays in the comparison. With noise-free sensors and the true
//! model the residual is zero and so is what is added. In a loop a sensor
//! delay and a thruster lag both slow the response, but only the delay also delays what the
//! controller answers to; the commands tell them apart.
//!
//! Tilt drives and the pump stay as logged (measured positions and a discrete command; the
//! controller's thrust allocation reads the tilt angles), so do rows in `raw` mode (the
//! logged commands pass through) and `off` mode (zero).

use crate::log::run::{ChannelKind, MeasuredRun, ReferenceKind};
use shoal_model::control::{
    ActuatorCommands, ControlParams, ControllerState, Mode, SensorReadings, Setpoints, Uauv2Control,
};
use shoal_model::math::{PerActuator, Quat, Vec3, euler_rpy, split6, wrap_pi};
use shoal_model::thruster::ThrusterParams;
use shoal_model::vehicle::{VehicleModel, VehicleState};
use std::collections::VecDeque;

/// The references a closed-loop replay follows: column indices into
/// [`MeasuredRun::references`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReferenceColumns {
    /// `r.mode` (the mode's code).
    pub mode: usize,
    /// `r.depth` \[m\].
    pub depth: Option<usize>,
    /// `r.yaw` \[rad\].
    pub yaw: Option<usize>,
    /// `r.surge` \[N\].
    pub surge: Option<usize>,
    /// `r.sway` \[N\].
    pub sway: Option<usize>,
}

/// What a closed-loop replay of one run needs that no model changes: the controller as
/// designed for the vehicle as given, and where its references are.
#[derive(Clone, Debug, PartialEq)]
pub struct ReplayControl {
    /// The controller's parameters (period, gains' design, filters).
    pub params: ControlParams,
    /// The μAUV² modes' gains and limits.
    pub uauv2: Uauv2Control,
    /// The thrusters as designed (the controller turns forces into commands through them).
    pub thrusters: Vec<ThrusterParams>,
    /// The references.
    pub refs: ReferenceColumns,
    /// Per row of the run, the depth \[m\], heading \[rad\] and yaw rate [rad/s] the log
    /// measured last (NaN before a channel's first sample or where it is not logged): what
    /// the real controller read.
    pub measured: Vec<[f64; 3]>,
}

/// Span of the past over which the fast part of the replay's residual is taken: the residual
/// less its mean over the last this many seconds \[s\].
pub const NOISE_WINDOW_S: f64 = 0.5;

impl ReplayControl {
    /// The closed-loop replay of `run` with the controller of `baseline` (the vehicle as
    /// given), or why there is none: the run carries no `r.mode`, or the vehicle has no
    /// built-in controller for its modes (the μAUV² layout).
    pub fn new(baseline: &VehicleModel, run: &MeasuredRun) -> Result<ReplayControl, String> {
        let col = |k: ReferenceKind| run.references.iter().position(|r| r.name == k.name());
        if run.references.is_empty() {
            return Err("the log carries no references (r.<name> columns)".into());
        }
        let Some(mode) = col(ReferenceKind::Mode) else {
            return Err(
                "the log's references have no `r.mode`: the controller's mode is unknown".into(),
            );
        };
        let Some(uauv2) = baseline.uauv2.clone() else {
            return Err(format!(
                "vehicle `{}` has no built-in controller for the logged modes (the μAUV² \
                 thruster and tilt layout)",
                baseline.params.name
            ));
        };
        Ok(ReplayControl {
            params: baseline.params.control.clone(),
            uauv2,
            thrusters: baseline.params.thrusters.clone(),
            refs: ReferenceColumns {
                mode,
                depth: col(ReferenceKind::Depth),
                yaw: col(ReferenceKind::Yaw),
                surge: col(ReferenceKind::Surge),
                sway: col(ReferenceKind::Sway),
            },
            measured: measured_last(run),
        })
    }

    /// The command channels a closed-loop replay of `run` compares: each thruster of the
    /// vehicle with a logged command (`u.<thruster>`).
    pub fn command_channels(&self, run: &MeasuredRun) -> Vec<ChannelKind> {
        self.thrusters
            .iter()
            .filter(|t| run.input(&t.name).is_some())
            .map(|t| ChannelKind::command(&t.name))
            .collect()
    }
}

/// The readings the controller takes, as the model's sensors would give them (without noise
/// and quantisation): depth \[m\], attitude, gyro rates [rad/s], tilt angles \[rad\].
#[derive(Clone, Debug, PartialEq)]
struct Sensed {
    time: f64,
    depth: f64,
    attitude: Quat,
    gyro: Vec3,
    tilts: PerActuator,
}

impl Sensed {
    fn of(model: &VehicleModel, state: &VehicleState) -> Sensed {
        let p = &model.params;
        let (_, w) = split6(&state.rigid.nu);
        Sensed {
            time: state.time,
            depth: depth_reading(model, state),
            attitude: state.rigid.attitude,
            gyro: w + p.imu.gyro_bias,
            tilts: state.actuators.tilt.clone(),
        }
    }

    /// Between `a` and `b` at fraction `f` (linear; the attitude normalised).
    fn between(a: &Sensed, b: &Sensed, f: f64) -> Sensed {
        let q = a.attitude.as_ref().lerp(b.attitude.as_ref(), f);
        Sensed {
            time: a.time + (b.time - a.time) * f,
            depth: a.depth + (b.depth - a.depth) * f,
            attitude: Quat::new_normalize(q),
            gyro: a.gyro + (b.gyro - a.gyro) * f,
            tilts: a
                .tilts
                .iter()
                .zip(&b.tilts)
                .map(|(x, y)| x + (y - x) * f)
                .collect(),
        }
    }
}

/// The depth the pressure sensor of `model` reads in `state`, without noise \[m\]: the
/// port's depth (the surface clamps it) plus any depth-sensor effect.
pub fn depth_reading(model: &VehicleModel, state: &VehicleState) -> f64 {
    state.depth_of(&model.params.pressure.position).max(0.0)
        + model.effects.depth_offset(state.time)
}

/// The controller running inside one replay.
#[derive(Clone, Debug)]
pub(super) struct Controlling<'a> {
    ctl: &'a ReplayControl,
    state: ControllerState,
    readings: SensorReadings,
    sp: Setpoints,
    out: ActuatorCommands,
    /// Time of the next control tick, since the run's start \[s\].
    next_tick: f64,
    /// The model's sensor delay \[s\].
    delay: f64,
    /// Readings of the last `delay` seconds and one more, oldest first (empty without delay).
    history: VecDeque<Sensed>,
    /// The residuals (measured − the replay's reading) of depth, heading and yaw rate at the
    /// ticks of the last [`NOISE_WINDOW_S`], with their times, oldest first.
    recent: VecDeque<(f64, [f64; 3])>,
}

impl<'a> Controlling<'a> {
    pub(super) fn new(ctl: &'a ReplayControl, model: &VehicleModel) -> Self {
        let n_th = ctl.thrusters.len();
        let n_tl = model.params.tilts.len();
        Self {
            ctl,
            state: ControllerState::new(&ctl.params, n_th, n_tl),
            readings: SensorReadings::zeros(n_tl),
            sp: Setpoints {
                raw: ActuatorCommands::zeros(n_th, n_tl),
                ..Default::default()
            },
            out: ActuatorCommands::zeros(n_th, n_tl),
            next_tick: 0.0,
            delay: model.effects.delay().max(0.0),
            history: VecDeque::new(),
            recent: VecDeque::new(),
        }
    }

    /// Keeps what the sensors read in `state` for a delayed reading later.
    pub(super) fn observe(&mut self, model: &VehicleModel, state: &VehicleState) {
        if self.delay <= 0.0 {
            return;
        }
        self.history.push_back(Sensed::of(model, state));
        let keep_from = state.time - self.delay;
        while self.history.len() > 2 && self.history[1].time <= keep_from {
            self.history.pop_front();
        }
    }

    /// What the sensors read `delay` seconds before `state`: between the kept readings
    /// (linearly; the vehicle's own sensor model holds the newest reading that old instead,
    /// the same where readings are taken that often), or a fresh reading while none is that
    /// old yet (the vehicle taken to have been as it is now before it started, as the
    /// simulation's sensors take it).
    fn sensed(&self, model: &VehicleModel, state: &VehicleState) -> Sensed {
        let t = state.time - self.delay;
        let h = &self.history;
        match h.iter().position(|s| s.time > t + 1e-9) {
            _ if self.delay <= 0.0 => Sensed::of(model, state),
            Some(0) => Sensed::of(model, state),
            Some(i) => {
                let (a, b) = (&h[i - 1], &h[i]);
                Sensed::between(a, b, ((t - a.time) / (b.time - a.time)).clamp(0.0, 1.0))
            }
            None => h
                .back()
                .cloned()
                .unwrap_or_else(|| Sensed::of(model, state)),
        }
    }

    /// The fast part of the residual of depth, heading and yaw rate at time `t` \[s\] (row
    /// `row`) for the replay's reading `s`: the residual less its mean over the ticks of the
    /// last [`NOISE_WINDOW_S`] (0 for a channel not measured).
    fn fast_part(&mut self, s: &Sensed, t: f64, row: usize) -> [f64; 3] {
        let Some(y) = self.ctl.measured.get(row) else {
            return [0.0; 3];
        };
        let (_, _, yaw) = euler_rpy(&s.attitude);
        let now = [y[0] - s.depth, wrap_pi(y[1] - yaw), y[2] - s.gyro.z];
        self.recent.push_back((t, now));
        while self
            .recent
            .front()
            .is_some_and(|(t0, _)| *t0 < t - NOISE_WINDOW_S)
        {
            self.recent.pop_front();
        }
        let n = self.recent.len() as f64;
        let mut out = [0.0; 3];
        for (k, o) in out.iter_mut().enumerate() {
            let mean = self.recent.iter().map(|(_, r)| r[k]).sum::<f64>() / n;
            *o = now[k] - mean;
            if !o.is_finite() {
                *o = 0.0;
            }
        }
        out
    }

    /// Runs the controller if a control tick is due in `state` (ticks every control period
    /// from the run's start), following the references of row `row` of `run` and writing the
    /// thruster commands into `cmd` (nothing between ticks). `logged` are the row's thruster commands
    /// (index, value) for the `raw` mode.
    pub(super) fn tick(
        &mut self,
        model: &VehicleModel,
        state: &VehicleState,
        run: &MeasuredRun,
        row: usize,
        logged: impl Iterator<Item = (usize, f64)>,
        cmd: &mut ActuatorCommands,
    ) {
        if state.time + 1e-9 < self.next_tick {
            return;
        }
        let period = self.ctl.params.period;
        while self.next_tick <= state.time + 1e-9 {
            self.next_tick += period;
        }
        let s = self.sensed(model, state);
        let finite = s.depth.is_finite()
            && s.gyro.iter().all(|x| x.is_finite())
            && s.attitude.coords.iter().all(|x| x.is_finite());
        if !finite {
            // A model that has blown up: its replay is not a number, and neither are its
            // commands (the controller's saturation has no answer for it).
            cmd.thrusters.iter_mut().for_each(|c| *c = f64::NAN);
            return;
        }
        // The model's readings plus the noise the real controller read (see the module doc).
        let fast = self.fast_part(&s, state.time, row);
        self.readings.depth = s.depth + fast[0];
        self.readings.attitude = Quat::from_axis_angle(&Vec3::z_axis(), fast[1]) * s.attitude;
        self.readings.gyro = s.gyro + Vec3::new(0.0, 0.0, fast[2]);
        self.readings.tilts.clone_from(&s.tilts);
        self.readings.tank_full = model
            .params
            .ballast
            .as_ref()
            .is_some_and(|b| b.is_full(state.ballast_volume));
        let r = self.ctl.refs;
        let at = |k: usize| run.references[k].values[row];
        let code = at(r.mode);
        self.sp.mode = if code >= 0.0 && code.fract() == 0.0 {
            Mode::BY_CODE
                .get(code as usize)
                .copied()
                .unwrap_or(Mode::Off)
        } else {
            Mode::Off
        };
        self.sp.depth = r.depth.map_or(0.0, at);
        self.sp.yaw = r.yaw.map_or(0.0, at);
        self.sp.surge = r.surge.map_or(0.0, at);
        self.sp.sway = r.sway.map_or(0.0, at);
        for (i, v) in logged {
            if let Some(c) = self.sp.raw.thrusters.get_mut(i) {
                *c = v;
            }
        }
        self.state.update(
            &self.ctl.params,
            Some(&self.ctl.uauv2),
            &self.ctl.thrusters,
            &self.readings,
            &self.sp,
            &mut self.out,
        );
        for (c, o) in cmd.thrusters.iter_mut().zip(&self.out.thrusters) {
            *c = *o;
        }
    }
}

/// The depth, heading and yaw rate the run measured last at each row (see
/// [`ReplayControl::measured`]).
fn measured_last(run: &MeasuredRun) -> Vec<[f64; 3]> {
    let mut out = vec![[f64::NAN; 3]; run.t.len()];
    for (slot, kind) in [ChannelKind::Depth, ChannelKind::Yaw, ChannelKind::R]
        .into_iter()
        .enumerate()
    {
        let Some(c) = run.channel(kind) else {
            continue;
        };
        for (i, (&row, &v)) in c.rows.iter().zip(&c.values).enumerate() {
            let end = c.rows.get(i + 1).copied().unwrap_or(run.t.len());
            out[row..end].iter_mut().for_each(|m| m[slot] = v);
        }
    }
    out
}
