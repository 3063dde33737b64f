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

mod simulate;

use crate::limits::{ClampNote, Limits};
use crate::numbers::short;
use crate::run::{ChannelKind, MeasuredRun, RunError};
use shoal_model::dynamics::Integrator;
use shoal_model::math::{Vec3, quat_from_rpy, wrap_pi};
use shoal_model::vehicle::VehicleParams;

pub use simulate::{simulate, simulate_many, simulate_with};

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

#[cfg(test)]
mod tests {
    use super::*;
    use shoal_model::rigid_body::Environment;
    use shoal_model::vehicle::VehicleModel;
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
