//! The local engine: the runs still to do on this machine, `--jobs` at a time, each as a
//! child process `shoal sweep run-one DIR --index I` of the same binary — exactly what a
//! Slurm task or a Kubernetes pod runs, so the table cannot depend on the engine, and a run
//! that crashes or runs out of memory takes only itself down. One progress bar with an ETA.
//!
//! A child's output goes to its run's `run.log`. A child that ends without writing its
//! result (killed, crashed) is recorded as failed with its exit status. On a stop request
//! (Ctrl-C, SIGTERM, SIGHUP) no further run starts and the running ones are asked to stop
//! (SIGTERM: they stop at their next step and write no result, so they count as missing and
//! run again next time); the engine waits for them, so the table written afterwards holds
//! exactly the runs that finished.

use super::plan::{Plan, RunResult, Status, run_dir, state, write_result};
use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use shoal_world::cancel::Cancel;
use std::collections::VecDeque;
use std::fs::File;
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// How the local engine runs.
pub struct Local<'a> {
    /// The sweep's output folder.
    pub dir: &'a Path,
    /// Its plan.
    pub plan: &'a Plan,
    /// Runs at once.
    pub jobs: usize,
    /// Run failed runs again.
    pub retry_failed: bool,
    /// No progress bar.
    pub quiet: bool,
}

/// Runs `todo` (indices) until all have run or a stop is requested; an error is a failure of
/// the engine itself (a child that cannot be started, a result that cannot be written).
pub fn run(l: &Local<'_>, todo: &[usize], cancel: &Arc<Cancel>) -> anyhow::Result<()> {
    if todo.is_empty() {
        return Ok(());
    }
    let exe = std::env::current_exe().context("cannot find this program's own path")?;
    let jobs = l.jobs.clamp(1, todo.len());
    let threads = (shoal_sim::parallel::all_cores() / jobs).max(1);
    let pb = if l.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(todo.len() as u64)
    };
    pb.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} runs, ETA {eta_precise} {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    pb.enable_steady_tick(Duration::from_millis(200));
    let queue = Mutex::new(todo.iter().copied().collect::<VecDeque<usize>>());
    let failed = Mutex::new(0usize);
    let first_error: Mutex<Option<anyhow::Error>> = Mutex::new(None);
    std::thread::scope(|s| {
        for _ in 0..jobs {
            s.spawn(|| {
                loop {
                    if cancel.is_requested() {
                        break;
                    }
                    let Some(index) = queue.lock().ok().and_then(|mut q| q.pop_front()) else {
                        break;
                    };
                    match one(l, &exe, index, threads, cancel) {
                        Ok(ok) => {
                            if !ok && let Ok(mut f) = failed.lock() {
                                *f += 1;
                                pb.set_message(format!("({f} failed)"));
                            }
                        }
                        Err(e) => {
                            if let Ok(mut slot) = first_error.lock() {
                                slot.get_or_insert(e);
                            }
                            break;
                        }
                    }
                    pb.inc(1);
                }
            });
        }
    });
    pb.finish_and_clear();
    match first_error.into_inner().ok().flatten() {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// Runs one index in a child; returns whether it is complete.
fn one(
    l: &Local<'_>,
    exe: &Path,
    index: usize,
    threads: usize,
    cancel: &Cancel,
) -> anyhow::Result<bool> {
    let run = &l.plan.runs[index];
    let rdir = run_dir(l.dir, &run.run);
    let log_path = rdir.join("run.log");
    let log =
        File::create(&log_path).with_context(|| format!("cannot create {}", log_path.display()))?;
    let log2 = log
        .try_clone()
        .with_context(|| format!("cannot write {}", log_path.display()))?;
    let mut cmd = Command::new(exe);
    cmd.args(["sweep", "run-one"])
        .arg(l.dir)
        .args(["--index", &index.to_string()])
        .args(["--plan", &l.plan.id()])
        .args(["--threads", &threads.to_string()])
        .stdin(Stdio::null())
        .stdout(Stdio::from(log))
        .stderr(Stdio::from(log2));
    if l.retry_failed {
        cmd.arg("--retry-failed");
    }
    let child = cmd
        .spawn()
        .with_context(|| format!("cannot start {}", exe.display()))?;
    let status = wait(child, cancel)?;
    let st = state(l.dir, &run.run);
    if st.is_ok() {
        return Ok(true);
    }
    if !st.is_failed() && !cancel.is_requested() {
        // It ended without a result and nobody asked it to stop: record why.
        let tail = std::fs::read_to_string(&log_path).unwrap_or_default();
        let last = tail
            .lines()
            .rev()
            .find(|l| !l.trim().is_empty())
            .unwrap_or("");
        write_result(
            l.dir,
            &RunResult {
                run: run.run.clone(),
                status: Status::Failed,
                error: Some(format!(
                    "the run's process ended without a result ({}){}",
                    describe(status),
                    if last.is_empty() {
                        String::new()
                    } else {
                        format!(": {last}")
                    }
                )),
                wall_s: 0.0,
            },
        )?;
    }
    Ok(false)
}

/// Waits for `child`; once a stop is requested, asks it to stop too (SIGTERM), and kills it
/// if it has not ended 30 s later.
fn wait(mut child: Child, cancel: &Cancel) -> anyhow::Result<ExitStatus> {
    let mut nap = Duration::from_millis(1);
    let mut asked: Option<std::time::Instant> = None;
    loop {
        if let Some(status) = child.try_wait()? {
            return Ok(status);
        }
        if cancel.is_requested() {
            match asked {
                None => {
                    asked = Some(std::time::Instant::now());
                    // Without a `kill` program the child is killed outright; it writes no
                    // result either way.
                    let sent = Command::new("kill")
                        .args(["-s", "TERM", &child.id().to_string()])
                        .stderr(Stdio::null())
                        .status()
                        .is_ok_and(|s| s.success());
                    if !sent {
                        let _ = child.kill();
                    }
                }
                Some(t) if t.elapsed() > Duration::from_secs(30) => {
                    let _ = child.kill();
                }
                Some(_) => {}
            }
        }
        std::thread::sleep(nap);
        nap = (nap * 2).min(Duration::from_millis(20));
    }
}

/// An exit status in words.
fn describe(s: ExitStatus) -> String {
    use std::os::unix::process::ExitStatusExt;
    match (s.code(), s.signal()) {
        (Some(c), _) => format!("exit code {c}"),
        (None, Some(sig)) => format!("killed by signal {sig}"),
        _ => "unknown exit status".into(),
    }
}
