//! `shoal sweep run-one DIR --index I`: one run of an expanded sweep, the unit every engine
//! executes (the local engine as a child process, Slurm as an array task, Kubernetes as an
//! indexed pod).
//!
//! It loads `runs/<hash>/world.toml`, runs it through the same path as `shoal run`
//! ([`crate::run::execute`], the library's `shoal_record::run::Run`) into the run's folder and writes `result.json` last: `ok`, or
//! `failed` with the error (a state that became non-finite, an output that could not be
//! written, a world the node cannot load). A run stopped by a signal writes no result, so it
//! counts as missing and is run again; so does one whose process dies outright. A run that is
//! already complete is not run again; one recorded as failed only with `--retry-failed`.

use super::plan::{Plan, RunResult, Status, WORLD, forget_result, run_dir, state, write_result};
use crate::exit::Failure;
use crate::exit::run_exit_code;
use crate::run::{execute, load};
use crate::signals;
use shoal_record::run::{Ending, Ran};
use shoal_world::load::LoadError;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Arguments of `shoal sweep run-one`.
#[derive(clap::Args, Debug)]
pub struct RunOneArgs {
    /// The sweep's output folder (with plan.json).
    pub dir: PathBuf,
    /// The run's index (results.csv's `index`; a Slurm array task id or a Kubernetes
    /// completion index).
    #[arg(long)]
    pub index: usize,
    /// Added to `--index` (Slurm arrays of sweeps larger than the cluster's MaxArraySize).
    #[arg(long, default_value_t = 0)]
    pub offset: usize,
    /// The plan this job was submitted for (plan.json's fingerprint); a different plan is an
    /// error instead of a run of the wrong world.
    #[arg(long)]
    pub plan: Option<String>,
    /// Working threads of the run [default: 1]. The results are the same for any number.
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=256))]
    pub threads: Option<u16>,
    /// Run it again if it is recorded as failed.
    #[arg(long)]
    pub retry_failed: bool,
}

/// `shoal sweep run-one`.
pub fn run_one(a: &RunOneArgs) -> Result<ExitCode, Failure> {
    let plan = Plan::read(&a.dir)?;
    if let Some(want) = &a.plan
        && *want != plan.id()
    {
        return Err(Failure::Input(format!(
            "{}: the plan changed (fingerprint {}, this job was submitted for {want}): the sweep \
             was expanded again after the job was submitted; submit again",
            a.dir.join(super::plan::PLAN).display(),
            plan.id()
        )));
    }
    let index = a.index + a.offset;
    let Some(run) = plan.get(index) else {
        return Err(Failure::Input(format!(
            "--index {index}: the sweep in {} has runs 0 … {}",
            a.dir.display(),
            plan.runs.len().saturating_sub(1)
        )));
    };
    let dir = &a.dir;
    let st = state(dir, &run.run);
    if st.is_ok() {
        println!("run {index} ({}): already complete", run.run);
        return Ok(ExitCode::SUCCESS);
    }
    if st.is_failed() && !a.retry_failed {
        println!(
            "run {index} ({}): recorded as failed; not run again (--retry-failed runs it)",
            run.run
        );
        return Ok(ExitCode::SUCCESS);
    }
    forget_result(dir, &run.run)?;
    let cancel = signals::install().map_err(|e| Failure::Other(e.into()))?;
    let rdir = run_dir(dir, &run.run);
    let start = Instant::now();
    let outcome = attempt(&rdir, &run.run, a.threads.map_or(1, usize::from), &cancel);
    let wall_s = start.elapsed().as_secs_f64();
    let (status, error, code) = match outcome {
        Attempt::Stopped(code) => {
            eprintln!("run {index} ({}): stopped by a signal; no result", run.run);
            return Ok(code);
        }
        Attempt::Ok => (Status::Ok, None, ExitCode::SUCCESS),
        Attempt::Failed(e, code) => (Status::Failed, Some(e), code),
    };
    let result = RunResult {
        run: run.run.clone(),
        status,
        error,
        wall_s,
    };
    write_result(dir, &result)?;
    match &result.error {
        None => println!("run {index} ({}): ok in {wall_s:.2} s", run.run),
        Some(e) => eprintln!("run {index} ({}): failed: {e}", run.run),
    }
    Ok(code)
}

/// What one attempt at a run came to.
enum Attempt {
    /// Complete.
    Ok,
    /// Failed: why, and the exit code.
    Failed(String, ExitCode),
    /// A signal stopped it (exit code of the signal).
    Stopped(ExitCode),
}

fn attempt(
    rdir: &Path,
    run: &str,
    threads: usize,
    cancel: &std::sync::Arc<shoal_world::cancel::Cancel>,
) -> Attempt {
    let world = rdir.join(WORLD);
    match std::fs::read(&world) {
        Ok(bytes) if super::plan::hash_hex(&bytes) == run => {}
        Ok(_) => {
            return Attempt::Failed(
                format!(
                    "{} changed since the sweep was expanded (its hash is no longer {run})",
                    world.display()
                ),
                ExitCode::from(2),
            );
        }
        Err(e) => {
            return Attempt::Failed(
                format!("cannot read {}: {e}", world.display()),
                ExitCode::from(2),
            );
        }
    }
    let desc = match load(Some(&world), cancel) {
        Ok(d) => d,
        Err(LoadError::World(e)) => return Attempt::Failed(e.to_string(), ExitCode::from(2)),
        Err(LoadError::Interrupted(_)) => {
            return Attempt::Stopped(cancel.cause().map_or(ExitCode::FAILURE, signals::exit_code));
        }
    };
    match execute(&desc, rdir, threads, true, cancel) {
        Ok(Ran::StoppedBeforeStart(cause)) => Attempt::Stopped(signals::exit_code(cause)),
        Ok(Ran::Finished { ending, .. }) => {
            let code = run_exit_code(&ending);
            match ending {
                Ending::Complete => Attempt::Ok,
                Ending::Interrupted(_) => Attempt::Stopped(code),
                Ending::Fault { message, .. } => Attempt::Failed(message, code),
                Ending::AgentsStopped => {
                    Attempt::Failed("the world's agents stopped the run".into(), code)
                }
            }
        }
        Err(Failure::Input(m)) => Attempt::Failed(m, ExitCode::from(2)),
        Err(Failure::Other(e)) => Attempt::Failed(format!("{e:#}"), ExitCode::FAILURE),
    }
}
