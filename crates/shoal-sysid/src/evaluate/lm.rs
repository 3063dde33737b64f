//! Bounded Levenberg–Marquardt for small nonlinear least-squares problems whose residuals come
//! from a simulation: forward-difference Jacobian, Marquardt's diagonal scaling, box bounds by
//! projection, parameters scaled to comparable magnitudes.
//!
//! Written here rather than taken from a crate: the maintained `levenberg-marquardt` crate
//! depends on an older nalgebra (0.34) than the workspace (0.35) and has no bounds, and every
//! effect parameter has physical bounds. The algorithm is the textbook one (Madsen, Nielsen &
//! Tingleff, *Methods for non-linear least squares problems*, 2004, alg. 3.16) with
//! projection onto the box.

use nalgebra::{DMatrix, DVector};

/// Settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LmOptions {
    /// Largest number of accepted-or-rejected steps.
    pub max_iterations: usize,
    /// Stop when a step lowers the cost by less than this fraction. The search's costs are
    /// weighted by the inverse residual variance, so the cost is about the number of
    /// residuals n and a relative step δ moves −2 log L by about n·δ: the default 1e-6 stops
    /// where a step gains less than 0.03 log-likelihood units on 30 000 residuals, far below
    /// every decision the search makes on BIC differences (≥ 2).
    pub rel_tolerance: f64,
    /// Finite-difference step in scaled units.
    pub fd_step: f64,
}

impl Default for LmOptions {
    fn default() -> Self {
        Self {
            max_iterations: 25,
            rel_tolerance: 1e-6,
            fd_step: 1e-4,
        }
    }
}

/// The outcome of a minimisation.
#[derive(Clone, Debug, PartialEq)]
pub struct LmResult {
    /// Parameters at the minimum found.
    pub x: Vec<f64>,
    /// Cost Σ e² there.
    pub cost: f64,
    /// Residuals there.
    pub residuals: Vec<f64>,
    /// Jacobian of the residuals with respect to the (unscaled) parameters there.
    pub jacobian: DMatrix<f64>,
    /// Residual evaluations spent.
    pub evaluations: usize,
}

/// Minimises Σ e(x)² over `lo ≤ x ≤ hi` from `x0`. `scale[j]` is a typical magnitude of a
/// change of parameter j; `residuals` returns `None` when the model cannot be evaluated there
/// (treated as an infinitely bad point).
pub fn minimise(
    residuals: &dyn Fn(&[f64]) -> Option<Vec<f64>>,
    x0: &[f64],
    lo: &[f64],
    hi: &[f64],
    scale: &[f64],
    opts: &LmOptions,
) -> Option<LmResult> {
    let each = |xs: &[Vec<f64>]| xs.iter().map(|x| residuals(x)).collect();
    minimise_from(&each, x0, None, lo, hi, scale, opts)
}

/// The residuals at each of several points (`None` where the model cannot be evaluated):
/// the points a minimisation can try independently of each other (the finite-difference
/// columns of a Jacobian) come in one call, for a caller that evaluates them together.
pub type BatchResiduals<'a> = dyn Fn(&[Vec<f64>]) -> Vec<Option<Vec<f64>>> + 'a;

/// [`minimise`] with the residuals of several points at once ([`BatchResiduals`]), given
/// the residuals `e0` at `x0` when the caller has them (they are used only where `x0` lies
/// inside the bounds, so that they are the residuals the minimisation starts from; a replay
/// saved). [`LmResult::evaluations`] counts the points evaluated.
pub fn minimise_from(
    residuals: &BatchResiduals,
    x0: &[f64],
    e0: Option<Vec<f64>>,
    lo: &[f64],
    hi: &[f64],
    scale: &[f64],
    opts: &LmOptions,
) -> Option<LmResult> {
    let n = x0.len();
    let one = |x: &[f64]| residuals(&[x.to_vec()]).pop().flatten();
    let clamp = |x: &mut [f64]| {
        for j in 0..n {
            x[j] = x[j].clamp(lo[j], hi[j]);
        }
    };
    let mut x: Vec<f64> = x0.to_vec();
    clamp(&mut x);
    let (mut evaluations, mut e) = match e0 {
        Some(e0) if x == x0 => (0, e0),
        _ => (1, one(&x)?),
    };
    let mut cost = sumsq(&e);
    let mut jac = jacobian(
        residuals,
        &x,
        &e,
        lo,
        hi,
        scale,
        opts.fd_step,
        &mut evaluations,
    )?;
    let mut lambda = 1e-3;
    for _ in 0..opts.max_iterations {
        if n == 0 {
            break;
        }
        // Scaled Jacobian Js = J·diag(scale).
        let js = DMatrix::from_fn(e.len(), n, |i, j| jac[(i, j)] * scale[j]);
        let a = js.transpose() * &js;
        let g = js.transpose() * DVector::from_column_slice(&e);
        let mut improved = false;
        while lambda < 1e10 {
            let mut m = a.clone();
            for j in 0..n {
                m[(j, j)] += lambda * a[(j, j)].max(1e-12) + 1e-15;
            }
            let Some(step) = m.cholesky().map(|c| c.solve(&(-&g))) else {
                lambda *= 4.0;
                continue;
            };
            let mut xn: Vec<f64> = (0..n).map(|j| x[j] + step[j] * scale[j]).collect();
            clamp(&mut xn);
            if xn == x {
                break;
            }
            evaluations += 1;
            match one(&xn) {
                Some(en) if sumsq(&en) < cost => {
                    let cn = sumsq(&en);
                    let rel = (cost - cn) / cost.max(1e-300);
                    x = xn;
                    e = en;
                    cost = cn;
                    lambda = (lambda / 3.0).max(1e-9);
                    improved = rel > opts.rel_tolerance;
                    break;
                }
                _ => lambda *= 4.0,
            }
        }
        if !improved {
            break;
        }
        jac = jacobian(
            residuals,
            &x,
            &e,
            lo,
            hi,
            scale,
            opts.fd_step,
            &mut evaluations,
        )?;
    }
    Some(LmResult {
        x,
        cost,
        residuals: e,
        jacobian: jac,
        evaluations,
    })
}

fn sumsq(e: &[f64]) -> f64 {
    e.iter().map(|v| v * v).sum()
}

/// Forward differences (backward at an upper bound), the columns' points evaluated together.
#[allow(clippy::too_many_arguments)]
fn jacobian(
    residuals: &BatchResiduals,
    x: &[f64],
    e: &[f64],
    lo: &[f64],
    hi: &[f64],
    scale: &[f64],
    step: f64,
    evaluations: &mut usize,
) -> Option<DMatrix<f64>> {
    let n = x.len();
    let h: Vec<f64> = (0..n)
        .map(|j| {
            let mut h = step * scale[j];
            if x[j] + h > hi[j] {
                h = -h;
            }
            if x[j] + h < lo[j] {
                h = (hi[j] - lo[j]) * 0.5 * step;
            }
            h
        })
        .collect();
    let points: Vec<Vec<f64>> = (0..n)
        .map(|j| {
            let mut xp = x.to_vec();
            xp[j] += h[j];
            xp
        })
        .collect();
    *evaluations += n;
    let mut jac = DMatrix::zeros(e.len(), n);
    for (j, ep) in residuals(&points).into_iter().enumerate() {
        let ep = ep?;
        for i in 0..e.len() {
            jac[(i, j)] = (ep[i] - e[i]) / h[j];
        }
    }
    Some(jac)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fits_an_exponential_and_respects_bounds() {
        // y = a·exp(−b·t) with a = 2, b = 0.7.
        let t: Vec<f64> = (0..50).map(|i| i as f64 * 0.1).collect();
        let y: Vec<f64> = t.iter().map(|t| 2.0 * (-0.7 * t).exp()).collect();
        let f = |x: &[f64]| -> Option<Vec<f64>> {
            Some(
                t.iter()
                    .zip(&y)
                    .map(|(t, y)| x[0] * (-x[1] * t).exp() - y)
                    .collect(),
            )
        };
        let r = minimise(
            &f,
            &[1.0, 0.1],
            &[0.0, 0.0],
            &[10.0, 5.0],
            &[1.0, 1.0],
            &LmOptions::default(),
        )
        .unwrap();
        assert!(
            (r.x[0] - 2.0).abs() < 1e-5 && (r.x[1] - 0.7).abs() < 1e-5,
            "{:?}",
            r.x
        );
        // With b capped at 0.5 the optimum sits on the bound.
        let r = minimise(
            &f,
            &[1.0, 0.1],
            &[0.0, 0.0],
            &[10.0, 0.5],
            &[1.0, 1.0],
            &LmOptions::default(),
        )
        .unwrap();
        assert_eq!(r.x[1], 0.5);
    }

    /// The columns of each Jacobian come in one batch; the result is the one of the
    /// same residuals asked one point at a time, bit for bit.
    #[test]
    fn jacobian_columns_are_asked_together() {
        let t: Vec<f64> = (0..40).map(|i| i as f64 * 0.1).collect();
        let one = |x: &[f64]| -> Option<Vec<f64>> {
            Some(
                t.iter()
                    .map(|t| x[0] * (-x[1] * t).exp() + x[2] * t - (2.0 * (-0.7 * t).exp()))
                    .collect(),
            )
        };
        let sizes = std::cell::RefCell::new(Vec::new());
        let batch = |xs: &[Vec<f64>]| {
            sizes.borrow_mut().push(xs.len());
            xs.iter().map(|x| one(x)).collect()
        };
        let (lo, hi, scale) = ([0.0; 3], [10.0, 5.0, 1.0], [1.0; 3]);
        let opts = LmOptions::default();
        let r = minimise_from(&batch, &[1.0, 0.1, 0.5], None, &lo, &hi, &scale, &opts).unwrap();
        let single = minimise(&one, &[1.0, 0.1, 0.5], &lo, &hi, &scale, &opts).unwrap();
        assert_eq!(r, single);
        let sizes = sizes.into_inner();
        // One batch of three columns per Jacobian, single points otherwise.
        let jacobians = sizes.iter().filter(|&&n| n == 3).count();
        assert!(jacobians >= 3, "{sizes:?}");
        assert!(sizes.iter().all(|&n| n == 1 || n == 3), "{sizes:?}");
        assert_eq!(sizes.iter().sum::<usize>(), r.evaluations);
    }
}
