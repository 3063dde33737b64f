//! Helpers of the sweep tests (with those of `common`): running `shoal sweep`, reading
//! results.csv, and the smoke sweep's expected parameter rows.

#![allow(dead_code)]

pub use crate::common::repo;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// worlds/sweeps/smoke.toml.
pub fn smoke() -> PathBuf {
    repo().join("worlds/sweeps/smoke.toml")
}

/// A fresh temporary folder for one test.
pub fn tmp(tag: &str) -> PathBuf {
    crate::common::tmp("sweep", tag)
}

/// Runs the shoal binary with `args`.
pub fn shoal(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_shoal"))
        .args(args)
        .output()
        .unwrap()
}

/// Standard output and error of `o`, for messages.
pub fn text(o: &Output) -> String {
    format!(
        "exit {:?}\n--- stdout\n{}--- stderr\n{}",
        o.status.code(),
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// One row of results.csv: column → value.
pub type Row = BTreeMap<String, String>;

/// results.csv of `dir`: header and rows.
pub fn table(dir: &Path) -> (Vec<String>, Vec<Row>) {
    let mut r = csv::Reader::from_path(dir.join("results.csv")).unwrap();
    let header: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    let rows = r
        .records()
        .map(|rec| {
            let rec = rec.unwrap();
            header
                .iter()
                .cloned()
                .zip(rec.iter().map(String::from))
                .collect()
        })
        .collect();
    (header, rows)
}

/// The rows without the wall-clock column, which is the only one allowed to differ between
/// engines and job counts.
pub fn without_wall(rows: &[Row]) -> Vec<Row> {
    rows.iter()
        .map(|r| {
            let mut r = r.clone();
            assert!(r.remove("wall_s").is_some(), "no wall_s column");
            r
        })
        .collect()
}

/// The smoke sweep's runs in index order: (west-lane vehicles, water, seed).
pub const SMOKE_RUNS: [(&str, &str, &str); 8] = [
    ("2", "pool", "0"),
    ("2", "pool", "1"),
    ("2", "turbid_harbour", "0"),
    ("2", "turbid_harbour", "1"),
    ("4", "pool", "0"),
    ("4", "pool", "1"),
    ("4", "turbid_harbour", "0"),
    ("4", "turbid_harbour", "1"),
];

/// The smoke sweep's header.
pub const SMOKE_HEADER: [&str; 14] = [
    "index",
    "run",
    "vehicles.0.count",
    "water.attenuation",
    "seed",
    "status",
    "error",
    "digest",
    "delivery_ratio_in_range",
    "frames_sent",
    "largest_fraction_end",
    "largest_fraction_mean",
    "impacts",
    "wall_s",
];

/// The summary.json of a run's row.
pub fn run_summary(dir: &Path, row: &Row) -> serde_json::Value {
    let path = dir.join("runs").join(&row["run"]).join("summary.json");
    serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap()
}

/// A number as results.csv writes it (Rust's shortest round-trip form).
pub fn num(v: &serde_json::Value) -> String {
    format!("{}", v.as_f64().unwrap())
}
