//! The nuisance thrust map: a thrust-map family that is only a stand-in for another family's
//! form.
//!
//! When the true law of an effect has no form in the catalogue (a gain that changes slope at
//! a knee, a reverse thrust that fades with the command), its best form leaves a residual that
//! follows the command, and a second *thrust-map* family (a gain, an asymmetry, a dead band, a
//! saturation: [`FamilyFacts::thrust_map`](shoal_model::effects::FamilyFacts)) soaks it up —
//! on the held-out data too, so every selection rule accepts it. Such a family is tested
//! against a non-parametric thrust map ([`ThrustMap`]: a factor piecewise linear in the
//! command, per direction) fitted in its place: a family that is really there fits its own
//! law with one or two parameters and beats the map's eight on the BIC; a stand-in follows a
//! shape that is not its own, and the map does at least as well. So a thrust-map family beside
//! another family — and any family beside a thrust-map family that explains the most, whose
//! form may leave a residual that a family of another kind soaks up (a damping error beside a
//! gain that steps smoothly with the command) — is kept only where it beats the map in its
//! place: it is a *stand-in* when the model with
//! the map in its place has the lower BIC, counted both ways: over every sample and with each
//! channel's effective sample count ([`delta_bic_eff`]; a smooth residual carries the
//! information of far fewer samples, which a real family's exact law keeps ahead of the map's
//! eight parameters). The held-out data are no test here: the map has no law to carry it
//! beyond the stretch it was fitted on (a sag that goes on draining, a depth that integrates
//! every thrust error), so it predicts them worse than a stand-in family's law even where it
//! fits better (on the recovery draws, the models with the map predicted the held-out data
//! 2 % to 2.2 × worse). The family that explains the most (whose removal costs the most BIC)
//! is never tested: it is the finding whose form the others would be standing in for.

use super::context::Search;
use super::fitted::Fit;
use super::measures::{bic, delta_bic_eff};
use super::par::par_map;
use super::step::Step;
use shoal_model::effects::{Effect, ThrustMap, facts};
use std::sync::Arc;

/// A family of the stepwise model that the nuisance thrust map replaces at least as well.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct StandIn {
    /// The family.
    pub effect: String,
    /// The family it stands in for (the one that explains the most).
    pub main: String,
    /// BIC of the model with the map in its place minus the model's (negative: the map fits
    /// better).
    pub delta_bic: f64,
    /// The same with effective sample counts ([`delta_bic_eff`]).
    pub delta_bic_eff: f64,
}

/// The families of `stepwise` that are stand-ins (see the module documentation): thrust-map
/// families beside the main one, and any family beside a thrust-map main one; none when it
/// has fewer than two families.
pub(super) fn stand_ins(
    s: &Search<'_>,
    stepwise: &Fit,
    progress: &(dyn Fn(Step<'_>) + Sync),
) -> Vec<StandIn> {
    if stepwise.effects.len() < 2 {
        return Vec::new();
    }
    let is_map = |n: &str| facts(n).is_some_and(|f| f.thrust_map);
    let names = stepwise.names();
    if !names.iter().any(|n| is_map(n)) {
        return Vec::new();
    }
    progress(Step::Stage {
        stage: "thrust-map families against a nuisance thrust map",
        fits: None,
    });
    let opts = s.ctx.opts;
    let whole = bic(&stepwise.eval, stepwise.k);
    // Each family's contribution: how much BIC the model loses without it.
    let reduced: Vec<(String, Option<Fit>)> = par_map(&names, opts.threads, |n| {
        let r = s.ctx.without(stepwise, n, &s.baseline);
        progress(Step::Fit(n));
        (n.clone(), r)
    });
    let cost = |r: &Option<Fit>| {
        r.as_ref()
            .map_or(f64::INFINITY, |r| bic(&r.eval, r.k) - whole)
    };
    let Some(main) = reduced
        .iter()
        .max_by(|a, b| cost(&a.1).total_cmp(&cost(&b.1)))
        .map(|(n, _)| n.clone())
    else {
        return Vec::new();
    };
    let map: Arc<dyn Effect> = Arc::new(knotted(s));
    let excited = s.ctx.excited(&map);
    if !excited.iter().any(|&x| x) {
        return Vec::new();
    }
    let tests: Vec<(String, Fit)> = reduced
        .into_iter()
        .filter(|(n, _)| *n != main && (is_map(n) || is_map(&main)))
        .filter_map(|(n, r)| r.map(|r| (n, r)))
        .collect();
    let found: Vec<Option<StandIn>> = par_map(&tests, opts.threads, |(n, r)| {
        // From the baseline map, without a scan: the map is nearly linear in its knots.
        let null = map.params(s.ctx.base).iter().map(|p| p.null).collect();
        let with_map = s.ctx.extend_unscanned(r, &map, &excited, null)?;
        progress(Step::Fit(&format!("thrust map for {n}")));
        let delta_bic = bic(&with_map.eval, with_map.k) - whole;
        let delta_bic_eff = delta_bic_eff(stepwise, &with_map, None);
        (delta_bic < 0.0 && delta_bic_eff < 0.0).then(|| StandIn {
            effect: n.clone(),
            main: main.clone(),
            delta_bic,
            delta_bic_eff,
        })
    });
    found.into_iter().flatten().collect()
}

/// Share of a direction's estimation commands below each knot of the map: the knots sit at
/// these quantiles of the commands (as fractions of the thruster's largest), so every piece
/// of the map has data under it and none reaches beyond the commands it is fitted on.
const QUANTILES: [f64; 4] = [0.25, 0.5, 0.75, 1.0];

/// Fewest estimation commands of one direction for its knots to be placed at their quantiles
/// (fewer: the default knots; the excitation probe then decides what the data show).
const MIN_COMMANDS: usize = 20;

/// Commands smaller than this fraction of the largest are not counted (a thruster at rest).
const AT_REST: f64 = 0.005;

/// The nuisance map with its knots at the [`QUANTILES`] of the estimation commands of every
/// thruster, per direction (see [`ThrustMap`]).
///
/// One search makes one such map: the search's memo tells models apart by their effects' names
/// and forms, which do not say where the knots are.
fn knotted(s: &Search<'_>) -> ThrustMap {
    let (mut fwd, mut rev) = (Vec::new(), Vec::new());
    for rd in &s.ctx.ds.runs {
        for &(ti, ci) in &rd.map.thrusters {
            let n_max = s.ctx.base.thrusters[ti].max_command;
            let values = &rd.run.inputs[ci].values;
            for (&t, &v) in rd.run.t.iter().zip(values) {
                let x = (v.abs() / n_max).min(1.0);
                if rd.is_estimation(t) && x >= AT_REST {
                    if v < 0.0 { rev.push(x) } else { fwd.push(x) }
                }
            }
        }
    }
    let defaults = ThrustMap::default();
    ThrustMap {
        forward: knots_at_quantiles(fwd).unwrap_or(defaults.forward),
        reverse: knots_at_quantiles(rev).unwrap_or(defaults.reverse),
    }
}

/// Knots at the [`QUANTILES`] of `x` (fractions 0…1), made strictly ascending; `None` with
/// fewer than [`MIN_COMMANDS`] values.
fn knots_at_quantiles(mut x: Vec<f64>) -> Option<[f64; 4]> {
    if x.len() < MIN_COMMANDS {
        return None;
    }
    x.sort_by(f64::total_cmp);
    let mut k = QUANTILES.map(|q| x[((q * x.len() as f64).ceil() as usize).clamp(1, x.len()) - 1]);
    // Commands held at a few levels put several quantiles on one level: each knot at least a
    // thousandth above the one before keeps every piece of the map a piece.
    for i in 1..k.len() {
        k[i] = k[i].max(k[i - 1] + 1e-3);
    }
    Some(k)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn knots_sit_at_quantiles_and_ascend_strictly() {
        let x: Vec<f64> = (1..=100).map(|i| f64::from(i) / 100.0).collect();
        assert_eq!(knots_at_quantiles(x), Some([0.25, 0.5, 0.75, 1.0]));
        // Two levels only: the knots on a level are pulled apart.
        let steps: Vec<f64> = (0..40).map(|i| if i < 20 { 0.3 } else { 0.6 }).collect();
        let k = knots_at_quantiles(steps).expect("enough commands");
        assert_eq!(k[0], 0.3);
        assert!(k.windows(2).all(|w| w[1] > w[0]), "{k:?}");
        assert_eq!(knots_at_quantiles(vec![0.5; MIN_COMMANDS - 1]), None);
    }
}
