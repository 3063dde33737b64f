//! What two models predict for a flight that has not been flown: the flight as a run with its
//! commands and the log's channels (held at the log's first readings, so that the replay
//! starts where the log started, at rest), replayed open loop through each model; their
//! separation is the RMS difference of the two predictions on each channel over what the two
//! leave unexplained on the log ([`Separation`]).

use super::library::Schedule;
use crate::evaluate::dataset::{DataOptions, Dataset};
use crate::evaluate::evaluation::Evaluation;
use crate::log::run::{Channel, ChannelKind, InputColumn, MeasuredRun};
use shoal_model::vehicle::VehicleParams;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// How far apart two models' predictions are, on the channel where they are furthest apart
/// relative to the residual.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Separation {
    /// The channel.
    pub channel: ChannelKind,
    /// RMS difference of the two predictions (channel unit).
    pub rms: f64,
    /// The yardstick: the larger held-out RMSE of the two models on the log (channel unit).
    pub residual: f64,
    /// `rms / residual` \[-\]: above 1, the difference stands out of what the model leaves
    /// unexplained at every sample.
    pub ratio: f64,
    /// Samples compared.
    pub samples: usize,
    /// `samples · ratio²` \[-\]: the expected difference of the two models' χ² (twice their
    /// log-likelihood ratio) were the residual white noise; what a flight adds to the
    /// evidence, comparable with a ΔBIC.
    pub evidence: f64,
}

/// The flight `schedule` as a run at the log's sample period `period` \[s\], measuring the
/// channels `start` lists, each held at its value there (channel unit).
pub fn flight_run(
    name: &str,
    schedule: &Schedule,
    period: f64,
    start: &[(ChannelKind, f64)],
) -> MeasuredRun {
    let n = (schedule.duration / period).round() as usize + 1;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * period).collect();
    let mut inputs: Vec<InputColumn> = schedule
        .inputs
        .iter()
        .enumerate()
        .map(|(i, name)| InputColumn::held(name, 2 + i))
        .collect();
    let mut step = 0;
    for &ti in &t {
        while step + 1 < schedule.steps.len() && schedule.steps[step + 1].0 <= ti + 1e-9 {
            step += 1;
        }
        for (col, v) in inputs.iter_mut().zip(&schedule.steps[step].1) {
            col.values.push(*v);
        }
    }
    let first = 2 + inputs.len();
    let channels = start
        .iter()
        .enumerate()
        .map(|(i, (kind, v))| Channel {
            kind: *kind,
            column: first + i,
            rows: (0..n).collect(),
            values: vec![*v; n],
        })
        .collect();
    MeasuredRun {
        path: PathBuf::from(format!("{name}.csv")),
        name: name.to_string(),
        t,
        inputs,
        channels,
        references: Vec::new(),
        extra: Vec::new(),
        header_line: 0,
        lines: Vec::new(),
        ingest: Default::default(),
    }
}

/// The flight as a dataset of one run (replayed open loop from its start), or why not.
pub fn flight_dataset(
    params: &VehicleParams,
    like: &Dataset,
    run: MeasuredRun,
) -> Result<Dataset, String> {
    let opts = DataOptions {
        split: 0.5,
        channels: None,
        replay: like.replay,
    };
    Dataset::new(params, like.env, vec![run], Vec::new(), &opts).map_err(|e| e.to_string())
}

/// Per channel (not the commands), the RMS difference of the predictions of `a` and `b` over
/// every sample, or over the held-out ones only.
fn differences(
    a: &Evaluation,
    b: &Evaluation,
    held_out_only: bool,
) -> BTreeMap<ChannelKind, (f64, usize)> {
    let mut ss: BTreeMap<ChannelKind, (f64, usize)> = BTreeMap::new();
    for (ra, rb) in a.runs.iter().zip(&b.runs) {
        for (ca, cb) in ra.channels.iter().zip(&rb.channels) {
            if ca.kind != cb.kind || ca.kind.is_command() {
                continue;
            }
            let e = ss.entry(ca.kind).or_insert((0.0, 0));
            for ((pa, pb), est) in ca.predicted.iter().zip(&cb.predicted).zip(&ca.est) {
                if held_out_only && *est {
                    continue;
                }
                e.0 += (pa - pb) * (pa - pb);
                e.1 += 1;
            }
        }
    }
    ss.into_iter()
        .filter(|(_, (_, n))| *n > 0)
        .map(|(k, (s, n))| (k, ((s / n as f64).sqrt(), n)))
        .collect()
}

/// The separation of `a` and `b` on the channel where it is largest relative to `residual`
/// (held-out samples only with `held_out_only`); `None` without a common channel with a
/// residual.
pub fn separation(
    a: &Evaluation,
    b: &Evaluation,
    residual: &BTreeMap<ChannelKind, f64>,
    held_out_only: bool,
) -> Option<Separation> {
    differences(a, b, held_out_only)
        .into_iter()
        .filter_map(|(k, (rms, n))| {
            let r = *residual.get(&k)?;
            (r > 0.0 && rms.is_finite()).then(|| Separation {
                channel: k,
                rms,
                residual: r,
                ratio: rms / r,
                samples: n,
                evidence: n as f64 * (rms / r).powi(2),
            })
        })
        .max_by(|x, y| x.ratio.total_cmp(&y.ratio))
}
