//! Time blocks of residuals: the unit of the held-out tests and of the block bootstrap.
//!
//! A replay's residuals are smooth: neighbouring samples of a 50 Hz log say almost the same
//! thing, so counting them as independent makes every comparison look overwhelmingly
//! significant. Blocks of a few seconds — longer than the residuals' correlation time — are
//! treated as the independent observations instead:
//!
//! * **held-out test** ([`heldout_t`]): the validation blocks' reductions of the sum of squared
//!   residuals from one model to another, each channel normalised by the first model's mean
//!   square, as a one-sample t statistic over blocks;
//! * **block bootstrap** ([`Resample`]): a resample of a log draws, within each run and part
//!   (estimation, validation), as many blocks as there are, with replacement; a sample's weight
//!   is its block's multiplicity. Refitting on resamples and asking which effects are still
//!   selected is stability selection (as ensemble SINDy does).
//!
//! Blocks are counted from the first sample of each run's estimation and validation part.

use crate::evaluate::evaluation::{ChannelResult, Evaluation, push_estimation};
use crate::log::run::ChannelKind;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeMap;

/// One block: (run index, estimation part?, block number within the part).
pub type BlockKey = (usize, bool, usize);

/// Block length the search uses by default \[s\].
pub const DEFAULT_BLOCK_S: f64 = 4.0;

/// The block of each sample of a channel, in sample order.
pub fn sample_blocks(c: &ChannelResult, len: f64) -> Vec<(bool, usize)> {
    blocks_of(&c.times, &c.est, len)
}

/// The block of each sample with times `times` \[s\] and estimation flags `est`: whether it is
/// estimation data, and the index of its `len`-second block within its part.
pub fn blocks_of(times: &[f64], est: &[bool], len: f64) -> Vec<(bool, usize)> {
    let first_est = times.iter().zip(est).find(|(_, e)| **e).map(|(t, _)| *t);
    let first_val = times.iter().zip(est).find(|(_, e)| !**e).map(|(t, _)| *t);
    times
        .iter()
        .zip(est)
        .map(|(&t, &e)| {
            let t0 = if e { first_est } else { first_val }.unwrap_or(t);
            (e, ((t - t0) / len).floor().max(0.0) as usize)
        })
        .collect()
}

/// Sums of squared residuals and sample counts per block and channel kind.
pub fn block_sse(
    eval: &Evaluation,
    len: f64,
) -> BTreeMap<BlockKey, BTreeMap<ChannelKind, (f64, usize)>> {
    let mut out: BTreeMap<BlockKey, BTreeMap<ChannelKind, (f64, usize)>> = BTreeMap::new();
    for (ri, r) in eval.runs.iter().enumerate() {
        for c in &r.channels {
            for ((e, b), x) in sample_blocks(c, len).into_iter().zip(&c.resid) {
                let s = out
                    .entry((ri, e, b))
                    .or_default()
                    .entry(c.kind)
                    .or_insert((0.0, 0));
                s.0 += x * x;
                s.1 += 1;
            }
        }
    }
    out
}

/// A block-bootstrap draw: the weight (multiplicity) of every block.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Resample {
    /// Block length \[s\].
    pub len: f64,
    /// Multiplicity of each block (absent: 0).
    pub weights: BTreeMap<BlockKey, f64>,
}

impl Resample {
    /// Draws a resample of the blocks of `eval`: within each run and part, as many blocks as
    /// there are, with replacement, from a seeded generator.
    pub fn draw(eval: &Evaluation, len: f64, seed: u64) -> Resample {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let keys: Vec<BlockKey> = block_sse(eval, len).into_keys().collect();
        let mut groups: BTreeMap<(usize, bool), Vec<BlockKey>> = BTreeMap::new();
        for k in keys {
            groups.entry((k.0, k.1)).or_default().push(k);
        }
        let mut weights = BTreeMap::new();
        for blocks in groups.values() {
            for _ in 0..blocks.len() {
                let k = blocks[rng.random_range(0..blocks.len())];
                *weights.entry(k).or_insert(0.0) += 1.0;
            }
        }
        Resample { len, weights }
    }

    /// The weight of a block.
    pub fn weight(&self, key: BlockKey) -> f64 {
        self.weights.get(&key).copied().unwrap_or(0.0)
    }
}

/// Per channel kind: (weighted sum of squares, weighted count) over the estimation
/// (`est = true`) or validation samples, with block weights from `resample` (all 1 without).
pub fn part_sse(
    eval: &Evaluation,
    est: bool,
    resample: Option<&Resample>,
    len: f64,
) -> BTreeMap<ChannelKind, (f64, f64)> {
    let len = resample.map_or(len, |r| r.len);
    let mut out: BTreeMap<ChannelKind, (f64, f64)> = BTreeMap::new();
    for ((ri, e, b), per) in block_sse(eval, len) {
        if e != est {
            continue;
        }
        let w = resample.map_or(1.0, |r| r.weight((ri, e, b)));
        for (k, (s, n)) in per {
            let o = out.entry(k).or_insert((0.0, 0.0));
            o.0 += w * s;
            o.1 += w * n as f64;
        }
    }
    out
}

/// The held-out test of `b` against `a`: per validation block, the reduction of the sum of
/// squared residuals Σ_ch (SSE_a − SSE_b)/MSE_a,ch; the result is the t statistic of its mean
/// over blocks (weighted by `resample`), positive where `b` predicts better. 0 with fewer than
/// three blocks.
pub fn heldout_t(a: &Evaluation, b: &Evaluation, len: f64, resample: Option<&Resample>) -> f64 {
    let len = resample.map_or(len, |r| r.len);
    let sa = block_sse(a, len);
    let sb = block_sse(b, len);
    let mse: BTreeMap<ChannelKind, f64> = part_sse(a, false, None, len)
        .into_iter()
        .map(|(k, (s, n))| (k, (s / n.max(1.0)).max(1e-300)))
        .collect();
    let mut d = Vec::new();
    let mut w = Vec::new();
    for (key, pa) in sa.iter().filter(|(k, _)| !k.1) {
        let Some(pb) = sb.get(key) else { continue };
        let x: f64 = pa
            .iter()
            .map(|(k, (s, _))| (s - pb.get(k).map_or(*s, |v| v.0)) / mse[k])
            .sum();
        let wt = resample.map_or(1.0, |r| r.weight(*key));
        if wt > 0.0 {
            d.push(x);
            w.push(wt);
        }
    }
    let wsum: f64 = w.iter().sum();
    if d.len() < 3 || wsum <= 0.0 {
        return 0.0;
    }
    let m = d.iter().zip(&w).map(|(x, w)| x * w).sum::<f64>() / wsum;
    let v = d
        .iter()
        .zip(&w)
        .map(|(x, w)| w * (x - m).powi(2))
        .sum::<f64>()
        / (wsum - 1.0).max(1.0);
    if v <= 0.0 {
        return if m > 0.0 { f64::INFINITY } else { 0.0 };
    }
    m / (v / wsum).sqrt()
}

/// The estimation residuals of `eval` as in [`Evaluation::weighted`], each sample also
/// multiplied by the square root of its block's weight in `resample` (the least-squares form
/// of a weighted fit).
pub fn weighted_residuals(
    eval: &Evaluation,
    factor: &BTreeMap<ChannelKind, f64>,
    resample: Option<&Resample>,
) -> Vec<f64> {
    let mut out = Vec::new();
    for (ri, r) in eval.runs.iter().enumerate() {
        for c in &r.channels {
            push_weighted(
                &mut out,
                &c.resid,
                &c.times,
                &c.est,
                factor[&c.kind],
                resample.map(|rs| (rs, ri)),
            );
        }
    }
    out
}

/// Appends the estimation samples of `resid` (times `times` \[s\], estimation flags `est`) to
/// `out`, each multiplied by `w` and, with a resample `(rs, run index)`, by the square root
/// of its block's weight (the least-squares form of a weighted fit).
pub(crate) fn push_weighted(
    out: &mut Vec<f64>,
    resid: &[f64],
    times: &[f64],
    est: &[bool],
    w: f64,
    resample: Option<(&Resample, usize)>,
) {
    match resample {
        None => push_estimation(out, resid, est, w),
        Some((rs, ri)) => out.extend(
            resid
                .iter()
                .zip(blocks_of(times, est, rs.len))
                .filter(|(_, (e, _))| *e)
                .map(|(r, (e, b))| r * w * rs.weight((ri, e, b)).sqrt()),
        ),
    }
}
