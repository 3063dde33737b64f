//! What a replay starts from and how it steps: which input column drives which actuator
//! ([`InputMap`], the inputs checked against the actuator limits), the physics step and
//! integrator ([`ReplayOptions`]) and the initial state taken from the first samples
//! ([`InitialState`]).

use super::anchors::Anchor;
use super::control::ReplayControl;
use crate::log::limits::{ClampNote, Limits};
use crate::log::numbers::short;
use crate::log::run::{ChannelKind, MeasuredRun, RunError};
use shoal_model::dynamics::Integrator;
use shoal_model::math::{Vec3, quat_from_rpy};
use shoal_model::vehicle::VehicleParams;
use std::sync::Arc;

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
    /// (see [`crate::log::limits`]).
    pub clamped: Vec<ClampNote>,
}

impl InputMap {
    /// Maps the run's `u.` columns onto the vehicle's actuators by name: `u.<thruster>`
    /// [%], `u.<tilt drive>` \[rad\], `u.pump`. Actuators without a column stay at zero.
    ///
    /// Checks every input value against its actuator's limits ([`crate::log::limits`]): values
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
/// [`ReplayOptions::steps`] (and cut there by `simulate`) instead of allocating by the time
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

/// The state a replay starts from, and where it is re-anchored to the measurements.
#[derive(Clone, Debug, PartialEq)]
pub struct InitialState {
    /// Where the replay's measured states are set to the data again, in step order (empty:
    /// an open-loop replay; see [`super::anchors`]).
    pub anchors: Vec<Anchor>,
    /// The dense anchors of the filter that gives a re-anchored replay its horizontal
    /// velocities at each of `anchors` (empty: they run on; see [`super::anchors`]).
    pub filter: Vec<Anchor>,
    /// Roll, pitch, yaw \[rad\].
    pub rpy: Vec3,
    /// World position of the body origin \[m\] (depth from the first depth reading).
    pub position: Vec3,
    /// Body velocity over ground (u, v, w) [m/s], if measured; otherwise the vehicle starts
    /// at rest relative to the water.
    pub velocity: Option<Vec3>,
    /// Body rates (p, q, r) [rad/s].
    pub rates: Vec3,
    /// The controller of the replay's closed-loop twin (`None`: no twin): the same model
    /// replayed beside it from the same start with this controller in the loop and never
    /// re-anchored, whose thruster commands the replay's command channels show, while the
    /// logged commands drive the replay itself (see [`super::control`]).
    pub control: Option<Arc<ReplayControl>>,
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
            anchors: Vec::new(),
            filter: Vec::new(),
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
            control: None,
        }
    }
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
