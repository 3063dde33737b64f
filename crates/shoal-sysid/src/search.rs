//! The model search: fit every catalogue effect on the estimation data, score it on the
//! validation data and by BIC, keep the best significant one, try adding each further effect
//! to it (greedy forward selection), stop when nothing more is significant.
//!
//! **Fitting.** Each candidate model is the baseline plus a set of effects. Its parameters are
//! fitted by maximum likelihood with unknown per-channel noise: bounded Levenberg–Marquardt
//! ([`crate::lm`]) on the estimation residuals of all channels, each channel weighted by the
//! inverse of the fit's own residual variance, the weights updated and the fit repeated until
//! they settle (iteratively reweighted least squares). It starts from several points: the null
//! values, typical values, the best points of a coarse scan, and earlier fits. Parameters that
//! the data cannot see — a current without tracked positions, a pump that never runs, a depth
//! offset that the free initial depth absorbs — are detected by a probe (moving the parameter
//! halfway to its far bound changes no residual) and kept at their null values.
//!
//! **Uncertainty.** From the Jacobian at the optimum, two ways: `sigma_white`, the
//! Gauss–Newton value for white residuals, and `sigma`, the honest one for a replay's smooth,
//! correlated residuals: each channel's information divided by κ = (1+ρ₁)/(1−ρ₁), the variance
//! inflation of residuals with lag-1 autocorrelation ρ₁.
//!
//! **Selection** (stepwise). *Forward*: every effect alone on the baseline; the one with the
//! lowest BIC among those that pass the forward test joins the model; then every remaining
//! promising effect is fitted together with the chosen ones, and so on. Forward test — all of:
//! 1. ΔBIC < −10 on the estimation data;
//! 2. the validation RMSE falls by at least `min_gain` (default 3 %) averaged over channels,
//!    each relative to the model it is added to;
//! 3. its parameters are jointly `z_threshold` (default 3) standard deviations away from their
//!    null values (Wald test with the white-residual covariance, expressed as the normal
//!    deviate of the same tail probability).
//!
//! *Backward*: in the final model every effect must still earn its place against the model
//! without it (refitted), by the same three rules. The weakest failing effect is removed and
//! the test repeated. The Wald test uses the white-residual covariance in both directions: on
//! real data with model error the κ-inflated (honest) σ is so wide that it would reject
//! effects that cut hold-out error in half; the honest σ is what the report quotes as a
//! parameter's uncertainty, and the validation-gain rule is what guards against fitting
//! noise.
//!
//! A run the baseline already explains therefore yields an empty verdict: nothing fitted to
//! noise generalises to the validation data.

use crate::data::{Dataset, Evaluation};
use crate::lm::{LmOptions, minimise};
use crate::run::ChannelKind;
use crate::stats;
use nalgebra::DMatrix;
use shoal_model::effects::{Effect, EffectInstance, Effects, ParamInfo};
use shoal_model::vehicle::{VehicleModel, VehicleParams};
use statrs::distribution::{ChiSquared, ContinuousCDF, Normal};
use std::collections::BTreeMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Settings of a search.
#[derive(Clone, Debug)]
pub struct SearchOptions {
    /// The effects to consider (default: the built-in catalogue).
    pub effects: Vec<Arc<dyn Effect>>,
    /// Smallest relative validation-RMSE reduction that counts (fraction, default 0.03).
    pub min_gain: f64,
    /// Largest ΔBIC that counts as an improvement (default −10).
    pub bic_threshold: f64,
    /// Smallest distance of a parameter from its null value in standard deviations
    /// (default 3).
    pub z_threshold: f64,
    /// Most effects in the verdict (default 4).
    pub max_effects: usize,
    /// After the first round, how many of the best first-round candidates are tried as
    /// additions (default 6).
    pub candidates_per_round: usize,
    /// Worker threads for candidate fits (results do not depend on it).
    pub threads: usize,
    /// Levenberg–Marquardt settings.
    pub lm: LmOptions,
    /// Effects that are part of the baseline itself (from the vehicle file), fixed.
    pub base_effects: Vec<EffectInstance>,
}

impl Default for SearchOptions {
    fn default() -> Self {
        Self {
            effects: shoal_model::effects::catalogue(),
            min_gain: 0.03,
            bic_threshold: -10.0,
            z_threshold: 3.0,
            max_effects: 4,
            candidates_per_round: 6,
            threads: 1,
            lm: LmOptions::default(),
            base_effects: Vec::new(),
        }
    }
}

/// A fitted parameter.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ParamEstimate {
    /// Parameter name.
    pub name: String,
    /// Unit.
    pub unit: String,
    /// Estimate (unit as above).
    pub value: f64,
    /// Standard deviation allowing for autocorrelated residuals (unit as above); `None` where
    /// not excited or not determined.
    pub sigma: Option<f64>,
    /// Gauss–Newton standard deviation for white residuals (unit as above).
    pub sigma_white: Option<f64>,
    /// The value at which the effect vanishes.
    pub null: f64,
    /// Whether the data excite it (otherwise it is held at `null`).
    pub excited: bool,
}

/// An effect with fitted parameters.
#[derive(Clone, Debug)]
pub struct FittedEffect {
    /// The effect.
    pub effect: Arc<dyn Effect>,
    /// Its parameters.
    pub params: Vec<ParamEstimate>,
}

impl FittedEffect {
    /// As an instance for a model.
    pub fn instance(&self) -> EffectInstance {
        EffectInstance {
            effect: self.effect.clone(),
            params: self.params.iter().map(|p| p.value).collect(),
        }
    }
}

/// A candidate model (baseline + effects) fitted and evaluated.
#[derive(Clone, Debug)]
pub struct Fit {
    /// Its effects.
    pub effects: Vec<FittedEffect>,
    /// Number of fitted (free) parameters.
    pub k: usize,
    /// Comparison with the data.
    pub eval: Evaluation,
    /// Model replays spent on the fit.
    pub evaluations: usize,
    /// (effect index, parameter index) of each free parameter, in the order of the
    /// covariance matrices.
    pub free: Vec<(usize, usize)>,
    /// Covariance of the free parameters allowing for autocorrelated residuals.
    pub cov: Option<DMatrix<f64>>,
    /// Gauss–Newton covariance of the free parameters for white residuals.
    pub cov_white: Option<DMatrix<f64>>,
}

impl Fit {
    /// Names of its effects.
    pub fn names(&self) -> Vec<String> {
        self.effects
            .iter()
            .map(|e| e.effect.name().to_string())
            .collect()
    }

    /// The model: `base` with `base_effects` and this fit's effects.
    pub fn model(
        &self,
        base: &VehicleParams,
        base_effects: &[EffectInstance],
        density: f64,
    ) -> VehicleModel {
        let mut list = base_effects.to_vec();
        list.extend(self.effects.iter().map(FittedEffect::instance));
        VehicleModel::with_effects(base.clone(), Effects::new(list), density)
    }
}

/// One candidate of one round.
#[derive(Clone, Debug)]
pub struct Candidate {
    /// Round (1 = each effect alone on the baseline).
    pub round: usize,
    /// Whether this is the backward check of an effect in the final model (`delta_bic`,
    /// `gain` and `z` then compare the model with and without it).
    pub backward: bool,
    /// The effect tried in this round.
    pub effect: String,
    /// The fit (none if the effect does not apply or is not excited).
    pub fit: Option<Fit>,
    /// ΔBIC against the model it was added to.
    pub delta_bic: f64,
    /// Relative validation-RMSE reduction against the model it was added to (fraction,
    /// mean over channels).
    pub gain: f64,
    /// Joint distance of its parameters from their null values: the Wald test with the
    /// white-residual covariance, as the normal deviate of the same tail probability
    /// [standard deviations].
    pub z: f64,
    /// Whether it passed all three significance tests.
    pub significant: bool,
    /// Why it was skipped or rejected, or what it achieved.
    pub note: String,
}

/// The search's result.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// The baseline, evaluated.
    pub baseline: Fit,
    /// Every candidate of every round.
    pub candidates: Vec<Candidate>,
    /// The chosen model (the baseline when nothing is significant).
    pub chosen: Fit,
    /// Residual weights of the baseline (see [`Evaluation::ml_factors`]).
    pub factors: BTreeMap<ChannelKind, f64>,
}

impl Outcome {
    /// Relative validation-RMSE reduction of the chosen model against the baseline, mean over
    /// channels [%].
    pub fn validation_gain_pct(&self) -> f64 {
        100.0 * gain(&self.baseline.eval, &self.chosen.eval)
    }
}

/// Mean over channels of 1 − RMSE_b/RMSE_a on validation data.
pub fn gain(a: &Evaluation, b: &Evaluation) -> f64 {
    let mut s = 0.0;
    let mut n = 0;
    for (k, ma) in &a.metrics {
        if let Some(mb) = b.metrics.get(k)
            && ma.rmse > 0.0
        {
            s += 1.0 - mb.rmse / ma.rmse;
            n += 1;
        }
    }
    if n > 0 { s / n as f64 } else { 0.0 }
}

/// BIC of an evaluation with `k` free parameters: Σ_ch n_ch·ln(SSE_ch/n_ch) + k·ln n over the
/// estimation samples (Gaussian likelihood with each channel's variance profiled out).
pub fn bic(eval: &Evaluation, k: usize) -> f64 {
    let mut b = 0.0;
    let mut ntot = 0.0;
    for m in eval.metrics.values() {
        let n = m.n_est.max(1) as f64;
        b += n * (m.sse_est / n).max(1e-300).ln();
        ntot += n;
    }
    b + k as f64 * ntot.max(1.0).ln()
}

/// ΔBIC of going from `a` to `b`.
pub fn delta_bic(a: &Fit, b: &Fit) -> f64 {
    bic(&b.eval, b.k) - bic(&a.eval, a.k)
}

struct Ctx<'a> {
    ds: &'a Dataset,
    base: &'a VehicleParams,
    /// Baseline residual factors (for the excitation probe).
    factors: BTreeMap<ChannelKind, f64>,
    opts: &'a SearchOptions,
}

impl Ctx<'_> {
    fn model(&self, effects: &[Arc<dyn Effect>], values: &[f64]) -> VehicleModel {
        let mut list = self.opts.base_effects.clone();
        let mut i = 0;
        for e in effects {
            let n = e.params(self.base).len();
            list.push(EffectInstance {
                effect: e.clone(),
                params: values[i..i + n].to_vec(),
            });
            i += n;
        }
        VehicleModel::with_effects(self.base.clone(), Effects::new(list), self.ds.env.density)
    }

    fn eval(&self, effects: &[Arc<dyn Effect>], values: &[f64]) -> Option<Evaluation> {
        let ev = self.ds.evaluate(&self.model(effects, values));
        ev.metrics
            .values()
            .all(|m| m.sse_est.is_finite())
            .then_some(ev)
    }

    fn weighted(
        &self,
        effects: &[Arc<dyn Effect>],
        values: &[f64],
        factors: &BTreeMap<ChannelKind, f64>,
    ) -> Option<Vec<f64>> {
        self.eval(effects, values).map(|e| e.weighted(factors))
    }

    fn infos(&self, effects: &[Arc<dyn Effect>]) -> Vec<ParamInfo> {
        effects.iter().flat_map(|e| e.params(self.base)).collect()
    }

    /// Which parameters of `effect` the data can see (probed from the baseline).
    fn excited(&self, effect: &Arc<dyn Effect>) -> Vec<bool> {
        let infos = effect.params(self.base);
        let null: Vec<f64> = infos.iter().map(|p| p.null).collect();
        let fx = [effect.clone()];
        let f = &self.factors;
        let Some(e0) = self.weighted(&fx, &null, f) else {
            return vec![false; infos.len()];
        };
        let tol = 1e-8 * f.len() as f64;
        (0..infos.len())
            .map(|j| {
                let p = &infos[j];
                let far = if (p.hi - p.null).abs() >= (p.null - p.lo).abs() {
                    p.hi
                } else {
                    p.lo
                };
                let mut x = null.clone();
                x[j] = p.null + 0.5 * (far - p.null);
                self.weighted(&fx, &x, f).is_some_and(|e| {
                    e.iter().zip(&e0).map(|(a, b)| (a - b).powi(2)).sum::<f64>() > tol
                })
            })
            .collect()
    }

    /// Fits `effects` (all parameters, excited ones free) from each start (full vectors).
    /// Fits `effects` (all parameters, excited ones free) from the best two of `starts` (full
    /// vectors) and, with `scan`, of a scan from the null values towards the far bounds.
    fn fit(
        &self,
        effects: &[Arc<dyn Effect>],
        excited: &[bool],
        starts: &[Vec<f64>],
        scan: bool,
    ) -> Option<Fit> {
        let infos = self.infos(effects);
        let free: Vec<usize> = (0..infos.len()).filter(|&j| excited[j]).collect();
        let null: Vec<f64> = infos.iter().map(|p| p.null).collect();
        let full = |xf: &[f64], start: &[f64]| {
            let mut x = start.to_vec();
            for (k, &j) in free.iter().enumerate() {
                x[j] = xf[k];
            }
            for (j, p) in infos.iter().enumerate() {
                if !excited[j] {
                    x[j] = p.null;
                }
            }
            x
        };
        let lo: Vec<f64> = free.iter().map(|&j| infos[j].lo).collect();
        let hi: Vec<f64> = free.iter().map(|&j| infos[j].hi).collect();
        let scale: Vec<f64> = free
            .iter()
            .map(|&j| {
                let p = &infos[j];
                let s = (p.typical - p.null).abs();
                if s > 0.0 { s } else { 0.1 * (p.hi - p.lo) }
            })
            .collect();
        // Candidate starts: the given ones and, with `scan`, points from the null values
        // towards the far bounds (all free parameters together), against multimodal costs.
        // The LM runs from the best two.
        let mut evaluations = 0;
        let mut points: Vec<(f64, Vec<f64>)> = Vec::new();
        for s in starts {
            let x = full(&free.iter().map(|&j| s[j]).collect::<Vec<_>>(), s);
            evaluations += 1;
            if let Some(ev) = self.eval(effects, &x) {
                points.push((bic(&ev, 0), x));
            }
        }
        for step in (1..=6).filter(|_| scan) {
            let a = step as f64 / 7.0;
            let x: Vec<f64> = infos
                .iter()
                .enumerate()
                .map(|(j, p)| {
                    if !excited[j] {
                        return p.null;
                    }
                    let far = if (p.hi - p.null).abs() >= (p.null - p.lo).abs() {
                        p.hi
                    } else {
                        p.lo
                    };
                    p.null + a * (far - p.null)
                })
                .collect();
            evaluations += 1;
            if let Some(ev) = self.eval(effects, &x) {
                points.push((bic(&ev, 0), x));
            }
        }
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        let starts: Vec<Vec<f64>> = points.into_iter().take(2).map(|(_, x)| x).collect();
        type Best = (
            f64,
            crate::lm::LmResult,
            BTreeMap<ChannelKind, f64>,
            Vec<f64>,
            Evaluation,
        );
        let mut best: Option<Best> = None;
        for s in &starts {
            let mut x = s.clone();
            let Some(mut ev) = self.eval(effects, &x) else {
                continue;
            };
            evaluations += 1;
            let mut result = None;
            // Iteratively reweighted: weights from the residuals, fit, new weights, … .
            for _ in 0..3 {
                let factors = ev.ml_factors();
                let x0: Vec<f64> = free.iter().map(|&j| x[j]).collect();
                let f = |xf: &[f64]| self.weighted(effects, &full(xf, &null), &factors);
                let Some(r) = minimise(&f, &x0, &lo, &hi, &scale, &self.opts.lm) else {
                    break;
                };
                evaluations += r.evaluations + 1;
                x = full(&r.x, &null);
                let Some(new_ev) = self.eval(effects, &x) else {
                    break;
                };
                let new_factors = new_ev.ml_factors();
                ev = new_ev;
                result = Some((r, factors.clone()));
                let settled = factors.iter().all(|(k, a)| {
                    let b = new_factors[k];
                    (b / a - 1.0).abs() < 0.05
                });
                if settled {
                    break;
                }
            }
            let Some((r, used)) = result else { continue };
            let score = bic(&ev, 0);
            if best.as_ref().is_none_or(|(b, ..)| score < *b) {
                best = Some((score, r, used, x, ev));
            }
        }
        let (_, lm, used, x, eval) = best?;
        let (cov, cov_white) = self.covariances(&eval, &lm.jacobian, &free, &used);
        let sd = |c: &Option<DMatrix<f64>>, k: usize| {
            c.as_ref().and_then(|c| {
                let v = c[(k, k)];
                (v.is_finite() && v > 0.0).then(|| v.sqrt())
            })
        };
        let sigmas: Vec<(Option<f64>, Option<f64>)> = (0..free.len())
            .map(|k| (sd(&cov, k), sd(&cov_white, k)))
            .collect();
        let mut free_index = Vec::new();
        let mut params = Vec::new();
        let mut i = 0;
        let mut fitted = Vec::new();
        for e in effects {
            let n = e.params(self.base).len();
            let mut ps = Vec::new();
            for j in i..i + n {
                let p = &infos[j];
                if excited[j] {
                    free_index.push((fitted.len(), j - i));
                }
                let (sigma, sigma_white) = free
                    .iter()
                    .position(|&f| f == j)
                    .and_then(|k| sigmas.get(k).copied())
                    .unwrap_or((None, None));
                ps.push(ParamEstimate {
                    name: p.name.to_string(),
                    unit: p.unit.to_string(),
                    value: x[j],
                    sigma,
                    sigma_white,
                    null: p.null,
                    excited: excited[j],
                });
            }
            params.extend(ps.clone());
            fitted.push(FittedEffect {
                effect: e.clone(),
                params: ps,
            });
            i += n;
        }
        Some(Fit {
            effects: fitted,
            k: free.len(),
            eval,
            evaluations: evaluations + 1,
            free: free_index,
            cov,
            cov_white,
        })
    }

    /// `cur` with `add` fitted on top, all parameters free, from `cur`'s values and each of
    /// `starts` for the new effect.
    fn extend(
        &self,
        cur: &Fit,
        add: &Arc<dyn Effect>,
        excited_add: &[bool],
        starts: &[Vec<f64>],
    ) -> Option<Fit> {
        let mut effects: Vec<Arc<dyn Effect>> =
            cur.effects.iter().map(|e| e.effect.clone()).collect();
        effects.push(add.clone());
        let mut excited: Vec<bool> = Vec::new();
        let mut held: Vec<f64> = Vec::new();
        for e in &cur.effects {
            excited.extend(e.params.iter().map(|p| p.excited));
            held.extend(e.params.iter().map(|p| p.value));
        }
        excited.extend_from_slice(excited_add);
        let starts: Vec<Vec<f64>> = starts
            .iter()
            .map(|s| {
                let mut x = held.clone();
                x.extend_from_slice(s);
                x
            })
            .collect();
        self.fit(&effects, &excited, &starts, false)
    }

    /// `cur` without the effect `name`, refitted (the baseline if nothing remains).
    fn without(&self, cur: &Fit, name: &str, baseline: &Fit) -> Option<Fit> {
        let keep: Vec<&FittedEffect> = cur
            .effects
            .iter()
            .filter(|e| e.effect.name() != name)
            .collect();
        if keep.is_empty() {
            return Some(baseline.clone());
        }
        let effects: Vec<Arc<dyn Effect>> = keep.iter().map(|e| e.effect.clone()).collect();
        let excited: Vec<bool> = keep
            .iter()
            .flat_map(|e| e.params.iter().map(|p| p.excited))
            .collect();
        let held: Vec<f64> = keep
            .iter()
            .flat_map(|e| e.params.iter().map(|p| p.value))
            .collect();
        self.fit(&effects, &excited, &[held], false)
    }

    /// How much adding `add` to `cur` promises to lower the weighted cost: the reduction of a
    /// linear least-squares step along the secants from its null to its typical values (a
    /// score test that also sees parameters whose effect starts abruptly).
    fn score(&self, cur: &Fit, add: &Arc<dyn Effect>, excited_add: &[bool]) -> f64 {
        let factors = cur.eval.ml_factors();
        let e0 = cur.eval.weighted(&factors);
        let mut effects: Vec<Arc<dyn Effect>> =
            cur.effects.iter().map(|e| e.effect.clone()).collect();
        effects.push(add.clone());
        let held: Vec<f64> = cur
            .effects
            .iter()
            .flat_map(|e| e.params.iter().map(|p| p.value))
            .collect();
        let infos = add.params(self.base);
        let null: Vec<f64> = infos.iter().map(|p| p.null).collect();
        let mut cols: Vec<Vec<f64>> = Vec::new();
        for (j, p) in infos.iter().enumerate() {
            if !excited_add.get(j).copied().unwrap_or(false) {
                continue;
            }
            let mut v = null.clone();
            v[j] = p.typical;
            let mut x = held.clone();
            x.extend_from_slice(&v);
            if let Some(e) = self.weighted(&effects, &x, &factors)
                && e.len() == e0.len()
            {
                cols.push(e.iter().zip(&e0).map(|(a, b)| a - b).collect());
            }
        }
        if cols.is_empty() {
            return 0.0;
        }
        let d = DMatrix::from_fn(e0.len(), cols.len(), |i, j| cols[j][i]);
        let g = d.transpose() * nalgebra::DVector::from_column_slice(&e0);
        let a = d.transpose() * &d;
        match a.clone().try_inverse() {
            Some(inv) => (g.transpose() * inv * &g)[(0, 0)].max(0.0),
            None => 0.0,
        }
    }

    /// Parameter covariances (honest, white) from the Jacobian `jac` of the residuals
    /// weighted by `factors` (the last weights of the fit), with the noise of `eval` (see the
    /// module docs).
    fn covariances(
        &self,
        eval: &Evaluation,
        jac: &DMatrix<f64>,
        free: &[usize],
        factors: &BTreeMap<ChannelKind, f64>,
    ) -> (Option<DMatrix<f64>>, Option<DMatrix<f64>>) {
        let n = free.len();
        if n == 0 || jac.ncols() != n {
            return (None, None);
        }
        let kinds = eval.weighted_kinds();
        let mut honest = DMatrix::<f64>::zeros(n, n);
        let mut white = DMatrix::<f64>::zeros(n, n);
        for (row, kind) in kinds.iter().enumerate() {
            let m = &eval.metrics[kind];
            let ne = m.n_est.max(1) as f64;
            let var = (m.sse_est / ne).max(1e-300);
            let w = factors[kind];
            let c = 1.0 / (w * w * var);
            let kappa = stats::inflation(m.rho1_est);
            for a in 0..n {
                let ja = jac[(row, a)];
                if ja == 0.0 {
                    continue;
                }
                for b in 0..n {
                    let v = ja * jac[(row, b)] * c;
                    white[(a, b)] += v;
                    honest[(a, b)] += v / kappa;
                }
            }
        }
        (honest.try_inverse(), white.try_inverse())
    }
}

/// Distance of `effect`'s parameters from their null values, jointly (Wald test with the
/// honest covariance, or the white-residual one with `white`), as the equivalent number of
/// standard deviations of a normal variable: for one parameter |θ − θ₀|/σ.
fn z_of(fit: &Fit, effect: &str, white: bool) -> f64 {
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
        .filter(|(_, (e, _))| *e == ei)
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

/// Runs `f` over `items` on `threads` threads; results in input order.
pub fn par_map<T: Sync, R: Send>(
    items: &[T],
    threads: usize,
    f: impl Fn(&T) -> R + Sync,
) -> Vec<R> {
    let next = AtomicUsize::new(0);
    let mut slots: Vec<Option<R>> = (0..items.len()).map(|_| None).collect();
    let threads = threads.clamp(1, items.len().max(1));
    let results: Vec<Vec<(usize, R)>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|_| {
                s.spawn(|| {
                    let mut out = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        if i >= items.len() {
                            break;
                        }
                        out.push((i, f(&items[i])));
                    }
                    out
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_default())
            .collect()
    });
    for (i, r) in results.into_iter().flatten() {
        slots[i] = Some(r);
    }
    slots.into_iter().flatten().collect()
}

/// Searches the effects of `opts` for the ones that explain `ds` better than `base`.
/// `progress` is called with a short message after each candidate fit.
pub fn search(
    ds: &Dataset,
    base: &VehicleParams,
    opts: &SearchOptions,
    progress: &(dyn Fn(&str) + Sync),
) -> Outcome {
    let base_model = VehicleModel::with_effects(
        base.clone(),
        Effects::new(opts.base_effects.clone()),
        ds.env.density,
    );
    let base_eval = ds.evaluate(&base_model);
    let factors = base_eval.ml_factors();
    let baseline = Fit {
        effects: Vec::new(),
        k: 0,
        eval: base_eval,
        evaluations: 1,
        free: Vec::new(),
        cov: None,
        cov_white: None,
    };
    let ctx = Ctx {
        ds,
        base,
        factors: factors.clone(),
        opts,
    };
    let mut candidates = Vec::new();
    // Round 1: every effect alone.
    let round1: Vec<(Candidate, Vec<bool>)> = par_map(&opts.effects, opts.threads, |e| {
        let name = e.name().to_string();
        if let Some(why) = e.not_applicable(base) {
            progress(&name);
            return (
                skipped(1, &name, format!("does not apply: {why}")),
                Vec::new(),
            );
        }
        let excited = ctx.excited(e);
        if !excited.iter().any(|&x| x) {
            progress(&name);
            return (
                skipped(
                    1,
                    &name,
                    "not excited: no input or measurement of these runs shows it".into(),
                ),
                excited,
            );
        }
        let infos = e.params(base);
        let starts = vec![
            infos.iter().map(|p| p.null).collect(),
            infos.iter().map(|p| p.typical).collect(),
        ];
        let c = match ctx.fit(std::slice::from_ref(e), &excited, &starts, true) {
            Some(fit) => judge(1, &name, &baseline, fit, opts, false),
            None => skipped(1, &name, "the replay failed for every start".into()),
        };
        progress(&name);
        (c, excited)
    });
    let excitation: BTreeMap<String, Vec<bool>> = round1
        .iter()
        .filter(|(_, x)| x.iter().any(|&v| v))
        .map(|(c, x)| (c.effect.clone(), x.clone()))
        .collect();
    let first_fits: BTreeMap<String, Vec<f64>> = round1
        .iter()
        .filter_map(|(c, _)| {
            c.fit.as_ref().map(|f| {
                (
                    c.effect.clone(),
                    f.effects[0].params.iter().map(|p| p.value).collect(),
                )
            })
        })
        .collect();
    candidates.extend(round1.into_iter().map(|(c, _)| c));
    let by_name = |n: &str| opts.effects.iter().find(|e| e.name() == n).cloned();
    // Candidates to add to `cur`: the best `candidates_per_round` by score.
    let promising = |cur: &Fit, exclude: &[String]| -> Vec<String> {
        let names: Vec<String> = excitation
            .keys()
            .filter(|n| !cur.names().contains(n) && !exclude.contains(n))
            .cloned()
            .collect();
        let scores = par_map(&names, opts.threads, |n| match by_name(n) {
            Some(e) => ctx.score(cur, &e, &excitation[n]),
            None => 0.0,
        });
        let mut ranked: Vec<(f64, String)> = scores.into_iter().zip(names).collect();
        ranked.sort_by(|a, b| b.0.total_cmp(&a.0));
        ranked
            .into_iter()
            .filter(|(s, _)| *s > 0.0)
            .take(opts.candidates_per_round)
            .map(|(_, n)| n)
            .collect()
    };
    let add = |cur: &Fit, name: &str| -> Option<Fit> {
        let e = by_name(name)?;
        let infos = e.params(base);
        let first = first_fits
            .get(name)
            .cloned()
            .unwrap_or_else(|| infos.iter().map(|p| p.typical).collect());
        let null: Vec<f64> = infos.iter().map(|p| p.null).collect();
        ctx.extend(cur, &e, &excitation[name], &[first, null])
    };
    let mut current = baseline.clone();
    let mut round = 1;
    // Forward.
    loop {
        let best = candidates
            .iter()
            .filter(|c| c.round == round && !c.backward && c.significant)
            .min_by(|a, b| {
                let ba = a.fit.as_ref().map_or(f64::INFINITY, |f| bic(&f.eval, f.k));
                let bb = b.fit.as_ref().map_or(f64::INFINITY, |f| bic(&f.eval, f.k));
                ba.total_cmp(&bb)
            });
        let Some(fit) = best.and_then(|c| c.fit.clone()) else {
            break;
        };
        current = fit;
        if current.effects.len() >= opts.max_effects {
            break;
        }
        round += 1;
        let tries = promising(&current, &[]);
        if tries.is_empty() {
            break;
        }
        let cur = &current;
        let next: Vec<Candidate> = par_map(&tries, opts.threads, |name| {
            let c = match add(cur, name) {
                Some(fit) => judge(round, name, cur, fit, opts, false),
                None => skipped(round, name, "the replay failed for every start".into()),
            };
            progress(name);
            c
        });
        candidates.extend(next);
    }
    // Backward checks, then swaps of one effect for another where that lowers the BIC
    // (equivalent explanations with fewer parameters), then backward checks again.
    let mut swaps = 0;
    loop {
        let mut reduced: Vec<(String, Option<Fit>)> = Vec::new();
        while !current.effects.is_empty() {
            round += 1;
            let names = current.names();
            let cur = &current;
            let checks: Vec<(Candidate, Option<Fit>)> = par_map(&names, opts.threads, |name| {
                let r = ctx.without(cur, name, &baseline);
                let c = match &r {
                    Some(r) => judge(round, name, r, cur.clone(), opts, true),
                    None => Candidate {
                        significant: true,
                        backward: true,
                        ..skipped(
                            round,
                            name,
                            "kept: the model without it could not be replayed".into(),
                        )
                    },
                };
                progress(name);
                (c, r)
            });
            let weakest = checks
                .iter()
                .filter(|(c, r)| !c.significant && r.is_some())
                .max_by(|a, b| a.0.delta_bic.total_cmp(&b.0.delta_bic))
                .and_then(|(_, r)| r.clone());
            reduced = checks
                .iter()
                .map(|(c, r)| (c.effect.clone(), r.clone()))
                .collect();
            candidates.extend(checks.into_iter().map(|(c, _)| c));
            match weakest {
                Some(r) => current = r,
                None => break,
            }
        }
        if current.effects.len() < 2 || swaps >= 2 {
            break;
        }
        let cur_bic = bic(&current.eval, current.k);
        let names = current.names();
        let options: Vec<(String, Fit)> = reduced
            .into_iter()
            .filter_map(|(n, r)| r.map(|r| (n, r)))
            .collect();
        let pairs: Vec<(String, Fit, String)> = options
            .iter()
            .flat_map(|(out, r)| {
                promising(r, &names)
                    .into_iter()
                    .take(3)
                    .map(|alt| (out.clone(), r.clone(), alt))
            })
            .collect();
        let swapped: Vec<Option<(Candidate, f64)>> =
            par_map(&pairs, opts.threads, |(out, r, alt)| {
                let fit = add(r, alt)?;
                let b = bic(&fit.eval, fit.k);
                let mut c = judge(round + 1, alt, r, fit, opts, false);
                c.note = format!("swap for {out}: {}", c.note);
                progress(alt);
                Some((c, b))
            });
        let best = swapped
            .into_iter()
            .flatten()
            .filter(|(c, b)| c.significant && *b < cur_bic - 2.0)
            .min_by(|a, b| a.1.total_cmp(&b.1));
        let Some((c, _)) = best else { break };
        round += 1;
        swaps += 1;
        if let Some(f) = &c.fit {
            current = f.clone();
        }
        candidates.push(c);
    }
    Outcome {
        baseline,
        candidates,
        chosen: current,
        factors,
    }
}

fn skipped(round: usize, name: &str, note: String) -> Candidate {
    Candidate {
        round,
        backward: false,
        effect: name.to_string(),
        fit: None,
        delta_bic: 0.0,
        gain: 0.0,
        z: 0.0,
        significant: false,
        note,
    }
}

/// Tests whether `name` earns its place in `fit` against `base` (the model without it):
/// the same rules forward and backward (see the module docs).
fn judge(
    round: usize,
    name: &str,
    base: &Fit,
    fit: Fit,
    opts: &SearchOptions,
    backward: bool,
) -> Candidate {
    let d = delta_bic(base, &fit);
    let g = gain(&base.eval, &fit.eval);
    let z = z_of(&fit, name, true);
    let ok_bic = d < opts.bic_threshold;
    let ok_gain = g >= opts.min_gain;
    let ok_z = z >= opts.z_threshold;
    let significant = ok_bic && ok_gain && ok_z;
    let mut why = Vec::new();
    if !ok_bic {
        why.push(format!("ΔBIC {d:.1} ≥ {}", opts.bic_threshold));
    }
    if !ok_gain {
        why.push(format!(
            "validation gain {:.2} % < {:.1} %",
            100.0 * g,
            100.0 * opts.min_gain
        ));
    }
    if !ok_z {
        why.push(format!(
            "parameters within {:.1} σ of null (< {})",
            z, opts.z_threshold
        ));
    }
    let note = if significant {
        format!(
            "significant: ΔBIC {d:.1}, validation gain {:.1} %, {z:.1} σ from null",
            100.0 * g
        )
    } else {
        format!("not significant: {}", why.join("; "))
    };
    Candidate {
        round,
        backward,
        effect: name.to_string(),
        fit: Some(fit),
        delta_bic: d,
        gain: g,
        z,
        significant,
        note,
    }
}
