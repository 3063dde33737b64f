//! A model compared with measured runs: per run and channel the measured, predicted and
//! residual series, and per channel kind the metrics pooled over runs (estimation SSE and
//! lag-1 autocorrelation, held-out RMSE, fit %, Ljung–Box) — what every score of the search
//! is computed from. The dataset (`dataset.rs`) makes it from a replay.

use crate::evaluate::stats;
use crate::log::run::ChannelKind;
use std::collections::BTreeMap;

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

/// Relative reduction of an RMSE from `before` to `after` \[%\] (0 when `before` is 0).
pub fn rmse_gain_pct(before: f64, after: f64) -> f64 {
    if before > 0.0 {
        100.0 * (1.0 - after / before)
    } else {
        0.0
    }
}

impl Evaluation {
    /// Whether every channel's residuals are white (Ljung–Box at 5 %).
    pub fn residuals_white(&self) -> bool {
        self.metrics.values().all(|m| m.ljung_box.white())
    }

    /// The metrics of `runs` for the channel `kinds`, with each kind's measurement
    /// `resolution`.
    pub(crate) fn new(
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
        let mut out = Vec::new();
        for r in &self.runs {
            for c in &r.channels {
                push_estimation(&mut out, &c.resid, &c.est, factor[&c.kind]);
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

/// Appends the estimation samples of `resid` (estimation flags `est`) to `out`, each
/// multiplied by `w`.
pub(crate) fn push_estimation(out: &mut Vec<f64>, resid: &[f64], est: &[bool], w: f64) {
    out.extend(
        resid
            .iter()
            .zip(est)
            .filter(|(_, e)| **e)
            .map(|(r, _)| r * w),
    );
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

/// The noise floor of a channel's held-out residuals: the RMS of their first differences over
/// √2 — what is left of white sensor noise when every smooth structure is taken out — and
/// never below the quantisation noise of its sensor, resolution/√12 (a vehicle that hardly
/// moves sits on one step of a coarse sensor, and the differences of its readings are then
/// mostly zero although the reading is up to half a step off).
pub fn noise_floor(eval: &Evaluation, kind: ChannelKind) -> f64 {
    let q = eval.metrics.get(&kind).map_or(0.0, |m| m.resolution);
    differenced_floor(eval, kind).max(q / 12f64.sqrt())
}

/// The RMS of the first differences of a channel's held-out residuals over √2.
fn differenced_floor(eval: &Evaluation, kind: ChannelKind) -> f64 {
    let mut diffs = Vec::new();
    for r in &eval.runs {
        for c in r.channels.iter().filter(|c| c.kind == kind) {
            let v: Vec<f64> = c
                .resid
                .iter()
                .zip(&c.est)
                .filter(|(_, e)| !**e)
                .map(|(x, _)| *x)
                .collect();
            diffs.extend(v.windows(2).map(|w| w[1] - w[0]));
        }
    }
    stats::rms(&diffs) / std::f64::consts::SQRT_2
}
