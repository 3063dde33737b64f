//! What `shoal validate` writes: `report.json` (machine-readable, the schema of
//! `../shared/spec/validation.md` plus details), `report.md` (a page a person reads: the
//! verdict, one section per named effect with its evidence, confidence intervals and residual
//! signature, what is only possible, ambiguous or unexplained, and plots of measured vs
//! baseline vs extended and of the residual autocorrelation before and after), and
//! `vehicle.toml` (the input model with the found effects switched on, as a world file
//! `shoal run` loads) and, when the log leaves a question open, `next_experiment.toml` (the
//! flight that would settle it, [`crate::experiment`]).
//!
//! One file per concern under `report/`: `json.rs` builds `report.json`, `markdown.rs`
//! `report.md`, `plots.rs` draws every figure, `signature.rs` maps an effect family to the
//! regressor its residual signature is plotted against ([`regressor_of`]); what they share is
//! in `input.rs` (what a report is made from), `wording.rs` (the verdict sentence and how
//! numbers are written) and `correlations.rs` (residuals against regressors). This file holds
//! the entry points: [`write_report`], [`report_value`] and [`vehicle_toml`].

mod correlations;
mod input;
mod json;
mod markdown;
mod plots;
mod signature;
mod wording;

pub use correlations::correlations;
pub use input::{ReportInput, Written};
pub use signature::{Regressor, regressor_of};
pub use wording::verdict_sentence;

use shoal_model::effects::EffectInstance;
use shoal_world::spec::VehicleSpec;
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
        next_experiment: None,
        plots: Vec::new(),
    };
    write_vehicle(input, &written.vehicle)?;
    if let Some(x) = input.next {
        let path = dir.join("next_experiment.toml");
        let text =
            crate::experiment::world_toml(x, input.vehicle, &input.log_name).map_err(|e| {
                ReportError::Write {
                    path: path.clone(),
                    message: e.to_string(),
                }
            })?;
        write(&path, &text)?;
        written.next_experiment = Some(path);
    }
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
