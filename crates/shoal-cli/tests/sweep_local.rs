//! `shoal sweep` on this machine: the smoke sweep's rows are the runs' own numbers, a second
//! call recomputes nothing, a failing run is recorded while the rest complete, the table is
//! the same whatever `--jobs`, a stop leaves a consistent table that the next call completes,
//! and a mistake in the sweep file is an error at its line.

mod common;
mod sweep_common;

use std::process::{Command, Stdio};
use std::time::{Duration, SystemTime};
use sweep_common::*;

fn mtime(p: &std::path::Path) -> SystemTime {
    std::fs::metadata(p).unwrap().modified().unwrap()
}

#[test]
fn the_smoke_sweep_gives_the_runs_numbers_and_a_second_call_recomputes_nothing() {
    let dir = tmp("smoke");
    let out = dir.join("out");
    let o = shoal(&[
        "sweep",
        smoke().to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--jobs",
        "2",
        "-q",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let (header, rows) = table(&out);
    assert_eq!(header, SMOKE_HEADER);
    assert_eq!(rows.len(), 8);
    for (i, (row, (count, water, seed))) in rows.iter().zip(SMOKE_RUNS).enumerate() {
        assert_eq!(row["index"], i.to_string());
        assert_eq!(
            (
                row["vehicles.0.count"].as_str(),
                row["water.attenuation"].as_str(),
                row["seed"].as_str()
            ),
            (count, water, seed)
        );
        assert_eq!((row["status"].as_str(), row["error"].as_str()), ("ok", ""));
        // Every cell is the run's own summary, read by its path.
        let s = run_summary(&out, row);
        assert_eq!(s["seed"].to_string(), seed);
        assert_eq!(
            s["vehicles"].as_u64().unwrap(),
            8 + count.parse::<u64>().unwrap()
        );
        assert_eq!(s["simulated_s"].as_f64(), Some(20.0));
        assert_eq!(row["digest"], s["digest"].as_str().unwrap());
        assert_eq!(
            row["delivery_ratio_in_range"],
            num(&s["comm"]["delivery_ratio"])
        );
        assert_eq!(row["frames_sent"], s["comm"]["frames_sent"].to_string());
        let n = s["vehicles"].as_f64().unwrap();
        let conn = s["comm"]["connectivity"].as_array().unwrap();
        let largest: Vec<f64> = conn
            .iter()
            .map(|c| c["largest"].as_f64().unwrap())
            .collect();
        assert_eq!(
            row["largest_fraction_end"],
            format!("{}", largest.last().unwrap() / n)
        );
        assert_eq!(
            row["largest_fraction_mean"],
            format!("{}", largest.iter().sum::<f64>() / largest.len() as f64 / n)
        );
        let impacts: u64 = s["groups"]
            .as_array()
            .unwrap()
            .iter()
            .map(|g| g["impacts"].as_u64().unwrap())
            .sum();
        assert_eq!(row["impacts"], impacts.to_string());
        // Real traffic: frames went out and some arrived.
        let dr: f64 = row["delivery_ratio_in_range"].parse().unwrap();
        assert!(dr > 0.0 && dr <= 1.0, "{row:?}");
        assert!(row["frames_sent"].parse::<u64>().unwrap() > 100, "{row:?}");
        assert!(row["wall_s"].parse::<f64>().unwrap() > 0.0);
    }
    // Turbid water (c = 2.19 /m) splits the swarm: the largest group in contact is smaller
    // than in pool water for the same vehicles and seed.
    for pair in [(0, 2), (1, 3), (4, 6), (5, 7)] {
        let f = |i: usize| rows[i]["largest_fraction_mean"].parse::<f64>().unwrap();
        assert!(
            f(pair.1) < f(pair.0),
            "{:?} vs {:?}",
            rows[pair.0],
            rows[pair.1]
        );
    }
    // Each run's world runs alone with `shoal run` to the same state.
    let row = &rows[5];
    let world = out.join("runs").join(&row["run"]).join("world.toml");
    let alone = dir.join("alone");
    let o = shoal(&[
        "run",
        world.to_str().unwrap(),
        "--out",
        alone.to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(alone.join("summary.json")).unwrap())
            .unwrap();
    assert_eq!(s["digest"].as_str().unwrap(), row["digest"]);
    // The aggregate table (4 points) and 5 metrics × 2 parameters figures (PNG and SVG).
    let agg = std::fs::read_to_string(out.join("aggregate.csv")).unwrap();
    assert_eq!(agg.lines().count(), 5, "{agg}");
    assert!(
        agg.starts_with("vehicles.0.count,water.attenuation,runs_ok,delivery_ratio_in_range_mean,")
    );
    let plots = std::fs::read_dir(out.join("plots")).unwrap().count();
    assert_eq!(plots, 20);
    // The delivery ratio rises in turbid water because it counts only receivers within the
    // (shorter) cut-off range: its column and its axis say so.
    let svg =
        std::fs::read_to_string(out.join("plots/delivery_ratio_in_range_vs_water_attenuation.svg"))
            .unwrap();
    assert!(
        svg.contains("delivered / receptions by vehicles within the cut-off range"),
        "the delivery ratio's axis does not say what it counts"
    );
    assert_smoke_figures(&out);

    // Again: nothing is run, nothing is rewritten.
    let results: Vec<_> = rows
        .iter()
        .map(|r| out.join("runs").join(&r["run"]).join("result.json"))
        .collect();
    let before: Vec<SystemTime> = results.iter().map(|p| mtime(p)).collect();
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let o = shoal(&[
        "sweep",
        smoke().to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("8 complete, 0 to run"), "{}", text(&o));
    let after: Vec<SystemTime> = results.iter().map(|p| mtime(p)).collect();
    assert_eq!(before, after);
    assert_eq!(
        std::fs::read_to_string(out.join("results.csv")).unwrap(),
        csv
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_table_is_the_same_whatever_the_number_of_jobs() {
    let dir = tmp("jobs");
    let mut tables = Vec::new();
    for jobs in ["1", "3"] {
        let out = dir.join(format!("jobs{jobs}"));
        let o = shoal(&[
            "sweep",
            smoke().to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--jobs",
            jobs,
            "--no-plots",
            "-q",
        ]);
        assert!(o.status.success(), "{}", text(&o));
        tables.push(without_wall(&table(&out).1));
    }
    assert_eq!(tables[0].len(), 8);
    assert_eq!(tables[0], tables[1]);
    std::fs::remove_dir_all(&dir).ok();
}

/// A μAUV² at full raw thrust; with 10⁵ quadratic damping its explicit integration blows up
/// within two steps, with mild damping it runs.
const BLOWUP: &str = r#"duration = 2.0
[pool]
size = [10.0, 10.0, 3.0]
[[vehicles]]
name = "probe"
position = [5.0, 5.0, 1.5]
mission = [{ t = 0.0, mode = "raw", thrusters = { top = 100.0, port = 100.0, stbd = 100.0 } }]
[[vehicles]]
name = "calm"
position = [2.0, 2.0, 1.0]
"#;

const FAILING_SWEEP: &str = r#"world = "base.toml"
seeds = 2
[grid]
vehicles.0.model.body.damping_quadratic = [[1.0, 1.0, 1.0, 0.01, 0.01, 0.01], [1e5, 1e5, 1e5, 1e5, 1e5, 1e5]]
[metrics]
simulated = "simulated_s"
"#;

#[test]
fn a_failing_run_is_recorded_the_rest_complete_and_it_is_retried_only_when_asked() {
    let dir = tmp("failing");
    std::fs::write(dir.join("base.toml"), BLOWUP).unwrap();
    std::fs::write(dir.join("sweep.toml"), FAILING_SWEEP).unwrap();
    let out = dir.join("out");
    let args = |extra: &[&'static str]| {
        let mut a: Vec<String> = vec![
            "sweep".into(),
            dir.join("sweep.toml").display().to_string(),
            "--out".into(),
            out.display().to_string(),
        ];
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };
    let run = |extra: &[&'static str]| {
        let a = args(extra);
        shoal(&a.iter().map(String::as_str).collect::<Vec<_>>())
    };
    let o = run(&[]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        String::from_utf8_lossy(&o.stdout).contains("4 runs: 2 ok, 2 failed, 0 missing"),
        "{}",
        text(&o)
    );
    let (_, rows) = table(&out);
    assert_eq!(
        rows.iter()
            .map(|r| r["status"].as_str())
            .collect::<Vec<_>>(),
        ["ok", "ok", "failed", "failed"]
    );
    for r in &rows[..2] {
        assert_eq!(r["simulated"], "2");
        assert_eq!(r["error"], "");
        assert_eq!(r["digest"].len(), 16);
    }
    for r in &rows[2..] {
        assert!(
            r["error"]
                .contains("the state of vehicle `probe` (id 0) became non-finite at t = 0.02 s"),
            "{r:?}"
        );
        assert_eq!((r["simulated"].as_str(), r["digest"].as_str()), ("", ""));
        // The failed run's own summary says so too.
        assert!(run_summary(&out, r)["failed"].is_string());
    }
    let result = |i: usize| out.join("runs").join(&rows[i]["run"]).join("result.json");
    let stamps = |ids: &[usize]| ids.iter().map(|&i| mtime(&result(i))).collect::<Vec<_>>();
    let (ok_before, failed_before) = (stamps(&[0, 1]), stamps(&[2, 3]));
    // Again: the failure is kept, nothing runs.
    let o = run(&[]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        String::from_utf8_lossy(&o.stderr)
            .contains("2 complete, 0 to run, 2 failed (kept; --retry-failed runs them again)"),
        "{}",
        text(&o)
    );
    assert_eq!(stamps(&[2, 3]), failed_before);
    // Asked: the failed runs run again (and fail again: the world is deterministic); the
    // complete ones are left alone.
    std::thread::sleep(Duration::from_millis(20));
    let o = run(&["--retry-failed"]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("2 complete, 2 to run"),
        "{}",
        text(&o)
    );
    assert_eq!(stamps(&[0, 1]), ok_before);
    assert!(
        stamps(&[2, 3])
            .iter()
            .zip(&failed_before)
            .all(|(a, b)| a > b)
    );
    assert_eq!(table(&out).1[2]["status"], "failed");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_stop_leaves_a_consistent_table_and_the_next_call_completes_it() {
    let dir = tmp("stop");
    // Six runs of the default world at its full 100 s (about a second each), one at a time.
    let sweep = format!(
        "world = \"{}\"\nseeds = 2\n[grid]\nvehicles.2.count = [2, 3, 4]\n[metrics]\n\
         delivery_ratio = \"comm.delivery_ratio\"\n",
        repo().join("worlds/default.toml").display()
    );
    std::fs::write(dir.join("sweep.toml"), sweep).unwrap();
    let out = dir.join("out");
    let args = [
        "sweep",
        dir.join("sweep.toml").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--jobs",
        "1",
        "-q",
    ]
    .map(String::from);
    let child = Command::new(env!("CARGO_BIN_EXE_shoal"))
        .args(&args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Stop it once the first run is complete.
    let start = std::time::Instant::now();
    loop {
        let done = std::fs::read_dir(out.join("runs"))
            .map(|d| d.flatten().any(|e| e.path().join("result.json").exists()))
            .unwrap_or(false);
        if done {
            break;
        }
        assert!(start.elapsed() < Duration::from_secs(60), "no run finished");
        std::thread::sleep(Duration::from_millis(10));
    }
    let status = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(143), "{}", text(&o));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("stopped by SIGTERM"),
        "{}",
        text(&o)
    );
    // Whole, and exactly the runs that finished.
    let (_, rows) = table(&out);
    assert_eq!(rows.len(), 6);
    let ok: Vec<&Row> = rows.iter().filter(|r| r["status"] == "ok").collect();
    assert!(!ok.is_empty() && ok.len() < 6, "{rows:?}");
    for r in &rows {
        let result = out.join("runs").join(&r["run"]).join("result.json");
        match r["status"].as_str() {
            "ok" => assert!(result.exists() && !r["delivery_ratio"].is_empty()),
            "missing" => assert!(!result.exists() && r["delivery_ratio"].is_empty()),
            other => panic!("status {other}: {r:?}"),
        }
    }
    let stray: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(stray.is_empty(), "{stray:?}");
    // The next call runs only the rest; the finished rows stay as they were.
    let o = shoal(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(o.status.success(), "{}", text(&o));
    let (_, after) = table(&out);
    assert!(after.iter().all(|r| r["status"] == "ok"), "{after:?}");
    for r in ok {
        assert_eq!(&after[r["index"].parse::<usize>().unwrap()], r);
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_path_the_world_format_does_not_have_is_an_error_at_its_line() {
    let dir = tmp("badpath");
    std::fs::write(
        dir.join("s.toml"),
        "seeds = 2\n[grid]\nmodem.range_m = [1.0, 2.0]\n[metrics]\nd = \"comm.delivery_ratio\"\n\
         x = \"comm.delivery_rate\"\n",
    )
    .unwrap();
    let out = dir.join("out");
    let o = shoal(&[
        "sweep",
        dir.join("s.toml").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("s.toml:6:1: metric `x`: `comm.delivery_rate`: summary.json has no field"),
        "{err}"
    );
    // Metrics are checked when the file is read; the path when the worlds are loaded.
    std::fs::write(
        dir.join("s.toml"),
        "seeds = 2\n[grid]\nmodem.range_m = [1.0, 2.0]\n[metrics]\nd = \"comm.delivery_ratio\"\n",
    )
    .unwrap();
    let o = shoal(&[
        "sweep",
        dir.join("s.toml").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("s.toml:3:7: `modem.range_m`: at the top level: unknown field `modem`"),
        "{err}"
    );
    // One line for the path, not one per value.
    assert_eq!(err.matches("unknown field `modem`").count(), 1, "{err}");
    assert!(!out.exists(), "nothing is written for an invalid sweep");
    std::fs::remove_dir_all(&dir).ok();
}
