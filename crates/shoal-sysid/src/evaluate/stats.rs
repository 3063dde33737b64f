//! Residual statistics: RMSE and fit %, autocorrelation, the Ljung–Box whiteness test, the
//! effective sample size of autocorrelated residuals, Pearson correlation, and the resolution
//! of a quantised sensor.

use shoal_model::math::wrap_pi;
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// Root mean square of `r`.
pub fn rms(r: &[f64]) -> f64 {
    if r.is_empty() {
        return 0.0;
    }
    (r.iter().map(|x| x * x).sum::<f64>() / r.len() as f64).sqrt()
}

/// Fit % = 100·(1 − ‖r‖ / ‖y − mean(y)‖) for residuals `r` of measurements whose deviations
/// from their mean are `dev` (NRMSE fit; 100 is perfect, 0 is no better than the mean, can be
/// negative).
pub fn fit_pct(r: &[f64], dev: &[f64]) -> f64 {
    let num = r.iter().map(|x| x * x).sum::<f64>().sqrt();
    let den = dev.iter().map(|x| x * x).sum::<f64>().sqrt();
    if den > 0.0 {
        100.0 * (1.0 - num / den)
    } else {
        0.0
    }
}

/// Sample autocorrelation of `r` at lags 0..=`max_lag` (mean removed; 1 at lag 0).
pub fn acf(r: &[f64], max_lag: usize) -> Vec<f64> {
    let n = r.len();
    if n < 2 {
        return vec![1.0];
    }
    let mean = r.iter().sum::<f64>() / n as f64;
    let c0: f64 = r.iter().map(|x| (x - mean).powi(2)).sum();
    if c0 <= 0.0 {
        return vec![1.0];
    }
    (0..=max_lag.min(n - 1))
        .map(|k| {
            r[..n - k]
                .iter()
                .zip(&r[k..])
                .map(|(a, b)| (a - mean) * (b - mean))
                .sum::<f64>()
                / c0
        })
        .collect()
}

/// Result of a Ljung–Box test.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct LjungBox {
    /// Statistic Q = n(n+2) Σ ρ_k²/(n−k).
    pub q: f64,
    /// Number of lags tested.
    pub lags: usize,
    /// p-value under whiteness (χ² with `lags` degrees of freedom).
    pub p_value: f64,
}

impl LjungBox {
    /// White at the 5 % level.
    pub fn white(&self) -> bool {
        self.p_value > 0.05
    }
}

/// Ljung–Box test of `r` over `lags` lags (fewer if the series is short).
pub fn ljung_box(r: &[f64], lags: usize) -> LjungBox {
    let n = r.len();
    let h = lags.min(n / 5).max(1);
    let rho = acf(r, h);
    let nf = n as f64;
    let q = nf
        * (nf + 2.0)
        * rho
            .iter()
            .enumerate()
            .skip(1)
            .map(|(k, p)| p * p / (nf - k as f64))
            .sum::<f64>();
    let p_value = ChiSquared::new(h as f64).map_or(f64::NAN, |d| 1.0 - d.cdf(q));
    LjungBox {
        q,
        lags: h,
        p_value,
    }
}

/// Variance inflation of the mean of an AR(1)-like series with lag-1 autocorrelation `rho1`:
/// (1 + ρ)/(1 − ρ) for ρ ∈ [0, 0.995], 1 for ρ ≤ 0.
pub fn inflation(rho1: f64) -> f64 {
    let r = rho1.clamp(0.0, 0.995);
    (1.0 + r) / (1.0 - r)
}

/// Pearson correlation of two equally long series (0 when either is constant).
pub fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    if n < 2 {
        return 0.0;
    }
    let ma = a[..n].iter().sum::<f64>() / n as f64;
    let mb = b[..n].iter().sum::<f64>() / n as f64;
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (x, y) = (a[i] - ma, b[i] - mb);
        sab += x * y;
        saa += x * x;
        sbb += y * y;
    }
    if saa > 0.0 && sbb > 0.0 {
        sab / (saa * sbb).sqrt()
    } else {
        0.0
    }
}

/// The resolution of a sampled signal: the step of the grid its values lie on (a pressure
/// sensor's ADC step, a logger's last digit), or 0 when they lie on none that is coarser than
/// the numbers' own rounding.
///
/// The step is the smallest gap between neighbouring distinct values (gaps within 1 % of it
/// count as it); the values lie on its grid when at most 1 % of them are further than 5 % of a
/// step from a multiple of it (counted from the smallest value) and at most a third of the
/// samples are distinct (a quantised signal repeats its levels).
pub fn resolution(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.len() < 10 {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    let lo = v[0];
    let scale = v[v.len() - 1].abs().max(lo.abs()).max(1e-300);
    let mut distinct: Vec<f64> = Vec::new();
    for &x in &v {
        if distinct.last().is_none_or(|&d| x - d > 1e-12 * scale) {
            distinct.push(x);
        }
    }
    if distinct.len() < 2 || distinct.len() * 3 > v.len() {
        return 0.0;
    }
    let q = distinct
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min);
    if !(q.is_finite() && q > 0.0) {
        return 0.0;
    }
    let off = v
        .iter()
        .filter(|&&x| {
            let k = (x - lo) / q;
            (k - k.round()).abs() > 0.05
        })
        .count();
    if off * 100 > v.len() { 0.0 } else { q }
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

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use rand_distr::{Distribution, StandardNormal};

    #[test]
    fn white_noise_is_white_and_a_random_walk_is_not() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let w: Vec<f64> = (0..2000).map(|_| StandardNormal.sample(&mut rng)).collect();
        let lb = ljung_box(&w, 20);
        assert!(lb.white(), "{lb:?}");
        let mut s = 0.0;
        let walk: Vec<f64> = w
            .iter()
            .map(|x| {
                s += x;
                s
            })
            .collect();
        let lb = ljung_box(&walk, 20);
        assert!(lb.p_value < 1e-6, "{lb:?}");
        assert!(acf(&walk, 1)[1] > 0.95);
        assert!(inflation(acf(&w, 1)[1]) < 1.2);
    }

    #[test]
    fn fit_and_correlation() {
        assert_eq!(fit_pct(&[0.0, 0.0], &[1.0, -1.0]), 100.0);
        assert!((fit_pct(&[1.0, -1.0], &[1.0, -1.0])).abs() < 1e-12);
        assert!((correlation(&[1.0, 2.0, 3.0], &[2.0, 4.0, 6.0]) - 1.0).abs() < 1e-12);
        assert!((rms(&[3.0, -3.0]) - 3.0).abs() < 1e-12);
    }

    #[test]
    fn resolution_of_a_quantised_sensor_and_of_a_continuous_signal() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        // A slow dive read by a 1.8 mm ADC with 0.5 mm noise before it, offset by −486.4 mm.
        let q = 1.8e-3;
        let depth: Vec<f64> = (0..3000)
            .map(|i| {
                let z = 0.3 * (i as f64 * 0.002).sin()
                    + 0.5e-3 * Distribution::<f64>::sample(&StandardNormal, &mut rng);
                -0.4864 + q * ((z + 0.4864) / q).round()
            })
            .collect();
        let r = resolution(&depth);
        assert!((r - q).abs() < 1e-9, "{r}");
        // Printed with six significant digits it stays on its grid.
        let printed: Vec<f64> = depth
            .iter()
            .map(|x| format!("{x:.6}").parse().unwrap())
            .collect();
        assert!((resolution(&printed) - q).abs() < 1e-6);
        // A gyro's rate is not quantised (every value distinct).
        let rate: Vec<f64> = (0..3000)
            .map(|_| 0.01 * Distribution::<f64>::sample(&StandardNormal, &mut rng))
            .collect();
        assert_eq!(resolution(&rate), 0.0);
        // Too few samples, or a constant: no grid to speak of.
        assert_eq!(resolution(&[1.0, 2.0]), 0.0);
        assert_eq!(resolution(&[0.5; 100]), 0.0);
    }
}
