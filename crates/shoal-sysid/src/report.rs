//! What `shoal validate` writes: `report.json` (machine-readable, the schema of
//! `../shared/spec/validation.md` plus details), `report.md` (a page a person reads, with
//! plots of measured vs baseline vs extended and of the residual autocorrelation before and
//! after), and `vehicle.toml` (the input model with the found effects switched on, as a world
//! file `shoal run` loads).

use crate::data::{ChannelResult, Dataset, Evaluation, RunData};
use crate::run::ChannelKind;
use crate::search::{Candidate, Fit, Outcome, SearchOptions};
use crate::stats;
use serde_json::{Map, Value, json};
use shoal_model::effects::EffectInstance;
use shoal_sim::plot::{Plot, Series};
use shoal_world::spec::VehicleSpec;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A problem writing the report.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// A file could not be written.
    #[error("cannot write {path}: {message}")]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
}

fn write(path: &Path, text: &str) -> Result<(), ReportError> {
    std::fs::write(path, text).map_err(|e| ReportError::Write {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// Everything the report needs besides the search outcome.
pub struct ReportInput<'a> {
    /// The data.
    pub ds: &'a Dataset,
    /// The baseline vehicle model in file form (its `effects` are the baseline's own).
    pub vehicle: &'a VehicleSpec,
    /// Where the baseline came from (a file, or the preset name).
    pub vehicle_source: String,
    /// The search settings.
    pub opts: &'a SearchOptions,
    /// The outcome.
    pub outcome: &'a Outcome,
    /// Draw plots.
    pub plots: bool,
}

/// Files written.
#[derive(Clone, Debug, Default)]
pub struct Written {
    /// `report.json`.
    pub json: PathBuf,
    /// `report.md`.
    pub markdown: PathBuf,
    /// `vehicle.toml`.
    pub vehicle: PathBuf,
    /// Plot files (PNG and SVG).
    pub plots: Vec<PathBuf>,
}

fn label(k: ChannelKind) -> String {
    format!("y.{}", k.name())
}

fn effect_key(name: &str, param: &str) -> String {
    format!("{name}.{param}")
}

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

fn white(ev: &Evaluation) -> bool {
    ev.metrics.values().all(|m| m.ljung_box.white())
}

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
                effect_key(e.effect.name(), &q.name)
            };
            p.insert(key.clone(), json!(q.value));
            s.insert(key, q.sigma.map_or(Value::Null, |v| json!(v)));
        }
    }
    (p, s)
}

fn candidate_json(c: &Candidate) -> Value {
    let stage = if c.backward {
        "backward"
    } else if c.note.starts_with("swap") {
        "swap"
    } else {
        "forward"
    };
    let mut v = json!({
        "effect": c.effect,
        "round": c.round,
        "stage": stage,
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
        v["validation_gain_pct"] = json!(100.0 * c.gain);
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

/// Pearson correlations of the baseline's estimation residuals with candidate regressors,
/// strongest first, per channel.
pub fn correlations(ds: &Dataset, ev: &Evaluation) -> BTreeMap<ChannelKind, Vec<(String, f64)>> {
    let mut out = BTreeMap::new();
    for &kind in &ds.kinds {
        let mut resid = Vec::new();
        let mut regs: BTreeMap<String, Vec<f64>> = BTreeMap::new();
        for (rd, rr) in ds.runs.iter().zip(&ev.runs) {
            for c in rr.channels.iter().filter(|c| c.kind == kind) {
                collect_regressors(rd, c, &mut resid, &mut regs);
            }
        }
        let mut list: Vec<(String, f64)> = regs
            .into_iter()
            .filter(|(_, v)| v.len() == resid.len())
            .map(|(n, v)| {
                let r = stats::correlation(&resid, &v);
                (n, r)
            })
            .filter(|(_, r)| r.is_finite() && *r != 0.0)
            .collect();
        list.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
        out.insert(kind, list);
    }
    out
}

fn collect_regressors(
    rd: &RunData,
    c: &ChannelResult,
    resid: &mut Vec<f64>,
    regs: &mut BTreeMap<String, Vec<f64>>,
) {
    let run = &rd.run;
    let t0 = run.t[0];
    let idx: Vec<usize> = (0..c.times.len()).filter(|&i| c.est[i]).collect();
    if idx.is_empty() {
        return;
    }
    // Rows of the samples (for the inputs in force).
    let ch = rd
        .channels
        .iter()
        .map(|&i| &run.channels[i])
        .find(|x| x.kind == c.kind);
    let Some(ch) = ch else { return };
    let mut push = |name: String, v: f64| regs.entry(name).or_default().push(v);
    for &i in &idx {
        resid.push(c.resid[i]);
        let row = ch.rows[i];
        push("time".into(), c.times[i] - t0);
        for inp in &run.inputs {
            let u = inp.values[row];
            push(format!("u.{}", inp.name), u);
            push(format!("|u.{}|", inp.name), u.abs());
            push(
                format!("u.{}·|u.{}| (thrust-like)", inp.name, inp.name),
                u * u.abs(),
            );
            push(format!("sign(u.{})", inp.name), u.signum());
        }
        // Rate of the replayed channel and its square: unmodelled damping-like terms.
        let j0 = i.saturating_sub(1);
        let j1 = (i + 1).min(c.times.len() - 1);
        let dt = (c.times[j1] - c.times[j0]).max(1e-9);
        let rate = (c.predicted[j1] - c.predicted[j0]) / dt;
        push(format!("d/dt {} (replayed)", label(c.kind)), rate);
        push(
            format!("|d/dt {0}|·d/dt {0} (replayed)", label(c.kind)),
            rate * rate.abs(),
        );
    }
}

fn channel_unit(k: ChannelKind) -> &'static str {
    k.unit()
}

/// Writes the report into `dir` (created if needed).
pub fn write_report(dir: &Path, input: &ReportInput<'_>) -> Result<Written, ReportError> {
    std::fs::create_dir_all(dir).map_err(|e| ReportError::Write {
        path: dir.to_path_buf(),
        message: e.to_string(),
    })?;
    let out = input.outcome;
    let ds = input.ds;
    let base = &out.baseline;
    let fin = &out.chosen;
    let mut written = Written {
        json: dir.join("report.json"),
        markdown: dir.join("report.md"),
        vehicle: dir.join("vehicle.toml"),
        plots: Vec::new(),
    };
    // vehicle.toml: the input model with the found effects on.
    let mut spec = input.vehicle.clone();
    let params = spec.to_params();
    let found: Vec<EffectInstance> = fin.effects.iter().map(|e| e.instance()).collect();
    spec.effects
        .extend(VehicleSpec::effect_specs(&found, &params));
    let toml = shoal_world::load::vehicle_world_toml(&spec, [5.0, 5.0, 1.0]).map_err(|e| {
        ReportError::Write {
            path: written.vehicle.clone(),
            message: e.to_string(),
        }
    })?;
    let header = format!(
        "# {} extended by `shoal validate`: {}.\n# Baseline: {}. Effects found and fitted on the \
         estimation data are listed under [[vehicles.model.effects]].\n# Run it: shoal run {}\n",
        spec.name,
        if found.is_empty() {
            "no effect was needed".to_string()
        } else {
            fin.names().join(", ")
        },
        input.vehicle_source,
        written.vehicle.display()
    );
    write(&written.vehicle, &(header + &toml))?;
    // Plots.
    let mut plot_refs: Vec<(String, String)> = Vec::new();
    if input.plots {
        let pdir = dir.join("plots");
        std::fs::create_dir_all(&pdir).map_err(|e| ReportError::Write {
            path: pdir.clone(),
            message: e.to_string(),
        })?;
        for (ri, rd) in ds.runs.iter().enumerate() {
            for (ci, cb) in base.eval.runs[ri].channels.iter().enumerate() {
                let cf = &fin.eval.runs[ri].channels[ci];
                let stem = pdir.join(format!("{}_{}", rd.run.name, cb.kind.name()));
                let mut series = vec![
                    Series {
                        label: Some("measured".into()),
                        points: cb
                            .times
                            .iter()
                            .copied()
                            .zip(cb.measured.iter().copied())
                            .collect(),
                        color: 7,
                        ..Default::default()
                    },
                    Series {
                        label: Some("baseline".into()),
                        points: cb
                            .times
                            .iter()
                            .copied()
                            .zip(cb.predicted.iter().copied())
                            .collect(),
                        color: 3,
                        ..Default::default()
                    },
                ];
                if !fin.effects.is_empty() {
                    series.push(Series {
                        label: Some(format!("extended ({})", fin.names().join(" + "))),
                        points: cf
                            .times
                            .iter()
                            .copied()
                            .zip(cf.predicted.iter().copied())
                            .collect(),
                        color: 2,
                        dashed: true,
                        ..Default::default()
                    });
                }
                if rd.split_time.is_finite() {
                    let (lo, hi) = cb
                        .measured
                        .iter()
                        .chain(&cb.predicted)
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                            (a.min(*v), b.max(*v))
                        });
                    series.push(Series {
                        label: Some("estimation | validation".into()),
                        points: vec![(rd.split_time, lo), (rd.split_time, hi)],
                        color: 0,
                        dashed: true,
                        ..Default::default()
                    });
                }
                let plot = Plot {
                    title: format!(
                        "{} — {} ({})",
                        rd.run.name,
                        label(cb.kind),
                        if rd.holdout {
                            "hold-out run"
                        } else {
                            "estimation run"
                        }
                    ),
                    x_label: "t [s]".into(),
                    y_label: format!("{} [{}]", label(cb.kind), channel_unit(cb.kind)),
                    series,
                    y_down: cb.kind == ChannelKind::Depth,
                    size: (1000, 480),
                    ..Default::default()
                };
                if let Ok(files) = plot.write(&stem) {
                    plot_refs.push((
                        format!("{} {}", rd.run.name, label(cb.kind)),
                        format!("plots/{}_{}.png", rd.run.name, cb.kind.name()),
                    ));
                    written.plots.extend(files);
                }
            }
        }
        for &kind in &ds.kinds {
            let rb = base.eval.validation_residuals(kind);
            let rf = fin.eval.validation_residuals(kind);
            let lags = 60.min(rb.len().saturating_sub(1));
            let bound = 1.96 / (rb.len().max(1) as f64).sqrt();
            let to_pts = |a: Vec<f64>| -> Vec<(f64, f64)> {
                a.into_iter()
                    .enumerate()
                    .map(|(k, v)| (k as f64, v))
                    .collect()
            };
            let mut series = vec![Series {
                label: Some("baseline".into()),
                points: to_pts(stats::acf(&rb, lags)),
                color: 3,
                ..Default::default()
            }];
            if !fin.effects.is_empty() {
                series.push(Series {
                    label: Some("extended".into()),
                    points: to_pts(stats::acf(&rf, lags)),
                    color: 2,
                    ..Default::default()
                });
            }
            series.push(Series {
                label: Some("95 % bounds of white noise".into()),
                points: vec![(0.0, bound), (lags as f64, bound)],
                color: 7,
                dashed: true,
                ..Default::default()
            });
            series.push(Series {
                label: None,
                points: vec![(0.0, -bound), (lags as f64, -bound)],
                color: 7,
                dashed: true,
                ..Default::default()
            });
            let stem = pdir.join(format!("acf_{}", kind.name()));
            let plot = Plot {
                title: format!(
                    "Residual autocorrelation, {} (validation data)",
                    label(kind)
                ),
                x_label: "lag [samples]".into(),
                y_label: "autocorrelation [-]".into(),
                series,
                y_range: Some((-1.05, 1.05)),
                size: (900, 420),
                ..Default::default()
            };
            if let Ok(files) = plot.write(&stem) {
                plot_refs.push((
                    format!("residual autocorrelation {}", label(kind)),
                    format!("plots/acf_{}.png", kind.name()),
                ));
                written.plots.extend(files);
            }
        }
    }
    let corr = correlations(ds, &base.eval);
    // JSON.
    let (vp, vs) = fit_params(fin, None);
    let mut per_channel = Map::new();
    for (k, mb) in &base.eval.metrics {
        if let Some(mf) = fin.eval.metrics.get(k) {
            per_channel.insert(
                label(*k),
                json!({
                    "rmse_before": mb.rmse, "rmse_after": mf.rmse,
                    "fit_pct_before": mb.fit_pct, "fit_pct_after": mf.fit_pct,
                    "gain_pct": if mb.rmse > 0.0 { 100.0 * (1.0 - mf.rmse / mb.rmse) } else { 0.0 },
                    "white_before": mb.ljung_box.white(), "white_after": mf.ljung_box.white(),
                }),
            );
        }
    }
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
            })
        })
        .collect();
    let report = json!({
        "tool": "shoal validate",
        "version": env!("CARGO_PKG_VERSION"),
        "vehicle": input.vehicle.name,
        "vehicle_source": input.vehicle_source,
        "runs": runs,
        "settings": {
            "replay_dt_s": ds.replay.dt,
            "min_validation_gain_pct": 100.0 * input.opts.min_gain,
            "bic_threshold": input.opts.bic_threshold,
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
            "residuals_white": white(&base.eval),
        },
        "candidates": out.candidates.iter().map(candidate_json).collect::<Vec<_>>(),
        "verdict": {
            "effects": fin.names(),
            "forms": out.verdict.forms,
            "possible": out.verdict.possible,
            "ambiguous": out.verdict.ambiguous,
            "unexplained": out.verdict.unexplained,
            "stability": out.verdict.stability,
            "stepwise": out.stepwise.names(),
            "params": vp,
            "params_sigma": vs,
            "validation_gain_pct": out.validation_gain_pct(),
            "residuals_white_before": white(&base.eval),
            "residuals_white_after": white(&fin.eval),
            "channels": per_channel,
            "explanations": explanations,
            "summary": verdict_sentence(out),
        },
        "diagnostics": { "baseline_residual_correlations": diag },
        "model_evaluations": out.candidates.iter().filter_map(|c| c.fit.as_ref()).map(|f| f.evaluations).sum::<usize>(),
    });
    let text = serde_json::to_string_pretty(&report).unwrap_or_default();
    write(&written.json, &text)?;
    write(
        &written.markdown,
        &markdown(input, &corr, &plot_refs, &written),
    )?;
    Ok(written)
}

/// One sentence: what was found and what it gained.
pub fn verdict_sentence(out: &Outcome) -> String {
    let fin = &out.chosen;
    let mut tail = String::new();
    for p in &out.verdict.possible {
        tail.push_str(&format!(
            " Possible, not named: {} ({}) — {}.",
            p.effect, p.form, p.reason
        ));
    }
    for u in &out.verdict.unexplained {
        tail.push_str(&format!(
            " Unexplained structure on channel y.{}: held-out RMSE {} {} against a noise floor of {} (Ljung–Box p = {:.2e}); no catalogue family explains it.",
            u.channel.name(),
            sig(u.rmse),
            u.channel.unit(),
            sig(u.noise_floor),
            u.ljung_box_p
        ));
    }
    if fin.effects.is_empty() {
        return format!(
            "No effect is needed with strong evidence: no catalogue effect improves the held-out \
             error significantly and stably.{tail}"
        );
    }
    let parts: Vec<String> = fin
        .effects
        .iter()
        .map(|e| {
            let ps: Vec<String> = e
                .params
                .iter()
                .filter(|p| p.excited)
                .map(|p| format!("{} = {}", p.name, fmt_pm(p.value, p.sigma)))
                .collect();
            let stab = out
                .verdict
                .stability
                .get(e.effect.name())
                .map(|f| format!(", chosen in {:.0} % of resamples", 100.0 * f))
                .unwrap_or_default();
            format!(
                "{} [form {}{stab}] ({})",
                e.effect.name(),
                e.effect.form(),
                ps.join(", ")
            )
        })
        .collect();
    format!(
        "Found {}: validation RMSE {:.1} % lower than the baseline's (mean over channels).{tail}",
        parts.join(" and "),
        out.validation_gain_pct()
    )
}

fn fmt_pm(v: f64, s: Option<f64>) -> String {
    match s {
        Some(s) if s > 0.0 => format!("{} ± {}", sig(v), sig(s)),
        _ => sig(v),
    }
}

fn sig(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (0.01..10000.0).contains(&a) {
        let d = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
        format!("{v:.d$}")
    } else {
        format!("{v:.3e}")
    }
}

fn markdown(
    input: &ReportInput<'_>,
    corr: &BTreeMap<ChannelKind, Vec<(String, f64)>>,
    plots: &[(String, String)],
    written: &Written,
) -> String {
    let out = input.outcome;
    let ds = input.ds;
    let base = &out.baseline;
    let fin = &out.chosen;
    let mut s = String::new();
    let _ = writeln!(s, "# Validation report: `{}`\n", input.vehicle.name);
    let _ = writeln!(s, "Baseline model: {}.\n", input.vehicle_source);
    let _ = writeln!(s, "## Verdict\n\n{}\n", verdict_sentence(out));
    for e in &fin.effects {
        let _ = writeln!(
            s,
            "- **{}** — {}. *Why:* {}",
            e.effect.name(),
            e.effect.summary(),
            e.effect.explanation()
        );
        for p in e.params.iter().filter(|p| p.excited) {
            let _ = writeln!(
                s,
                "  - `{}` = {}{} (null {}; white-residual σ {})",
                p.name,
                fmt_pm(p.value, p.sigma),
                if p.unit == "-" || p.unit.is_empty() {
                    String::new()
                } else {
                    format!(" {}", p.unit)
                },
                sig(p.null),
                p.sigma_white.map_or("—".into(), sig)
            );
        }
    }
    let _ = writeln!(
        s,
        "\nResiduals white (Ljung–Box, 5 %) before: **{}**, after: **{}**.\n",
        yes(white(&base.eval)),
        yes(white(&fin.eval))
    );
    let _ = writeln!(
        s,
        "The extended model is in [`{}`]({}) — run it with `shoal run {}`.\n",
        file_name(&written.vehicle),
        file_name(&written.vehicle),
        written.vehicle.display()
    );
    let _ = writeln!(s, "## Validation error per channel\n");
    let _ = writeln!(
        s,
        "| channel | RMSE baseline | RMSE extended | gain | fit % baseline | fit % extended | white before (p) | white after (p) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    for (k, mb) in &base.eval.metrics {
        let mf = &fin.eval.metrics[k];
        let g = if mb.rmse > 0.0 {
            100.0 * (1.0 - mf.rmse / mb.rmse)
        } else {
            0.0
        };
        let _ = writeln!(
            s,
            "| {} [{}] | {} | {} | {:.1} % | {:.1} | {:.1} | {} ({:.3}) | {} ({:.3}) |",
            label(*k),
            k.unit(),
            sig(mb.rmse),
            sig(mf.rmse),
            g,
            mb.fit_pct,
            mf.fit_pct,
            yes(mb.ljung_box.white()),
            mb.ljung_box.p_value,
            yes(mf.ljung_box.white()),
            mf.ljung_box.p_value
        );
    }
    let _ = writeln!(s, "\n## Runs\n");
    let _ = writeln!(s, "| run | role | duration [s] | channels | inputs |");
    let _ = writeln!(s, "|---|---|---|---|---|");
    for rd in &ds.runs {
        let role = if rd.holdout {
            "hold-out (scored only)".to_string()
        } else if rd.split_time.is_finite() {
            format!(
                "estimation until t = {:.1} s, validation after",
                rd.split_time
            )
        } else {
            "estimation".to_string()
        };
        let chans: Vec<String> = rd
            .channels
            .iter()
            .map(|&i| label(rd.run.channels[i].kind))
            .collect();
        let inputs: Vec<String> = rd
            .run
            .inputs
            .iter()
            .map(|i| format!("u.{}", i.name))
            .collect();
        let _ = writeln!(
            s,
            "| {} | {} | {:.1} | {} | {} |",
            rd.run.name,
            role,
            rd.run.duration(),
            chans.join(", "),
            inputs.join(", ")
        );
    }
    let _ = writeln!(s, "\n## What the baseline gets wrong\n");
    let _ = writeln!(
        s,
        "Correlation of the baseline's estimation residuals with candidate regressors (the strongest three per channel):\n"
    );
    for (k, list) in corr {
        let top: Vec<String> = list
            .iter()
            .take(3)
            .map(|(n, r)| format!("{n} (r = {r:+.2})"))
            .collect();
        let _ = writeln!(s, "- {}: {}", label(*k), top.join("; "));
    }
    let _ = writeln!(s, "\n## Candidates\n");
    let _ = writeln!(
        s,
        "Stage *forward*: each effect fitted alone on the baseline (round 1), then added to the chosen ones; *backward*: each chosen effect tested against the model without it; *swap*: one effect exchanged for another. Significant = ΔBIC < {}, validation gain ≥ {:.0} % and a parameter ≥ {} σ from its null value.\n",
        input.opts.bic_threshold,
        100.0 * input.opts.min_gain,
        input.opts.z_threshold
    );
    let _ = writeln!(
        s,
        "| round | stage | effect | ΔBIC | validation gain | z | parameters | result |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    for c in &out.candidates {
        let stage = if c.backward {
            "backward"
        } else if c.note.starts_with("swap") {
            "swap"
        } else {
            "forward"
        };
        let params = c.fit.as_ref().map_or(String::new(), |f| {
            f.effects
                .iter()
                .filter(|e| e.effect.name() == c.effect)
                .flat_map(|e| e.params.iter())
                .filter(|p| p.excited)
                .map(|p| format!("{} = {}", p.name, fmt_pm(p.value, p.sigma)))
                .collect::<Vec<_>>()
                .join(", ")
        });
        if c.fit.is_some() {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {:.1} | {:.1} % | {:.1} | {} | {} |",
                c.round,
                stage,
                c.effect,
                c.delta_bic,
                100.0 * c.gain,
                c.z,
                params,
                c.note
            );
        } else {
            let _ = writeln!(
                s,
                "| {} | {} | {} | — | — | — | — | {} |",
                c.round, stage, c.effect, c.note
            );
        }
    }
    if !plots.is_empty() {
        let _ = writeln!(s, "\n## Plots\n");
        for (title, path) in plots {
            let _ = writeln!(s, "### {title}\n\n![{title}]({path})\n");
        }
    }
    let _ = writeln!(s, "\n## Method\n");
    let _ = writeln!(
        s,
        "The baseline is replayed open-loop with the measured inputs (zero-order hold) from the measured initial state, through the sensor models, every {} s. Residual = measured − replayed; heading and position offsets are estimated from the estimation samples (from the run itself for hold-out runs); angles are compared modulo 2π. Each effect's parameters are fitted by bounded Levenberg–Marquardt (maximum likelihood, per-channel noise estimated) on the estimation data only; validation samples are never fitted. Parameter σ allow for autocorrelated residuals; see `docs/validation.md`.",
        ds.replay.dt
    );
    s
}

fn yes(b: bool) -> &'static str {
    if b { "yes" } else { "no" }
}

fn file_name(p: &Path) -> String {
    p.file_name().map_or_else(
        || p.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}
