//! Helpers shared by the agent tests: the repository root and the example agents of
//! shoal-bridge, built with cargo like the binary under test.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus};
use std::time::{Duration, Instant};

/// The repository root.
pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Builds the shoal-bridge example `name` (same profile as the `shoal` binary under test)
/// and returns its path.
pub fn example_agent(name: &str) -> PathBuf {
    let bin_dir = Path::new(env!("CARGO_BIN_EXE_shoal")).parent().unwrap();
    let mut build = Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()));
    build
        .args(["build", "-q", "-p", "shoal-bridge", "--example", name])
        .current_dir(repo());
    if bin_dir.ends_with("release") {
        build.arg("--release");
    }
    let o = build.output().unwrap();
    assert!(
        o.status.success(),
        "building {name} failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let exe = bin_dir
        .join("examples")
        .join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    assert!(exe.exists(), "{} missing", exe.display());
    exe
}

/// Runs `shoal bench --agents LANG --vehicles 1,20 --json` with `extra` arguments and checks
/// the rows: every tick of at least one simulated second measured, statistics ordered.
pub fn check_agent_bench(lang: &str, extra: &[&std::ffi::OsStr]) {
    let o = Command::new(env!("CARGO_BIN_EXE_shoal"))
        .args([
            "bench",
            "--agents",
            lang,
            "--vehicles",
            "1,20",
            "--seconds",
            "0.2",
            "--json",
        ])
        .args(extra)
        .current_dir(repo())
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{out}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    println!("{out}");
    let json: serde_json::Value = serde_json::from_str(&out[out.find("\n[").unwrap()..]).unwrap();
    let rows = json.as_array().unwrap();
    assert_eq!(rows.len(), 2);
    for (row, n) in rows.iter().zip([1, 20]) {
        assert_eq!(row["agent"], lang);
        assert_eq!(row["vehicles"], n);
        // At least 1 s simulated at a 0.05 s control period, each tick one round trip.
        assert!(row["ticks"].as_u64().unwrap() >= 20, "{row}");
        let (m, p, x) = (
            row["median_us"].as_f64().unwrap(),
            row["p99_us"].as_f64().unwrap(),
            row["max_us"].as_f64().unwrap(),
        );
        assert!(m > 0.0 && m <= p && p <= x, "{row}");
    }
}

/// A fresh temporary directory `shoal-<tag>-<pid>-<name>`.
pub fn tmp(tag: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("shoal-{tag}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Waits for `c` at most `limit`, killing it after that (a test never hangs).
pub fn wait(c: &mut Child, limit: Duration) -> ExitStatus {
    let start = Instant::now();
    loop {
        if let Some(s) = c.try_wait().unwrap() {
            return s;
        }
        if start.elapsed() > limit {
            let _ = c.kill();
            let s = c.wait().unwrap();
            panic!("process did not finish within {limit:?} (killed: {s})");
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// A run's summary.json.
pub fn summary(out: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
}
