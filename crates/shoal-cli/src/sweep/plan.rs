//! The output folder of a sweep and what is in it.
//!
//! ```text
//! DIR/plan.json               the runs: index → run (content hash), parameter values, seed;
//!                             the parameters and metrics (so `collect` needs no sweep file)
//! DIR/sweep.toml              the sweep file as given (a record)
//! DIR/runs/<hash>/world.toml  the run's whole world: `shoal run world.toml` repeats it
//! DIR/runs/<hash>/result.json written last by `run-one`: ok or failed (with the error), wall time
//! DIR/runs/<hash>/…           the run's outputs (summary.json, tables)
//! DIR/results.csv, aggregate.csv, plots/   the table and figures (`super::table`, `super::plots`)
//! DIR/slurm/, DIR/k8s/        the cluster engines' scripts, logs and manifests
//! ```
//!
//! A run's folder is named by the hash of its world file, so a run is found again whatever
//! index it has in a later expansion (a value added to the grid renumbers the runs but redoes
//! nothing), and a result belongs to exactly the world it was computed from. Every path in
//! plan.json is relative to DIR, so the folder can be moved or mounted elsewhere (a cluster's
//! shared filesystem, a Kubernetes volume).

use super::metrics::Metric;
use anyhow::Context;
use serde::{Deserialize, Serialize};
use shoal_output::files::write_whole;
use std::path::{Path, PathBuf};

/// The plan's file name in DIR.
pub const PLAN: &str = "plan.json";
/// A run's result file name in its folder.
pub const RESULT: &str = "result.json";
/// A run's world file name in its folder.
pub const WORLD: &str = "world.toml";

/// One run of the sweep.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlannedRun {
    /// Row number in results.csv (0-based, the order of the expansion).
    pub index: usize,
    /// Content hash of its world file (16 hex digits): its folder `runs/<run>`.
    pub run: String,
    /// The values of the varied parameters, as written in results.csv.
    pub values: Vec<String>,
    /// World seed.
    pub seed: u64,
}

/// A sweep expanded into runs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    /// Name of the sweep.
    pub name: String,
    /// The sweep file it came from (as given on the command line).
    pub sweep_file: String,
    /// The varied parameters' dotted paths (results.csv's parameter columns).
    pub parameters: Vec<String>,
    /// The metrics' columns.
    pub metrics: Vec<Metric>,
    /// The runs in index order.
    pub runs: Vec<PlannedRun>,
}

impl Plan {
    /// A short fingerprint of the runs (index → world): a job submitted for one plan refuses
    /// to run indices of another.
    pub fn id(&self) -> String {
        let mut text = String::new();
        for r in &self.runs {
            text.push_str(&format!("{}:{}\n", r.index, r.run));
        }
        hash_hex(text.as_bytes())
    }

    /// Reads DIR/plan.json.
    pub fn read(dir: &Path) -> anyhow::Result<Plan> {
        let path = dir.join(PLAN);
        let text = std::fs::read_to_string(&path).with_context(|| {
            format!(
                "cannot read {} (is {} the output folder of a sweep?)",
                path.display(),
                dir.display()
            )
        })?;
        let plan: Plan = serde_json::from_str(&text)
            .with_context(|| format!("{} is damaged", path.display()))?;
        // Every run has its place and a value per parameter; a run's folder name is a hash.
        for (i, r) in plan.runs.iter().enumerate() {
            if r.index != i
                || r.values.len() != plan.parameters.len()
                || r.run.len() != 16
                || !r.run.chars().all(|c| c.is_ascii_hexdigit())
            {
                anyhow::bail!(
                    "{} is damaged: run {i} does not fit the plan (index {}, {} values for {} \
                     parameters, folder `{}`)",
                    path.display(),
                    r.index,
                    r.values.len(),
                    plan.parameters.len(),
                    r.run
                );
            }
        }
        Ok(plan)
    }

    /// Writes DIR/plan.json (whole), unless it already says the same.
    pub fn write(&self, dir: &Path) -> anyhow::Result<()> {
        let text = serde_json::to_string_pretty(self)? + "\n";
        write_if_changed(&dir.join(PLAN), &text)
    }

    /// The run with this index.
    pub fn get(&self, index: usize) -> Option<&PlannedRun> {
        self.runs.get(index).filter(|r| r.index == index)
    }
}

/// Writes `path` whole unless it already holds exactly `text`.
pub fn write_if_changed(path: &Path, text: &str) -> anyhow::Result<()> {
    if std::fs::read(path).is_ok_and(|old| old == text.as_bytes()) {
        return Ok(());
    }
    write_whole(path, text.as_bytes())?;
    Ok(())
}

/// FNV-1a (64 bit) of `bytes` as 16 hex digits: names a run's folder after its world file.
pub fn hash_hex(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// The folder of run `run` (its hash).
pub fn run_dir(dir: &Path, run: &str) -> PathBuf {
    dir.join("runs").join(run)
}

/// How a run ended, as `run-one` recorded it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// Complete: its summary.json is the run's.
    Ok,
    /// Failed: the error says why.
    Failed,
}

/// A run's result.json.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunResult {
    /// The run (hash of its world file).
    pub run: String,
    /// Ok or failed.
    pub status: Status,
    /// Why it failed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Wall-clock time of the run from loading its world to writing this file \[s\].
    pub wall_s: f64,
}

/// Where a run stands.
#[derive(Clone, Debug, PartialEq)]
pub enum State {
    /// Not run, still running, interrupted, or ended without a result (a killed task).
    Missing,
    /// Recorded by `run-one`.
    Done(RunResult),
}

impl State {
    /// Whether the run is complete.
    pub fn is_ok(&self) -> bool {
        matches!(self, State::Done(r) if r.status == Status::Ok)
    }
    /// Whether the run is recorded as failed.
    pub fn is_failed(&self) -> bool {
        matches!(self, State::Done(r) if r.status == Status::Failed)
    }
}

/// The state of run `run`: its result.json when it is there, readable and about this run.
pub fn state(dir: &Path, run: &str) -> State {
    let path = run_dir(dir, run).join(RESULT);
    std::fs::read_to_string(path)
        .ok()
        .and_then(|t| serde_json::from_str::<RunResult>(&t).ok())
        .filter(|r| r.run == run)
        .map_or(State::Missing, State::Done)
}

/// Writes a run's result.json (whole).
pub fn write_result(dir: &Path, r: &RunResult) -> anyhow::Result<()> {
    let path = run_dir(dir, &r.run).join(RESULT);
    write_whole(&path, (serde_json::to_string_pretty(r)? + "\n").as_bytes())?;
    Ok(())
}

/// Removes a run's result.json, so that it is run again (a retried failure).
pub fn forget_result(dir: &Path, run: &str) -> anyhow::Result<()> {
    let path = run_dir(dir, run).join(RESULT);
    match std::fs::remove_file(&path) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(e).with_context(|| format!("cannot remove {}", path.display())),
    }
}

/// Which runs still need running: the missing ones, and the failed ones when `retry_failed`.
pub fn todo(dir: &Path, plan: &Plan, retry_failed: bool) -> Vec<usize> {
    plan.runs
        .iter()
        .filter(|r| {
            let s = state(dir, &r.run);
            !s.is_ok() && (retry_failed || !s.is_failed())
        })
        .map(|r| r.index)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hash_is_fnv1a() {
        // The published FNV-1a 64 test vectors.
        assert_eq!(hash_hex(b""), "cbf29ce484222325");
        assert_eq!(hash_hex(b"a"), "af63dc4c8601ec8c");
        assert_eq!(hash_hex(b"foobar"), "85944171f73967e8");
    }
}
