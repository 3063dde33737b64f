//! The water's wandering current, estimated on a re-anchored replay as a prediction-error
//! method estimates its disturbance model.
//!
//! In a pool with a pump running, or in the sea, the water wanders: a current of a few mm/s to
//! cm/s that changes over seconds to minutes carries the hull — its depth and its position —
//! without changing how it moves through the water (the equation of motion is written in the
//! velocity relative to the water, [`shoal_model::lanes`]). No vehicle model has it, and in a
//! replay re-anchored every few seconds its transport since the last anchor is most of what is
//! left on the depth: on the kit's gusty missions five times the sensor noise, so much that an
//! effect the model lacks changes the error by a few per cent only, and in calm water the same
//! missions give up their hidden effects (docs/validation.md, "Long closed-loop test set").
//!
//! The current is modelled as what it is, a random process, and estimated from the data as a
//! Kalman filter estimates a disturbance: along each transported channel ([`transported`]) an
//! Ornstein–Uhlenbeck velocity `c` (standard deviation σ, correlation time τ) whose integral
//! `d` since the last anchor adds to the model's prediction, the channel read with white noise.
//! The filter runs forward along each run's residuals and turns each into its innovation — the
//! measurement less the model's prediction and the transport the filter predicts from the
//! samples before it. σ and τ are the maximum-likelihood values over a grid ([`estimate`]) on
//! the baseline's re-anchored replay; where no current beats white noise alone, none is
//! reported. The report says how much of the residual the water's transport is
//! ([`Current::residual_m`] against [`Current::innovation_m`]): structure no catalogue effect
//! can explain, named.
//!
//! The search does not judge candidates by the innovations. Tried on the kit's gusty
//! five-minute missions (docs/validation.md), it cleaned the null missions and halved the
//! search time but named no more hidden effects: what a model gets wrong in the steady state
//! (a slow sink, a battery's sag, a thrust deficit at full command) looks like a wandering
//! current and is taken for water, and what is left of an effect — its transients — looks
//! like a sensor delay.

use crate::evaluate::evaluation::{Evaluation, noise_floor};
use crate::log::run::ChannelKind;
use std::collections::BTreeMap;

/// A wandering current along one transported channel.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Current {
    /// Standard deviation of the current's velocity along the channel \[m/s\].
    pub sigma_m_s: f64,
    /// Correlation time of the current \[s\].
    pub tau_s: f64,
    /// Standard deviation of the channel's white measurement noise \[m\].
    pub noise_m: f64,
    /// RMS of the estimation residuals it was estimated from (the baseline's) \[m\].
    pub residual_m: f64,
    /// RMS of their innovations through it: what is left once the water's transport is
    /// predicted \[m\].
    pub innovation_m: f64,
}

/// Whether a current carries the quantity a channel measures (the depth, a tracked position).
pub fn transported(kind: ChannelKind) -> bool {
    matches!(kind, ChannelKind::Depth | ChannelKind::X | ChannelKind::Y)
}

/// One channel of one run as the filter reads it.
#[derive(Clone, Copy, Debug)]
pub struct Series<'a> {
    /// The samples' times, on the replay's clock (the reading's time less any sensor delay) \[s\].
    pub times: &'a [f64],
    /// The anchors' times on the same clock, ascending \[s\]: there the replay is set to the
    /// measurement and the transport starts again from zero.
    pub resets: &'a [f64],
    /// Which samples count in the likelihood (the estimation part).
    pub counted: &'a [bool],
}

/// Correlation times tried by [`estimate`] \[s\].
const TAUS_S: [f64; 7] = [2.0, 4.0, 8.0, 15.0, 30.0, 60.0, 120.0];

/// Current standard deviations tried by [`estimate`] \[m/s\] (0.25 mm/s … 6.4 cm/s).
const SIGMAS_M_S: [f64; 9] = [
    0.00025, 0.0005, 0.001, 0.002, 0.004, 0.008, 0.016, 0.032, 0.064,
];

impl Current {
    /// Runs the filter along `series`: each residual in `resid` becomes its innovation (the
    /// residual less the transport the filter predicted for it from the samples before).
    /// Returns −2 log-likelihood (without the 2π term) over the counted samples. Non-finite
    /// residuals are passed over.
    pub fn filter(&self, series: &Series, resid: &mut [f64]) -> f64 {
        let r_noise = self.noise_m * self.noise_m;
        let q_rate = self.sigma_m_s * self.sigma_m_s;
        // State: transport since the last anchor d [m], current c [m/s]; covariance P.
        let (mut d, mut c) = (0.0, 0.0);
        let (mut pdd, mut pdc, mut pcc) = (0.0, 0.0, q_rate);
        let mut t_prev = series.times.first().copied().unwrap_or(0.0);
        let mut next_reset = series.resets.partition_point(|&a| a <= t_prev);
        let mut m2ll = 0.0;
        let advance = |d: &mut f64, c: &mut f64, p: (&mut f64, &mut f64, &mut f64), dt: f64| {
            if dt <= 0.0 {
                return;
            }
            let phi = (-dt / self.tau_s).exp();
            let g = self.tau_s * (1.0 - phi);
            *d += g * *c;
            *c *= phi;
            let (pdd, pdc, pcc) = p;
            // F P Fᵀ with F = [[1, g], [0, φ]], plus the OU increment's covariance.
            let q = q_rate * (1.0 - phi * phi);
            let ndd = *pdd + 2.0 * g * *pdc + g * g * *pcc + q * dt * dt / 3.0;
            let ndc = phi * (*pdc + g * *pcc) + q * dt / 2.0;
            let ncc = phi * phi * *pcc + q;
            (*pdd, *pdc, *pcc) = (ndd, ndc, ncc);
        };
        for (k, &t) in series.times.iter().enumerate() {
            while next_reset < series.resets.len() && series.resets[next_reset] <= t {
                let a = series.resets[next_reset];
                advance(&mut d, &mut c, (&mut pdd, &mut pdc, &mut pcc), a - t_prev);
                // The anchor sets the replay to the measurement: no transport so far.
                d = 0.0;
                (pdd, pdc) = (0.0, 0.0);
                t_prev = a;
                next_reset += 1;
            }
            advance(&mut d, &mut c, (&mut pdd, &mut pdc, &mut pcc), t - t_prev);
            t_prev = t;
            let r = resid[k];
            if !r.is_finite() {
                continue;
            }
            let s = pdd + r_noise;
            let e = r - d;
            resid[k] = e;
            if series.counted.get(k).copied().unwrap_or(false) {
                m2ll += e * e / s + s.ln();
            }
            let (kd, kc) = (pdd / s, pdc / s);
            d += kd * e;
            c += kc * e;
            (pdd, pdc, pcc) = (pdd - kd * pdd, pdc - kd * pdc, pcc - kc * pdc);
        }
        m2ll
    }
}

/// −2 log-likelihood of white noise of standard deviation `noise` for the counted samples.
fn white(series: &[(Series, &[f64])], noise: f64) -> f64 {
    let v = noise * noise;
    series
        .iter()
        .flat_map(|(s, r)| r.iter().zip(s.counted))
        .filter(|(r, c)| **c && r.is_finite())
        .map(|(r, _)| r * r / v + v.ln())
        .sum()
}

/// The maximum-likelihood current over the grid of σ and τ for the residuals `series`
/// (each with its run's residuals) read with white noise of `noise_m` \[m\], or `None` when
/// no current explains them better than that noise alone (by more than a BIC's penalty for
/// the two parameters).
pub fn estimate(series: &[(Series, &[f64])], noise_m: f64) -> Option<Current> {
    if noise_m.is_nan() || noise_m <= 0.0 {
        return None;
    }
    let counted: usize = series
        .iter()
        .map(|(s, r)| {
            r.iter()
                .zip(s.counted)
                .filter(|(r, c)| **c && r.is_finite())
                .count()
        })
        .sum();
    let penalty = 2.0 * (counted.max(1) as f64).ln();
    let mut best = (white(series, noise_m) - penalty, None);
    let residual_m = counted_rms(series.iter().map(|(s, r)| (s.counted, *r)));
    for &tau_s in &TAUS_S {
        for &sigma_m_s in &SIGMAS_M_S {
            let cur = Current {
                sigma_m_s,
                tau_s,
                noise_m,
                residual_m,
                innovation_m: 0.0,
            };
            let mut innovations = Vec::with_capacity(series.len());
            let mut m2ll = 0.0;
            for (s, r) in series {
                let mut e = r.to_vec();
                m2ll += cur.filter(s, &mut e);
                innovations.push(e);
            }
            if m2ll.is_finite() && m2ll < best.0 {
                let innovation_m = counted_rms(
                    series
                        .iter()
                        .zip(&innovations)
                        .map(|((s, _), e)| (s.counted, e.as_slice())),
                );
                best = (
                    m2ll,
                    Some(Current {
                        innovation_m,
                        ..cur
                    }),
                );
            }
        }
    }
    best.1
}

/// RMS of the counted finite values of (counted, values) pairs.
fn counted_rms<'a>(series: impl Iterator<Item = (&'a [bool], &'a [f64])>) -> f64 {
    let (mut ss, mut n) = (0.0, 0usize);
    for (counted, values) in series {
        for (v, _) in values
            .iter()
            .zip(counted)
            .filter(|(v, c)| **c && v.is_finite())
        {
            ss += v * v;
            n += 1;
        }
    }
    if n == 0 { 0.0 } else { (ss / n as f64).sqrt() }
}

/// The current of each transported channel of `eval` — the evaluation of a re-anchored
/// replay made without any current, its runs anchored at `resets[run]` (replay clock, \[s\])
/// and read `delay` \[s\] late —, read with the channel's noise floor; channels where no
/// current beats white noise are left out.
pub fn of_evaluation(
    eval: &Evaluation,
    resets: &[Vec<f64>],
    delay: f64,
) -> BTreeMap<ChannelKind, Current> {
    let mut out = BTreeMap::new();
    for &kind in eval.metrics.keys().filter(|k| transported(**k)) {
        let mut held = Vec::new();
        for (r, resets) in eval.runs.iter().zip(resets) {
            for c in r.channels.iter().filter(|c| c.kind == kind) {
                let times: Vec<f64> = c.times.iter().map(|t| t - delay).collect();
                held.push((times, resets, c));
            }
        }
        let series: Vec<(Series, &[f64])> = held
            .iter()
            .map(|(times, resets, c)| {
                let s = Series {
                    times,
                    resets,
                    counted: &c.est,
                };
                (s, c.resid.as_slice())
            })
            .collect();
        if let Some(c) = estimate(&series, noise_floor(eval, kind)) {
            out.insert(kind, c);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use rand_distr::{Distribution, StandardNormal};

    /// A residual of one run with its sample times and anchors, every sample counted.
    struct Carried {
        times: Vec<f64>,
        resets: Vec<f64>,
        resid: Vec<f64>,
        counted: Vec<bool>,
    }

    impl Carried {
        fn series(&self) -> Series<'_> {
            Series {
                times: &self.times,
                resets: &self.resets,
                counted: &self.counted,
            }
        }
    }

    /// A residual that is a current's transport since the last anchor (σ, τ; anchors every
    /// `every` s) plus white noise, sampled at 20 Hz for `span` s; with its anchors.
    fn carried(sigma: f64, tau: f64, noise: f64, every: f64, span: f64) -> Carried {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut n = || -> f64 { StandardNormal.sample(&mut rng) };
        let h = 0.001;
        let (mut c, mut d) = (sigma * n(), 0.0);
        let (mut times, mut resid) = (Vec::new(), Vec::new());
        let resets: Vec<f64> = (1..)
            .map(|k| k as f64 * every)
            .take_while(|&a| a < span)
            .collect();
        let steps = (span / h).round() as usize;
        let mut next = 0;
        for i in 0..=steps {
            let t = i as f64 * h;
            if next < resets.len() && t >= resets[next] - 1e-12 {
                d = 0.0;
                next += 1;
            }
            if i % 50 == 0 {
                times.push(t);
                resid.push(d + noise * n());
            }
            d += c * h;
            c += -c / tau * h + sigma * (2.0 * h / tau).sqrt() * n();
        }
        let counted = vec![true; times.len()];
        Carried {
            times,
            resets,
            resid,
            counted,
        }
    }

    fn rms(v: &[f64]) -> f64 {
        (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt()
    }

    #[test]
    fn a_wandering_current_is_estimated_and_taken_out_of_the_residual() {
        // 5 mm/s over 15 s, 1.7 mm of sensor noise, anchors every 2 s: the transport is a few
        // times the noise, the innovations are back near the noise.
        let run = carried(0.005, 15.0, 0.0017, 2.0, 600.0);
        let (s, resid) = (run.series(), &run.resid);
        let raw = rms(resid);
        assert!(raw > 2.5 * 0.0017, "{raw}");
        let cur = estimate(&[(s, resid)], 0.0017).expect("a current");
        assert!((0.002..=0.008).contains(&cur.sigma_m_s), "{cur:?}");
        assert!((8.0..=30.0).contains(&cur.tau_s), "{cur:?}");
        let mut e = resid.clone();
        cur.filter(&s, &mut e);
        let inno = rms(&e);
        assert!(inno < 1.4 * 0.0017, "innovations {inno} against raw {raw}");
        assert!((cur.residual_m - raw).abs() < 1e-12 && (cur.innovation_m - inno).abs() < 1e-12);
        // The innovations are white (the raw residual is a ramp per horizon): lag-1
        // autocorrelation near zero.
        let lag1 = |v: &[f64]| {
            let c1: f64 = v.windows(2).map(|w| w[0] * w[1]).sum();
            c1 / v.iter().map(|x| x * x).sum::<f64>()
        };
        assert!(lag1(resid) > 0.5, "raw lag-1 {}", lag1(resid));
        assert!(lag1(&e).abs() < 0.1, "innovations' lag-1 {}", lag1(&e));
    }

    #[test]
    fn white_noise_gets_no_current() {
        let run = carried(0.0, 15.0, 0.0017, 2.0, 600.0);
        let (s, resid) = (run.series(), &run.resid);
        assert_eq!(estimate(&[(s, resid)], 0.0017), None);
    }

    #[test]
    fn the_filter_predicts_from_the_past_only() {
        let run = carried(0.005, 15.0, 0.0017, 2.0, 60.0);
        let (s, resid) = (run.series(), &run.resid);
        let cur = Current {
            sigma_m_s: 0.005,
            tau_s: 15.0,
            noise_m: 0.0017,
            residual_m: 0.0,
            innovation_m: 0.0,
        };
        let filtered = |r: &[f64]| {
            let mut e = r.to_vec();
            cur.filter(&s, &mut e);
            e
        };
        let a = filtered(resid);
        let mut later = resid.clone();
        for x in &mut later[600..] {
            *x += 1.0;
        }
        let b = filtered(&later);
        assert_eq!(a[..600], b[..600]);
        assert_ne!(a[600], b[600]);
    }
}
