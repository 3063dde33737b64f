//! The results table: one row per run, built from what is in the output folder at the time
//! (so `shoal sweep collect` works while a cluster is still running the sweep).
//!
//! `results.csv` columns: `index`, `run` (the run's folder `runs/<run>`), one column per
//! varied parameter (named by its path), `seed`, `status` (`ok`, `failed`, or `missing`: not
//! run yet, interrupted, or a task that died without a result), `error` (why a run failed),
//! `digest` (the final-state digest of summary.json: equal digests mean bit-identical runs),
//! one column per metric, and `wall_s` (the run's wall-clock time \[s\]). Numbers are written
//! in the shortest form that reads back exactly; a metric a run's summary does not have is
//! empty. Everything but `wall_s` depends only on the sweep, never on the engine or on how
//! many runs ran at once.

use super::metrics::{Cell, extract};
use super::plan::{Plan, State, Status, run_dir, state};
use anyhow::Context;
use shoal_output::files::write_whole;
use std::path::{Path, PathBuf};

/// The table's file name in the output folder.
pub const RESULTS: &str = "results.csv";

/// One row of results.csv.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// Index of the run.
    pub index: usize,
    /// The run's hash.
    pub run: String,
    /// Parameter values (as written).
    pub values: Vec<String>,
    /// Seed.
    pub seed: u64,
    /// `ok`, `failed` or `missing`.
    pub status: &'static str,
    /// Why it failed.
    pub error: Option<String>,
    /// summary.json's digest (complete runs).
    pub digest: Option<String>,
    /// Metric values, in the plan's order.
    pub metrics: Vec<Option<Cell>>,
    /// Wall-clock time of the run \[s\].
    pub wall_s: Option<f64>,
}

/// The rows of a sweep, in index order.
pub fn collect(dir: &Path, plan: &Plan) -> Vec<Row> {
    plan.runs
        .iter()
        .map(|r| {
            let mut row = Row {
                index: r.index,
                run: r.run.clone(),
                values: r.values.clone(),
                seed: r.seed,
                status: "missing",
                error: None,
                digest: None,
                metrics: vec![None; plan.metrics.len()],
                wall_s: None,
            };
            let State::Done(result) = state(dir, &r.run) else {
                return row;
            };
            row.wall_s = Some(result.wall_s);
            if result.status == Status::Failed {
                row.status = "failed";
                row.error = result.error;
                return row;
            }
            let path = run_dir(dir, &r.run).join("summary.json");
            match read_json(&path) {
                Ok(summary) => {
                    row.status = "ok";
                    row.digest = summary["digest"].as_str().map(String::from);
                    row.metrics = plan.metrics.iter().map(|m| extract(m, &summary)).collect();
                }
                Err(e) => {
                    row.status = "failed";
                    row.error = Some(format!(
                        "the run is recorded complete but its summary cannot be read: {e:#}"
                    ));
                }
            }
            row
        })
        .collect()
}

fn read_json(path: &Path) -> anyhow::Result<serde_json::Value> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    serde_json::from_str(&text).with_context(|| format!("{} is not JSON", path.display()))
}

/// results.csv's header.
pub fn header(plan: &Plan) -> Vec<String> {
    let mut h: Vec<String> = vec!["index".into(), "run".into()];
    h.extend(plan.parameters.iter().cloned());
    h.extend(["seed", "status", "error", "digest"].map(String::from));
    h.extend(plan.metrics.iter().map(|m| m.name.clone()));
    h.push("wall_s".into());
    h
}

/// The rows as CSV text (header first).
pub fn to_csv(plan: &Plan, rows: &[Row]) -> anyhow::Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(header(plan))?;
    for r in rows {
        let mut rec: Vec<String> = vec![r.index.to_string(), r.run.clone()];
        rec.extend(r.values.iter().cloned());
        rec.push(r.seed.to_string());
        rec.push(r.status.into());
        rec.push(r.error.clone().unwrap_or_default());
        rec.push(r.digest.clone().unwrap_or_default());
        rec.extend(
            r.metrics
                .iter()
                .map(|c| c.as_ref().map(Cell::to_csv).unwrap_or_default()),
        );
        rec.push(r.wall_s.map(|w| format!("{w:.3}")).unwrap_or_default());
        w.write_record(&rec)?;
    }
    let bytes = w.into_inner().map_err(|e| anyhow::anyhow!("{e}"))?;
    Ok(String::from_utf8(bytes)?)
}

/// Writes results.csv (whole) into `dir`; returns its path.
pub fn write(dir: &Path, plan: &Plan, rows: &[Row]) -> anyhow::Result<PathBuf> {
    let path = dir.join(RESULTS);
    write_whole(&path, to_csv(plan, rows)?.as_bytes())?;
    Ok(path)
}

/// How many runs are ok, failed and missing.
pub fn counts(rows: &[Row]) -> (usize, usize, usize) {
    let n = |s: &str| rows.iter().filter(|r| r.status == s).count();
    (n("ok"), n("failed"), n("missing"))
}

/// A few lines for people: the counts, and each failed run with its error.
pub fn report(rows: &[Row]) -> String {
    let (ok, failed, missing) = counts(rows);
    let mut out = format!(
        "{} runs: {ok} ok, {failed} failed, {missing} missing",
        rows.len()
    );
    for r in rows.iter().filter(|r| r.status == "failed").take(10) {
        let e = r.error.as_deref().unwrap_or("");
        let first = e.lines().next().unwrap_or("");
        out.push_str(&format!("\n  run {} failed: {first}", r.index));
    }
    if failed > 10 {
        out.push_str(&format!("\n  … and {} more failed runs", failed - 10));
    }
    out
}
