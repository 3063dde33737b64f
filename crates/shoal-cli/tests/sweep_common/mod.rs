//! Helpers of the sweep tests (with those of `common`): running `shoal sweep`, reading
//! results.csv, and the smoke sweep's expected parameter rows.

#![allow(dead_code)]

#[path = "../../../shoal-record/tests/support/plots.rs"]
mod plots;

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
    crate::common::read_table(&dir.join("results.csv"))
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

/// Checks every figure of the smoke sweep in `dir` (5 metrics against each of its two
/// parameters, `vehicles.0.count` and `water.attenuation`) against aggregate.csv: in each, a
/// line per value of the other parameter (palette colours in the order of the table), a dot
/// at each mean and a bar over each 95 % interval; and each PNG decodes with those colours
/// drawn in the plot area.
pub fn assert_smoke_figures(dir: &Path) {
    let (_, rows) = crate::common::read_table(&dir.join("aggregate.csv"));
    let params = ["vehicles.0.count", "water.attenuation"];
    let mut drawn = 0;
    for metric in [
        "delivery_ratio_in_range",
        "frames_sent",
        "largest_fraction_end",
        "largest_fraction_mean",
        "impacts",
    ] {
        for (p, param) in params.iter().enumerate() {
            let other = params[1 - p];
            // Lines: the other parameter's values; categories: this one's, in table order.
            let mut lines: Vec<&str> = Vec::new();
            for row in &rows {
                if !lines.contains(&row[other].as_str()) {
                    lines.push(&row[other]);
                }
            }
            let groups: Vec<(plots::Rgb, Vec<(f64, f64)>)> = lines
                .iter()
                .enumerate()
                .map(|(g, value)| {
                    let points = rows
                        .iter()
                        .filter(|r| r[other] == *value)
                        .map(|r| {
                            let f = |c: &str| r[c].parse::<f64>().unwrap();
                            (f(&format!("{metric}_mean")), f(&format!("{metric}_ci95")))
                        })
                        .collect();
                    (shoal_output::plot::rgb(g), points)
                })
                .collect();
            let stem = dir
                .join("plots")
                .join(format!("{metric}_vs_{}", param.replace('.', "_")));
            plots::assert_ci_svg(&stem.with_extension("svg"), &groups);
            let colours: Vec<plots::Rgb> = groups.iter().map(|g| g.0).collect();
            plots::assert_png_colours(&stem.with_extension("png"), &colours, 30);
            drawn += 1;
        }
    }
    assert_eq!(drawn, 10);
}
