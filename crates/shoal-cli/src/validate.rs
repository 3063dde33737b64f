//! `shoal validate`: measured runs → what the model gets wrong, the effects that explain it,
//! the fitted extension and its gain on data it did not fit.

use crate::exit::Failure;
use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use shoal_sysid::log::format::TimeUnit;
use shoal_sysid::log::segments::{GapMode, Segments};
use shoal_sysid::validate::{Config, Horizon, Progress, RunInput, ValidateError, Vehicle};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::{Mutex, OnceLock};
use std::time::Instant;

/// Arguments of `shoal validate`.
#[derive(clap::Args, Debug)]
pub struct ValidateArgs {
    /// Measured runs to fit on: CSV files (see docs/validation.md), or rosbag2s (an `.mcap`
    /// file or a rosbag2 folder, read through --mapping); without --holdout each is split into
    /// an estimation part and a later validation part.
    #[arg(required = true, value_name = "RUN.csv|BAG")]
    pub runs: Vec<PathBuf>,
    /// Runs used only for scoring, never for fitting.
    #[arg(long, num_args = 1.., value_name = "RUN.csv|BAG")]
    pub holdout: Vec<PathBuf>,
    /// How the rosbag2s among the runs map onto inputs and channels (TOML: topic, field,
    /// scale/offset, clock and axes per `u.` and `y.` name; docs/validation.md "Your rosbag2").
    #[arg(long, value_name = "MAPPING.toml")]
    pub mapping: Option<PathBuf>,
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
    /// How runs are replayed: `choose` (as `auto` for a run of 300 s or longer, else open
    /// loop; the report says why), `closed` (as `auto`, and beside each replay its
    /// closed-loop twin: the vehicle's controller following the logged references `r.*`,
    /// its commands compared with the logged ones), `open` (open loop from
    /// each run's first samples), SECONDS (re-anchored to the measured depth, attitude and
    /// rates every SECONDS, 0.5 … 3600), or `auto` (re-anchored at a horizon chosen from how
    /// long the baseline stays near the data; open loop where it stays there throughout).
    #[arg(
        long,
        value_name = "choose|closed|open|auto|SECONDS",
        default_value = "choose"
    )]
    pub horizon: Horizon,
    /// Skip plots.
    #[arg(long)]
    pub no_plots: bool,
    /// Print only the summary.
    #[arg(long, short)]
    pub quiet: bool,
}

/// The library's settings from the command line; files are read through shoal-rosbag's
/// readers (CSV, and rosbag2s through --mapping).
fn config(args: &ValidateArgs) -> Result<Config, Failure> {
    let readers = shoal_rosbag::readers(args.mapping.as_deref())
        .map_err(|e| Failure::Input(e.to_string()))?;
    Ok(Config {
        vehicle: args.vehicle.clone().map_or(Vehicle::Preset, Vehicle::File),
        split: args.split,
        dt: args.dt,
        time_unit: args.time_unit,
        gaps: args.gaps,
        max_gap: args.max_gap,
        min_segment: args.min_segment,
        channels: args.channels.clone(),
        effects: args.effects.clone(),
        threads: args.threads.map(usize::from),
        horizon: args.horizon,
        readers,
    })
}

/// A library error as the command line says it: settings by their flags.
fn input_error(e: ValidateError) -> Failure {
    let flag = |s: &str| format!("--{}", s.replace('_', "-"));
    Failure::Input(match e {
        ValidateError::Setting {
            setting,
            value,
            allowed,
        } => format!("{} {value}: allowed {allowed}", flag(setting)),
        ValidateError::UnknownName {
            setting,
            what,
            name,
            allowed,
        } => format!(
            "{}: unknown {what} `{name}` (allowed: {})",
            flag(setting),
            allowed.join(", ")
        ),
        other => other.to_string(),
    })
}

/// `shoal validate`.
pub fn validate(args: &ValidateArgs) -> Result<ExitCode, Failure> {
    let pb = if args.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new_spinner()
    };
    pb.set_style(
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {prefix} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    pb.enable_steady_tick(std::time::Duration::from_millis(200));
    let started = OnceLock::new();
    let stage = Mutex::new(StageClock::default());
    let config = config(args)?;
    let files = |paths: &[PathBuf]| -> Vec<RunInput> {
        paths.iter().map(|p| RunInput::File(p.clone())).collect()
    };
    let progress = |p: Progress<'_>| match p {
        Progress::Fit { name } => {
            let mut s = stage.lock().unwrap_or_else(|e| e.into_inner());
            s.done += 1;
            pb.set_prefix(s.line());
            pb.set_message(format!("last: {name}"));
        }
        Progress::Stage { stage: what, fits } => {
            // The search's time runs from its first stage (also when quiet).
            let _ = started.set(Instant::now());
            let mut s = stage.lock().unwrap_or_else(|e| e.into_inner());
            *s = StageClock::start(what, fits);
            pb.set_prefix(s.line());
            if !args.quiet {
                pb.suspend(|| {
                    eprintln!(
                        "shoal: {what}{}",
                        fits.map(|n| format!(" ({n} fits)")).unwrap_or_default()
                    )
                });
            }
        }
        _ if args.quiet => {}
        Progress::Read { path, segments } => print_segments(path, segments),
        Progress::Clamped { run, note } => eprintln!("  {run}: {note}"),
        Progress::Start {
            vehicle,
            estimation,
            holdout,
            split,
            families,
            forms,
            threads,
        } => {
            eprintln!(
                "shoal: validating `{vehicle}` on {estimation} run(s){} — {families} effect \
                 families in {forms} forms, {threads} thread(s) → {}",
                match split {
                    Some(s) => format!(" (split {:.0} % / {:.0} %)", 100.0 * s, 100.0 * (1.0 - s)),
                    None => format!(" + {holdout} hold-out run(s)"),
                },
                args.out.display()
            );
        }
    };
    let v = shoal_sysid::validate::validate(
        &config,
        &files(&args.runs),
        &files(&args.holdout),
        &progress,
    )
    .map_err(input_error)?;
    pb.finish_and_clear();
    let written = v
        .write(&args.out, !args.no_plots)
        .with_context(|| format!("cannot write the report into {}", args.out.display()))?;
    let wall = started.get().map_or(0.0, |t| t.elapsed().as_secs_f64());
    println!("{}", v.verdict_sentence());
    println!("Replay: {}.", v.dataset.anchoring.why);
    if let (Some(x), Some(path)) = (&v.next_experiment, &written.next_experiment) {
        let questions: Vec<String> = x
            .questions
            .iter()
            .map(|q| {
                let flight = q
                    .on_flight
                    .as_ref()
                    .map_or("—".to_string(), shoal_sysid::experiment::describe);
                format!("{} or {}: {flight}", q.a, q.b)
            })
            .collect();
        println!(
            "Next experiment: {} ({:.0} s), predicted apart by {} — {}",
            x.manoeuvre,
            x.schedule.duration,
            questions.join("; "),
            path.display()
        );
    }
    println!();
    println!(
        "{:<10} {:>16} {:>16} {:>8} {:>10} {:>10}",
        "channel", "RMSE before", "RMSE after", "gain", "fit% bef.", "fit% aft."
    );
    for r in v.channels() {
        let k = r.channel;
        println!(
            "{:<10} {:>16} {:>16} {:>7.1}% {:>10.1} {:>10.1}",
            k.label(),
            format!("{:.4} {:<5}", r.rmse_before, k.unit()),
            format!("{:.4} {:<5}", r.rmse_after, k.unit()),
            r.gain_pct,
            r.fit_pct_before,
            r.fit_pct_after
        );
    }
    let (white_before, white_after) = v.residuals_white();
    let yes = |w: bool| if w { "yes" } else { "no" };
    println!(
        "\nresiduals white (Ljung–Box 5 %): before {}, after {}",
        yes(white_before),
        yes(white_after)
    );
    let (fits, evals) = v.work();
    println!(
        "{fits} candidate fits, {evals} replays in {wall:.1} s\nwrote {}, {}, {} ({} plot files)",
        written.json.display(),
        written.markdown.display(),
        written.vehicle.display(),
        written.plots.len()
    );
    Ok(ExitCode::SUCCESS)
}

/// The stage of the search running now, for the progress line.
#[derive(Default)]
struct StageClock {
    /// What it does.
    name: String,
    /// Fits it makes, when known.
    fits: Option<usize>,
    /// Fits finished in it.
    done: usize,
    /// When it began.
    since: Option<Instant>,
}

impl StageClock {
    fn start(name: &str, fits: Option<usize>) -> Self {
        Self {
            name: name.to_string(),
            fits,
            done: 0,
            since: Some(Instant::now()),
        }
    }

    /// `stage: done/fits fits, ≈ T s left` (the time left from the stage's rate so far).
    fn line(&self) -> String {
        match self.fits {
            Some(n) if n > 0 => {
                let left = match self.since {
                    Some(t) if self.done > 0 && self.done < n => {
                        let per = t.elapsed().as_secs_f64() / self.done as f64;
                        format!(", ≈ {:.0} s left", per * (n - self.done) as f64)
                    }
                    _ => String::new(),
                };
                format!("{}: {}/{n} fits{left}", self.name, self.done.min(n))
            }
            _ => format!("{}: {} fits", self.name, self.done),
        }
    }
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
