//! What `shoal validate` writes: `report.json` (machine-readable, the schema of
//! `../shared/spec/validation.md` plus details), `report.md` (a page a person reads: the
//! verdict, one section per named effect with its evidence, confidence intervals and residual
//! signature, what is only possible, ambiguous or unexplained, and plots of measured vs
//! baseline vs extended and of the residual autocorrelation before and after), and
//! `vehicle.toml` (the input model with the found effects switched on, as a world file
//! `shoal run` loads).
//!
//! One file per concern under `report/`: `json.rs` builds `report.json`, `markdown.rs`
//! `report.md`, `plots.rs` draws every figure, `signature.rs` maps an effect family to the
//! regressor its residual signature is plotted against ([`regressor_of`]). This file holds
//! the public API and what they share.

mod json;
mod markdown;
mod plots;
mod signature;

pub use signature::{Regressor, regressor_of};

use crate::dataset::{Dataset, RunData};
use crate::evaluation::{ChannelResult, Evaluation};
use crate::run::ChannelKind;
use crate::search::{Candidate, Outcome, ParamEstimate, SearchOptions};
use crate::stats;
use shoal_model::effects::EffectInstance;
use shoal_world::spec::VehicleSpec;
use std::collections::BTreeMap;
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

/// Writes a whole file: under a temporary name, renamed when complete, so an interrupted or
/// failed write never leaves a truncated report that looks whole.
fn write(path: &Path, text: &str) -> Result<(), ReportError> {
    shoal_output::files::write_whole(path, text.as_bytes())
        .map(|_| ())
        .map_err(|e| ReportError::Write {
            path: path.to_path_buf(),
            message: e.reason.to_string(),
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

/// Writes the report into `dir` (created if needed).
pub fn write_report(dir: &Path, input: &ReportInput<'_>) -> Result<Written, ReportError> {
    std::fs::create_dir_all(dir).map_err(|e| ReportError::Write {
        path: dir.to_path_buf(),
        message: e.to_string(),
    })?;
    let mut written = Written {
        json: dir.join("report.json"),
        markdown: dir.join("report.md"),
        vehicle: dir.join("vehicle.toml"),
        plots: Vec::new(),
    };
    write_vehicle(input, &written.vehicle)?;
    let refs = if input.plots {
        let pdir = dir.join("plots");
        std::fs::create_dir_all(&pdir).map_err(|e| ReportError::Write {
            path: pdir.clone(),
            message: e.to_string(),
        })?;
        plots::write_all(&pdir, input, &mut written.plots)
    } else {
        plots::PlotRefs::default()
    };
    let corr = correlations(input.ds, &input.outcome.baseline.eval);
    let report = json::report(input, &corr, &refs);
    write(
        &written.json,
        &serde_json::to_string_pretty(&report).unwrap_or_default(),
    )?;
    write(
        &written.markdown,
        &markdown::markdown(input, &corr, &refs, &written),
    )?;
    Ok(written)
}

/// The content of `report.json` without plots (no plot files are referenced).
pub fn report_value(input: &ReportInput<'_>) -> serde_json::Value {
    let corr = correlations(input.ds, &input.outcome.baseline.eval);
    json::report(input, &corr, &plots::PlotRefs::default())
}

/// `vehicle.toml`: the input model with the found effects on.
fn write_vehicle(input: &ReportInput<'_>, path: &Path) -> Result<(), ReportError> {
    write(path, &vehicle_toml(input, path)?)
}

/// The text of `vehicle.toml` (the input model with the found effects on) to be written at
/// `path` (named in its header comment).
pub fn vehicle_toml(input: &ReportInput<'_>, path: &Path) -> Result<String, ReportError> {
    let fin = &input.outcome.chosen;
    let mut spec = input.vehicle.clone();
    let params = spec.to_params();
    let found: Vec<EffectInstance> = fin.effects.iter().map(|e| e.instance()).collect();
    spec.effects
        .extend(VehicleSpec::effect_specs(&found, &params));
    let toml = shoal_world::load::vehicle_world_toml(&spec, [5.0, 5.0, 1.0]).map_err(|e| {
        ReportError::Write {
            path: path.to_path_buf(),
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
        path.display()
    );
    Ok(header + &toml)
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
    let Some(ch) = channel_of(rd, c.kind) else {
        return;
    };
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

/// The measured channel of `kind` among the run's used channels.
fn channel_of(rd: &RunData, kind: ChannelKind) -> Option<&crate::run::Channel> {
    rd.channels
        .iter()
        .map(|&i| &rd.run.channels[i])
        .find(|x| x.kind == kind)
}

/// The search's evidence for the family `name`: its last backward check (the stepwise model
/// with against without it) if it has one, else its last fitted forward candidate.
fn evidence<'a>(out: &'a Outcome, name: &str) -> Option<&'a Candidate> {
    let fitted = |backward: bool| {
        out.candidates
            .iter()
            .rev()
            .find(|c| c.effect == name && c.backward == backward && c.fit.is_some())
    };
    fitted(true).or_else(|| fitted(false))
}

/// The candidate whose form comparison stands for the family `name`: the last forward one
/// that fitted forms, preferring one whose best form is `form`.
fn form_candidate<'a>(out: &'a Outcome, name: &str, form: &str) -> Option<&'a Candidate> {
    let with_forms = || {
        out.candidates
            .iter()
            .rev()
            .filter(|c| c.effect == name && !c.backward && !c.forms.is_empty())
    };
    with_forms()
        .find(|c| c.form == form)
        .or_else(|| with_forms().next())
}

/// The 95 % confidence interval value ± 1.96 σ with the honest σ (allowing for
/// autocorrelated residuals); `None` where σ is unknown.
pub(crate) fn ci95(p: &ParamEstimate) -> Option<(f64, f64)> {
    p.sigma
        .filter(|s| s.is_finite() && *s > 0.0)
        .map(|s| (p.value - 1.96 * s, p.value + 1.96 * s))
}

fn label(k: ChannelKind) -> String {
    format!("y.{}", k.name())
}

fn white(ev: &Evaluation) -> bool {
    ev.metrics.values().all(|m| m.ljung_box.white())
}

fn fmt_pm(v: f64, s: Option<f64>) -> String {
    match s {
        Some(s) if s > 0.0 => format!("{} ± {}", sig(v), sig(s)),
        _ => sig(v),
    }
}

/// A number with about four significant digits.
fn sig(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if (0.01..10000.0).contains(&a) {
        let d = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
        format!("{v:.d$}")
    } else {
        format!("{v:.3e}")
    }
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
