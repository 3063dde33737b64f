//! `shoal sweep`: many runs, one table (docs/sweeps.md).
//!
//! `shoal sweep FILE --out DIR` reads a sweep file ([`file`]), expands it into numbered runs
//! whose whole world files it writes under `DIR/runs/<hash>/` ([`expand`], [`plan`]), runs the
//! ones not yet complete with an engine — this machine's cores ([`local`]), a Slurm job array
//! ([`slurm`]) or a Kubernetes Indexed Job manifest ([`k8s`]) — and builds `DIR/results.csv`
//! ([`table`]) and the aggregate table and figures ([`plots`]). Every engine runs the same unit,
//! `shoal sweep run-one DIR --index I` ([`run_one`]), which runs one world through `shoal
//! run`'s own path; so the table is the same whatever the engine and however many runs ran at
//! once (only the wall times differ). Metrics are read from each run's summary.json by path
//! ([`metrics`]).
//!
//! Exit codes: 0 when every run is complete; 1 when some failed or are missing (the table
//! lists them) or an output cannot be written; 2 for an invalid sweep file or option;
//! 128 + n when a signal stopped the sweep (the table then holds the runs that finished).

mod expand;
mod file;
mod k8s;
mod local;
mod metrics;
mod plan;
mod plots;
mod run_one;
mod slurm;
mod table;

use crate::exit::Failure;
use crate::signals;
use anyhow::Context;
use clap::{Subcommand, ValueEnum};
use plan::Plan;
use shoal_world::cancel::Cancel;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// `shoal sweep` and its subcommands.
#[derive(clap::Args, Debug)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct SweepCmd {
    /// Work on a sweep's output folder instead of running a sweep file.
    #[command(subcommand)]
    pub sub: Option<SweepSub>,
    /// Run a sweep file.
    #[command(flatten)]
    pub run: SweepArgs,
}

/// The subcommands of `shoal sweep`.
#[derive(Subcommand, Debug)]
pub enum SweepSub {
    /// Run one run of an expanded sweep (what each engine runs: a local child process, a
    /// Slurm array task, a Kubernetes pod).
    RunOne(run_one::RunOneArgs),
    /// Build results.csv, aggregate.csv and the plots from whatever runs are done.
    Collect(CollectArgs),
}

/// Where the runs run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Engine {
    /// On this machine, `--jobs` runs at a time.
    Local,
    /// As a Slurm job array (`sbatch`).
    Slurm,
    /// Write a Kubernetes Indexed Job manifest (`kubectl apply -f DIR/k8s/job.json`).
    K8s,
}

/// Arguments of `shoal sweep FILE --out DIR`.
#[derive(clap::Args, Debug)]
pub struct SweepArgs {
    /// The sweep file (TOML, e.g. worlds/sweeps/smoke.toml).
    #[arg(required = true)]
    pub file: Option<PathBuf>,
    /// Output folder (on a filesystem shared by all nodes for `--engine slurm` or `k8s`).
    #[arg(long, required = true)]
    pub out: Option<PathBuf>,
    /// Where the runs run.
    #[arg(long, value_enum, default_value_t = Engine::Local)]
    pub engine: Engine,
    /// Runs at once on this machine (local engine) [default: every core].
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=1024))]
    pub jobs: Option<u16>,
    /// Run the runs recorded as failed again (otherwise they are kept as failed).
    #[arg(long)]
    pub retry_failed: bool,
    /// Write the tables but no plots.
    #[arg(long)]
    pub no_plots: bool,
    /// No progress bar.
    #[arg(long, short)]
    pub quiet: bool,
    #[command(flatten)]
    pub slurm: slurm::SlurmArgs,
    #[command(flatten)]
    pub k8s: k8s::K8sArgs,
}

/// Arguments of `shoal sweep collect`.
#[derive(clap::Args, Debug)]
pub struct CollectArgs {
    /// The sweep's output folder.
    pub dir: PathBuf,
    /// Write the tables but no plots.
    #[arg(long)]
    pub no_plots: bool,
}

/// `shoal sweep …`.
pub fn main(cmd: &SweepCmd) -> Result<ExitCode, Failure> {
    match &cmd.sub {
        Some(SweepSub::RunOne(a)) => run_one::run_one(a),
        Some(SweepSub::Collect(a)) => {
            let plan = Plan::read(&a.dir)?;
            finish(&a.dir, &plan, &Cancel::new(), a.no_plots)
        }
        None => sweep(&cmd.run),
    }
}

/// An absolute form of `p` (for scripts that run elsewhere), without resolving links.
fn absolute(p: &Path) -> anyhow::Result<PathBuf> {
    std::path::absolute(p).with_context(|| format!("cannot make {} absolute", p.display()))
}

fn sweep(a: &SweepArgs) -> Result<ExitCode, Failure> {
    let (Some(file), Some(out)) = (&a.file, &a.out) else {
        return Err(Failure::Input(
            "usage: shoal sweep FILE --out DIR (see shoal sweep --help)".into(),
        ));
    };
    let cancel = signals::install().context("cannot catch signals")?;
    let jobs = a
        .jobs
        .map_or_else(shoal_sim::parallel::all_cores, usize::from);
    let sweep = file::read(file).map_err(Failure::Input)?;
    let ex = expand::expand(&sweep, &file.display().to_string(), jobs).map_err(Failure::Input)?;
    let dir = absolute(out)?;
    expand::write(&dir, &ex, &sweep.text)?;
    let plan = ex.plan;
    let todo = plan::todo(&dir, &plan, a.retry_failed);
    let complete = plan
        .runs
        .iter()
        .filter(|r| plan::state(&dir, &r.run).is_ok())
        .count();
    let failed = plan.runs.len() - complete - plan::todo(&dir, &plan, false).len();
    let seeds = sweep.seeds.as_ref().map_or(1, Vec::len);
    if !a.quiet {
        eprintln!(
            "shoal: sweep `{}`: {} runs ({} point(s) × {seeds} seed(s)) in {}; {complete} \
             complete, {} to run{}",
            plan.name,
            plan.runs.len(),
            plan.runs.len() / seeds.max(1),
            dir.display(),
            todo.len(),
            if failed > 0 && !a.retry_failed {
                format!(", {failed} failed (kept; --retry-failed runs them again)")
            } else {
                String::new()
            }
        );
    }
    match a.engine {
        Engine::Local => {
            local::run(
                &local::Local {
                    dir: &dir,
                    plan: &plan,
                    jobs,
                    retry_failed: a.retry_failed,
                    quiet: a.quiet,
                },
                &todo,
                &cancel,
            )?;
            finish(&dir, &plan, &cancel, a.no_plots)
        }
        Engine::Slurm => {
            let subs = slurm::submit(&dir, &plan, &todo, a.retry_failed, &a.slurm)?;
            if subs.is_empty() && todo.is_empty() {
                println!("shoal: nothing to submit: every run is complete or recorded as failed");
            }
            if !a.slurm.wait {
                println!(
                    "shoal: `shoal sweep collect {}` builds the table from the runs done so \
                     far; the same `shoal sweep` command submits what is still missing",
                    dir.display()
                );
                return Ok(ExitCode::SUCCESS);
            }
            // The runs still to do, whether submitted now or by an earlier call.
            slurm::wait(&dir, &plan, &todo, &cancel, a.quiet)?;
            finish(&dir, &plan, &cancel, a.no_plots)
        }
        Engine::K8s => {
            let path = k8s::write(&dir, &plan, a.slurm.max_parallel, a.retry_failed, &a.k8s)?;
            println!(
                "shoal: wrote {} (an Indexed Job of {} runs). Put {} on the volume `{}`, then \
                 `kubectl apply -f {}`; `shoal sweep collect {}` builds the table from the \
                 runs done so far (docs/sweeps.md)",
                path.display(),
                plan.runs.len(),
                dir.display(),
                a.k8s.pvc,
                path.display(),
                dir.display()
            );
            Ok(ExitCode::SUCCESS)
        }
    }
}

/// Writes the table (and, unless stopped or `no_plots`, the aggregate table and plots),
/// prints the counts, and gives the sweep's exit code.
fn finish(dir: &Path, plan: &Plan, cancel: &Cancel, no_plots: bool) -> Result<ExitCode, Failure> {
    let rows = table::collect(dir, plan);
    let csv = table::write(dir, plan, &rows)?;
    if !no_plots && !cancel.is_requested() {
        let seen = cancel.requests();
        plots::write(dir, plan, &rows, &|| cancel.requests() > seen)?;
    }
    println!("shoal: {} → {}", table::report(&rows), csv.display());
    if let Some(cause) = cancel.cause() {
        eprintln!(
            "shoal: stopped by {}; the table holds the runs that finished (the same command \
             runs the rest)",
            cause.name
        );
        return Ok(signals::exit_code(cause));
    }
    let (ok, failed, missing) = table::counts(&rows);
    if ok == rows.len() {
        Ok(ExitCode::SUCCESS)
    } else {
        Err(Failure::Other(anyhow::anyhow!(
            "{failed} run(s) failed and {missing} are missing (results.csv lists them; \
             --retry-failed runs the failed ones again)"
        )))
    }
}
