//! `shoal validate`: measured runs → what the model gets wrong, the effects that explain it,
//! the fitted extension and its gain on data it did not fit.

use crate::Failure;
use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use shoal_model::effects;
use shoal_model::presets;
use shoal_model::rigid_body::Environment;
use shoal_sysid::data::{DataOptions, Dataset};
use shoal_sysid::ingest::{ReadOptions, TimeUnit};
use shoal_sysid::replay::ReplayOptions;
use shoal_sysid::report::{ReportInput, verdict_sentence, write_report};
use shoal_sysid::run::{ChannelKind, MeasuredRun};
use shoal_sysid::search::{SearchOptions, search};
use shoal_sysid::segments::{GapMode, GapOptions, Segments};
use shoal_world::load::load_vehicle;
use shoal_world::spec::VehicleSpec;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Arguments of `shoal validate`.
#[derive(clap::Args, Debug)]
pub struct ValidateArgs {
    /// Measured runs (CSV, see docs/validation.md) to fit on; without --holdout each is split
    /// into an estimation part and a later validation part.
    #[arg(required = true, value_name = "RUN.csv")]
    pub runs: Vec<PathBuf>,
    /// Runs used only for scoring, never for fitting.
    #[arg(long, num_args = 1.., value_name = "RUN.csv")]
    pub holdout: Vec<PathBuf>,
    /// Vehicle model in the world-file format (its first vehicle group) [default: the μAUV²
    /// preset].
    #[arg(long, value_name = "FILE")]
    pub vehicle: Option<PathBuf>,
    /// Output folder for report.json, report.md, plots and vehicle.toml.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Fraction of each run used for estimation when no hold-out runs are given (0…1).
    #[arg(long, default_value_t = 0.6)]
    pub split: f64,
    /// Replay time step [s] (1e-4 … 0.1).
    #[arg(long, default_value_t = 0.01)]
    pub dt: f64,
    /// Unit of a plain `t` column: s or ms (a header `t_s`, `t[s]`, `t_ms`, `t[ms]` declares
    /// its own; a conflict is an error) [default: s].
    #[arg(long, value_name = "s|ms")]
    pub time_unit: Option<TimeUnit>,
    /// At a gap in time: split the run into segments NAME#1, NAME#2, … or refuse it (error).
    #[arg(long, value_name = "split|error", default_value = "split")]
    pub gaps: GapMode,
    /// A step between rows longer than this is a gap [s] [default: max(10 × the median
    /// sample period, 1 s)].
    #[arg(long, value_name = "SECONDS")]
    pub max_gap: Option<f64>,
    /// Segments shorter than this are dropped [s].
    #[arg(long, value_name = "SECONDS", default_value_t = 1.0)]
    pub min_segment: f64,
    /// Use only these measurements (comma separated, e.g. y.r,y.depth).
    #[arg(long, value_delimiter = ',', value_name = "y.NAME")]
    pub channels: Vec<String>,
    /// Consider only these effects (comma separated) [default: the whole catalogue].
    #[arg(long, value_delimiter = ',', value_name = "EFFECT")]
    pub effects: Vec<String>,
    /// Worker threads for candidate fits (results do not depend on it) [default: all cores].
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=256))]
    pub threads: Option<u16>,
    /// Skip plots.
    #[arg(long)]
    pub no_plots: bool,
    /// Print only the summary.
    #[arg(long, short)]
    pub quiet: bool,
}

/// `shoal validate`.
pub fn validate(args: &ValidateArgs) -> Result<ExitCode, Failure> {
    if !(args.dt >= ReplayOptions::DT_MIN && args.dt <= ReplayOptions::DT_MAX) {
        return Err(Failure::Input(format!(
            "--dt {}: allowed {} ≤ dt ≤ {} s",
            args.dt,
            ReplayOptions::DT_MIN,
            ReplayOptions::DT_MAX
        )));
    }
    if args.max_gap.is_some_and(|g| !(g.is_finite() && g > 0.0)) {
        return Err(Failure::Input(format!(
            "--max-gap {}: allowed a number of seconds > 0",
            args.max_gap.unwrap_or_default()
        )));
    }
    if !(args.min_segment.is_finite() && args.min_segment >= 0.0) {
        return Err(Failure::Input(format!(
            "--min-segment {}: allowed a number of seconds ≥ 0",
            args.min_segment
        )));
    }
    if args.holdout.is_empty() && !(args.split > 0.0 && args.split < 1.0) {
        return Err(Failure::Input(format!(
            "--split {}: allowed 0 < split < 1",
            args.split
        )));
    }
    let channels = if args.channels.is_empty() {
        None
    } else {
        let mut v = Vec::new();
        for c in &args.channels {
            let name = c.strip_prefix("y.").unwrap_or(c);
            match ChannelKind::from_name(name) {
                Some(k) => v.push(k),
                None => {
                    let all: Vec<String> = ChannelKind::ALL
                        .iter()
                        .map(|(_, n)| format!("y.{n}"))
                        .collect();
                    return Err(Failure::Input(format!(
                        "--channels: unknown measurement `{c}` (allowed: {})",
                        all.join(", ")
                    )));
                }
            }
        }
        Some(v)
    };
    let mut catalogue = effects::catalogue();
    if !args.effects.is_empty() {
        for e in &args.effects {
            if effects::by_name(e).is_none() {
                return Err(Failure::Input(format!(
                    "--effects: unknown effect `{e}` (allowed: {})",
                    effects::names().join(", ")
                )));
            }
        }
        catalogue.retain(|e| args.effects.iter().any(|n| n == e.name()));
    }
    let (spec, env, source) = match &args.vehicle {
        Some(p) => {
            let vf = load_vehicle(p).map_err(|e| Failure::Input(e.to_string()))?;
            (vf.spec, vf.env, format!("`{}`", p.display()))
        }
        None => (
            VehicleSpec::from_params(&presets::uauv2()),
            Environment::default(),
            "the built-in `uauv2` preset (`shoal preset uauv2`)".to_string(),
        ),
    };
    let params = spec.to_params();
    let base_effects = spec.effects(&params).list().to_vec();
    let read_opts = ReadOptions {
        time_unit: args.time_unit,
    };
    let gap_opts = GapOptions {
        mode: args.gaps,
        max_gap: args.max_gap,
        min_duration: args.min_segment,
        ..Default::default()
    };
    let read = |paths: &[PathBuf]| -> Result<Vec<MeasuredRun>, Failure> {
        let mut runs = Vec::new();
        for p in paths {
            let run = MeasuredRun::read_with(p, &read_opts)
                .and_then(|r| r.split_at_gaps(&gap_opts))
                .map_err(|e| Failure::Input(e.to_string()))?;
            if !args.quiet {
                print_segments(p, &run);
            }
            runs.extend(run.runs);
        }
        Ok(runs)
    };
    let est = read(&args.runs)?;
    let hold = read(&args.holdout)?;
    let ds = Dataset::new(
        &params,
        env,
        est,
        hold,
        &DataOptions {
            split: args.split,
            channels,
            replay: ReplayOptions {
                dt: args.dt,
                ..Default::default()
            },
        },
    )
    .map_err(|e| Failure::Input(e.to_string()))?;
    if !args.quiet {
        for rd in &ds.runs {
            for note in &rd.map.clamped {
                eprintln!("  {}: {note}", rd.run.name);
            }
        }
    }
    let threads = args.threads.map_or_else(
        || std::thread::available_parallelism().map_or(1, |n| n.get().min(8)),
        usize::from,
    );
    let opts = SearchOptions {
        effects: catalogue,
        threads,
        base_effects,
        ..Default::default()
    };
    if !args.quiet {
        eprintln!(
            "shoal: validating `{}` on {} run(s){} — {} effects, {} thread(s) → {}",
            spec.name,
            ds.runs.iter().filter(|r| !r.holdout).count(),
            if args.holdout.is_empty() {
                format!(
                    " (split {:.0} % / {:.0} %)",
                    100.0 * args.split,
                    100.0 * (1.0 - args.split)
                )
            } else {
                format!(
                    " + {} hold-out run(s)",
                    ds.runs.iter().filter(|r| r.holdout).count()
                )
            },
            opts.effects.len(),
            threads,
            args.out.display()
        );
    }
    let pb = if args.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new_spinner()
    };
    pb.set_style(
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {pos} fits  {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    let start = Instant::now();
    let outcome = search(&ds, &params, &opts, &|name| {
        pb.inc(1);
        pb.set_message(format!("last: {name}"));
    });
    pb.finish_and_clear();
    let written = write_report(
        &args.out,
        &ReportInput {
            ds: &ds,
            vehicle: &spec,
            vehicle_source: source,
            opts: &opts,
            outcome: &outcome,
            plots: !args.no_plots,
        },
    )
    .with_context(|| format!("cannot write the report into {}", args.out.display()))?;
    let wall = start.elapsed().as_secs_f64();
    println!("{}", verdict_sentence(&outcome));
    println!();
    println!(
        "{:<10} {:>16} {:>16} {:>8} {:>10} {:>10}",
        "channel", "RMSE before", "RMSE after", "gain", "fit% bef.", "fit% aft."
    );
    for (k, mb) in &outcome.baseline.eval.metrics {
        let mf = &outcome.chosen.eval.metrics[k];
        let gain = if mb.rmse > 0.0 {
            100.0 * (1.0 - mf.rmse / mb.rmse)
        } else {
            0.0
        };
        println!(
            "{:<10} {:>16} {:>16} {:>7.1}% {:>10.1} {:>10.1}",
            format!("y.{}", k.name()),
            format!("{:.4} {:<5}", mb.rmse, k.unit()),
            format!("{:.4} {:<5}", mf.rmse, k.unit()),
            gain,
            mb.fit_pct,
            mf.fit_pct
        );
    }
    let white = |e: &shoal_sysid::data::Evaluation| e.metrics.values().all(|m| m.ljung_box.white());
    println!(
        "\nresiduals white (Ljung–Box 5 %): before {}, after {}",
        if white(&outcome.baseline.eval) {
            "yes"
        } else {
            "no"
        },
        if white(&outcome.chosen.eval) {
            "yes"
        } else {
            "no"
        }
    );
    let fits = outcome
        .candidates
        .iter()
        .filter(|c| c.fit.is_some())
        .count();
    let evals: usize = outcome
        .candidates
        .iter()
        .filter_map(|c| c.fit.as_ref())
        .map(|f| f.evaluations)
        .sum();
    println!(
        "{fits} candidate fits, {evals} replays in {wall:.1} s\nwrote {}, {}, {} ({} plot files)",
        written.json.display(),
        written.markdown.display(),
        written.vehicle.display(),
        written.plots.len()
    );
    Ok(ExitCode::SUCCESS)
}

/// Prints how a file was read and, when it has gaps, its segments (at most 20 listed).
fn print_segments(path: &Path, seg: &Segments) {
    let info = seg
        .runs
        .first()
        .map(|r| r.ingest.to_string())
        .unwrap_or_default();
    eprintln!("shoal: read {}: {info}", path.display());
    if seg.notes.len() > 1 {
        const SHOWN: usize = 20;
        for note in seg.notes.iter().take(SHOWN) {
            eprintln!("  {note}");
        }
        if seg.notes.len() > SHOWN {
            eprintln!(
                "  … and {} more segment(s) ({} dropped in all)",
                seg.notes.len() - SHOWN,
                seg.dropped()
            );
        }
    }
}
