//! The whole validation in one call ([`validate`]): measured runs (files, or CSV text already
//! in memory) and a baseline vehicle → read, split at gaps, checked against the vehicle,
//! searched, judged. The command line (`shoal validate`) and the Python package
//! (`shoal.validate`) are thin layers over it. Settings are checked before anything is read,
//! with errors that name the setting and its allowed range ([`ValidateError`]).

pub use crate::evaluate::anchoring::Horizon;
use crate::evaluate::dataset::{DataError, DataOptions, Dataset};
use crate::evaluate::evaluation::rmse_gain_pct;
use crate::evaluate::open_loop::ReplayOptions;
use crate::experiment::{NextExperiment, next_experiment};
use crate::log::format::{ReadOptions, TimeUnit};
use crate::log::limits::ClampNote;
use crate::log::readers::Readers;
use crate::log::run::{ChannelKind, MeasuredRun, RunError};
use crate::log::segments::{GapMode, GapOptions, Segments};
use crate::report::{
    ReportError, ReportInput, Written, report_value, vehicle_toml, verdict_sentence, write_report,
};
use crate::search::{Outcome, SearchOptions, Step, search};
use shoal_model::effects;
use shoal_model::presets;
use shoal_model::rigid_body::Environment;
use shoal_world::error::WorldError;
use shoal_world::load::load_vehicle;
use shoal_world::spec::VehicleSpec;
use std::path::{Path, PathBuf};

/// The baseline vehicle of a validation.
#[derive(Clone, Debug, Default)]
pub enum Vehicle {
    /// The built-in μAUV² preset.
    #[default]
    Preset,
    /// A world file: the model of its first vehicle group, in its water.
    File(PathBuf),
}

/// One measured run to read.
#[derive(Clone, Debug)]
pub enum RunInput {
    /// A log file or folder, read by the first of [`Config::readers`] that recognises it by
    /// content (CSV as docs/validation.md describes; a rosbag2 through its mapping).
    File(PathBuf),
    /// CSV text already in memory; `name` stands for the file name in messages and reports.
    Text {
        /// Name of the run (as a file name: `yaw_1.csv` → run `yaw_1`).
        name: String,
        /// The CSV text, header first.
        csv: String,
    },
    /// A run already read (by another reader: a rosbag2 through its mapping); it is split at
    /// gaps and checked like a file.
    Measured(Box<MeasuredRun>),
}

impl RunInput {
    /// The path that names this run in messages.
    pub fn path(&self) -> &Path {
        match self {
            RunInput::File(p) => p,
            RunInput::Text { name, .. } => Path::new(name),
            RunInput::Measured(run) => &run.path,
        }
    }
}

/// Everything a validation can be told besides its runs.
#[derive(Clone, Debug)]
pub struct Config {
    /// The baseline vehicle.
    pub vehicle: Vehicle,
    /// Fraction of each run used for estimation when no hold-out runs are given (0 < split <
    /// 1; default 0.6).
    pub split: f64,
    /// Replay time step \[s\] (1e-4 … 0.1; default 0.01).
    pub dt: f64,
    /// Unit of a plain `t` column (a header `t_s`, `t_ms`, … declares its own; default s).
    pub time_unit: Option<TimeUnit>,
    /// What a gap in time does: split the run into segments, or refuse it.
    pub gaps: GapMode,
    /// A step between rows longer than this is a gap \[s\] (> 0; default max(10 × the median
    /// sample period, 1 s)).
    pub max_gap: Option<f64>,
    /// Segments shorter than this are dropped \[s\] (≥ 0; default 1).
    pub min_segment: f64,
    /// Use only these measurements, named with or without `y.` (empty: every one measured).
    pub channels: Vec<String>,
    /// Consider only these effects (empty: the whole catalogue).
    pub effects: Vec<String>,
    /// Worker threads for candidate fits (results do not depend on it; default: every core,
    /// at most 8).
    pub threads: Option<usize>,
    /// How runs are replayed (see [`Horizon`]): chosen from the log (the default:
    /// re-anchored as [`Horizon::Auto`] for runs of 300 s or longer, else open loop), or as
    /// asked — open loop, closed loop with the vehicle's controller following the logged
    /// references, or re-anchored to the measurements every so many seconds (given, or
    /// chosen from the data).
    pub horizon: Horizon,
    /// The readers files are read through, the first that recognises a file reading it
    /// (default: CSV, and a rosbag2 refused for want of a mapping; `shoal_rosbag::readers`
    /// adds the rosbag2 reader with its mapping).
    pub readers: Readers,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            vehicle: Vehicle::Preset,
            split: 0.6,
            dt: ReplayOptions::default().dt,
            time_unit: None,
            gaps: GapMode::Split,
            max_gap: None,
            min_segment: 1.0,
            channels: Vec::new(),
            effects: Vec::new(),
            threads: None,
            horizon: Horizon::Choose,
            readers: Readers::default(),
        }
    }
}

/// Why a validation could not run.
#[derive(Debug, thiserror::Error)]
pub enum ValidateError {
    /// A setting outside its allowed range.
    #[error("{setting} = {value}: allowed {allowed}")]
    Setting {
        /// The setting (a field of [`Config`]).
        setting: &'static str,
        /// Its value.
        value: f64,
        /// What is allowed.
        allowed: String,
    },
    /// A measurement or effect name that does not exist.
    #[error("{setting}: unknown {what} `{name}` (allowed: {})", allowed.join(", "))]
    UnknownName {
        /// The setting (`channels` or `effects`).
        setting: &'static str,
        /// What was named (`measurement` or `effect`).
        what: &'static str,
        /// The name given.
        name: String,
        /// Every allowed name.
        allowed: Vec<String>,
    },
    /// The vehicle file cannot be loaded.
    #[error(transparent)]
    Vehicle(#[from] WorldError),
    /// A run cannot be read, or does not fit the vehicle.
    #[error(transparent)]
    Run(#[from] RunError),
    /// The runs together cannot make a dataset.
    #[error(transparent)]
    Data(#[from] DataError),
}

/// What a validation reports while it works.
#[derive(Debug)]
pub enum Progress<'a> {
    /// A file was read: how, and its segments (more than one when it had gaps).
    Read {
        /// The run's path (or name).
        path: &'a Path,
        /// Its segments.
        segments: &'a Segments,
    },
    /// Measured inputs of a run were clamped to the vehicle's limits.
    Clamped {
        /// The run.
        run: &'a str,
        /// What was clamped, and how often.
        note: &'a ClampNote,
    },
    /// The search starts.
    Start {
        /// The vehicle's name.
        vehicle: &'a str,
        /// Runs (segments) fitted on.
        estimation: usize,
        /// Hold-out runs (segments).
        holdout: usize,
        /// The estimation fraction of each run, when there are no hold-out runs.
        split: Option<f64>,
        /// Effect families considered.
        families: usize,
        /// Their forms (each fitted on its own in round 1).
        forms: usize,
        /// Worker threads.
        threads: usize,
    },
    /// A stage of the search begins.
    Stage {
        /// What it does.
        stage: &'a str,
        /// Candidate fits it makes, when known in advance.
        fits: Option<usize>,
    },
    /// A candidate fit finished.
    Fit {
        /// The candidate.
        name: &'a str,
    },
}

/// A finished validation: the data, the search's outcome and the settings that made it.
pub struct Validation {
    /// The runs as evaluated.
    pub dataset: Dataset,
    /// The baseline vehicle in file form.
    pub vehicle: VehicleSpec,
    /// Where the baseline came from (for the report).
    pub vehicle_source: String,
    /// The search settings used.
    pub options: SearchOptions,
    /// What the search found.
    pub outcome: Outcome,
    /// The flight that would settle the questions the log leaves open ("A or B", effects
    /// only possible), when there are any.
    pub next_experiment: Option<NextExperiment>,
    /// The name of the first run as given (a file name), for the next experiment's header.
    pub log_name: String,
}

/// One row of the before/after table of a validation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChannelRow {
    /// The measurement.
    pub channel: ChannelKind,
    /// Validation RMSE of the baseline (unit of the channel, see [`ChannelKind::unit`]).
    pub rmse_before: f64,
    /// Validation RMSE of the chosen model (same unit).
    pub rmse_after: f64,
    /// Relative RMSE reduction \[%\] (0 when the baseline's RMSE is 0).
    pub gain_pct: f64,
    /// NRMSE fit of the baseline \[%\].
    pub fit_pct_before: f64,
    /// NRMSE fit of the chosen model \[%\].
    pub fit_pct_after: f64,
}

impl Validation {
    /// One sentence: what was found and what it gained.
    pub fn verdict_sentence(&self) -> String {
        verdict_sentence(&self.outcome)
    }

    /// The per-channel validation error before and after, in channel order.
    pub fn channels(&self) -> Vec<ChannelRow> {
        let (before, after) = (&self.outcome.baseline.eval, &self.outcome.chosen.eval);
        before
            .metrics
            .iter()
            .map(|(k, mb)| {
                let mf = &after.metrics[k];
                ChannelRow {
                    channel: *k,
                    rmse_before: mb.rmse,
                    rmse_after: mf.rmse,
                    gain_pct: rmse_gain_pct(mb.rmse, mf.rmse),
                    fit_pct_before: mb.fit_pct,
                    fit_pct_after: mf.fit_pct,
                }
            })
            .collect()
    }

    /// Whether every channel's held-out residuals are white (Ljung–Box at 5 %): (baseline,
    /// chosen model).
    pub fn residuals_white(&self) -> (bool, bool) {
        (
            self.outcome.baseline.eval.residuals_white(),
            self.outcome.chosen.eval.residuals_white(),
        )
    }

    /// Candidate fits made and the open-loop replays they took.
    pub fn work(&self) -> (usize, usize) {
        let fits = self
            .outcome
            .candidates
            .iter()
            .filter_map(|c| c.fit.as_ref());
        (fits.clone().count(), fits.map(|f| f.evaluations).sum())
    }

    /// Writes `report.json`, `report.md`, `vehicle.toml` and (with `plots`) the plots into
    /// `dir`, created if missing.
    pub fn write(&self, dir: &Path, plots: bool) -> Result<Written, ReportError> {
        write_report(dir, &self.report_input(plots))
    }

    /// The content of `report.json` (without plots).
    pub fn report_value(&self) -> serde_json::Value {
        report_value(&self.report_input(false))
    }

    /// The fitted vehicle as a world file (`vehicle.toml`; its header names `path`).
    pub fn vehicle_toml(&self, path: &Path) -> Result<String, ReportError> {
        vehicle_toml(&self.report_input(false), path)
    }

    /// The suggested next experiment as a world file (the text of `next_experiment.toml`), or
    /// `None` when the log leaves no question open.
    pub fn next_experiment_toml(&self) -> Result<Option<String>, ReportError> {
        let Some(x) = &self.next_experiment else {
            return Ok(None);
        };
        crate::experiment::world_toml(x, &self.vehicle, &self.log_name)
            .map(Some)
            .map_err(|e| ReportError::Write {
                path: PathBuf::from("next_experiment.toml"),
                message: e.to_string(),
            })
    }

    /// The report's input (for the report's parts written one by one).
    pub fn report_input(&self, plots: bool) -> ReportInput<'_> {
        ReportInput {
            ds: &self.dataset,
            vehicle: &self.vehicle,
            vehicle_source: self.vehicle_source.clone(),
            opts: &self.options,
            outcome: &self.outcome,
            plots,
            next: self.next_experiment.as_ref(),
            log_name: self.log_name.clone(),
        }
    }
}

/// Checks `config` against the allowed ranges (before anything is read).
fn check(config: &Config, has_holdout: bool) -> Result<(), ValidateError> {
    let range = |setting, value: f64, ok: bool, allowed: String| {
        if ok {
            Ok(())
        } else {
            Err(ValidateError::Setting {
                setting,
                value,
                allowed,
            })
        }
    };
    let (lo, hi) = (ReplayOptions::DT_MIN, ReplayOptions::DT_MAX);
    let dt = config.dt;
    range(
        "dt",
        dt,
        dt >= lo && dt <= hi,
        format!("{lo} ≤ dt ≤ {hi} s"),
    )?;
    if let Some(g) = config.max_gap {
        let ok = g.is_finite() && g > 0.0;
        range("max_gap", g, ok, "a number of seconds > 0".into())?;
    }
    let m = config.min_segment;
    let ok = m.is_finite() && m >= 0.0;
    range("min_segment", m, ok, "a number of seconds ≥ 0".into())?;
    if !has_holdout {
        let s = config.split;
        range("split", s, s > 0.0 && s < 1.0, "0 < split < 1".into())?;
    }
    if let Horizon::Every(h) = config.horizon {
        let (lo, hi) = (Horizon::MIN_S, Horizon::MAX_S);
        let ok = (lo..=hi).contains(&h);
        range(
            "horizon",
            h,
            ok,
            format!("{lo} ≤ horizon ≤ {hi} s, or auto"),
        )?;
    }
    Ok(())
}

/// The measurements `names` (with or without `y.`), or `None` for all.
fn channel_kinds(names: &[String]) -> Result<Option<Vec<ChannelKind>>, ValidateError> {
    if names.is_empty() {
        return Ok(None);
    }
    names
        .iter()
        .map(|c| {
            ChannelKind::from_name(c.strip_prefix("y.").unwrap_or(c)).ok_or_else(|| {
                ValidateError::UnknownName {
                    setting: "channels",
                    what: "measurement",
                    name: c.clone(),
                    allowed: ChannelKind::ALL
                        .iter()
                        .map(|(_, n)| format!("y.{n}"))
                        .collect(),
                }
            })
        })
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
}

/// The effect catalogue, or only the effects `names`.
fn catalogue(names: &[String]) -> Result<Vec<std::sync::Arc<dyn effects::Effect>>, ValidateError> {
    if let Some(e) = names.iter().find(|e| effects::by_name(e).is_none()) {
        return Err(ValidateError::UnknownName {
            setting: "effects",
            what: "effect",
            name: e.clone(),
            allowed: effects::names().iter().map(|n| n.to_string()).collect(),
        });
    }
    let mut all = effects::catalogue();
    if !names.is_empty() {
        all.retain(|e| names.iter().any(|n| n == e.name()));
    }
    Ok(all)
}

/// The baseline vehicle, its water and where it came from.
fn baseline(v: &Vehicle) -> Result<(VehicleSpec, Environment, String), ValidateError> {
    Ok(match v {
        Vehicle::File(p) => {
            let vf = load_vehicle(p)?;
            (vf.spec, vf.env, format!("`{}`", p.display()))
        }
        Vehicle::Preset => (
            VehicleSpec::from_params(&presets::uauv2()),
            Environment::default(),
            "the built-in `uauv2` preset (`shoal preset uauv2`)".to_string(),
        ),
    })
}

/// Reads `inputs` and splits each at its gaps; reports each file read.
fn read_runs(
    inputs: &[RunInput],
    readers: &Readers,
    read: &ReadOptions,
    gaps: &GapOptions,
    progress: &(dyn Fn(Progress<'_>) + Sync),
) -> Result<Vec<MeasuredRun>, ValidateError> {
    let mut runs = Vec::new();
    for input in inputs {
        let run = match input {
            RunInput::File(p) => readers.read(p, read),
            RunInput::Text { name, csv } => MeasuredRun::parse_with(csv, Path::new(name), read),
            RunInput::Measured(run) => Ok(run.as_ref().clone()),
        }?;
        let segments = run.split_at_gaps(gaps)?;
        progress(Progress::Read {
            path: input.path(),
            segments: &segments,
        });
        runs.extend(segments.runs);
    }
    Ok(runs)
}

/// Validates the baseline of `config` on the measured `runs` (fitted on; without hold-out
/// runs each is split into an estimation part and a later validation part) and `holdouts`
/// (scored only): reads and checks every run, searches the effect catalogue and judges
/// what it finds. `progress` hears of every file read, every clamped input, the start of the
/// search and every candidate fit. Writes nothing: see [`Validation::write`].
pub fn validate(
    config: &Config,
    runs: &[RunInput],
    holdouts: &[RunInput],
    progress: &(dyn Fn(Progress<'_>) + Sync),
) -> Result<Validation, ValidateError> {
    check(config, !holdouts.is_empty())?;
    let channels = channel_kinds(&config.channels)?;
    let effects = catalogue(&config.effects)?;
    let (vehicle, env, vehicle_source) = baseline(&config.vehicle)?;
    let params = vehicle.to_params();
    let base_effects = vehicle.effects(&params).list().to_vec();
    let read = ReadOptions {
        time_unit: config.time_unit,
    };
    let gaps = GapOptions {
        mode: config.gaps,
        max_gap: config.max_gap,
        min_duration: config.min_segment,
        ..Default::default()
    };
    let est = read_runs(runs, &config.readers, &read, &gaps, progress)?;
    let hold = read_runs(holdouts, &config.readers, &read, &gaps, progress)?;
    let mut dataset = Dataset::new(
        &params,
        env,
        est,
        hold,
        &DataOptions {
            split: config.split,
            channels,
            replay: ReplayOptions {
                dt: config.dt,
                ..Default::default()
            },
        },
    )?;
    for rd in &dataset.runs {
        for note in &rd.map.clamped {
            progress(Progress::Clamped {
                run: &rd.run.name,
                note,
            });
        }
    }
    let threads = config
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get().min(8)));
    let options = SearchOptions {
        effects,
        threads: threads.max(1),
        base_effects,
        ..Default::default()
    };
    dataset.anchor(
        config.horizon,
        &options.baseline_model(&params, dataset.env.density),
    );
    let count = |holdout: bool| dataset.runs.iter().filter(|r| r.holdout == holdout).count();
    progress(Progress::Start {
        vehicle: &vehicle.name,
        estimation: count(false),
        holdout: count(true),
        split: holdouts.is_empty().then_some(config.split),
        families: options.family_count(),
        forms: options.effects.len(),
        threads: options.threads,
    });
    let outcome = search(&dataset, &params, &options, &|step| match step {
        Step::Stage { stage, fits } => progress(Progress::Stage { stage, fits }),
        Step::Fit(name) => progress(Progress::Fit { name }),
    });
    progress(Progress::Stage {
        stage: "the next experiment",
        fits: None,
    });
    let next_experiment = next_experiment(&dataset, &params, &options, &outcome);
    let log_name = runs.first().map_or_else(String::new, |r| {
        r.path()
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
    });
    Ok(Validation {
        dataset,
        vehicle,
        vehicle_source,
        options,
        outcome,
        next_experiment,
        log_name,
    })
}
