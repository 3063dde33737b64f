//! Stability selection: is each chosen effect still chosen when the log is resampled?
//!
//! The stepwise model is refitted on block-bootstrap resamples of the log
//! ([`crate::evaluate::blocks::Resample`]: estimation and validation blocks drawn with replacement, a
//! warm start from the full-data fit with a few Levenberg–Marquardt iterations), and on each the
//! backward test is repeated with the resample's statistics: ΔBIC on the resampled
//! estimation blocks; held-out gain, block test and materiality (share of the baseline's
//! held-out error, or of the gap to the noise floor, that the effect removes) on the
//! resampled validation blocks. An effect's selection frequency is the share of resamples on
//! which it passes. (The backward checks' effective-ΔBIC rule is not repeated: a resample
//! duplicates blocks, and its count of independent samples is not defined.)

use super::context::Search;
use super::fit::Ctx;
use super::fitted::Fit;
use super::measures::{bic_resampled, closure_resampled, gain_resampled, material_resampled};
use super::par::par_map;
use super::step::Step;
use crate::evaluate::blocks::{Resample, heldout_t};
use crate::evaluate::lm::LmOptions;
use std::collections::BTreeMap;

/// Levenberg–Marquardt iterations of a warm refit on a resample.
const REFIT_ITERATIONS: usize = 6;

/// Selection frequency (0…1) of each effect of `stepwise` over the resamples; empty when
/// `stepwise` has no effect or no resamples are asked for.
pub(super) fn frequencies(
    s: &Search<'_>,
    stepwise: &Fit,
    progress: &(dyn Fn(Step<'_>) + Sync),
) -> BTreeMap<String, f64> {
    let opts = s.ctx.opts;
    let names = stepwise.names();
    if names.is_empty() || opts.stability_draws == 0 {
        return BTreeMap::new();
    }
    progress(Step::Stage {
        stage: "stability over resamples",
        fits: Some(opts.stability_draws),
    });
    let draws: Vec<u64> = (0..opts.stability_draws as u64).collect();
    let picks: Vec<Vec<bool>> = par_map(&draws, opts.threads, |&d| {
        let rs = Resample::draw(
            &stepwise.eval,
            opts.block_s,
            opts.seed.wrapping_add(d.wrapping_mul(0x9e37_79b9)),
        );
        let ctx = Ctx {
            ds: s.ctx.ds,
            base: s.ctx.base,
            factors: s.ctx.factors.clone(),
            opts,
            resample: Some(&rs),
            lm: LmOptions {
                max_iterations: REFIT_ITERATIONS,
                ..opts.lm
            },
            memo: s.ctx.memo,
        };
        // Refit everything (no effect is named "")…
        let Some(full) = ctx.without(stepwise, "", &s.baseline) else {
            return vec![false; names.len()];
        };
        progress(Step::Fit(&format!("resample {}", d + 1)));
        // …and each effect's backward test on this resample.
        names
            .iter()
            .map(|n| {
                ctx.without(&full, n, &s.baseline).is_some_and(|red| {
                    bic_resampled(&full.eval, full.k, Some(&rs))
                        - bic_resampled(&red.eval, red.k, Some(&rs))
                        < opts.bic_threshold
                        && gain_resampled(&red.eval, &full.eval, Some(&rs)) >= opts.min_gain
                        && heldout_t(&red.eval, &full.eval, opts.block_s, Some(&rs))
                            >= opts.t_threshold
                        && (material_resampled(&s.baseline.eval, &red.eval, &full.eval, Some(&rs))
                            >= opts.min_material
                            || closure_resampled(&red.eval, &full.eval, Some(&rs))
                                >= opts.min_closure)
                })
            })
            .collect()
    });
    names
        .iter()
        .enumerate()
        .map(|(i, n)| {
            let k = picks.iter().filter(|p| p[i]).count();
            (n.clone(), k as f64 / picks.len().max(1) as f64)
        })
        .collect()
}
