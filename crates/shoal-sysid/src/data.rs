//! The data a search works on: runs mapped onto a vehicle, each sample marked as estimation or
//! validation, and the evaluation of a model on them (replay, residuals, per-channel metrics).
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

use crate::replay::{InitialState, InputMap, ReplayOptions, Trace, simulate};
use crate::run::{ChannelKind, MeasuredRun, RunError};
use crate::stats;
use shoal_model::math::wrap_pi;
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::{VehicleModel, VehicleParams};
use std::collections::BTreeMap;

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
    /// Something about the set of runs as a whole.
    #[error("{0}")]
    Other(String),
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
            return Err(DataError::Other("no estimation run given".into()));
        }
        if !(opts.split > 0.0 && opts.split < 1.0) && holdout.is_empty() {
            return Err(DataError::Other(format!(
                "split {} is out of range; allowed: 0 < split < 1",
                opts.split
            )));
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
                return Err(DataError::Other(format!(
                    "{}: none of the selected channels is measured in this run",
                    run.path.display()
                )));
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
        let mut kinds: Vec<ChannelKind> = runs
            .iter()
            .flat_map(|r| r.channels.iter().map(|&i| r.run.channels[i].kind))
            .collect();
        kinds.sort();
        kinds.dedup();
        let mut resolution: BTreeMap<ChannelKind, f64> = BTreeMap::new();
        for r in &runs {
            for &i in &r.channels {
                let c = &r.run.channels[i];
                let q = resolution.entry(c.kind).or_insert(0.0);
                *q = q.max(stats::resolution(&c.values));
            }
        }
        let ds = Dataset {
            runs,
            kinds,
            env,
            replay: opts.replay,
            resolution,
        };
        for k in &ds.kinds {
            let (ne, nv) = ds.counts(*k);
            if ne < 5 || nv < 5 {
                return Err(DataError::Other(format!(
                    "channel y.{} has {ne} estimation and {nv} validation samples: at least 5 \
                     of each are needed (use longer runs, another split, or hold-out runs)",
                    k.name()
                )));
            }
        }
        Ok(ds)
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
                    if r.run.t[row] < r.split_time {
                        ne += 1;
                    } else {
                        nv += 1;
                    }
                }
            }
        }
        (ne, nv)
    }

    /// Replays every run on `model` and compares with the measurements.
    pub fn evaluate(&self, model: &VehicleModel) -> Evaluation {
        let delay = model.effects.delay();
        let runs = self
            .runs
            .iter()
            .map(|rd| {
                let kinds: Vec<ChannelKind> = rd
                    .channels
                    .iter()
                    .map(|&i| rd.run.channels[i].kind)
                    .collect();
                let mut trace_kinds = kinds.clone();
                trace_kinds.sort();
                trace_kinds.dedup();
                let trace = simulate(
                    model,
                    &self.env,
                    &rd.run,
                    &rd.map,
                    &rd.init,
                    &trace_kinds,
                    &self.replay,
                );
                let channels = rd
                    .channels
                    .iter()
                    .map(|&ci| compare(rd, ci, &trace, &trace_kinds, delay))
                    .collect();
                RunResult {
                    name: rd.run.name.clone(),
                    holdout: rd.holdout,
                    channels,
                }
            })
            .collect();
        Evaluation::new(runs, &self.kinds, &self.resolution)
    }
}

fn compare(
    rd: &RunData,
    ci: usize,
    trace: &Trace,
    trace_kinds: &[ChannelKind],
    delay: f64,
) -> ChannelResult {
    let c = &rd.run.channels[ci];
    let col = trace_kinds.iter().position(|k| *k == c.kind).unwrap_or(0);
    let angle = c.kind.is_angle();
    let times: Vec<f64> = c.rows.iter().map(|&r| rd.run.t[r]).collect();
    let mut predicted: Vec<f64> = times.iter().map(|&t| trace.at(col, t - delay)).collect();
    let est: Vec<bool> = times.iter().map(|&t| t < rd.split_time).collect();
    let mut measured = c.values.clone();
    if angle {
        // Angles are compared as continuous (unwrapped) series whose difference starts within
        // (−π, π]: modulo 2π, yet a model that falls behind by a turn is a turn wrong, and the
        // fit sees a smooth cost instead of one folded at ±π.
        unwrap(&mut measured);
        unwrap(&mut predicted);
        if let (Some(y0), Some(p0)) = (measured.first(), predicted.first()) {
            let shift = (y0 - p0) - wrap_pi(y0 - p0);
            for p in &mut predicted {
                *p += shift;
            }
        }
    }
    let mut resid: Vec<f64> = measured
        .iter()
        .zip(&predicted)
        .map(|(&y, &p)| y - p)
        .collect();
    if c.kind.has_free_offset() {
        let mean_of = |keep: &dyn Fn(usize) -> bool| {
            let sel: Vec<f64> = (0..resid.len())
                .filter(|&i| keep(i))
                .map(|i| resid[i])
                .collect();
            (!sel.is_empty()).then(|| sel.iter().sum::<f64>() / sel.len() as f64)
        };
        // Estimation samples give the offset (a hold-out run's own samples when it has none):
        // the validation part continues the replay from it, so a prediction is judged over
        // the whole held-out stretch, drift included.
        let use_est = est.iter().any(|&e| e);
        let off = mean_of(&|i| est[i] == use_est).unwrap_or(0.0);
        for i in 0..resid.len() {
            resid[i] -= off;
            predicted[i] += off;
        }
    }
    ChannelResult {
        kind: c.kind,
        times,
        measured,
        predicted,
        resid,
        est,
    }
}

/// Makes a sampled angle continuous by removing jumps of more than π between samples.
pub fn unwrap(a: &mut [f64]) {
    let mut shift = 0.0;
    for i in 1..a.len() {
        let raw = a[i];
        let prev = a[i - 1];
        let d = wrap_pi(raw + shift - prev);
        let v = prev + d;
        shift = v - raw;
        a[i] = v;
    }
}

/// One channel of one run, compared.
#[derive(Clone, Debug, PartialEq)]
pub struct ChannelResult {
    /// What it measures.
    pub kind: ChannelKind,
    /// Sample times \[s\].
    pub times: Vec<f64>,
    /// Measured values (angles unwrapped into a continuous series).
    pub measured: Vec<f64>,
    /// Replayed values (initial offset included; angles continuous, starting within ±π of
    /// the measurement).
    pub predicted: Vec<f64>,
    /// Residual measured − predicted.
    pub resid: Vec<f64>,
    /// Whether each sample is estimation data.
    pub est: Vec<bool>,
}

/// One run, compared.
#[derive(Clone, Debug, PartialEq)]
pub struct RunResult {
    /// Run name.
    pub name: String,
    /// Whether it is a hold-out run.
    pub holdout: bool,
    /// Its channels.
    pub channels: Vec<ChannelResult>,
}

/// Per-channel metrics over all runs.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ChannelMetrics {
    /// Estimation samples.
    pub n_est: usize,
    /// Sum of squared estimation residuals.
    pub sse_est: f64,
    /// Lag-1 autocorrelation of the estimation residuals (sample-weighted over runs).
    pub rho1_est: f64,
    /// Validation samples.
    pub n_val: usize,
    /// RMSE on validation samples (channel unit).
    pub rmse: f64,
    /// Fit % on validation samples.
    pub fit_pct: f64,
    /// RMSE on estimation samples (channel unit).
    pub rmse_est: f64,
    /// Ljung–Box whiteness test of the validation residuals (first run with validation
    /// samples of this channel… pooled by concatenation).
    pub ljung_box: stats::LjungBox,
    /// Resolution of the measurements (quantisation step, channel unit; 0: not quantised).
    pub resolution: f64,
}

/// A model compared with all runs.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    /// Per run and channel.
    pub runs: Vec<RunResult>,
    /// Per channel kind, pooled over runs.
    pub metrics: BTreeMap<ChannelKind, ChannelMetrics>,
}

impl Evaluation {
    fn new(
        runs: Vec<RunResult>,
        kinds: &[ChannelKind],
        resolution: &BTreeMap<ChannelKind, f64>,
    ) -> Self {
        let mut metrics = BTreeMap::new();
        for &k in kinds {
            let mut est_r = Vec::new();
            let mut val_r = Vec::new();
            let mut val_dev = Vec::new();
            let mut rho_w = 0.0;
            let mut rho_n = 0usize;
            for r in &runs {
                for c in r.channels.iter().filter(|c| c.kind == k) {
                    let e: Vec<f64> = sel(&c.resid, &c.est, true);
                    if e.len() > 2 {
                        rho_w += stats::acf(&e, 1).get(1).copied().unwrap_or(0.0) * e.len() as f64;
                        rho_n += e.len();
                    }
                    est_r.extend(e);
                    let v = sel(&c.resid, &c.est, false);
                    let y = sel(&c.measured, &c.est, false);
                    val_dev.extend(deviations(&y));
                    val_r.extend(v);
                }
            }
            let sse_est: f64 = est_r.iter().map(|x| x * x).sum();
            metrics.insert(
                k,
                ChannelMetrics {
                    n_est: est_r.len(),
                    sse_est,
                    rho1_est: if rho_n > 0 { rho_w / rho_n as f64 } else { 0.0 },
                    n_val: val_r.len(),
                    rmse: stats::rms(&val_r),
                    fit_pct: stats::fit_pct(&val_r, &val_dev),
                    rmse_est: stats::rms(&est_r),
                    ljung_box: stats::ljung_box(&val_r, 20),
                    resolution: resolution.get(&k).copied().unwrap_or(0.0),
                },
            );
        }
        Self { runs, metrics }
    }

    /// Estimation residuals of every channel, each multiplied by `factor[kind]`, in a fixed
    /// order (run, channel, sample): the vector a fit minimises.
    pub fn weighted(&self, factor: &BTreeMap<ChannelKind, f64>) -> Vec<f64> {
        self.weighted_with(factor, None)
    }

    /// Estimation residuals as in [`Evaluation::weighted`], each sample also multiplied by the square root
    /// of its block's weight in `resample` (the least-squares form of a weighted fit).
    pub fn weighted_with(
        &self,
        factor: &BTreeMap<ChannelKind, f64>,
        resample: Option<&crate::blocks::Resample>,
    ) -> Vec<f64> {
        let mut out = Vec::new();
        for (ri, r) in self.runs.iter().enumerate() {
            for c in &r.channels {
                let w = factor[&c.kind];
                match resample {
                    None => out.extend(
                        c.resid
                            .iter()
                            .zip(&c.est)
                            .filter(|(_, e)| **e)
                            .map(|(r, _)| r * w),
                    ),
                    Some(rs) => out.extend(
                        c.resid
                            .iter()
                            .zip(crate::blocks::sample_blocks(c, rs.len))
                            .filter(|(_, (e, _))| *e)
                            .map(|(r, (e, b))| r * w * rs.weight((ri, e, b)).sqrt()),
                    ),
                }
            }
        }
        out
    }

    /// Maximum-likelihood residual factors for this evaluation: 1/σ̂ per channel, with σ̂² the
    /// estimation residuals' mean square. Weighted this way, a channel counts by its
    /// information: a noisy or badly modelled channel less, a clean one more.
    pub fn ml_factors(&self) -> BTreeMap<ChannelKind, f64> {
        self.metrics
            .iter()
            .map(|(k, m)| {
                let var = (m.sse_est / m.n_est.max(1) as f64).max(1e-30);
                (*k, 1.0 / var.sqrt())
            })
            .collect()
    }

    /// The channel kind of each entry of [`Evaluation::weighted`].
    pub fn weighted_kinds(&self) -> Vec<ChannelKind> {
        let mut out = Vec::new();
        for r in &self.runs {
            for c in &r.channels {
                out.extend(c.est.iter().filter(|e| **e).map(|_| c.kind));
            }
        }
        out
    }

    /// Validation residuals of a channel kind, run after run.
    pub fn validation_residuals(&self, kind: ChannelKind) -> Vec<f64> {
        let mut out = Vec::new();
        for r in &self.runs {
            for c in r.channels.iter().filter(|c| c.kind == kind) {
                out.extend(sel(&c.resid, &c.est, false));
            }
        }
        out
    }
}

fn sel(v: &[f64], est: &[bool], want: bool) -> Vec<f64> {
    v.iter()
        .zip(est)
        .filter(|(_, e)| **e == want)
        .map(|(x, _)| *x)
        .collect()
}

fn deviations(y: &[f64]) -> Vec<f64> {
    if y.is_empty() {
        return Vec::new();
    }
    let m = y.iter().sum::<f64>() / y.len() as f64;
    y.iter().map(|a| a - m).collect()
}
