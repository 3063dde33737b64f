//! The `shoal` binary end to end: outputs of a run, errors for bad input (exit 2, located
//! messages, no panic), `check` on every shipped world, and the bench table's shape (no
//! timing assertions: speed belongs in benches). Signals: `signals.rs`; write errors:
//! `disk_full.rs`.

mod common;
mod run_plots;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn shoal() -> Command {
    Command::new(env!("CARGO_BIN_EXE_shoal"))
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("shoal-cli-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn text(o: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn default_run_writes_all_outputs() {
    let out = tmp("default");
    let o = shoal()
        .args(["run", "--quiet", "--duration", "5", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let (stdout, stderr) = text(&o);
    assert!(o.status.success(), "{stdout}\n{stderr}");
    assert!(
        stdout.contains("default swarm: 12 vehicles") && stdout.contains("digest"),
        "{stdout}"
    );
    // The plots draw the trajectories' numbers (a 5-s run: tracks are short).
    run_plots::assert_depth_and_top(&out, 500, 60);
    // 12 vehicles × (5 s · 10 Hz + the initial row), plus the header.
    let csv = std::fs::read_to_string(out.join("trajectories.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 1 + 12 * 51);
    let header: Vec<&str> = lines[0].split(',').collect();
    for c in [
        "t_s",
        "vehicle",
        "x_m",
        "yaw_rad",
        "w_m_s",
        "depth_reading_m",
        "cmd_port_pct",
        "tilt_beta_rad",
    ] {
        assert!(header.contains(&c), "column {c} in {header:?}");
    }
    assert!(
        lines
            .iter()
            .skip(1)
            .all(|l| l.split(',').count() == header.len())
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["vehicles"], 12);
    assert_eq!(summary["interrupted"], false);
    assert_eq!(summary["steps"], 500);
    assert_eq!(summary["trajectory_rows"], 12 * 51);
}

#[test]
fn bad_world_file_exits_2_with_a_located_message() {
    let dir = tmp("bad");
    let cases = [
        (
            "typo.toml",
            "duration = 10\ndurration = 5\n",
            "typo.toml:2:1",
            "did you mean `duration`",
        ),
        (
            "unit.toml",
            "duration = \"10 s\"\n",
            "unit.toml:1:",
            "seconds",
        ),
        (
            "mass.toml",
            "[[vehicles]]\nposition = [1, 1, 1]\n[vehicles.model.body]\nmass = -3\n",
            "mass.toml:4:1",
            "0.001 ≤ mass ≤ 1e5 kg",
        ),
        (
            "overlap.toml",
            "[[vehicles]]\nname = \"a\"\nposition = [1, 1, 1]\n[[vehicles]]\nname = \"b\"\nposition = [1.05, 1, 1]\n",
            "overlap.toml:4:",
            "overlaps vehicle `a`",
        ),
        ("syntax.toml", "[pool\n", "syntax.toml:1:", ""),
    ];
    for (name, body, location, hint) in cases {
        let p = dir.join(name);
        std::fs::write(&p, body).unwrap();
        for cmd in ["run", "check"] {
            let o = shoal().arg(cmd).arg(&p).output().unwrap();
            let (_, stderr) = text(&o);
            assert_eq!(o.status.code(), Some(2), "{cmd} {name}: {stderr}");
            assert!(
                stderr.contains(location) && stderr.contains(hint),
                "{cmd} {name}: {stderr}"
            );
            assert!(!stderr.contains("panicked"), "{stderr}");
        }
    }
    let o = shoal()
        .args(["run", "no/such/world.toml"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).1.contains("no/such/world.toml: cannot read"));
}

#[test]
fn every_shipped_world_checks() {
    for e in std::fs::read_dir(repo().join("worlds")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "toml") {
            let o = shoal().arg("check").arg(&p).output().unwrap();
            assert!(o.status.success(), "{}: {}", p.display(), text(&o).1);
        }
    }
}

/// Vehicles of the thread test: well above the threshold below which every loop runs on the
/// calling thread ([`shoal_sim::parallel::MIN_PARALLEL`]), and enough that the medium's
/// reception loop has more receivers than that in some steps (with 400 vehicles in none, the
/// beacons being spread over 50 ms); the summary's `parallel_dispatches` shows it.
const THREADS_VEHICLES: usize = 600;

/// The phases of a step as summary.json and `shoal bench --json` name them.
const STEP_PHASES: [&str; 6] = [
    "ingest",
    "vehicles",
    "medium_snapshot",
    "medium_transmit",
    "medium_delivery",
    "recorder",
];

#[test]
fn one_and_two_threads_give_the_same_digest() {
    use shoal_sim::bench::{TRAFFIC_SPACING, swarm_text};
    use shoal_sim::parallel::MIN_PARALLEL;
    const { assert!(THREADS_VEHICLES >= MIN_PARALLEL + MIN_PARALLEL / 2) };
    // The benchmark swarm with optical traffic: every vehicle in auto mode with its tilt
    // drives moving, a ring of four modems each and a beacon a second (within 50 ms), so that
    // the vehicle loops and the medium's reception loop (over the vehicles that may hear a
    // frame ending in the step) take the parallel path on 2 threads. 3 s: three rounds of
    // beacons.
    let dir = tmp("threads");
    let world = dir.join("swarm.toml");
    std::fs::write(
        &world,
        swarm_text(THREADS_VEHICLES, 11, TRAFFIC_SPACING, true),
    )
    .unwrap();
    let run = |threads: &str| {
        let out = dir.join(format!("threads{threads}"));
        let o = shoal()
            .args([
                "run",
                "--quiet",
                "--duration",
                "3",
                "--no-plots",
                "--threads",
            ])
            .arg(threads)
            .arg("--out")
            .arg(&out)
            .arg(&world)
            .output()
            .unwrap();
        let (stdout, stderr) = text(&o);
        assert!(o.status.success(), "{stdout}\n{stderr}");
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        assert_eq!(s["threads"], threads.parse::<u64>().unwrap());
        assert_eq!(s["vehicles"], THREADS_VEHICLES);
        (s, std::fs::read(out.join("trajectories.csv")).unwrap())
    };
    let (s1, c1) = run("1");
    let (s2, c2) = run("2");
    // The parallel path ran on 2 threads, in every kind of loop: each step's vehicle pass
    // (300 steps), the behaviours on each control tick (0.05 s) and the medium's deliveries
    // in some steps. None on 1 thread.
    let split = |s: &serde_json::Value, kind: &str| {
        s["parallel_dispatches"][kind]
            .as_u64()
            .unwrap_or_else(|| panic!("summary.json has no parallel_dispatches.{kind}"))
    };
    for kind in ["vehicles", "behaviour", "delivery"] {
        assert_eq!(split(&s1, kind), 0, "{kind} on 1 thread");
    }
    assert_eq!(split(&s2, "vehicles"), 300, "{}", s2["parallel_dispatches"]);
    assert_eq!(split(&s2, "behaviour"), 60, "{}", s2["parallel_dispatches"]);
    assert!(split(&s2, "delivery") > 0, "{}", s2["parallel_dispatches"]);
    // The summary says where the wall time went: every phase of the step had work in this
    // world, rows were written while it ran, and the phases fit in the run's wall time.
    for s in [&s1, &s2] {
        let phases = &s["phases_s"];
        let mut sum = 0.0;
        for p in STEP_PHASES.iter().chain(&["outputs"]) {
            let t = phases[p]
                .as_f64()
                .unwrap_or_else(|| panic!("summary.json has no phases_s.{p}"));
            assert!(t > 0.0, "{p}: {phases}");
            sum += t;
        }
        assert!(
            sum <= s["wall_s"].as_f64().unwrap(),
            "{phases} vs {}",
            s["wall_s"]
        );
    }
    // The medium ran: every vehicle beaconed (at t ≈ 1 and 2 s at least) and a frame was
    // heard by several neighbours on average.
    let comm = &s1["comm"];
    let (sent, delivered) = (
        comm["frames_sent"].as_u64().unwrap(),
        comm["receptions"]["delivered"].as_u64().unwrap(),
    );
    assert!(
        sent >= 2 * THREADS_VEHICLES as u64 && delivered > 2 * sent,
        "{sent} frames sent, {delivered} receptions delivered"
    );
    assert_eq!(s1["digest"], s2["digest"], "state digests differ");
    assert!(c1 == c2, "trajectories differ between 1 and 2 threads");
    assert!(
        comm == &s2["comm"],
        "the optical link's statistics differ: receptions {} vs {}",
        comm["receptions"],
        s2["comm"]["receptions"]
    );
    assert_eq!(s1["groups"], s2["groups"]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `bench --access`: a row per protocol, its frames the swarm's beacons (every vehicle's four
/// modems once a second, whatever the protocol: the load is low) over the steps measured —
/// each modem's count within 1.2 of the window's seconds (a beacon leaves up to 0.05 s after
/// its time, and carrier sensing holds it a little longer) —, its cost against ALOHA's a
/// positive ratio, its phases the whole step.
#[test]
fn bench_access_rows_send_every_beacon_and_cost_each_protocol_against_aloha() {
    let dir = tmp("bench_access");
    let (stdout, doc) = bench_json(
        &[
            "--vehicles",
            "100",
            "--threads",
            "1",
            "--seconds",
            "1",
            "--access",
            "aloha,csma_ca",
        ],
        &dir.join("rows.json"),
    );
    assert!(stdout.contains("cost × ALOHA"), "{stdout}");
    let rows = doc.as_array().unwrap();
    let names: Vec<&str> = rows.iter().map(|r| r["access"].as_str().unwrap()).collect();
    assert_eq!(names, ["aloha", "csma_ca"]);
    for r in rows {
        let frames = r["frames_per_s"].as_f64().unwrap();
        let window = r["steps"].as_f64().unwrap() * 0.01;
        assert!((frames - 400.0).abs() * window <= 1.2 * 400.0, "{r}");
        let cost = r["cost_vs_aloha"].as_f64().unwrap();
        assert!(cost.is_finite() && cost > 0.0, "{r}");
        // The median round's ratio lies within the rounds' range.
        let (lo, hi) = (
            r["cost_rounds"][0].as_f64().unwrap(),
            r["cost_rounds"][1].as_f64().unwrap(),
        );
        assert!(lo > 0.0 && lo <= cost && cost <= hi, "{r}");
        let shares: f64 = STEP_PHASES
            .iter()
            .map(|k| r["phase_shares"][k].as_f64().unwrap())
            .sum();
        assert!((shares - 1.0).abs() < 1e-9, "{r}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `shoal bench` with `args` and `--json` to `json`: what it printed and the rows it wrote
/// (it succeeded).
fn bench_json(args: &[&str], json: &Path) -> (String, serde_json::Value) {
    let o = shoal()
        .arg("bench")
        .args(args)
        .arg("--json")
        .arg(json)
        .output()
        .unwrap();
    let (stdout, stderr) = text(&o);
    assert!(o.status.success(), "{stderr}");
    let doc = serde_json::from_str(&std::fs::read_to_string(json).unwrap()).unwrap();
    (stdout, doc)
}

#[test]
fn bench_prints_a_row_per_cell_and_writes_them_as_json() {
    let dir = tmp("bench");
    let json = dir.join("rows.json");
    let (stdout, doc) = bench_json(
        &[
            "--vehicles",
            "1,300",
            "--threads",
            "1,2",
            "--seconds",
            "0.05",
        ],
        &json,
    );
    for column in [
        "vehicle-steps/s",
        "real-time ×",
        "medium",
        "peak RSS MB",
        "cycles/v-step",
        "where the time goes",
        "delivery",
        "ns/attempt",
    ] {
        assert!(stdout.contains(column), "{column}: {stdout}");
    }
    assert!(doc["machine"]["cores"].as_u64().unwrap() >= 1);
    let clock_known = doc["machine"]["clock_hz"].is_number();
    let rows = doc["rows"].as_array().unwrap();
    let count = |traffic: bool| rows.iter().filter(|r| r["traffic"] == traffic).count();
    assert_eq!((count(false), count(true)), (4, 4));
    for r in rows {
        assert_eq!(r["binary"], "this");
        assert!(r["vehicle_steps_per_s"].as_f64().unwrap() > 0.0, "{r}");
        assert!(r["realtime_factor"].as_f64().unwrap() > 0.0, "{r}");
        // Each row is measured in a process of its own: its peak memory is a few MB.
        let rss = r["peak_rss_bytes"].as_u64().unwrap();
        assert!((1_000_000..2_000_000_000).contains(&rss), "{r}");
        assert_eq!(r["medium_share"].is_number(), r["traffic"] == true, "{r}");
        assert_eq!(r["cycles_per_vehicle_step"].is_number(), clock_known, "{r}");
        // Loops are split over the pool with 2 threads and 300 vehicles only.
        let split = r["parallel_dispatches"].as_u64().unwrap();
        assert_eq!(split > 0, r["threads"] == 2 && r["vehicles"] == 300, "{r}");
        // Every phase of the step has its share; the shares add up to the whole step, and
        // with traffic the medium decided receptions.
        let phases = &r["phase_shares"];
        let shares: Vec<f64> = STEP_PHASES
            .iter()
            .map(|k| phases[k].as_f64().unwrap())
            .collect();
        assert!(shares.iter().all(|s| (0.0..=1.0).contains(s)), "{r}");
        assert!((shares.iter().sum::<f64>() - 1.0).abs() < 1e-9, "{r}");
        assert!(shares[1] > 0.0, "{r}");
        if r["traffic"] == true {
            assert!(shares[4] > 0.0, "{r}");
        }
        // Reception attempts: only with traffic; with 300 vehicles beaconing once a second
        // (3 frames a step) some every step, and never more than every frame at every other
        // vehicle (n (n − 1) / 100 a step on average; 2× for the beacons' jitter).
        let n = r["vehicles"].as_f64().unwrap();
        match r["attempts_per_step"].as_f64() {
            Some(a) => {
                assert!(r["traffic"] == true, "{r}");
                assert!(a > 0.0 && a <= 2.0 * n * (n - 1.0) / 100.0, "{r}");
                assert!(r["delivery_ns_per_attempt"].as_f64().unwrap() > 0.0, "{r}");
            }
            None => assert!(r["traffic"] == false || n < 300.0, "{r}"),
        }
    }
    // Without the traffic table; side by side with another binary (here: itself).
    let me = env!("CARGO_BIN_EXE_shoal");
    let (stdout, doc) = bench_json(
        &[
            "--vehicles",
            "10",
            "--threads",
            "1",
            "--seconds",
            "0.02",
            "--no-comm",
            "--compare",
            me,
        ],
        &json,
    );
    assert!(
        stdout.contains("this/other") && !stdout.contains(" yes "),
        "{stdout}"
    );
    let binaries: Vec<&str> = doc["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["binary"].as_str().unwrap())
        .collect();
    assert_eq!(binaries, ["this", "other"]);
    let o = shoal()
        .args(["bench", "--vehicles", "1", "--compare", "/no/such/shoal"])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(text(&o).1.contains("/no/such/shoal"), "{}", text(&o).1);
    let o = shoal().args(["bench", "--vehicles", "0"]).output().unwrap();
    assert!(!o.status.success());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_world_with_traffic_writes_link_statistics_and_plots() {
    let out = tmp("gossip");
    let world = repo().join("worlds/gossip.toml");
    let o = shoal()
        .args(["run", "--quiet", "--out"])
        .arg(&out)
        .arg(&world)
        .output()
        .unwrap();
    let (stdout, stderr) = text(&o);
    assert!(o.status.success(), "{stderr}");
    assert!(
        stdout.contains("optical link:")
            && stdout.contains("gossip: the value reached all 65 vehicles"),
        "{stdout}"
    );
    // The link plots draw the link tables' and the summary's numbers.
    run_plots::assert_gossip_plots(&out, 65);
    // The origin's depth line lies under the 64 relays' (same depth): its SVG line counts.
    run_plots::assert_depth_and_top(&out, 1, 1);
    let pairs = std::fs::read_to_string(out.join("link_pairs.csv")).unwrap();
    let header = pairs.lines().next().unwrap();
    assert_eq!(
        header,
        "sender,receiver,attempts,delivered,lost_range,lost_occlusion,lost_collision,lost_half_duplex,mean_latency_s"
    );
    // Every row adds up: attempts = delivered + losses.
    for row in pairs.lines().skip(1) {
        let v: Vec<&str> = row.split(',').collect();
        let n = |i: usize| v[i].parse::<u64>().unwrap();
        assert_eq!(n(2), n(3) + n(4) + n(5) + n(6) + n(7), "{row}");
    }
    assert_link_tables_match_the_summary(&out, 65);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let c = &s["comm"];
    assert!(c["frames_sent"].as_u64().unwrap() > 65);
    assert_eq!(c["gossip"]["informed"], 65);
    assert!(c["gossip"]["time_to_all_s"].as_f64().unwrap() > 0.0);
    assert!(c["by_distance"].as_array().unwrap().len() > 10);
}

/// A synthetic diving-mode run of the μAUV² with `effect` hidden in it, as a CSV file.
fn hidden_run(dir: &Path, name: &str, effect: Option<(&str, Vec<f64>)>, seed: u64) -> PathBuf {
    use shoal_model::effects::{EffectInstance, Effects, by_name};
    let effects = Effects::new(
        effect
            .into_iter()
            .map(|(n, p)| EffectInstance {
                effect: by_name(n).unwrap(),
                params: p,
            })
            .collect(),
    );
    let truth = shoal_model::vehicle::VehicleModel::with_effects(
        shoal_model::presets::uauv2(),
        effects,
        1000.0,
    );
    let exp = shoal_testkit::design::uauv2_heave(seed, 120.0);
    let run = shoal_testkit::synth::synthesize(
        &truth,
        &shoal_model::rigid_body::Environment::default(),
        &exp,
        0.005,
        seed,
    );
    let p = dir.join(format!("{name}.csv"));
    std::fs::write(&p, run.to_csv()).unwrap();
    p
}

/// The headline of a validation (printed and in report.json) is the mean of the printed
/// table's per-channel gains, and the figure "on the channels it changes" the mean of those
/// channels' rows.
fn headline_agrees_with_the_table(stdout: &str, report: &serde_json::Value) {
    let rows: Vec<(String, f64)> = stdout
        .lines()
        .filter(|l| l.starts_with("y."))
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            let gain = f.iter().find(|w| w.ends_with('%')).unwrap();
            (
                f[0].to_string(),
                gain.trim_end_matches('%').parse().unwrap(),
            )
        })
        .collect();
    assert!(rows.len() >= 2, "{stdout}");
    let mean = rows.iter().map(|r| r.1).sum::<f64>() / rows.len() as f64;
    let found = stdout.lines().find(|l| l.starts_with("Found")).unwrap();
    let printed = |after: &str| -> f64 {
        let at = found.find(after).unwrap() + after.len();
        found[at..]
            .split_whitespace()
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    let headline = printed("validation RMSE ");
    assert!(
        (headline - mean).abs() <= 0.051,
        "{headline} vs table mean {mean}: {stdout}"
    );
    let json = report["verdict"]["validation_gain_pct"].as_f64().unwrap();
    assert!((json - mean).abs() <= 0.051, "{json} vs {mean}");
    let changed: Vec<&str> = report["verdict"]["changed_channels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_str().unwrap())
        .collect();
    assert!(!changed.is_empty());
    let on: Vec<f64> = rows
        .iter()
        .filter(|r| changed.contains(&r.0.as_str()))
        .map(|r| r.1)
        .collect();
    let on_mean = on.iter().sum::<f64>() / on.len() as f64;
    let json_on = report["verdict"]["changed_channels_gain_pct"]
        .as_f64()
        .unwrap();
    assert!((json_on - on_mean).abs() <= 0.051, "{json_on} vs {on_mean}");
    if changed.len() < rows.len() {
        assert!((printed("; ") - on_mean).abs() <= 0.051, "{found}");
    }
}

#[test]
fn validate_names_a_hidden_lag_and_writes_a_runnable_model() {
    let dir = tmp("validate");
    let est = hidden_run(&dir, "dive_a", Some(("thruster_lag", vec![0.4])), 1);
    let hold = hidden_run(&dir, "dive_b", Some(("thruster_lag", vec![0.4])), 2);
    let out = dir.join("report");
    let o = shoal()
        .args(["validate", "--quiet", "--dt", "0.02"])
        .arg(&est)
        .arg("--holdout")
        .arg(&hold)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let (stdout, stderr) = text(&o);
    assert!(o.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("Found thruster_lag"), "{stdout}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(
        report["verdict"]["effects"],
        serde_json::json!(["thruster_lag"])
    );
    let tau = report["verdict"]["params"]["thruster_lag.tau_s"]
        .as_f64()
        .unwrap();
    assert!((tau - 0.4).abs() < 0.04, "{tau}");
    assert!(report["verdict"]["validation_gain_pct"].as_f64().unwrap() > 15.0);
    headline_agrees_with_the_table(&stdout, &report);
    assert_eq!(report["verdict"]["residuals_white_after"], true);
    assert!(report["baseline"]["channels"]["y.depth"]["fit_pct"].is_number());
    let cands = report["candidates"].as_array().unwrap();
    assert!(cands.len() >= 15, "every catalogue effect is a candidate");
    assert_eq!(report["runs"][1]["role"], "holdout");
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("thruster_lag") && md.contains("![")); // plots embedded
    run_plots::assert_validate_plots(&out, &hold);
    // The extended model runs.
    let vehicle = out.join("vehicle.toml");
    let o = shoal().arg("check").arg(&vehicle).output().unwrap();
    assert!(o.status.success(), "{:?}", text(&o));
    let o = shoal()
        .args(["run", "--quiet", "--no-plots", "--duration", "2", "--out"])
        .arg(dir.join("run"))
        .arg(&vehicle)
        .output()
        .unwrap();
    assert!(o.status.success(), "{:?}", text(&o));
}

#[test]
fn malformed_measured_runs_are_rejected_with_line_and_column() {
    let dir = tmp("badruns");
    let cases = [
        (
            "t,u.port,y.depth\n0,10,1.0\n0.1,10,1.0\n0.1,10,1.0\n",
            "time.csv:4: column 1 `t`: time 0.1 s does not increase",
        ),
        (
            "t,u.port,y.depth\n0,10,1.0\n0.1,ten,1.0\n",
            "text.csv:3: column 2 `u.port`: `ten` is not a number",
        ),
        (
            "t,u.port,y.depth,speed\n0,10,1.0,2\n",
            "column.csv:1: column 4 `speed`: unknown column `speed`",
        ),
        (
            "t,u.port,x.note\n0,10,a\n0.1,10,b\n",
            "noy.csv:1: no measurement column",
        ),
        (
            "t,u.prot,y.depth\n0,10,1.0\n0.1,10,1.0\n",
            "actuator.csv:1: column 2 `u.prot`: vehicle `uauv2` has no actuator `prot`",
        ),
    ];
    for (body, want) in cases {
        let name = want.split(':').next().unwrap();
        let p = dir.join(name);
        std::fs::write(&p, body).unwrap();
        let o = shoal()
            .args(["validate", "--quiet", "--out"])
            .arg(dir.join("out"))
            .arg(&p)
            .output()
            .unwrap();
        let (_, stderr) = text(&o);
        assert_eq!(o.status.code(), Some(2), "{name}: {stderr}");
        assert!(stderr.contains(want), "{name}: {stderr}");
        assert!(!stderr.contains("panicked"));
    }
    // A vehicle file with a typo is located too.
    let v = dir.join("vehicle.toml");
    std::fs::write(
        &v,
        "[[vehicles]]\nposition = [1.0, 1.0, 1.0]\nheadin_deg = 3.0\n",
    )
    .unwrap();
    let run = hidden_run(&dir, "ok", None, 3);
    let o = shoal()
        .args(["validate", "--quiet", "--vehicle"])
        .arg(&v)
        .arg("--out")
        .arg(dir.join("out"))
        .arg(&run)
        .output()
        .unwrap();
    let (_, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("vehicle.toml:3") && stderr.contains("heading_deg"),
        "{stderr}"
    );
}

/// A diving log as a logger writes it — `;` separators, CRLF, comments (indented ones too),
/// times in milliseconds, a trailing separator, the tilt at −1.5708, a 100 s pause in the
/// middle — is read, split at the pause into two runs, its tilt clamped and counted, and
/// validated.
#[test]
fn validate_reads_a_log_as_a_logger_writes_it() {
    let dir = tmp("loggerlog");
    let src = hidden_run(&dir, "src", Some(("thruster_lag", vec![0.4])), 4);
    let csv = std::fs::read_to_string(&src).unwrap();
    let mut out = String::from("# logger v2.1\r\n   # pool test, 50 Hz\r\n");
    for (i, line) in csv.lines().enumerate() {
        let mut cells: Vec<String> = line.split(',').map(str::to_string).collect();
        if i == 0 {
            cells[0] = "t[ms]".into();
        } else {
            let t: f64 = cells[0].parse().unwrap();
            let pause = if i > 3000 { 100.0 } else { 0.0 };
            cells[0] = format!("{}", ((t + pause) * 1000.0).round());
            for c in &mut cells {
                if c.starts_with("-1.570796") {
                    *c = "-1.5708".into();
                }
            }
        }
        if i == 3001 {
            out.push_str("\t# restarted after a pause\r\n");
        }
        out.push_str(&cells.join(";"));
        out.push_str(";\r\n");
    }
    let log = dir.join("dive.csv");
    std::fs::write(&log, out).unwrap();
    let o = shoal()
        .args([
            "validate",
            "--no-plots",
            "--dt",
            "0.02",
            "--effects",
            "thruster_lag",
        ])
        .arg(&log)
        .arg("--out")
        .arg(dir.join("report"))
        .output()
        .unwrap();
    let (stdout, stderr) = text(&o);
    assert!(o.status.success(), "{stdout}\n{stderr}");
    for want in [
        "6001 rows, separator `;`, time in ms, 3 comment line(s), trailing separators, 2 \
         segments split at gaps > 1 s (0 dropped as too short)",
        "dive#1: lines 4–3003, 3000 rows, t = 0 … 59.98 s",
        "dive#2: lines 3005–6005, 3001 rows, t = 160 … 220 s",
        "dive#1: u.beta: 3000 value(s) within 0.0001 rad of the limit −1.570796 rad clamped",
        "dive#2: u.beta: 3001 value(s)",
        "on 2 run(s)",
    ] {
        assert!(stderr.contains(want), "missing `{want}` in:\n{stderr}");
    }
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report/report.json")).unwrap())
            .unwrap();
    assert_eq!(report["runs"][1]["name"], "dive#2");
}

/// Input problems found while reading or mapping a log: exit 2 with file, line, column and
/// what is allowed.
#[test]
fn measured_run_limits_units_and_gaps_are_checked() {
    let dir = tmp("runlimits");
    // 100 rows at 10 Hz; `t(i)` and `pump(i)` override the time and the pump of row i.
    let log = |t: &dyn Fn(u32) -> f64, pump: &dyn Fn(u32) -> &'static str| {
        let mut s = String::from("t,u.port,u.stbd,u.beta,u.pump,y.depth\n");
        for i in 0..100 {
            s.push_str(&format!("{},10,10,-1.5708,{},1\n", t(i), pump(i)));
        }
        s
    };
    let t = |i: u32| f64::from(i) / 10.0;
    let rows = |p: &'static str| log(&t, &move |i| if i == 40 { p } else { "0" });
    let gap = log(&|i| t(i) + if i >= 50 { 495.0 } else { 0.0 }, &|_| "0");
    let long = log(&|i| if i == 99 { 1e8 } else { t(i) }, &|_| "0");
    let cases: Vec<(&str, String, Vec<&str>, &str)> = vec![
        (
            "pump.csv",
            rows("0.5"),
            vec![],
            "pump.csv:42: column 5 `u.pump`: pump command 0.5 is not a pump state; allowed: −1 \
             (empty), 0 (off), +1 (fill)",
        ),
        (
            "pump_big.csv",
            rows("1e9"),
            vec![],
            "pump_big.csv:42: column 5 `u.pump`: pump command 1e9",
        ),
        (
            "tilt.csv",
            rows("0").replacen("-1.5708", "-1.6", 1),
            vec![],
            "tilt.csv:2: column 4 `u.beta`: tilt angle −1.6 rad is beyond the lower limit \
             −1.570796 rad",
        ),
        (
            "gaps.csv",
            gap,
            vec!["--gaps", "error"],
            "gaps.csv:52: column 1 `t`: the time jumps by 495.1 s",
        ),
        (
            "unit.csv",
            rows("0").replacen("t,", "t_s,", 1),
            vec!["--time-unit", "ms"],
            "unit.csv:1: column 1 `t_s`: the header declares the time in s, but the time unit ms",
        ),
        (
            "dt.csv",
            rows("0"),
            vec!["--dt", "1e-9"],
            "--dt 0.000000001: allowed 0.0001 ≤ dt ≤ 0.1 s",
        ),
        (
            "horizon.csv",
            rows("0"),
            vec!["--horizon", "0.1"],
            "--horizon 0.1: allowed 0.5 ≤ horizon ≤ 3600 s, or auto",
        ),
        (
            "horizon_word.csv",
            rows("0"),
            vec!["--horizon", "sometimes"],
            "`sometimes`: allowed choose, open, auto, closed or a number of seconds",
        ),
        (
            "long.csv",
            long,
            vec!["--max-gap", "1e9"],
            "long.csv: run `long`: replaying its 1e8 s at a 0.01 s step needs 1.000e10 steps",
        ),
    ];
    for (name, body, args, want) in cases {
        let p = dir.join(name);
        std::fs::write(&p, body).unwrap();
        let o = shoal()
            .args(["validate", "--quiet", "--out"])
            .arg(dir.join("out"))
            .args(&args)
            .arg(&p)
            .output()
            .unwrap();
        let (_, stderr) = text(&o);
        assert_eq!(o.status.code(), Some(2), "{name}: {stderr}");
        assert!(stderr.contains(want), "{name}: want `{want}` in:\n{stderr}");
        assert!(!stderr.contains("panicked"));
    }
}

/// The real BlueROV pool logs (not shipped: read from `../shared/data` beside the checkout)
/// converted by `examples/bluerov1/convert.py` and validated against `worlds/bluerov1.toml`:
/// the extended model must predict the two hold-out runs clearly better than the baseline on
/// every channel, and name the excess yaw authority of the baseline as too little damping.
/// Without the logs or python3 it fails: they are always there in CI.
#[test]
fn bluerov_logs_are_explained_better_on_hold_out_runs() {
    // The only test on real data: missing data or python3 is a failure, not a skip.
    let data = repo().join("../shared/data/bluerov1_liu2016");
    assert!(
        data.is_dir(),
        "the BlueROV logs are missing: expected the folder {} (the shared data beside the \
         checkout, see ../shared/data/README.md)",
        data.display()
    );
    let py = Command::new("python3").arg("--version").output();
    assert!(
        py.as_ref().is_ok_and(|o| o.status.success()),
        "python3 is needed to convert the BlueROV logs (examples/bluerov1/convert.py) but \
         `python3 --version` failed: {py:?}"
    );
    let dir = tmp("bluerov");
    let runs = dir.join("runs");
    let o = Command::new("python3")
        .arg(repo().join("examples/bluerov1/convert.py"))
        .arg(&data)
        .arg(&runs)
        .output()
        .unwrap();
    assert!(o.status.success(), "{:?}", text(&o));
    let out = dir.join("report");
    let o = shoal()
        .args(["validate", "--quiet", "--channels", "y.r,y.yaw,y.depth"])
        .args(["--vehicle"])
        .arg(repo().join("worlds/bluerov1.toml"))
        .args(["yaw_1", "yaw_2", "yaw_3"].map(|r| runs.join(format!("{r}.csv"))))
        .args(["--holdout"])
        .arg(runs.join("yaw_4.csv"))
        .args(["--holdout"])
        .arg(runs.join("yaw_5.csv"))
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let (stdout, stderr) = text(&o);
    assert!(o.status.success(), "{stdout}\n{stderr}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    let v = &report["verdict"];
    let effects: Vec<&str> = v["effects"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e.as_str().unwrap())
        .collect();
    // The published model lacks damping: the search finds it, and either names it or — where
    // these yaw runs cannot tell it from an inflow thrust loss, which also acts in proportion
    // to speed — reports "damping_error or inflow_thrust_loss". Either way the stepwise model
    // that contains it is better on the two runs it never saw.
    let ambiguous_with_damping = v["ambiguous"].as_array().unwrap().iter().any(|a| {
        a["effects"]
            .as_array()
            .unwrap()
            .iter()
            .any(|e| e == "damping_error")
    });
    assert!(
        effects.contains(&"damping_error") || ambiguous_with_damping,
        "{effects:?}; {}",
        v["ambiguous"]
    );
    let stepwise: Vec<&str> = v["stepwise"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e.as_str().unwrap())
        .collect();
    assert!(stepwise.contains(&"damping_error"), "{stepwise:?}");
    let gain = v["stepwise_validation_gain_pct"].as_f64().unwrap();
    assert!(gain > 30.0, "hold-out gain {gain} %");
    for ch in ["y.r", "y.yaw", "y.depth"] {
        let g = v["stepwise_channel_gain_pct"][ch].as_f64().unwrap();
        assert!(g > 5.0, "{ch}: hold-out gain {g} %");
    }
    eprintln!(
        "BlueROV hold-out gains of the stepwise model {stepwise:?}: mean {gain:.1} %, per channel {}",
        v["stepwise_channel_gain_pct"]
    );
    assert_eq!(report["runs"][4]["role"], "holdout");
    let o = shoal()
        .arg("check")
        .arg(out.join("vehicle.toml"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{:?}", text(&o));
}

/// `shoal effects --markdown` lists every catalogue effect with its parameters, and
/// docs/validation.md shows exactly that table for the μAUV² preset (so the docs cannot drift
/// from the code).
#[test]
fn effect_catalogue_table_matches_the_docs() {
    let o = shoal().args(["effects", "--markdown"]).output().unwrap();
    let (stdout, stderr) = text(&o);
    assert!(o.status.success(), "{stderr}");
    for name in shoal_model::effects::names() {
        assert!(
            stdout.contains(&format!("| `{name}` |")),
            "{name} missing:\n{stdout}"
        );
    }
    let table: Vec<&str> = stdout.lines().filter(|l| l.starts_with('|')).collect();
    let docs = std::fs::read_to_string(repo().join("docs/validation.md")).unwrap();
    let start = docs
        .find(table[0])
        .expect("docs/validation.md contains the catalogue table");
    let doc_rows: Vec<&str> = docs[start..]
        .lines()
        .take_while(|l| l.starts_with('|'))
        .collect();
    assert_eq!(
        doc_rows, table,
        "docs/validation.md is out of date: paste the output of `shoal effects --markdown`"
    );
    // Bounds follow the vehicle; the BlueROV has no tank.
    let o = shoal()
        .args(["effects", "--markdown", "--vehicle"])
        .arg(repo().join("worlds/bluerov1.toml"))
        .output()
        .unwrap();
    let (blue, _) = text(&o);
    // ±10 % of its weight: 0.1 · 6.621 kg · 9.81 m/s² = 6.4952 N.
    assert!(blue.contains("| N | -6.4952 … 6.4952 |"), "{blue}");
    assert!(
        blue.contains("does not apply: the vehicle has no buoyancy tank"),
        "{blue}"
    );
}

/// `shoal effects` prints plain text for people: every effect, form and parameter, and not
/// one Markdown escape, table rule or code span.
#[test]
fn the_effect_catalogue_is_plain_text() {
    let o = shoal().arg("effects").output().unwrap();
    let (stdout, stderr) = text(&o);
    assert!(o.status.success(), "{stderr}");
    for markup in ["\\", "`", "|---", "**"] {
        assert!(
            !stdout.contains(markup),
            "`shoal effects` prints Markdown ({markup:?}):\n{stdout}"
        );
    }
    assert!(
        !stdout.lines().any(|l| l.starts_with('|')),
        "`shoal effects` prints a Markdown table:\n{stdout}"
    );
    for e in shoal_model::effects::catalogue() {
        let head = format!("\n{} ({}): {}\n", e.name(), e.form(), e.summary());
        assert!(stdout.contains(&head), "{head:?} missing:\n{stdout}");
        for p in e.params(&shoal_model::presets::uauv2()) {
            assert!(
                stdout
                    .lines()
                    .any(|l| l.trim_start().starts_with(p.name) && l.contains(p.doc)),
                "{} of {} missing",
                p.name,
                e.name()
            );
        }
    }
    // The summaries hold a literal |n| (a magnitude), printed as it is.
    assert!(stdout.contains("k·(|n|/50 %)^e"), "{stdout}");
}

/// `links.csv` (per second) and `connectivity.csv` (per second) against the summary: the
/// per-second counts add up to the summary's reception totals, every row adds up, and the
/// connectivity rows are the summary's samples.
fn assert_link_tables_match_the_summary(out: &Path, vehicles: u64) {
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let rx = &s["comm"]["receptions"];
    let total = |k: &str| rx[k].as_u64().unwrap();
    let links = std::fs::read_to_string(out.join("links.csv")).unwrap();
    let mut lines = links.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t_start_s,attempted,delivered,collided,occluded,out_of_budget,half_duplex,delivery_ratio"
    );
    let mut sums = [0u64; 6];
    let mut seconds = 0;
    for (k, row) in lines.enumerate() {
        let v: Vec<&str> = row.split(',').collect();
        assert_eq!(v[0], k.to_string(), "one row per second: {row}");
        let n: Vec<u64> = v[1..7].iter().map(|x| x.parse().unwrap()).collect();
        assert_eq!(n[0], n[1..].iter().sum::<u64>(), "{row}");
        for (a, b) in sums.iter_mut().zip(&n) {
            *a += b;
        }
        seconds += 1;
    }
    assert!(seconds as f64 >= s["simulated_s"].as_f64().unwrap().floor());
    assert_eq!(sums[0], total("attempts"));
    assert_eq!(sums[1], total("delivered"));
    assert_eq!(sums[2], total("lost_collision"));
    assert_eq!(sums[3], total("lost_occlusion"));
    assert_eq!(sums[4], total("lost_range"));
    assert_eq!(sums[5], total("lost_half_duplex"));
    let conn = std::fs::read_to_string(out.join("connectivity.csv")).unwrap();
    let mut lines = conn.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t_s,components,largest_component,largest_fraction,edges,mean_degree"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    let samples = s["comm"]["connectivity"].as_array().unwrap();
    assert_eq!(rows.len(), samples.len());
    for (r, c) in rows.iter().zip(samples) {
        assert_eq!(r[0], c["t"].as_f64().unwrap());
        assert_eq!(r[1], c["components"].as_f64().unwrap());
        assert_eq!(r[2], c["largest"].as_f64().unwrap());
        assert!((r[3] - r[2] / vehicles as f64).abs() < 1e-6);
        assert!((r[5] - 2.0 * r[4] / vehicles as f64).abs() < 1e-6);
    }
}

#[test]
fn the_default_world_talks_and_its_link_tables_add_up() {
    let out = tmp("default_talks");
    let o = shoal()
        .args(["run", "--quiet", "--duration", "30", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let (stdout, stderr) = text(&o);
    assert!(o.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("optical link:"), "{stdout}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let rx = &s["comm"]["receptions"];
    // 12 vehicles beaconing twice a second for 30 s; most frames reach someone, and the pillar
    // between the lanes blocks some.
    assert!(
        s["comm"]["frames_sent"].as_u64().unwrap() > 600,
        "{}",
        s["comm"]
    );
    assert!(rx["delivered"].as_u64().unwrap() > 1000, "{rx}");
    assert!(rx["lost_occlusion"].as_u64().unwrap() > 0, "{rx}");
    assert_link_tables_match_the_summary(&out, 12);
}
