//! The baseline's estimation residuals correlated with candidate regressors (inputs, their
//! magnitudes and thrust-like squares, the replayed rates): the diagnostics of `report.json`
//! and `report.md`.

use super::wording::label;
use crate::evaluate::dataset::{Dataset, RunData};
use crate::evaluate::evaluation::{ChannelResult, Evaluation};
use crate::evaluate::stats;
use crate::log::run::{Channel, ChannelKind};
use std::collections::BTreeMap;

/// Pearson correlations of the baseline's estimation residuals with candidate regressors,
/// strongest first, per channel.
pub fn correlations(ds: &Dataset, ev: &Evaluation) -> BTreeMap<ChannelKind, Vec<(String, f64)>> {
    let mut out = BTreeMap::new();
    for &kind in &ds.kinds {
        let mut resid = Vec::new();
        let mut regs: BTreeMap<String, Vec<f64>> = BTreeMap::new();
        for (rd, rr) in ds.runs.iter().zip(&ev.runs) {
            for c in rr.channels.iter().filter(|c| c.kind == kind) {
                collect_regressors(rd, c, &mut resid, &mut regs);
            }
        }
        let mut list: Vec<(String, f64)> = regs
            .into_iter()
            .filter(|(_, v)| v.len() == resid.len())
            .map(|(n, v)| {
                let r = stats::correlation(&resid, &v);
                (n, r)
            })
            .filter(|(_, r)| r.is_finite() && *r != 0.0)
            .collect();
        list.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
        out.insert(kind, list);
    }
    out
}

fn collect_regressors(
    rd: &RunData,
    c: &ChannelResult,
    resid: &mut Vec<f64>,
    regs: &mut BTreeMap<String, Vec<f64>>,
) {
    let run = &rd.run;
    let t0 = run.t[0];
    let idx: Vec<usize> = (0..c.times.len()).filter(|&i| c.est[i]).collect();
    if idx.is_empty() {
        return;
    }
    // Rows of the samples (for the inputs in force).
    let Some(ch) = channel_of(rd, c.kind) else {
        return;
    };
    let mut push = |name: String, v: f64| regs.entry(name).or_default().push(v);
    for &i in &idx {
        resid.push(c.resid[i]);
        let row = ch.rows[i];
        push("time".into(), c.times[i] - t0);
        for inp in &run.inputs {
            let u = inp.values[row];
            push(format!("u.{}", inp.name), u);
            push(format!("|u.{}|", inp.name), u.abs());
            push(
                format!("u.{}·|u.{}| (thrust-like)", inp.name, inp.name),
                u * u.abs(),
            );
            push(format!("sign(u.{})", inp.name), u.signum());
        }
        // Rate of the replayed channel and its square: unmodelled damping-like terms.
        let j0 = i.saturating_sub(1);
        let j1 = (i + 1).min(c.times.len() - 1);
        let dt = (c.times[j1] - c.times[j0]).max(1e-9);
        let rate = (c.predicted[j1] - c.predicted[j0]) / dt;
        push(format!("d/dt {} (replayed)", label(c.kind)), rate);
        push(
            format!("|d/dt {0}|·d/dt {0} (replayed)", label(c.kind)),
            rate * rate.abs(),
        );
    }
}

/// The measured channel of `kind` among the run's used channels.
pub(super) fn channel_of(rd: &RunData, kind: ChannelKind) -> Option<&Channel> {
    rd.channels
        .iter()
        .map(|&i| &rd.run.channels[i])
        .find(|x| x.kind == kind)
}
