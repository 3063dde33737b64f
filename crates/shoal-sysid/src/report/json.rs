//! `report.json`: the schema of `../shared/spec/validation.md` plus details — every candidate
//! with its forms and tests, and per named effect its evidence, parameters with 95 %
//! confidence intervals and the residual-signature plot.

use super::input::ReportInput;
use super::plots::PlotRefs;
use super::wording::{ci95, evidence, label, verdict_sentence};
use crate::evaluate::evaluation::{Evaluation, rmse_gain_pct};
use crate::log::run::ChannelKind;
use crate::search::{Candidate, Fit};
use serde_json::{Map, Value, json};
use std::collections::BTreeMap;

fn channels_json(ev: &Evaluation) -> Value {
    let mut m = Map::new();
    for (k, c) in &ev.metrics {
        m.insert(
            label(*k),
            json!({
                "rmse": c.rmse,
                "fit_pct": c.fit_pct,
                "rmse_estimation": c.rmse_est,
                "n_validation": c.n_val,
                "n_estimation": c.n_est,
                "ljung_box_p": c.ljung_box.p_value,
                "white": c.ljung_box.white(),
            }),
        );
    }
    Value::Object(m)
}

/// Parameters and their σ of the effects of `fit` (only the family `only`, keyed by parameter
/// name; else all, keyed `effect.param`).
fn fit_params(fit: &Fit, only: Option<&str>) -> (Map<String, Value>, Map<String, Value>) {
    let mut p = Map::new();
    let mut s = Map::new();
    for e in &fit.effects {
        if only.is_some_and(|o| o != e.effect.name()) {
            continue;
        }
        for q in &e.params {
            let key = if only.is_some() {
                q.name.clone()
            } else {
                format!("{}.{}", e.effect.name(), q.name)
            };
            p.insert(key.clone(), json!(q.value));
            s.insert(key, q.sigma.map_or(Value::Null, |v| json!(v)));
        }
    }
    (p, s)
}

fn stage(c: &Candidate) -> &'static str {
    if c.backward {
        "backward"
    } else if c.note.starts_with("swap") {
        "swap"
    } else {
        "forward"
    }
}

fn candidate_json(c: &Candidate) -> Value {
    let mut v = json!({
        "effect": c.effect,
        "round": c.round,
        "stage": stage(c),
        "significant": c.significant,
        "note": c.note,
    });
    if let Some(f) = &c.fit {
        let (p, s) = fit_params(f, Some(&c.effect));
        v["params"] = Value::Object(p);
        v["params_sigma"] = Value::Object(s);
        v["model"] = json!(f.names());
        v["form"] = json!(c.form);
        v["forms"] = json!(c.forms);
        v["delta_bic"] = json!(c.delta_bic);
        v["delta_bic_eff"] = json!(c.delta_bic_eff);
        v["heldout_block_t"] = json!(c.heldout_t);
        v["changed_channels_gain_pct"] = json!(100.0 * c.gain);
        v["z"] = json!(c.z);
        let mut val = Map::new();
        for (k, m) in &f.eval.metrics {
            val.insert(
                label(*k),
                json!({"rmse": m.rmse, "fit_pct": m.fit_pct, "ljung_box_p": m.ljung_box.p_value}),
            );
        }
        v["validation"] = Value::Object(val);
    }
    v
}

/// Per named effect: form, evidence, parameters with 95 % intervals, signature plot.
fn named_json(input: &ReportInput<'_>, refs: &PlotRefs) -> Vec<Value> {
    let out = input.outcome;
    out.chosen
        .effects
        .iter()
        .map(|e| {
            let name = e.effect.name();
            let ev = evidence(out, name).map(|c| {
                json!({
                    "stage": stage(c),
                    "round": c.round,
                    "changed_channels_gain_pct": 100.0 * c.gain,
                    "delta_bic_eff": c.delta_bic_eff,
                    "heldout_block_t": c.heldout_t,
                    "z": c.z,
                })
            });
            let params: Vec<Value> = e
                .params
                .iter()
                .map(|p| {
                    json!({
                        "name": p.name,
                        "unit": p.unit,
                        "value": p.value,
                        "sigma": p.sigma,
                        "sigma_white": p.sigma_white,
                        "ci95": ci95(p).map(|(a, b)| [a, b]),
                        "null": p.null,
                        "excited": p.excited,
                        "shape": p.shape,
                    })
                })
                .collect();
            json!({
                "effect": name,
                "form": e.effect.form(),
                "evidence": ev,
                "stability": out.verdict.stability.get(name),
                "params": params,
                "signature_plot": refs.signatures.get(name).map(|s| &s.path),
            })
        })
        .collect()
}

/// The whole `report.json`.
pub(super) fn report(
    input: &ReportInput<'_>,
    corr: &BTreeMap<ChannelKind, Vec<(String, f64)>>,
    refs: &PlotRefs,
) -> Value {
    let out = input.outcome;
    let ds = input.ds;
    let base = &out.baseline;
    let fin = &out.chosen;
    let (vp, vs) = fit_params(fin, None);
    let ci: Map<String, Value> = fin
        .effects
        .iter()
        .flat_map(|e| {
            e.params.iter().map(move |p| {
                (
                    format!("{}.{}", e.effect.name(), p.name),
                    ci95(p).map_or(Value::Null, |(a, b)| json!([a, b])),
                )
            })
        })
        .collect();
    let mut per_channel = Map::new();
    for (k, mb) in &base.eval.metrics {
        if let Some(mf) = fin.eval.metrics.get(k) {
            per_channel.insert(
                label(*k),
                json!({
                    "rmse_before": mb.rmse, "rmse_after": mf.rmse,
                    "fit_pct_before": mb.fit_pct, "fit_pct_after": mf.fit_pct,
                    "gain_pct": rmse_gain_pct(mb.rmse, mf.rmse),
                    "white_before": mb.ljung_box.white(), "white_after": mf.ljung_box.white(),
                }),
            );
        }
    }
    // The stepwise model (before the stability and identifiability checks): what a user who
    // picks one of an "A or B" pair would get.
    let (changed, on_changed) = out.changed_channels_gain_pct();
    let stepwise_gains: Map<String, Value> = base
        .eval
        .metrics
        .iter()
        .filter_map(|(k, mb)| {
            let ms = out.stepwise.eval.metrics.get(k)?;
            Some((label(*k), json!(rmse_gain_pct(mb.rmse, ms.rmse))))
        })
        .collect();
    let explanations: Map<String, Value> = fin
        .effects
        .iter()
        .map(|e| (e.effect.name().to_string(), json!(e.effect.explanation())))
        .collect();
    let diag: Map<String, Value> = corr
        .iter()
        .map(|(k, list)| {
            (
                label(*k),
                Value::Array(
                    list.iter()
                        .take(5)
                        .map(|(n, r)| json!({"regressor": n, "r": r}))
                        .collect(),
                ),
            )
        })
        .collect();
    let runs: Vec<Value> = ds
        .runs
        .iter()
        .map(|rd| {
            json!({
                "name": rd.run.name,
                "path": rd.run.path.display().to_string(),
                "role": if rd.holdout { "holdout" } else if rd.split_time.is_finite() { "split" } else { "estimation" },
                "duration_s": rd.run.duration(),
                "split_time_s": if rd.split_time.is_finite() { json!(rd.split_time) } else { Value::Null },
                "channels": rd.channels.iter().map(|&i| label(rd.run.channels[i].kind)).collect::<Vec<_>>(),
                "inputs": rd.run.inputs.iter().map(|i| format!("u.{}", i.name)).collect::<Vec<_>>(),
                "ingest": rd.run.ingest,
                "clamped": rd.map.clamped,
            })
        })
        .collect();
    json!({
        "tool": "shoal validate",
        "version": env!("CARGO_PKG_VERSION"),
        "vehicle": input.vehicle.name,
        "vehicle_source": input.vehicle_source,
        "runs": runs,
        "settings": {
            "replay_dt_s": ds.replay.dt,
            "replay_horizon_s": ds.anchoring.horizon,
            "replay_why": ds.anchoring.why,
            "replay_currents": ds.anchoring.currents.iter().map(|(k, c)| (k.label(), c)).collect::<BTreeMap<_, _>>(),
            "min_validation_gain_pct": 100.0 * input.opts.min_gain,
            "bic_threshold": input.opts.bic_threshold,
            "backward_eff_bic_threshold": input.opts.backward_eff_bic_threshold,
            "heldout_t_threshold": input.opts.t_threshold,
            "block_s": input.opts.block_s,
            "stability_draws": input.opts.stability_draws,
            "stability_threshold": input.opts.stability_threshold,
            "z_threshold": input.opts.z_threshold,
            "max_effects": input.opts.max_effects,
            "effects_considered": input.opts.effects.iter().map(|e| e.name()).collect::<Vec<_>>(),
        },
        "baseline": {
            "channels": channels_json(&base.eval),
            "residuals_white": base.eval.residuals_white(),
        },
        "candidates": out.candidates.iter().map(candidate_json).collect::<Vec<_>>(),
        "verdict": {
            "effects": fin.names(),
            "forms": out.verdict.forms,
            "named": named_json(input, refs),
            "possible": out.verdict.possible,
            "ambiguous": out.verdict.ambiguous,
            "next_experiment": input.next.map(|x| json!({
                "manoeuvre": x.manoeuvre,
                "what": x.what,
                "file": "next_experiment.toml",
                "duration_s": x.schedule.duration,
                "questions": x.questions,
                "tried": x.tried.iter().map(|(m, r)| json!({"manoeuvre": m, "smallest_ratio": r})).collect::<Vec<_>>(),
            })),
            "unexplained": out.verdict.unexplained,
            "stability": out.verdict.stability,
            "inclusion": out.verdict.inclusion,
            "stepwise": out.stepwise.names(),
            "stepwise_validation_gain_pct": crate::search::measures::mean_channel_gain_pct(&base.eval, &out.stepwise.eval),
            "stepwise_channel_gain_pct": stepwise_gains,
            "params": vp,
            "params_sigma": vs,
            "params_ci95": ci,
            "validation_gain_pct": out.validation_gain_pct(),
            "changed_channels": changed.iter().map(|k| label(*k)).collect::<Vec<_>>(),
            "changed_channels_gain_pct": on_changed,
            "worsened_channels": out.worsened_channels().iter().map(|(k, g)| (label(*k), json!(g))).collect::<Map<String, Value>>(),
            "residuals_white_before": base.eval.residuals_white(),
            "residuals_white_after": fin.eval.residuals_white(),
            "channels": per_channel,
            "explanations": explanations,
            "summary": verdict_sentence(out),
        },
        "diagnostics": { "baseline_residual_correlations": diag },
        "model_evaluations": out.candidates.iter().filter_map(|c| c.fit.as_ref()).map(|f| f.evaluations).sum::<usize>(),
    })
}
