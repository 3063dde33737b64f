//! Signals end `shoal run` cleanly. SIGINT, SIGTERM or SIGHUP in the middle of a run (a world
//! with an agent slot, so it has shared memory): exit 128 + the signal number, the summary
//! marked interrupted by that signal, every CSV whole, no temporaries, plots still drawn, and
//! the agent services' shared memory removed. SIGTERM while a world of 10⁶ vehicles is loaded
//! or built: exit 143 before the run starts, nothing written. A signal ignored at the start
//! (SIGHUP under `nohup`) stays ignored. Real processes of the built binary.

mod common;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Longest wait for a stage of a run (a hang guard, never a timing assertion).
const GUARD: Duration = Duration::from_secs(60);
/// Longest wait for the exit after a signal (a hang guard).
const EXIT_GUARD: Duration = Duration::from_secs(20);

/// A long world (10⁵ s) with a vehicle on a mission and an agent slot nobody attaches to
/// (free-running, so the run goes on without it).
fn agent_world(dir: &Path) -> PathBuf {
    let world = dir.join("world.toml");
    std::fs::write(
        &world,
        "name = \"signals\"\nduration = 100000.0\n[pool]\nsize = [10.0, 10.0, 3.0]\n\
         [agents]\ntiming = \"free\"\nattach_timeout = 0.0\n\
         [[vehicles]]\nname = \"auv\"\nposition = [5.0, 5.0, 0.5]\n\
         mission = [{ t = 0, mode = \"auto\", depth = 1.0, yaw_deg = 0 }, { t = 1, surge = 0.03 }]\n\
         [[vehicles]]\nname = \"slot\"\nposition = [2.0, 2.0, 0.5]\nagent = \"pilot\"\n",
    )
    .unwrap();
    world
}

/// Starts the agent world, waits until trajectory rows are being written, sends `signal`
/// and checks the clean end with exit code `code`.
fn interrupt_mid_run(signal: &str, code: i32) {
    let name = format!("SIG{signal}");
    let dir = common::tmp("signals", &name);
    let world = agent_world(&dir);
    let out = dir.join("out");
    let prefix = format!("sig{}{}", signal.to_lowercase(), std::process::id());
    let mut child = common::start_run(&["--quiet", "--prefix", &prefix], &out, &world, None);
    // Running: rows are streamed to the trajectories' temporary.
    common::wait_for_size(&out.join(".trajectories.csv.tmp"), 20_000, &mut child);
    let shm = common::mapped_shm(child.id());
    let records = common::ipc_records(&prefix);
    assert!(!shm.is_empty(), "the world maps no shared memory");
    assert!(!records.is_empty(), "no iceoryx2 service names `{prefix}`");

    common::kill(&child, signal);
    let status = common::wait(&mut child, EXIT_GUARD);
    let o = child.wait_with_output().unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr),
    );
    assert_eq!(status.code(), Some(code), "{stdout}\n{stderr}");
    assert!(
        stdout.contains(&format!("INTERRUPTED ({name}) after")),
        "{stdout}"
    );

    let s = common::summary(&out);
    assert_eq!(s["interrupted"], true, "{s}");
    assert_eq!(s["signal"], name.as_str());
    assert!(s.get("output_error").is_none(), "{s}");
    let (simulated, planned) = (
        s["simulated_s"].as_f64().unwrap(),
        s["planned_s"].as_f64().unwrap(),
    );
    assert!(simulated > 0.0 && simulated < planned, "{simulated} s");
    // Whole rows only, all of them counted; no temporaries.
    let rows = common::whole_csv_rows(&out.join("trajectories.csv"));
    assert!(rows > 0);
    assert_eq!(s["trajectory_rows"].as_u64(), Some(rows as u64));
    for csv in common::files_ending(&out, ".csv") {
        common::whole_csv_rows(&out.join(csv));
    }
    assert_eq!(common::files_ending(&out, ".tmp"), Vec::<String>::new());
    // The summary lists exactly the files there are (plots are drawn after a first signal).
    let listed: BTreeSet<String> = common::summary_files(&s)
        .into_iter()
        .map(|p| {
            assert!(p.is_file(), "listed but missing: {}", p.display());
            p.file_name().unwrap().to_string_lossy().into_owned()
        })
        .collect();
    let present: BTreeSet<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(listed, present);
    for f in ["summary.json", "trajectories.csv", "depth.png", "top.svg"] {
        assert!(listed.contains(f), "{f} missing from {listed:?}");
    }
    // The agent services are gone: their memory and their records.
    let left: Vec<&PathBuf> = shm.iter().filter(|p| p.exists()).collect();
    assert!(left.is_empty(), "left in /dev/shm: {left:?}");
    assert_eq!(common::ipc_records(&prefix), Vec::<PathBuf>::new());
}

#[test]
fn sigterm_mid_run_exits_143_with_whole_outputs_and_no_shared_memory() {
    interrupt_mid_run("TERM", 143);
}

#[test]
fn sighup_mid_run_exits_129_with_whole_outputs_and_no_shared_memory() {
    interrupt_mid_run("HUP", 129);
}

#[test]
fn sigint_mid_run_exits_130_with_whole_outputs_and_no_shared_memory() {
    interrupt_mid_run("INT", 130);
}

/// Writes a world of 10⁶ vehicles (a 1000 × 1000 grid), starts it without `--quiet`, sends
/// SIGTERM as soon as stderr shows `marker`, and checks that it stops while `phase` the
/// world, before the run, writing nothing. Prints how long the answer took.
fn interrupt_large_world(marker: &str, phase: &str) {
    let dir = common::tmp("signals", &format!("large-{phase}"));
    let world = dir.join("large.toml");
    std::fs::write(
        &world,
        "name = \"large\"\nduration = 10.0\n[pool]\nsize = [1002.0, 1002.0, 3.0]\n\
         [[vehicles]]\nname = \"v\"\ncount = 1000000\n\
         grid = { origin = [1.0, 1.0, 1.0], spacing = [1.0, 1.0], columns = 1000 }\n\
         mission = [{ t = 0, mode = \"auto\", depth = 1.0, yaw_deg = 0 }]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let mut child = common::start_run(&[], &out, &world, None);
    let mut stderr = common::StderrLines::take(&mut child);
    stderr.wait_for(marker, GUARD, &mut child);
    common::kill(&child, "TERM");
    let signalled = Instant::now();
    let status = common::wait(&mut child, EXIT_GUARD);
    let answered = signalled.elapsed();
    let rest = stderr.finish();
    eprintln!("SIGTERM while {phase} 10^6 vehicles: exited after {answered:?}");
    assert_eq!(status.code(), Some(143), "{rest}");
    assert!(
        rest.contains(&format!(
            "interrupted by SIGTERM while {phase} the world, before the run started; nothing was written"
        )),
        "{rest}"
    );
    assert!(!out.exists(), "{} was created", out.display());
}

#[test]
fn sigterm_while_loading_a_world_of_a_million_vehicles_stops_before_the_run() {
    interrupt_large_world("shoal: loading", "loading");
}

#[test]
fn sigterm_while_building_a_world_of_a_million_vehicles_stops_before_the_run() {
    interrupt_large_world("shoal: building", "building");
}

/// A signal ignored when shoal starts (here SIGHUP, as under `nohup`) stays ignored: the run
/// goes on, and the SIGTERM after it decides the exit code and the summary.
#[test]
fn sighup_ignored_at_the_start_stays_ignored() {
    let dir = common::tmp("signals", "nohup");
    let world = agent_world(&dir);
    let out = dir.join("out");
    let prefix = format!("signohup{}", std::process::id());
    let mut child = common::start_run(
        &["--quiet", "--no-plots", "--prefix", &prefix],
        &out,
        &world,
        Some("trap '' HUP;"),
    );
    let tmp = out.join(".trajectories.csv.tmp");
    common::wait_for_size(&tmp, 20_000, &mut child);
    common::kill(&child, "HUP");
    // Still running: the file keeps growing.
    let after_hup = tmp.metadata().unwrap().len();
    common::wait_for_size(&tmp, after_hup + 20_000, &mut child);
    common::kill(&child, "TERM");
    let status = common::wait(&mut child, EXIT_GUARD);
    assert_eq!(status.code(), Some(143));
    let s = common::summary(&out);
    assert_eq!(s["signal"], "SIGTERM", "{s}");
}
