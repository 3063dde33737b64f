//! Fitting one candidate model: replays, the excitation probe, bounded Levenberg–Marquardt from
//! several starts (`scan.rs`) with iterative reweighting, and the covariances of the estimates
//! (the Wald distance from null that uses them is in `measures.rs`).

use super::fitted::{Fit, FittedEffect, ParamEstimate};
use super::measures::bic_resampled;
use super::memo::Memo;
use super::options::SearchOptions;
use super::scan::scan_points;
use crate::evaluate::blocks::{Resample, weighted_residuals};
use crate::evaluate::dataset::{Dataset, Part, Replayed};
use crate::evaluate::evaluation::Evaluation;
use crate::evaluate::lm::{LmOptions, LmResult, minimise_from};
use crate::evaluate::stats;
use crate::log::run::ChannelKind;
use nalgebra::DMatrix;
use shoal_model::effects::{Effect, EffectInstance, Effects, ParamInfo};
use shoal_model::lanes::LANES;
use shoal_model::vehicle::{VehicleModel, VehicleParams};
use std::collections::BTreeMap;
use std::sync::Arc;

/// What a fit works on: the data, the baseline, the options and, for stability selection, a
/// block-bootstrap resample that weights the estimation samples.
pub(super) struct Ctx<'a> {
    pub ds: &'a Dataset,
    pub base: &'a VehicleParams,
    /// Baseline residual factors (for the excitation probe).
    pub factors: BTreeMap<ChannelKind, f64>,
    pub opts: &'a SearchOptions,
    /// Weights of the estimation blocks (none: every sample once).
    pub resample: Option<&'a Resample>,
    /// Levenberg–Marquardt settings (the options' own, or fewer iterations for warm refits).
    pub lm: LmOptions,
    /// The search's latest replays (shared by every context of one search).
    pub memo: &'a Memo,
}

impl Ctx<'_> {
    pub fn model(&self, effects: &[Arc<dyn Effect>], values: &[f64]) -> VehicleModel {
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

    /// The replay of the model with `effects` at `values` for the samples of `part` (from the
    /// memo when it was made before).
    fn replayed(&self, effects: &[Arc<dyn Effect>], values: &[f64], part: Part) -> Arc<Replayed> {
        self.memo.get_or_replay(effects, values, part, || {
            self.ds.replayed(&self.model(effects, values), part)
        })
    }

    /// [`Ctx::replayed`] for the models with `effects` at each of `values` (those not in the
    /// memo replayed together, [`Dataset::replayed_many`]).
    fn replayed_many(
        &self,
        effects: &[Arc<dyn Effect>],
        values: &[Vec<f64>],
        part: Part,
    ) -> Vec<Arc<Replayed>> {
        let values: Vec<&[f64]> = values.iter().map(Vec::as_slice).collect();
        self.memo
            .get_or_replay_many(effects, &values, part, |missing| {
                let models: Vec<VehicleModel> =
                    missing.iter().map(|v| self.model(effects, v)).collect();
                self.ds.replayed_many(&models, part)
            })
    }

    /// The evaluation of the model with `effects` at `values` on every sample, or `None` when
    /// a sum of squared estimation residuals is not finite.
    pub fn eval(&self, effects: &[Arc<dyn Effect>], values: &[f64]) -> Option<Evaluation> {
        self.eval_part(effects, values, Part::All)
    }

    /// [`Ctx::eval`] on the samples of `part` (see [`Dataset::evaluation`]).
    fn eval_part(
        &self,
        effects: &[Arc<dyn Effect>],
        values: &[f64],
        part: Part,
    ) -> Option<Evaluation> {
        finite(self.ds.evaluation(&self.replayed(effects, values, part)))
    }

    /// [`Ctx::eval_part`] of the models with `effects` at each of `values`.
    fn eval_parts(
        &self,
        effects: &[Arc<dyn Effect>],
        values: &[Vec<f64>],
        part: Part,
    ) -> Vec<Option<Evaluation>> {
        self.replayed_many(effects, values, part)
            .iter()
            .map(|r| finite(self.ds.evaluation(r)))
            .collect()
    }

    /// The weighted estimation residuals ([`Dataset::weighted`] with `factors` and the
    /// resample) of the models with `effects` at each of `values`, `None` for one whose sum
    /// of squares is not finite.
    fn weighted_many(
        &self,
        effects: &[Arc<dyn Effect>],
        values: &[Vec<f64>],
        factors: &BTreeMap<ChannelKind, f64>,
    ) -> Vec<Option<Vec<f64>>> {
        self.replayed_many(effects, values, Part::Estimation)
            .iter()
            .map(|r| self.ds.weighted(r, factors, self.resample))
            .collect()
    }

    fn infos(&self, effects: &[Arc<dyn Effect>]) -> Vec<ParamInfo> {
        effects.iter().flat_map(|e| e.params(self.base)).collect()
    }

    /// Which parameters of `effect` the data can see (probed from the baseline): a parameter
    /// is excited when moving it halfway to its far bound changes the residuals. Ordinary
    /// parameters are probed with the others at their nulls; shape parameters with the others
    /// at their typical values (a time constant of a vanishing effect changes nothing).
    pub fn excited(&self, effect: &Arc<dyn Effect>) -> Vec<bool> {
        let infos = effect.params(self.base);
        let null: Vec<f64> = infos.iter().map(|p| p.null).collect();
        let active: Vec<f64> = infos
            .iter()
            .map(|p| if p.shape { p.null } else { p.typical })
            .collect();
        let fx = [effect.clone()];
        let f = &self.factors;
        let shapes = infos.iter().any(|p| p.shape);
        // The probes: each parameter halfway to its far bound from where it is probed.
        let probes: Vec<Vec<f64>> = infos
            .iter()
            .enumerate()
            .map(|(j, p)| {
                let far = if (p.hi - p.null).abs() >= (p.null - p.lo).abs() {
                    p.hi
                } else {
                    p.lo
                };
                let mut x = if p.shape {
                    active.clone()
                } else {
                    null.clone()
                };
                x[j] = p.null + 0.5 * (far - p.null);
                x
            })
            .collect();
        // Replayed together with the points they are compared with (a probe from a start
        // that cannot be evaluated is replayed in vain: it is not looked at, as before).
        let mut points = vec![null.clone()];
        if shapes {
            points.push(active.clone());
        }
        points.extend(probes);
        let mut e = self.weighted_many(&fx, &points, f).into_iter();
        let Some(e_null) = e.next().flatten() else {
            return vec![false; infos.len()];
        };
        let e_active = if shapes { e.next().flatten() } else { None };
        let tol = 1e-8 * f.len() as f64;
        infos
            .iter()
            .zip(e)
            .map(|(p, probe)| {
                let e0 = if p.shape {
                    match &e_active {
                        Some(e) => e,
                        None => return false,
                    }
                } else {
                    &e_null
                };
                probe.is_some_and(|e| {
                    e.len() == e0.len()
                        && e.iter().zip(e0).map(|(a, b)| (a - b).powi(2)).sum::<f64>() > tol
                })
            })
            .collect()
    }

    /// Fits `effects` (all parameters, excited ones free) from the best two of `starts` (full
    /// vectors) and, with `scan = Some(from)`, of a scan of the parameters from index `from` on
    /// (the others as in the first start): from the null values towards the far bounds, and
    /// a space-filling design over their whole box ([`scan_points`]).
    pub fn fit(
        &self,
        effects: &[Arc<dyn Effect>],
        excited: &[bool],
        starts: &[Vec<f64>],
        scan: Option<usize>,
    ) -> Option<Fit> {
        let infos = self.infos(effects);
        let params = FreeParams::new(&infos, excited);
        // Candidate starts: the given ones and, with `scan`, points from the null values
        // towards the far bounds (all free parameters together), against multimodal costs.
        // The LM runs from the best two (by BIC; the earlier point first among equals), each
        // with the evaluation that ranked it. Until the LM is done, everything is decided on
        // the estimation samples (BIC, weights, residuals): their replays stop there.
        let mut points: Vec<Vec<f64>> = starts
            .iter()
            .map(|s| params.full(&params.free.iter().map(|&j| s[j]).collect::<Vec<_>>(), s))
            .collect();
        if let (Some(from), Some(first)) = (scan, starts.first()) {
            points.extend(scan_points(&infos, excited, first, from));
        }
        let mut evaluations = points.len();
        let top = self.best_starts(effects, &points);
        let best = self.minimise_from_best(effects, top, &params, &mut evaluations)?;
        Some(self.fitted(effects, &params, best, evaluations))
    }

    /// The best two of `points` by BIC on the estimation samples (the earlier point first among
    /// equals), each with its evaluation; points that cannot be evaluated are left out.
    fn best_starts(
        &self,
        effects: &[Arc<dyn Effect>],
        points: &[Vec<f64>],
    ) -> Vec<(f64, Vec<f64>, Evaluation)> {
        let mut top: Vec<(f64, Vec<f64>, Evaluation)> = Vec::with_capacity(3);
        // Evaluated LANES at a time (replayed together), ranked in their order.
        for batch in points.chunks(LANES) {
            let evals = self.eval_parts(effects, batch, Part::Estimation);
            for (x, ev) in batch.iter().zip(evals) {
                if let Some(ev) = ev {
                    let b = bic_resampled(&ev, 0, self.resample);
                    let at = top.partition_point(|(t, ..)| t.total_cmp(&b).is_le());
                    top.insert(at, (b, x.clone(), ev));
                    top.truncate(2);
                }
            }
        }
        top
    }

    /// Levenberg–Marquardt from each of `top` (a point with its evaluation), iteratively
    /// reweighted: weights from the residuals, fit, new weights, … until they settle (at most
    /// three passes). The result of lowest BIC, or `None` when no pass succeeded; the replays
    /// spent are added to `evaluations`.
    fn minimise_from_best(
        &self,
        effects: &[Arc<dyn Effect>],
        top: Vec<(f64, Vec<f64>, Evaluation)>,
        p: &FreeParams<'_>,
        evaluations: &mut usize,
    ) -> Option<Best> {
        let mut best: Option<Best> = None;
        for (_, mut x, mut ev) in top {
            let mut result = None;
            // Iteratively reweighted: weights from the residuals, fit, new weights, … .
            for _ in 0..3 {
                let factors = ev.ml_factors();
                let x0: Vec<f64> = p.free.iter().map(|&j| x[j]).collect();
                let f = |xs: &[Vec<f64>]| {
                    let xs: Vec<Vec<f64>> = xs.iter().map(|xf| p.full(xf, &p.null)).collect();
                    self.weighted_many(effects, &xs, &factors)
                };
                // The residuals at the start are those of `ev` (x is `full(x0, null)`).
                let e0 = weighted_residuals(&ev, &factors, self.resample);
                let Some(r) = minimise_from(&f, &x0, Some(e0), &p.lo, &p.hi, &p.scale, &self.lm)
                else {
                    break;
                };
                *evaluations += r.evaluations + 1;
                x = p.full(&r.x, &p.null);
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
            let score = bic_resampled(&ev, 0, self.resample);
            if best.as_ref().is_none_or(|(b, ..)| score < *b) {
                best = Some((score, r, used, x, ev));
            }
        }
        best
    }

    /// The fit of `effects` at the minimum `best`: every parameter with its estimate and
    /// standard deviations (from the covariances at the minimum), `evaluations` replays spent
    /// (and one more).
    fn fitted(
        &self,
        effects: &[Arc<dyn Effect>],
        p: &FreeParams<'_>,
        best: Best,
        evaluations: usize,
    ) -> Fit {
        let (infos, excited, free) = (p.infos, p.excited, &p.free);
        let (_, lm, used, x, eval) = best;
        let (cov, cov_white) = self.covariances(&eval, &lm.jacobian, free, &used);
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
                    shape: p.shape,
                });
            }
            params.extend(ps.clone());
            fitted.push(FittedEffect {
                effect: e.clone(),
                params: ps,
            });
            i += n;
        }
        Fit {
            effects: fitted,
            k: free.len(),
            eval,
            evaluations: evaluations + 1,
            free: free_index,
            cov,
            cov_white,
        }
    }

    /// `cur` with `add` fitted on top, all parameters free, from `cur`'s values and each of
    /// `starts` for the new effect.
    pub fn extend(
        &self,
        cur: &Fit,
        add: &Arc<dyn Effect>,
        excited_add: &[bool],
        starts: &[Vec<f64>],
    ) -> Option<Fit> {
        self.extend_with(cur, &[(add, excited_add)], starts)
    }

    /// `cur` with the effects `adds` (each with its excitation) fitted on top, all parameters
    /// free, from `cur`'s values and each of `starts` for the new effects' parameters (all of
    /// them, in the order of `adds`); the scan covers the new parameters.
    pub fn extend_with(
        &self,
        cur: &Fit,
        adds: &[(&Arc<dyn Effect>, &[bool])],
        starts: &[Vec<f64>],
    ) -> Option<Fit> {
        self.stacked(cur, adds, starts, true)
    }

    /// [`Ctx::extend`] from `start` alone, without a scan of the new parameters (for an effect
    /// whose null values are a good start and whose many parameters would make a scan dear).
    pub fn extend_unscanned(
        &self,
        cur: &Fit,
        add: &Arc<dyn Effect>,
        excited_add: &[bool],
        start: Vec<f64>,
    ) -> Option<Fit> {
        self.stacked(cur, &[(add, excited_add)], &[start], false)
    }

    /// `cur` with `adds` fitted on top from `cur`'s values and each of `starts` (the new
    /// parameters), with a scan of the new parameters when `scan`.
    fn stacked(
        &self,
        cur: &Fit,
        adds: &[(&Arc<dyn Effect>, &[bool])],
        starts: &[Vec<f64>],
        scan: bool,
    ) -> Option<Fit> {
        let mut effects: Vec<Arc<dyn Effect>> =
            cur.effects.iter().map(|e| e.effect.clone()).collect();
        let mut excited: Vec<bool> = Vec::new();
        let mut held: Vec<f64> = Vec::new();
        for e in &cur.effects {
            excited.extend(e.params.iter().map(|p| p.excited));
            held.extend(e.params.iter().map(|p| p.value));
        }
        for (add, excited_add) in adds {
            effects.push((*add).clone());
            excited.extend_from_slice(excited_add);
        }
        let starts: Vec<Vec<f64>> = starts
            .iter()
            .map(|s| {
                let mut x = held.clone();
                x.extend_from_slice(s);
                x
            })
            .collect();
        let from = held.len();
        self.fit(&effects, &excited, &starts, scan.then_some(from))
    }

    /// `cur` without the effect `name`, refitted (the baseline if nothing remains).
    pub fn without(&self, cur: &Fit, name: &str, baseline: &Fit) -> Option<Fit> {
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
        self.fit(&effects, &excited, &[held], None)
    }

    /// How much adding `add` to `cur` promises to lower the weighted cost: the reduction of a
    /// linear least-squares step along the secants from its null to its typical values (a
    /// score test that also sees parameters whose effect starts abruptly).
    pub fn score(&self, cur: &Fit, add: &Arc<dyn Effect>, excited_add: &[bool]) -> f64 {
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
        let points: Vec<Vec<f64>> = infos
            .iter()
            .enumerate()
            .filter(|(j, _)| excited_add.get(*j).copied().unwrap_or(false))
            .map(|(j, p)| {
                let mut v = null.clone();
                v[j] = p.typical;
                let mut x = held.clone();
                x.extend_from_slice(&v);
                x
            })
            .collect();
        let cols: Vec<Vec<f64>> = self
            .weighted_many(&effects, &points, &factors)
            .into_iter()
            .flatten()
            .filter(|e| e.len() == e0.len())
            .map(|e| e.iter().zip(&e0).map(|(a, b)| a - b).collect())
            .collect();
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

/// The minimum a fit reached: (BIC, the Levenberg–Marquardt result, the residual weights of
/// its last pass, the full parameter vector, its evaluation).
type Best = (
    f64,
    LmResult,
    BTreeMap<ChannelKind, f64>,
    Vec<f64>,
    Evaluation,
);

/// The parameters of one fit: which are free (the excited ones), their null values, bounds and
/// scales, and how a vector of the free ones is completed.
struct FreeParams<'p> {
    infos: &'p [ParamInfo],
    excited: &'p [bool],
    /// Indices of the free parameters.
    free: Vec<usize>,
    null: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    scale: Vec<f64>,
}

impl<'p> FreeParams<'p> {
    fn new(infos: &'p [ParamInfo], excited: &'p [bool]) -> Self {
        let free: Vec<usize> = (0..infos.len()).filter(|&j| excited[j]).collect();
        let null: Vec<f64> = infos.iter().map(|p| p.null).collect();
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
        Self {
            infos,
            excited,
            free,
            null,
            lo,
            hi,
            scale,
        }
    }

    /// `start` with the free parameters set to `xf` and the others not excited at their nulls.
    fn full(&self, xf: &[f64], start: &[f64]) -> Vec<f64> {
        let mut x = start.to_vec();
        for (k, &j) in self.free.iter().enumerate() {
            x[j] = xf[k];
        }
        for (j, p) in self.infos.iter().enumerate() {
            if !self.excited[j] {
                x[j] = p.null;
            }
        }
        x
    }
}

/// `ev` when every sum of squared estimation residuals is finite.
fn finite(ev: Evaluation) -> Option<Evaluation> {
    ev.metrics
        .values()
        .all(|m| m.sse_est.is_finite())
        .then_some(ev)
}
