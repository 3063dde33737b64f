//! The data a search works on: runs mapped onto a vehicle, each sample marked as estimation or
//! validation, and their replays on a model compared with the measurements (predictions and
//! residuals, from which [`crate::evaluate::evaluation`] derives the per-channel metrics).
//!
//! **Splitting.** Without hold-out runs, each run is split in time: samples before
//! `t₀ + split·duration` are for estimation, the rest for validation; the replay runs through
//! the whole run, so validation is a free-run prediction beyond the fitted part. With hold-out
//! runs, the other runs are estimation data and the hold-out runs are only scored.
//!
//! **Initial offsets.** Depth, heading and tracked position start at free initial conditions
//! of the replay. Their initial values are refined from the data: the residual's mean over the
//! run's estimation samples (over all samples for a hold-out run, whose initial condition
//! must come from its own data) is removed. For a model whose motion does not depend on the
//! absolute position and heading (true away from the surface) this is the least-squares
//! estimate of the initial position.

use crate::evaluate::anchoring::{Anchoring, Horizon, choose};
use crate::evaluate::blocks::{Resample, push_weighted};
use crate::evaluate::current::{self, Current};
use crate::evaluate::evaluation::{ChannelResult, Evaluation, RunResult};
use crate::evaluate::masses::MassTable;
use crate::evaluate::open_loop::anchors::{Anchor, OBSERVER_S};
use crate::evaluate::open_loop::{
    InitialState, InputMap, ReplayOptions, Trace, grid_position, replay_steps, simulate_many,
};
use crate::evaluate::stats;
pub use crate::evaluate::stats::unwrap;
use crate::log::run::{ChannelKind, MeasuredRun, ReferenceKind, RunError};
use shoal_model::lanes::LANES;
use shoal_model::math::wrap_pi;
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::{VehicleModel, VehicleParams};
use std::collections::BTreeMap;
use std::sync::Arc;

/// One run prepared for replay.
#[derive(Clone, Debug)]
pub struct RunData {
    /// The run.
    pub run: MeasuredRun,
    /// Inputs → actuators.
    pub map: InputMap,
    /// Where the replay starts.
    pub init: InitialState,
    /// The channels used, in the order of [`MeasuredRun::channels`] (indices into it).
    pub channels: Vec<usize>,
    /// Samples at times before this are estimation data \[s\] (+∞: all; −∞: none).
    pub split_time: f64,
    /// Whether the run is a hold-out run (scored only).
    pub holdout: bool,
}

impl RunData {
    /// Whether a sample at time `t` \[s\] is estimation data (before the split; never in a
    /// hold-out run, whose split is at −∞).
    pub fn is_estimation(&self, t: f64) -> bool {
        t < self.split_time
    }
}

/// Runs prepared for a search.
#[derive(Clone, Debug)]
pub struct Dataset {
    /// The runs.
    pub runs: Vec<RunData>,
    /// Every channel kind that appears, sorted.
    pub kinds: Vec<ChannelKind>,
    /// The water.
    pub env: Environment,
    /// Replay settings.
    pub replay: ReplayOptions,
    /// Resolution of each channel kind's measurements (the coarsest over the runs; 0: not
    /// quantised), see [`stats::resolution`].
    pub resolution: BTreeMap<ChannelKind, f64>,
    /// Per run, what its comparison with a replay needs that no model changes.
    plans: Vec<RunPlan>,
    /// The mass properties of the ballast volumes the replays met (shared by clones).
    masses: Arc<MassTable>,
    /// Whether the runs are replayed open loop or re-anchored, and why (set by
    /// [`Dataset::anchor`]).
    pub anchoring: Anchoring,
}

/// What comparing one run with its replay needs that does not depend on the model: worked
/// out once per dataset instead of once per replay (a search replays a log thousands of
/// times).
#[derive(Clone, Debug)]
struct RunPlan {
    /// The kinds the replay records, sorted, without repeats.
    trace_kinds: Vec<ChannelKind>,
    /// The compared channels, in the order of [`RunData::channels`].
    channels: Vec<ChannelPlan>,
    /// The physics steps a replay must take for the estimation samples of every channel
    /// (the grid point after the last one, for its interpolation); `None` when the run has
    /// no estimation samples (a hold-out run).
    estimation_steps: Option<usize>,
}

/// Which samples a replay is made for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Part {
    /// Every sample: the estimation and the held-out (validation) ones.
    All,
    /// The estimation samples only: each run is replayed up to its last estimation sample
    /// (a free-run prediction never looks ahead, so they are the same as in a whole replay),
    /// hold-out runs not at all. What a fit's inner loop needs.
    Estimation,
}

/// One compared channel of a [`RunPlan`].
#[derive(Clone, Debug)]
struct ChannelPlan {
    kind: ChannelKind,
    /// Column of `kind` in the replay's trace.
    col: usize,
    /// Sample times \[s\].
    times: Vec<f64>,
    /// Measured values, angles unwrapped (see [`ChannelResult::measured`]).
    measured: Vec<f64>,
    /// Whether each sample is estimation data.
    est: Vec<bool>,
    /// How many samples an estimation replay compares: the estimation samples, which come
    /// first (samples are in time order; all of them in the unlikely case they are not).
    n_est: usize,
    /// Each sample time's position on the replay's grid ([`grid_position`]), for a model
    /// without a sensor delay.
    grid: Vec<(usize, f64)>,
}

impl RunPlan {
    fn new(rd: &RunData, replay: &ReplayOptions) -> Self {
        let mut trace_kinds: Vec<ChannelKind> = rd
            .channels
            .iter()
            .map(|&i| rd.run.channels[i].kind)
            .collect();
        trace_kinds.sort();
        trace_kinds.dedup();
        let n = replay_steps(&rd.run, replay.dt) + 1;
        let t0 = rd.run.t[0];
        let channels = rd
            .channels
            .iter()
            .map(|&ci| {
                let c = &rd.run.channels[ci];
                let times: Vec<f64> = c.rows.iter().map(|&r| rd.run.t[r]).collect();
                let mut measured = c.values.clone();
                if c.kind.is_angle() {
                    unwrap(&mut measured);
                }
                let est: Vec<bool> = times.iter().map(|&t| rd.is_estimation(t)).collect();
                let leading = est.iter().take_while(|&&e| e).count();
                let n_est = if est[leading..].iter().any(|&e| e) {
                    est.len()
                } else {
                    leading
                };
                ChannelPlan {
                    kind: c.kind,
                    col: trace_kinds.iter().position(|k| *k == c.kind).unwrap_or(0),
                    est,
                    n_est,
                    grid: times
                        .iter()
                        .map(|&t| grid_position(t0, replay.dt, n, t))
                        .collect(),
                    times,
                    measured,
                }
            })
            .collect::<Vec<ChannelPlan>>();
        // The grid point after the last compared sample: its interpolation reads it (a
        // sensor delay reads earlier points only).
        let estimation_steps = channels
            .iter()
            .filter(|c| c.n_est > 0)
            .map(|c| c.grid[c.n_est - 1].0 + 1)
            .max()
            .map(|k| k.min(n - 1));
        Self {
            trace_kinds,
            channels,
            estimation_steps,
        }
    }

    /// How a model with sensor delay `delay` \[s\] is replayed for the samples of `part`:
    /// the most physics steps and whether only the estimation samples are compared, or
    /// `None` when the run is not replayed (a hold-out run's estimation samples: none).
    fn bounds(&self, part: Part, delay: f64) -> Option<(usize, bool)> {
        match part {
            Part::All => Some((usize::MAX, false)),
            // A negative delay (none exists) would read ahead: then everything.
            Part::Estimation if delay >= 0.0 => self.estimation_steps.map(|k| (k, true)),
            Part::Estimation => Some((usize::MAX, true)),
        }
    }
}

/// How to build a [`Dataset`].
#[derive(Clone, Debug, PartialEq)]
pub struct DataOptions {
    /// Fraction of each run used for estimation when there are no hold-out runs (0…1).
    pub split: f64,
    /// Use only these channels (all measured ones when `None`).
    pub channels: Option<Vec<ChannelKind>>,
    /// Replay settings.
    pub replay: ReplayOptions,
}

impl Default for DataOptions {
    fn default() -> Self {
        Self {
            split: 0.6,
            channels: None,
            replay: ReplayOptions::default(),
        }
    }
}

/// A problem building a dataset.
#[derive(Debug, thiserror::Error)]
pub enum DataError {
    /// A run does not fit the vehicle.
    #[error(transparent)]
    Run(#[from] RunError),
    /// No run to fit on.
    #[error("no estimation run given")]
    NoEstimationRun,
    /// The estimation fraction is out of range (and there are no hold-out runs).
    #[error("split {split} is out of range; allowed: 0 < split < 1")]
    Split {
        /// The fraction given.
        split: f64,
    },
    /// A run measures none of the selected channels.
    #[error("{}: none of the selected channels is measured in this run", file.display())]
    NoSelectedChannel {
        /// The run's file.
        file: std::path::PathBuf,
    },
    /// A channel has too few samples on one side of the split.
    #[error(
        "channel y.{} has {estimation} estimation and {validation} validation samples: at \
         least 5 of each are needed (use longer runs, another split, or hold-out runs)",
        channel.name()
    )]
    TooFewSamples {
        /// The channel.
        channel: ChannelKind,
        /// Its estimation samples.
        estimation: usize,
        /// Its validation samples.
        validation: usize,
    },
}

impl Dataset {
    /// Prepares `estimation` and `holdout` runs for `params` in water `env`.
    pub fn new(
        params: &VehicleParams,
        env: Environment,
        estimation: Vec<MeasuredRun>,
        holdout: Vec<MeasuredRun>,
        opts: &DataOptions,
    ) -> Result<Dataset, DataError> {
        if estimation.is_empty() {
            return Err(DataError::NoEstimationRun);
        }
        if !(opts.split > 0.0 && opts.split < 1.0) && holdout.is_empty() {
            return Err(DataError::Split { split: opts.split });
        }
        let have_holdout = !holdout.is_empty();
        let mut runs = Vec::new();
        let all = estimation
            .into_iter()
            .map(|r| (r, false))
            .chain(holdout.into_iter().map(|r| (r, true)));
        for (mut run, is_holdout) in all {
            let map = InputMap::new(params, &mut run)?;
            opts.replay.steps(&run)?;
            let init = InitialState::from_run(params, &run, 0.5);
            let channels: Vec<usize> = run
                .channels
                .iter()
                .enumerate()
                .filter(|(_, c)| opts.channels.as_ref().is_none_or(|k| k.contains(&c.kind)))
                .map(|(i, _)| i)
                .collect();
            if channels.is_empty() {
                return Err(DataError::NoSelectedChannel {
                    file: run.path.clone(),
                });
            }
            let split_time = if is_holdout {
                f64::NEG_INFINITY
            } else if have_holdout {
                f64::INFINITY
            } else {
                run.t[0] + opts.split * run.duration()
            };
            runs.push(RunData {
                run,
                map,
                init,
                channels,
                split_time,
                holdout: is_holdout,
            });
        }
        let mut ds = Dataset {
            runs,
            kinds: Vec::new(),
            env,
            replay: opts.replay,
            resolution: BTreeMap::new(),
            plans: Vec::new(),
            masses: Arc::default(),
            anchoring: Anchoring::default(),
        };
        ds.replan();
        for k in &ds.kinds {
            let (ne, nv) = ds.counts(*k);
            if ne < 5 || nv < 5 {
                return Err(DataError::TooFewSamples {
                    channel: *k,
                    estimation: ne,
                    validation: nv,
                });
            }
        }
        Ok(ds)
    }

    /// Works out again what the runs' compared channels are and what comparing them needs:
    /// the kinds, their resolutions and each run's plan (after channels were added).
    pub(crate) fn replan(&mut self) {
        let runs = &self.runs;
        let mut kinds: Vec<ChannelKind> = runs
            .iter()
            .flat_map(|r| r.channels.iter().map(|&i| r.run.channels[i].kind))
            .collect();
        kinds.sort();
        kinds.dedup();
        let mut resolution: BTreeMap<ChannelKind, f64> = BTreeMap::new();
        for r in runs {
            for &i in &r.channels {
                let c = &r.run.channels[i];
                let q = resolution.entry(c.kind).or_insert(0.0);
                *q = q.max(stats::resolution(&c.values));
            }
        }
        self.plans = runs.iter().map(|r| RunPlan::new(r, &self.replay)).collect();
        self.kinds = kinds;
        self.resolution = resolution;
    }

    /// (estimation, validation) sample counts of a channel over all runs.
    pub fn counts(&self, kind: ChannelKind) -> (usize, usize) {
        let mut ne = 0;
        let mut nv = 0;
        for r in &self.runs {
            for &ci in &r.channels {
                let c = &r.run.channels[ci];
                if c.kind != kind {
                    continue;
                }
                for &row in &c.rows {
                    if r.is_estimation(r.run.t[row]) {
                        ne += 1;
                    } else {
                        nv += 1;
                    }
                }
            }
        }
        (ne, nv)
    }

    /// Sets how every run is replayed: re-anchored at `horizon` (for [`Horizon::Auto`] and
    /// [`Horizon::Closed`], chosen from the replay of `baseline`; [`Horizon::Choose`] as
    /// `Auto` for long runs), or open loop; for [`Horizon::Closed`], where the runs allow it,
    /// with the controller's closed-loop twin whose commands are compared with the logged
    /// ones ([`Dataset::close_loop`]). Returns what was chosen.
    pub fn anchor(&mut self, horizon: Horizon, baseline: &VehicleModel) -> &Anchoring {
        for rd in &mut self.runs {
            rd.init.anchors.clear();
            rd.init.filter.clear();
        }
        self.anchoring.currents.clear();
        self.open_loop();
        let referenced = self
            .runs
            .iter()
            .all(|rd| rd.run.reference(ReferenceKind::Mode).is_some());
        let longest = self
            .runs
            .iter()
            .map(|rd| rd.run.duration())
            .fold(0.0, f64::max);
        let mut chosen = choose(horizon, longest, referenced, || self.evaluate(baseline));
        if let Some(h) = chosen.horizon {
            let dt = self.replay.dt;
            for rd in &mut self.runs {
                rd.init.anchors = Anchor::every(&rd.run, h, dt);
                // The horizontal velocities at each anchor: from the model replayed through
                // the data, anchored every OBSERVER_S.
                rd.init.filter = Anchor::every(&rd.run, OBSERVER_S, dt);
            }
            chosen.currents = self.currents(baseline);
            for (kind, c) in &chosen.currents {
                chosen.why = format!(
                    "{}; between anchors the water carries {}: a wandering current (σ {:.2} \
                     mm/s, correlation time {} s, the maximum-likelihood noise model on the \
                     baseline's replay) would leave {:.2} mm of its {:.2} mm residual — motion \
                     no vehicle model has",
                    chosen.why,
                    kind.label(),
                    c.sigma_m_s * 1e3,
                    c.tau_s,
                    c.innovation_m * 1e3,
                    c.residual_m * 1e3
                );
            }
        }
        if horizon == Horizon::Closed {
            match self.close_loop(baseline) {
                Ok(added) => {
                    let names: Vec<String> = added.iter().map(|k| k.label()).collect();
                    chosen.closed_loop = true;
                    chosen.why = format!(
                        "{}; beside each replay a closed-loop twin, the vehicle's controller \
                         following the logged references, sends commands that are compared \
                         with the logged ones ({})",
                        chosen.why,
                        names.join(", ")
                    );
                }
                Err(why) => chosen.why = format!("no closed-loop replay ({why}); {}", chosen.why),
            }
        }
        self.anchoring = chosen;
        &self.anchoring
    }

    /// Replays every run on `model` and compares with the measurements.
    pub fn evaluate(&self, model: &VehicleModel) -> Evaluation {
        self.evaluation(&self.replayed(model, Part::All))
    }

    /// The wandering current of each transported channel ([`current::of_evaluation`]), from
    /// the residuals of `baseline`'s re-anchored replay (made without any current).
    fn currents(&self, baseline: &VehicleModel) -> BTreeMap<ChannelKind, Current> {
        let resets: Vec<Vec<f64>> = self
            .runs
            .iter()
            .map(|rd| anchor_times(rd, self.replay.dt))
            .collect();
        current::of_evaluation(&self.evaluate(baseline), &resets, baseline.effects.delay())
    }

    /// Replays every run on `model` for the samples of `part`: each compared channel's
    /// predictions and residuals.
    pub fn replayed(&self, model: &VehicleModel, part: Part) -> Replayed {
        let mut one = self.replayed_many(std::slice::from_ref(model), part);
        one.pop().expect("a replay per model")
    }

    /// [`Dataset::replayed`] for each of `models`, bit for bit, with [`LANES`] models
    /// replayed together ([`simulate_many`]: one lane of the RK4 kernel each).
    pub fn replayed_many(&self, models: &[VehicleModel], part: Part) -> Vec<Replayed> {
        let mut out = Vec::with_capacity(models.len());
        for group in models.chunks(LANES) {
            let mut runs = vec![Vec::with_capacity(self.runs.len()); group.len()];
            for (rd, plan) in self.runs.iter().zip(&self.plans) {
                let delays: Vec<f64> = group.iter().map(|m| m.effects.delay()).collect();
                let bounds: Vec<Option<(usize, bool)>> =
                    delays.iter().map(|&d| plan.bounds(part, d)).collect();
                let (simulated, max_steps): (Vec<&VehicleModel>, Vec<usize>) = group
                    .iter()
                    .zip(&bounds)
                    .filter_map(|(m, b)| b.map(|(steps, _)| (m, steps)))
                    .unzip();
                let mut traces = simulate_many(
                    &simulated,
                    &max_steps,
                    &self.env,
                    &rd.run,
                    &rd.map,
                    &rd.init,
                    &plan.trace_kinds,
                    &self.replay,
                    &self.masses,
                )
                .into_iter();
                for ((series, b), &delay) in runs.iter_mut().zip(&bounds).zip(&delays) {
                    let Some((_, est_only)) = *b else {
                        series.push(vec![(Vec::new(), Vec::new()); plan.channels.len()]);
                        continue;
                    };
                    let trace = traces.next().expect("a trace per replayed model");
                    series.push(
                        plan.channels
                            .iter()
                            .map(|cp| {
                                let n = if est_only { cp.n_est } else { cp.times.len() };
                                let (mut predicted, mut resid) = (Vec::new(), Vec::new());
                                let anchored = !rd.init.anchors.is_empty();
                                compare(cp, n, &trace, delay, anchored, &mut predicted, &mut resid);
                                (predicted, resid)
                            })
                            .collect(),
                    );
                }
            }
            out.extend(runs.into_iter().map(|runs| Replayed { runs, part }));
        }
        out
    }

    /// The evaluation of a replay of this dataset. Of a replay of [`Part::Estimation`], it
    /// holds the estimation samples only: its estimation metrics are those of the whole
    /// replay, its validation metrics are of no samples.
    pub fn evaluation(&self, replayed: &Replayed) -> Evaluation {
        let runs = self
            .runs
            .iter()
            .zip(&self.plans)
            .zip(&replayed.runs)
            .map(|((rd, plan), channels)| RunResult {
                name: rd.run.name.clone(),
                holdout: rd.holdout,
                channels: plan
                    .channels
                    .iter()
                    .zip(channels)
                    .map(|(cp, (predicted, resid))| {
                        let n = predicted.len();
                        ChannelResult {
                            kind: cp.kind,
                            times: cp.times[..n].to_vec(),
                            measured: cp.measured[..n].to_vec(),
                            predicted: predicted.clone(),
                            resid: resid.clone(),
                            est: cp.est[..n].to_vec(),
                        }
                    })
                    .collect(),
            })
            .collect();
        Evaluation::new(runs, &self.kinds, &self.resolution)
    }

    /// The estimation residuals of a replay of this dataset, weighted as
    /// [`weighted_residuals`](crate::evaluate::blocks::weighted_residuals) weighs them, or
    /// `None` where [`Evaluation::metrics`] would hold a sum of squares that is not finite:
    /// the same numbers as `weighted_residuals(&evaluation(replayed), factor, resample)`,
    /// without the per-channel metrics and series a fit's inner loop never looks at.
    pub fn weighted(
        &self,
        replayed: &Replayed,
        factor: &BTreeMap<ChannelKind, f64>,
        resample: Option<&Resample>,
    ) -> Option<Vec<f64>> {
        let mut out = Vec::new();
        // Per kind, the sum of squared estimation residuals, added in the order in which
        // `Evaluation::new` adds them (run by run, channel by channel).
        let mut sse: BTreeMap<ChannelKind, f64> = BTreeMap::new();
        for (ri, (plan, channels)) in self.plans.iter().zip(&replayed.runs).enumerate() {
            for (cp, (_, resid)) in plan.channels.iter().zip(channels) {
                let s = sse.entry(cp.kind).or_insert(0.0);
                for (r, _) in resid.iter().zip(&cp.est).filter(|(_, e)| **e) {
                    *s += r * r;
                }
                push_weighted(
                    &mut out,
                    resid,
                    &cp.times,
                    &cp.est,
                    factor[&cp.kind],
                    resample.map(|rs| (rs, ri)),
                );
            }
        }
        sse.values().all(|s| s.is_finite()).then_some(out)
    }
}

/// The predictions and residuals of every compared channel of a dataset's runs on one model
/// ([`Dataset::replayed`]): what a replay yields, from which [`Dataset::evaluation`] and
/// [`Dataset::weighted`] derive everything else.
#[derive(Clone, Debug, PartialEq)]
pub struct Replayed {
    /// Per run, per compared channel: (predicted, residual) per sample (channel units); the
    /// leading samples of `part` (none of a hold-out run's for [`Part::Estimation`]).
    runs: Vec<Vec<(Vec<f64>, Vec<f64>)>>,
    /// The samples it holds.
    part: Part,
}

impl Replayed {
    /// From its series: per run, per compared channel, (predicted, residual) for the leading
    /// samples of `part`.
    pub fn from_series(runs: Vec<Vec<(Vec<f64>, Vec<f64>)>>, part: Part) -> Self {
        Self { runs, part }
    }

    /// The samples it holds.
    pub fn part(&self) -> Part {
        self.part
    }

    /// The bytes its series take.
    pub fn bytes(&self) -> usize {
        self.runs
            .iter()
            .flatten()
            .map(|(p, r)| 8 * (p.len() + r.len()))
            .sum()
    }
}

/// The times of `rd`'s anchors on its replay's clock of steps of `dt` \[s\].
fn anchor_times(rd: &RunData, dt: f64) -> Vec<f64> {
    let t0 = rd.run.t.first().copied().unwrap_or(0.0);
    rd.init
        .anchors
        .iter()
        .map(|a| t0 + a.step as f64 * dt)
        .collect()
}

/// Compares the leading `n` samples of one channel with a replay (which must reach them):
/// their predictions (`predicted`) and residuals measured − predicted (`resid`), both
/// replaced. The replay is read `delay` \[s\] earlier
/// than each sample time (a sensor delay); angles are compared as continuous series whose
/// difference starts within (−π, π] (modulo 2π, yet a model that falls behind by a turn is a
/// turn wrong, and the fit sees a smooth cost instead of one folded at ±π); a channel with a
/// free initial offset has the mean residual of its estimation samples removed (of all its
/// samples in a hold-out run, which has no estimation samples) — unless the replay is
/// `anchored` and sets the channel to the data at every [`Anchor`].
fn compare(
    cp: &ChannelPlan,
    n: usize,
    trace: &Trace,
    delay: f64,
    anchored: bool,
    predicted: &mut Vec<f64>,
    resid: &mut Vec<f64>,
) {
    predicted.clear();
    // A command is no sensor reading: the controller read late, not the logger.
    let delay = if cp.kind.is_command() { 0.0 } else { delay };
    if delay == 0.0 {
        predicted.extend(cp.grid[..n].iter().map(|&g| trace.at_position(cp.col, g)));
    } else {
        predicted.extend(cp.times[..n].iter().map(|&t| trace.at(cp.col, t - delay)));
    }
    let measured = &cp.measured[..n];
    if cp.kind.is_angle() {
        unwrap(predicted);
        if let (Some(y0), Some(p0)) = (measured.first(), predicted.first()) {
            let shift = (y0 - p0) - wrap_pi(y0 - p0);
            for p in predicted.iter_mut() {
                *p += shift;
            }
        }
    }
    resid.clear();
    resid.extend(measured.iter().zip(predicted.iter()).map(|(&y, &p)| y - p));
    if cp.kind.has_free_offset() && !(anchored && cp.kind.is_anchored()) {
        // Estimation samples give the offset (a hold-out run's own samples when it has none):
        // the validation part continues the replay from it, so a prediction is judged over
        // the whole held-out stretch, drift included.
        let use_est = cp.est.iter().any(|&e| e);
        // (`resid` holds the leading `n` samples: all of those the offset is taken from.)
        let part = || {
            resid
                .iter()
                .zip(&cp.est)
                .filter(|(_, e)| **e == use_est)
                .map(|(r, _)| *r)
        };
        let n = part().count();
        let off = if n > 0 {
            part().sum::<f64>() / n as f64
        } else {
            0.0
        };
        for (r, p) in resid.iter_mut().zip(predicted.iter_mut()) {
            *r -= off;
            *p += off;
        }
    }
}
