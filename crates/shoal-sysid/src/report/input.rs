//! What a report is made from besides the search outcome ([`ReportInput`]), and the files
//! it wrote ([`Written`]).

use crate::evaluate::dataset::Dataset;
use crate::experiment::NextExperiment;
use crate::search::{Outcome, SearchOptions};
use shoal_world::spec::VehicleSpec;
use std::path::PathBuf;

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
    /// The suggested next experiment, when the log leaves a question open.
    pub next: Option<&'a NextExperiment>,
    /// The log's name as a user gave it (the first run's file), for the next experiment's
    /// header.
    pub log_name: String,
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
    /// `next_experiment.toml`, when a next experiment is suggested.
    pub next_experiment: Option<PathBuf>,
    /// Plot files (PNG and SVG).
    pub plots: Vec<PathBuf>,
}
