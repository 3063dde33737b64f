//! The measures the search compares models by: information criteria (BIC, and the effective
//! ΔBIC with the residuals' correlation taken into account), the held-out gain, materiality
//! and closure of the gap to the noise floor, each also on the blocks of a bootstrap resample,
//! and the Wald distance of an effect's parameters from their null values. The rules
//! (`rules.rs`) decide with them.

use super::fitted::Fit;
use crate::evaluate::blocks::{Resample, part_sse};
use crate::evaluate::evaluation::Evaluation;
pub use crate::evaluate::evaluation::noise_floor;
use crate::log::run::ChannelKind;
use nalgebra::DMatrix;
use statrs::distribution::{ChiSquared, ContinuousCDF, Normal};
use std::collections::BTreeMap;

/// Mean over the channels `b` changes of 1 − RMSE_b/RMSE_a on validation data. A channel the
/// change does not touch (a heave effect's yaw channel) is left out: the gain of an effect
/// must not depend on how many unrelated channels a log happens to carry.
pub fn gain(a: &Evaluation, b: &Evaluation) -> f64 {
    gain_resampled(a, b, None)
}

/// [`gain`] on the validation blocks of a resample (all blocks once without).
pub fn gain_resampled(a: &Evaluation, b: &Evaluation, rs: Option<&Resample>) -> f64 {
    if rs.is_none() {
        let ks = changed(a, b);
        let s: f64 = ks
            .iter()
            .map(|k| 1.0 - b.metrics[k].rmse / a.metrics[k].rmse)
            .sum();
        return if ks.is_empty() {
            0.0
        } else {
            s / ks.len() as f64
        };
    }
    let len = rs.map_or(crate::evaluate::blocks::DEFAULT_BLOCK_S, |r| r.len);
    let pa = part_sse(a, false, rs, len);
    let pb = part_sse(b, false, rs, len);
    let mut s = 0.0;
    let mut n = 0;
    for (k, (sa, na)) in &pa {
        if let Some((sb, nb)) = pb.get(k)
            && *sa > 0.0
            && *na > 0.0
            && *nb > 0.0
            && counts(a, b, *k, *sa, *sb)
        {
            s += 1.0 - ((sb / nb) / (sa / na)).sqrt();
            n += 1;
        }
    }
    if n > 0 { s / n as f64 } else { 0.0 }
}

/// Every channel of `a` (that `b` also measures) with the relative reduction of its pooled
/// validation RMSE from `a` to `b` [%] (its
/// [`rmse_gain_pct`](crate::evaluate::evaluation::rmse_gain_pct), as a report's table shows
/// it; negative: `b` made the channel worse), in channel order.
pub fn channel_gains_pct(a: &Evaluation, b: &Evaluation) -> Vec<(ChannelKind, f64)> {
    a.metrics
        .iter()
        .filter_map(|(k, ma)| {
            b.metrics.get(k).map(|mb| {
                (
                    *k,
                    crate::evaluate::evaluation::rmse_gain_pct(ma.rmse, mb.rmse),
                )
            })
        })
        .collect()
}

/// The mean over every channel of [`channel_gains_pct`] [%] (0 without channels).
pub fn mean_channel_gain_pct(a: &Evaluation, b: &Evaluation) -> f64 {
    let gains = channel_gains_pct(a, b);
    if gains.is_empty() {
        0.0
    } else {
        gains.iter().map(|g| g.1).sum::<f64>() / gains.len() as f64
    }
}

/// The channels whose validation error `b` changes against `a` in a way their sensors can
/// show (those [`gain`] averages over), in channel order.
pub fn changed(a: &Evaluation, b: &Evaluation) -> Vec<ChannelKind> {
    a.metrics
        .iter()
        .filter(|(k, ma)| {
            b.metrics
                .get(k)
                .is_some_and(|mb| ma.rmse > 0.0 && counts(a, b, **k, ma.rmse, mb.rmse))
        })
        .map(|(k, _)| *k)
        .collect()
}

/// Whether a channel's error measure moved from `a` to `b` by more than rounding.
fn touched(a: f64, b: f64) -> bool {
    (a - b).abs() > 1e-9 * a.abs().max(b.abs())
}

/// RMS difference of the held-out predictions of channel `kind` between `a` and `b`
/// (channel unit).
pub fn moved(a: &Evaluation, b: &Evaluation, kind: ChannelKind) -> f64 {
    let mut ss = 0.0;
    let mut n = 0usize;
    for (ra, rb) in a.runs.iter().zip(&b.runs) {
        for (ca, cb) in ra.channels.iter().zip(&rb.channels) {
            if ca.kind != kind || cb.kind != kind {
                continue;
            }
            for ((pa, pb), e) in ca.predicted.iter().zip(&cb.predicted).zip(&ca.est) {
                if !*e {
                    ss += (pb - pa) * (pb - pa);
                    n += 1;
                }
            }
        }
    }
    if n > 0 { (ss / n as f64).sqrt() } else { 0.0 }
}

/// Whether going from `a` to `b` changes channel `kind` in a way its sensor can show: its
/// error measure moves (`ea` → `eb`, [`touched`]) and its held-out prediction moves by at
/// least one step of the sensor's resolution (RMS): a change smaller than one bit of a
/// quantised sensor is indistinguishable from the quantisation itself (a "bias" of a
/// millimetre on a 1.8 mm pressure sensor whose vehicle hardly moves), so it is no evidence
/// for an effect.
fn counts(a: &Evaluation, b: &Evaluation, kind: ChannelKind, ea: f64, eb: f64) -> bool {
    touched(ea, eb)
        && a.metrics
            .get(&kind)
            .is_none_or(|m| m.resolution <= 0.0 || moved(a, b, kind) >= m.resolution)
}

/// BIC of an evaluation with `k` free parameters: Σ_ch n_ch·ln(SSE_ch/n_ch) + k·ln n over the
/// estimation samples (Gaussian likelihood with each channel's variance profiled out).
pub fn bic(eval: &Evaluation, k: usize) -> f64 {
    bic_resampled(eval, k, None)
}

/// [`bic`] on the estimation blocks of a resample (every sample once without).
pub fn bic_resampled(eval: &Evaluation, k: usize, rs: Option<&Resample>) -> f64 {
    let mut b = 0.0;
    let mut ntot = 0.0;
    if rs.is_none() {
        for m in eval.metrics.values() {
            let n = m.n_est.max(1) as f64;
            b += n * (m.sse_est / n).max(1e-300).ln();
            ntot += n;
        }
    } else {
        for (s, n) in part_sse(eval, true, rs, 0.0).values() {
            let n = n.max(1.0);
            b += n * (s / n).max(1e-300).ln();
            ntot += n;
        }
    }
    b + k as f64 * ntot.max(1.0).ln()
}

/// ΔBIC of going from `a` to `b`.
pub fn delta_bic(a: &Fit, b: &Fit) -> f64 {
    bic(&b.eval, b.k) - bic(&a.eval, a.k)
}

/// ΔBIC of going from the smaller model `a` to the larger `b` with each channel's sample
/// count replaced by its effective count n·(1−ρ₁)/(1+ρ₁), ρ₁ the lag-1 autocorrelation of
/// `b`'s estimation residuals: a smooth residual that a mis-shaped extra effect only bends
/// carries the information of a few dozen samples, not of thousands. (On a resample, counts
/// and sums are the resample's.)
pub fn delta_bic_eff(a: &Fit, b: &Fit, rs: Option<&Resample>) -> f64 {
    let pa = part_sse(&a.eval, true, rs, rs.map_or(1.0, |r| r.len));
    let pb = part_sse(&b.eval, true, rs, rs.map_or(1.0, |r| r.len));
    let mut d = 0.0;
    let mut ntot = 0.0;
    for (k, (sb, nb)) in &pb {
        let Some((sa, na)) = pa.get(k) else { continue };
        if *na <= 0.0 || *nb <= 0.0 {
            continue;
        }
        let rho = b
            .eval
            .metrics
            .get(k)
            .map_or(0.0, |m| m.rho1_est)
            .clamp(0.0, 0.999);
        let n_eff = (nb * (1.0 - rho) / (1.0 + rho)).max(1.0);
        d += n_eff * ((sb / nb).max(1e-300) / (sa / na).max(1e-300)).ln();
        ntot += n_eff;
    }
    d + (b.k as f64 - a.k as f64) * ntot.max(2.0).ln()
}

/// Held-out RMSE per channel kind: the evaluation's own, or on the validation blocks of a
/// resample (weighted as drawn).
fn heldout_rmse(eval: &Evaluation, rs: Option<&Resample>) -> BTreeMap<ChannelKind, f64> {
    match rs {
        None => eval.metrics.iter().map(|(k, m)| (*k, m.rmse)).collect(),
        Some(r) => part_sse(eval, false, Some(r), r.len)
            .into_iter()
            .filter(|(_, (_, n))| *n > 0.0)
            .map(|(k, (s, n))| (k, (s / n).sqrt()))
            .collect(),
    }
}

/// How much going from `a` to `b` lowers the held-out RMSE, as a fraction of the baseline's
/// held-out RMSE (mean over the channels the change touches): an effect that only trims what is left after the
/// others — a form mismatch being soaked up — moves little of the error the user started
/// with.
pub fn material(baseline: &Evaluation, a: &Evaluation, b: &Evaluation) -> f64 {
    material_resampled(baseline, a, b, None)
}

/// [`material`] on the validation blocks of a resample.
pub fn material_resampled(
    baseline: &Evaluation,
    a: &Evaluation,
    b: &Evaluation,
    rs: Option<&Resample>,
) -> f64 {
    let (r0, ra, rb) = (
        heldout_rmse(baseline, rs),
        heldout_rmse(a, rs),
        heldout_rmse(b, rs),
    );
    let mut s = 0.0;
    let mut n = 0;
    for (k, m0) in &r0 {
        if let (Some(ma), Some(mb)) = (ra.get(k), rb.get(k))
            && *m0 > 0.0
            && counts(a, b, *k, *ma, *mb)
        {
            s += (ma - mb) / m0;
            n += 1;
        }
    }
    if n > 0 { s / n as f64 } else { 0.0 }
}

/// `b`'s held-out RMSE relative to `a`'s, averaged over every channel of `a` (1: no change,
/// below 1: `b` predicts the held-out data better). Unlike the gain of a candidate (averaged
/// over the channels it touches), comparable between candidates that touch different channels.
pub fn heldout_ratio(a: &Evaluation, b: &Evaluation) -> f64 {
    let (ra, rb) = (heldout_rmse(a, None), heldout_rmse(b, None));
    let ratios: Vec<f64> = ra
        .iter()
        .filter(|(_, m)| **m > 0.0)
        .map(|(k, m)| rb.get(k).map_or(1.0, |r| r / m))
        .collect();
    if ratios.is_empty() {
        1.0
    } else {
        ratios.iter().sum::<f64>() / ratios.len() as f64
    }
}

/// How far above its noise floor a channel's held-out RMSE must be for its residual to count
/// as structure (for the closure rule and for "unexplained structure").
pub const STRUCTURE_RATIO: f64 = 2.0;

/// How much of the gap between `a`'s held-out RMSE and the noise floor going to `b` closes
/// (mean over the channels the change touches; 0 on a channel where `a` is within
/// [`STRUCTURE_RATIO`] of its floor: what is left there is mostly noise, and closing such a gap
/// says nothing).
pub fn closure(a: &Evaluation, b: &Evaluation) -> f64 {
    closure_resampled(a, b, None)
}

/// [`closure`] on the validation blocks of a resample (the noise floor stays the full log's:
/// it is the sensor's, not the resample's).
pub fn closure_resampled(a: &Evaluation, b: &Evaluation, rs: Option<&Resample>) -> f64 {
    let (ra, rb) = (heldout_rmse(a, rs), heldout_rmse(b, rs));
    let mut s = 0.0;
    let mut n = 0;
    for (k, ma) in &ra {
        if let Some(mb) = rb.get(k)
            && counts(a, b, *k, *ma, *mb)
        {
            let floor = noise_floor(a, *k);
            let gap = ma - floor;
            s += if *ma > STRUCTURE_RATIO * floor && gap > 0.0 {
                ((ma - mb) / gap).min(1.0)
            } else {
                0.0
            };
            n += 1;
        }
    }
    if n > 0 { s / n as f64 } else { 0.0 }
}

/// Distance of `effect`'s parameters from their null values, jointly (Wald test with the
/// honest covariance, or the white-residual one with `white`), as the equivalent number of
/// standard deviations of a normal variable: for one parameter |θ − θ₀|/σ.
pub fn z_of(fit: &Fit, effect: &str, white: bool) -> f64 {
    let Some(ei) = fit.effects.iter().position(|e| e.effect.name() == effect) else {
        return 0.0;
    };
    let Some(cov) = (if white { &fit.cov_white } else { &fit.cov }) else {
        return 0.0;
    };
    let idx: Vec<usize> = fit
        .free
        .iter()
        .enumerate()
        .filter(|(_, (e, j))| *e == ei && !fit.effects[*e].params[*j].shape)
        .map(|(k, _)| k)
        .collect();
    if idx.is_empty() {
        return 0.0;
    }
    let d = nalgebra::DVector::from_iterator(
        idx.len(),
        idx.iter().map(|&k| {
            let (e, j) = fit.free[k];
            let p = &fit.effects[e].params[j];
            p.value - p.null
        }),
    );
    let sub = DMatrix::from_fn(idx.len(), idx.len(), |a, b| cov[(idx[a], idx[b])]);
    let Some(inv) = sub.try_inverse() else {
        return 0.0;
    };
    let w = (d.transpose() * inv * &d)[(0, 0)].max(0.0);
    if idx.len() == 1 {
        return w.sqrt();
    }
    let p = ChiSquared::new(idx.len() as f64).map_or(0.0, |c| c.sf(w));
    if p < 1e-15 {
        // Beyond the precision of the tail: the normal deviate of the same χ² (≈ √W).
        return (w - (idx.len() as f64 - 1.0)).max(0.0).sqrt().max(8.0);
    }
    Normal::standard().inverse_cdf(1.0 - 0.5 * p)
}
