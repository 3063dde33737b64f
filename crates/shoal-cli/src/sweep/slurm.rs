//! The Slurm engine: the runs still to do as a Slurm job array, each task running
//! `shoal sweep run-one DIR --index $SLURM_ARRAY_TASK_ID` with this very binary (by its
//! absolute path). shoal never runs a cluster of its own: it writes an sbatch script
//! (`DIR/slurm/submit-<n>.sbatch`), submits it with `sbatch --parsable`, prints the job id and
//! records it in `DIR/slurm/jobs.json`. Task logs go to `DIR/slurm/<job>_<task>.out`.
//!
//! The output folder (and the binary) must be on a filesystem every node shares: tasks read
//! their worlds from it and write their results into it, and the submitting machine reads
//! them back. Submitting again submits only what is missing (and, with `--retry-failed`, what
//! failed), leaving out tasks of earlier jobs that are still queued or running.
//!
//! With `--wait` the engine waits for the results itself: it watches the result files and
//! asks `squeue` now and then whether its tasks still exist (not `sbatch --wait`, which polls
//! at up to 32 s on a cluster with the default MinJobAge and cannot tell which task failed).
//! A stop request while waiting cancels the jobs (`scancel`): killing `sbatch --wait` would
//! leave the array running. A sweep larger than the cluster's MaxArraySize (which bounds the
//! task ids, 1001 by default) is submitted as several arrays whose tasks add an `--offset`.

use super::plan::{Plan, forget_result, state};
use anyhow::{Context, bail};
use indicatif::{ProgressBar, ProgressStyle};
use serde::{Deserialize, Serialize};
use shoal_output::files::write_whole;
use shoal_world::cancel::Cancel;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

/// Options of the Slurm engine.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct SlurmArgs {
    /// Slurm partition (`sbatch --partition`) [default: the cluster's default].
    #[arg(long)]
    pub partition: Option<String>,
    /// Time limit of each task (`sbatch --time`: minutes, MM:SS, HH:MM:SS, D-HH:MM, …).
    #[arg(long)]
    pub time: Option<String>,
    /// Most runs at once on the cluster (Slurm: `--array=…%K`; Kubernetes: the Job's
    /// `parallelism`).
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u32).range(1..))]
    pub max_parallel: Option<u32>,
    /// Wait until the submitted runs are done, then write the table and plots.
    #[arg(long)]
    pub wait: bool,
}

/// One submitted array, as recorded in `DIR/slurm/jobs.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Submission {
    /// The array's job id.
    pub job: String,
    /// Added to each task id to give the run's index.
    pub offset: usize,
    /// The runs (indices) it was submitted for.
    pub indices: Vec<usize>,
    /// The plan's fingerprint.
    pub plan: String,
    /// The script, relative to DIR.
    pub script: String,
}

/// The Slurm folder of a sweep.
pub fn slurm_dir(dir: &Path) -> PathBuf {
    dir.join("slurm")
}

/// The submissions recorded so far.
pub fn submissions(dir: &Path) -> Vec<Submission> {
    std::fs::read_to_string(slurm_dir(dir).join("jobs.json"))
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .unwrap_or_default()
}

fn record(dir: &Path, all: &[Submission]) -> anyhow::Result<()> {
    write_whole(
        &slurm_dir(dir).join("jobs.json"),
        (serde_json::to_string_pretty(all)? + "\n").as_bytes(),
    )?;
    Ok(())
}

/// A sorted list of indices in Slurm's array syntax: ranges `a-b`, single ids, commas
/// (`0-3,5,7-9`), with `%K` when at most K may run at once.
pub fn array_spec(ids: &[usize], throttle: Option<u32>) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut i = 0;
    while i < ids.len() {
        let mut j = i;
        while j + 1 < ids.len() && ids[j + 1] == ids[j] + 1 {
            j += 1;
        }
        parts.push(if j == i {
            ids[i].to_string()
        } else {
            format!("{}-{}", ids[i], ids[j])
        });
        i = j + 1;
    }
    let mut s = parts.join(",");
    if let Some(k) = throttle {
        s.push_str(&format!("%{k}"));
    }
    s
}

/// Splits sorted indices into arrays whose task ids stay below `max_array_size`: one array of
/// the indices themselves when they fit, else one per block of `max_array_size` indices, its
/// tasks numbered from 0 with the block's start as offset.
pub fn chunks(indices: &[usize], max_array_size: usize) -> Vec<(usize, Vec<usize>)> {
    let m = max_array_size.max(1);
    if indices.last().is_none_or(|&l| l < m) {
        return vec![(0, indices.to_vec())];
    }
    let mut out: Vec<(usize, Vec<usize>)> = Vec::new();
    for &i in indices {
        let offset = i / m * m;
        match out.last_mut() {
            Some((o, ids)) if *o == offset => ids.push(i - offset),
            _ => out.push((offset, vec![i - offset])),
        }
    }
    out
}

/// A path or word quoted for a POSIX shell.
fn sh_quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

/// Runs a Slurm command; its standard output, or an error with its standard error.
fn slurm_cmd(program: &str, args: &[&str]) -> anyhow::Result<String> {
    let out = Command::new(program).args(args).output().map_err(|e| {
        anyhow::anyhow!(
            "cannot run `{program}` ({e}): the Slurm engine needs Slurm's commands (sbatch, \
             squeue, scancel, scontrol) on PATH, and SLURM_CONF or /etc/slurm/slurm.conf \
             naming the cluster"
        )
    })?;
    if !out.status.success() {
        bail!(
            "`{program} {}` failed ({}): {}",
            args.join(" "),
            out.status,
            String::from_utf8_lossy(&out.stderr).trim()
        );
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// The cluster's MaxArraySize (`scontrol show config`; 1001, Slurm's default, when it cannot
/// be read).
fn max_array_size() -> usize {
    slurm_cmd("scontrol", &["show", "config"])
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.trim_start().starts_with("MaxArraySize"))
                .and_then(|l| l.split('=').nth(1))
                .and_then(|v| v.trim().parse().ok())
        })
        .unwrap_or(1001)
}

/// Indices of the recorded submissions (for this plan) whose tasks are still queued or
/// running, by `squeue`.
fn active(dir: &Path, plan_id: &str) -> anyhow::Result<BTreeSet<usize>> {
    let subs: Vec<Submission> = submissions(dir)
        .into_iter()
        .filter(|s| s.plan == plan_id)
        .collect();
    if subs.is_empty() {
        return Ok(BTreeSet::new());
    }
    // All of this user's tasks, one line each (`-r`); filtered here by job id, because
    // `squeue -j` fails outright once one of the ids is purged.
    let text = slurm_cmd("squeue", &["-h", "-r", "--me", "-o", "%F|%K"])?;
    let mut out = BTreeSet::new();
    for line in text.lines() {
        let Some((job, task)) = line.trim().split_once('|') else {
            continue;
        };
        for s in subs.iter().filter(|s| s.job == job) {
            if let Ok(t) = task.parse::<usize>() {
                out.insert(s.offset + t);
            } else {
                // A pending remainder not broken into tasks: count every index of the job.
                out.extend(s.indices.iter().copied());
            }
        }
    }
    Ok(out)
}

/// The sbatch script of one array.
fn script(
    plan: &Plan,
    dir: &Path,
    exe: &Path,
    spec: &str,
    offset: usize,
    retry_failed: bool,
    o: &SlurmArgs,
) -> String {
    let logs = slurm_dir(dir);
    let mut s = format!(
        "#!/bin/sh\n# shoal sweep `{}`: runs of {} (plan {}), written by `shoal sweep --engine \
         slurm`.\n# Submitting the sweep again submits only what is missing; this script is the \
         record of one submission.\n",
        plan.name,
        dir.display(),
        plan.id()
    );
    let safe_name: String = plan
        .name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    s.push_str(&format!("#SBATCH --job-name=shoal-{safe_name}\n"));
    s.push_str(&format!("#SBATCH --array={spec}\n"));
    s.push_str(&format!("#SBATCH --output={}/%A_%a.out\n", logs.display()));
    s.push_str(&format!("#SBATCH --chdir={}\n", dir.display()));
    s.push_str("#SBATCH --cpus-per-task=1\n");
    if let Some(p) = &o.partition {
        s.push_str(&format!("#SBATCH --partition={p}\n"));
    }
    if let Some(t) = &o.time {
        s.push_str(&format!("#SBATCH --time={t}\n"));
    }
    s.push_str(&format!(
        "exec {} sweep run-one {} --index \"$SLURM_ARRAY_TASK_ID\"{} --plan {} --threads \
         \"${{SLURM_CPUS_PER_TASK:-1}}\"{}\n",
        sh_quote(&exe.display().to_string()),
        sh_quote(&dir.display().to_string()),
        if offset > 0 {
            format!(" --offset {offset}")
        } else {
            String::new()
        },
        plan.id(),
        if retry_failed { " --retry-failed" } else { "" }
    ));
    s
}

/// Checks the options and the folder's path for what an sbatch script can hold.
fn check(dir: &Path, exe: &Path, o: &SlurmArgs) -> Result<(), String> {
    for (what, p) in [("the output folder", dir), ("the shoal binary", exe)] {
        let t = p.display().to_string();
        if t.chars()
            .any(|c| c.is_whitespace() || c == '"' || c == '\'' || c == '%')
        {
            return Err(format!(
                "{what} {t}: the Slurm engine needs a path without spaces, quotes or `%` \
                 (sbatch reads it from `#SBATCH` lines)"
            ));
        }
    }
    if let Some(p) = &o.partition
        && (p.is_empty()
            || !p
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "_-.,".contains(c)))
    {
        return Err(format!(
            "--partition `{p}`: a partition name (letters, digits, `_`, `-`, `.`; several \
             separated by commas)"
        ));
    }
    if let Some(t) = &o.time
        && (t.is_empty()
            || !t
                .chars()
                .all(|c| c.is_ascii_digit() || c == ':' || c == '-')
            || t.matches('-').count() > 1)
    {
        return Err(format!(
            "--time `{t}`: Slurm's time format: minutes, MM:SS, HH:MM:SS, D-HH, D-HH:MM or \
             D-HH:MM:SS"
        ));
    }
    Ok(())
}

/// Submits the runs `todo` (indices; `dir` is absolute) as one array per chunk; prints and
/// records the job ids; returns the submissions.
pub fn submit(
    dir: &Path,
    plan: &Plan,
    todo: &[usize],
    retry_failed: bool,
    o: &SlurmArgs,
) -> Result<Vec<Submission>, crate::exit::Failure> {
    let exe = std::env::current_exe().context("cannot find this program's own path")?;
    check(dir, &exe, o).map_err(crate::exit::Failure::Input)?;
    let id = plan.id();
    let busy = active(dir, &id)?;
    let todo: Vec<usize> = todo.iter().copied().filter(|i| !busy.contains(i)).collect();
    if !busy.is_empty() {
        println!(
            "shoal: {} run(s) are still queued or running in earlier jobs ({}); not submitted \
             again",
            busy.len(),
            array_spec(&busy.iter().copied().collect::<Vec<_>>(), None)
        );
    }
    if todo.is_empty() {
        return Ok(Vec::new());
    }
    let sdir = slurm_dir(dir);
    std::fs::create_dir_all(&sdir)
        .with_context(|| format!("cannot create the folder {}", sdir.display()))?;
    let mut all = submissions(dir);
    let mut made = Vec::new();
    for (offset, ids) in chunks(&todo, max_array_size()) {
        // A retried failure's old result goes first, so waiting sees the new one.
        for &t in &ids {
            forget_result(dir, &plan.runs[offset + t].run)?;
        }
        let spec = array_spec(&ids, o.max_parallel);
        let name = format!("submit-{}.sbatch", all.len() + 1);
        let path = sdir.join(&name);
        write_whole(
            &path,
            script(plan, dir, &exe, &spec, offset, retry_failed, o).as_bytes(),
        )
        .map_err(anyhow::Error::from)?;
        let out = slurm_cmd("sbatch", &["--parsable", &path.display().to_string()])?;
        // `--parsable` prints `<id>` or `<id>;<cluster>`.
        let job = out
            .trim()
            .split(';')
            .next()
            .filter(|j| !j.is_empty() && j.chars().all(|c| c.is_ascii_digit()))
            .with_context(|| format!("sbatch printed no job id: `{}`", out.trim()))?
            .to_string();
        println!(
            "shoal: submitted Slurm job {job}: array {spec} ({} run(s){}); task logs in {}/{job}_<task>.out",
            ids.len(),
            if offset > 0 {
                format!(", runs {offset} + task id")
            } else {
                String::new()
            },
            sdir.display()
        );
        let s = Submission {
            job,
            offset,
            indices: ids.iter().map(|t| offset + t).collect(),
            plan: id.clone(),
            script: format!("slurm/{name}"),
        };
        all.push(s.clone());
        record(dir, &all)?;
        made.push(s);
    }
    Ok(made)
}

/// Waits until every run of `indices` has a result or no task for them is left in Slurm
/// (then gives a shared filesystem 10 s to show late results). A stop request cancels the
/// jobs of this plan that hold any of them (`scancel`) and returns.
pub fn wait(
    dir: &Path,
    plan: &Plan,
    indices: &[usize],
    cancel: &Cancel,
    quiet: bool,
) -> anyhow::Result<()> {
    let id = plan.id();
    let jobs: Vec<String> = submissions(dir)
        .into_iter()
        .filter(|s| s.plan == id && s.indices.iter().any(|i| indices.contains(i)))
        .map(|s| s.job)
        .collect();
    if jobs.is_empty() {
        return Ok(());
    }
    let done = || {
        indices
            .iter()
            .filter(|&&i| !matches!(state(dir, &plan.runs[i].run), super::plan::State::Missing))
            .count()
    };
    let pb = if quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(indices.len() as u64)
    };
    pb.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} runs, ETA {eta_precise} (Slurm job {msg})",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    pb.set_message(jobs.join(", "));
    pb.enable_steady_tick(Duration::from_millis(200));
    let mut next_ask = Instant::now() + Duration::from_millis(500);
    let mut gap = Duration::from_millis(500);
    let mut gone: Option<Instant> = None;
    loop {
        let n = done();
        pb.set_position(n as u64);
        if n == indices.len() {
            break;
        }
        if cancel.is_requested() {
            pb.finish_and_clear();
            let mut args = vec!["--quiet"];
            args.extend(jobs.iter().map(String::as_str));
            slurm_cmd("scancel", &args)?;
            eprintln!("shoal: cancelled Slurm job(s) {}", jobs.join(", "));
            return Ok(());
        }
        if let Some(t) = gone {
            if t.elapsed() > Duration::from_secs(10) {
                break;
            }
        } else if Instant::now() >= next_ask {
            let busy = active(dir, &id)?;
            if indices.iter().all(|i| !busy.contains(i)) {
                gone = Some(Instant::now());
            }
            // Ask squeue less often the longer the wait (at most every 15 s).
            gap = (gap * 3 / 2).min(Duration::from_secs(15));
            next_ask = Instant::now() + gap;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    pb.finish_and_clear();
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arrays_are_written_in_slurm_syntax() {
        assert_eq!(array_spec(&[0, 1, 2, 3], Some(2)), "0-3%2");
        assert_eq!(array_spec(&[0, 1, 2, 3, 5, 7, 8, 9], None), "0-3,5,7-9");
        assert_eq!(array_spec(&[4], None), "4");
    }

    #[test]
    fn large_sweeps_are_split_below_max_array_size() {
        assert_eq!(chunks(&[0, 5, 1000], 1001), vec![(0, vec![0, 5, 1000])]);
        assert_eq!(
            chunks(&[3, 999, 1000, 1001, 2500], 1000),
            vec![(0, vec![3, 999]), (1000, vec![0, 1]), (2000, vec![500])]
        );
    }

    #[test]
    fn the_script_runs_this_binary_on_the_array_task() {
        let plan = Plan {
            name: "smoke test".into(),
            sweep_file: "s.toml".into(),
            parameters: vec![],
            metrics: vec![],
            runs: vec![],
        };
        let o = SlurmArgs {
            partition: Some("debug".into()),
            time: Some("10:00".into()),
            ..Default::default()
        };
        let s = script(
            &plan,
            Path::new("/data/sw"),
            Path::new("/opt/shoal"),
            "0-7%2",
            1000,
            false,
            &o,
        );
        for want in [
            "#SBATCH --array=0-7%2\n",
            "#SBATCH --output=/data/sw/slurm/%A_%a.out\n",
            "#SBATCH --partition=debug\n",
            "#SBATCH --time=10:00\n",
            "#SBATCH --job-name=shoal-smoke_test\n",
            "exec '/opt/shoal' sweep run-one '/data/sw' --index \"$SLURM_ARRAY_TASK_ID\" --offset 1000",
        ] {
            assert!(s.contains(want), "missing {want} in\n{s}");
        }
        assert!(check(Path::new("/a b"), Path::new("/x"), &o).is_err());
        let bad = SlurmArgs {
            time: Some("1 hour".into()),
            ..Default::default()
        };
        assert!(check(Path::new("/a"), Path::new("/x"), &bad).is_err());
    }
}
