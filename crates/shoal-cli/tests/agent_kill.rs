//! `kill -9` of an agent in the middle of a lock-step run: the world notices (timeout, then
//! the dead node is cleaned up), the vehicle falls back to holding depth and heading, the run
//! finishes normally, the summary says what happened, and no shared memory is left behind.
//! Ctrl-C of the world: it ends the run, its agent is told and leaves, nothing is left.
//! (Its own test binary: it compares /dev/shm before and after, so its tests run one at a
//! time and nothing else may run beside them.)

mod common;

use std::collections::BTreeSet;
use std::sync::Mutex;

/// Held by each test: the /dev/shm comparisons must not see each other's segments.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());
use std::path::PathBuf;
use std::process::{Child, Command};
use std::time::Duration;

fn shm() -> BTreeSet<String> {
    std::fs::read_dir("/dev/shm")
        .map(|d| {
            d.filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                // iceoryx2 keeps one global management segment per machine by design.
                .filter(|n| !n.ends_with("global_mgmt"))
                .collect()
        })
        .unwrap_or_default()
}

/// A lock-step world of `duration` s with one vehicle driven by a goto agent that takes 2 ms
/// per tick (so the run lasts a while), both started. Returns the world, the agent, the
/// output directory and the agent's log (`--log`: what it observes each simulated second).
fn start(name: &str, duration: f64) -> (Child, Child, PathBuf, PathBuf) {
    let agent_bin = common::example_agent("goto_agent");
    let dir = common::tmp("kill", name);
    let world = dir.join("world.toml");
    std::fs::write(
        &world,
        format!(
            "name = \"{name}\"\nduration = {duration}\n[pool]\nsize = [10.0, 10.0, 3.0]\n\
             [agents]\ntiming = \"lockstep\"\ntimeout = 0.5\nattach_timeout = 20.0\nfallback = \"hold\"\n\
             [[vehicles]]\nname = \"auv\"\nposition = [5.0, 5.0, 0.5]\nagent = \"pilot\"\n"
        ),
    )
    .unwrap();
    let prefix = format!("{name}{}", std::process::id());
    let out = dir.join("out");
    let sim = common::start_run(
        &["--quiet", "--no-plots", "--prefix", &prefix],
        &out,
        &world,
        None,
    );
    let log = dir.join("agent.err");
    let agent = Command::new(&agent_bin)
        .args([&prefix, "pilot", "1.5", "0", "--slow", "2", "--log"])
        .stderr(common::log_file(&log))
        .spawn()
        .unwrap();
    (sim, agent, out, log)
}

#[test]
fn killed_agent_is_detected_its_vehicle_falls_back_and_nothing_is_left() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let before = shm();
    // 120 s at 2 ms per tick: ≈ 5 s of wall time.
    let (mut sim, mut agent, out, log) = start("kill", 120.0);
    // Killed once it has driven 20 s (simulated) towards its target.
    let driven = common::wait_logged(&log, 20.0);
    assert!(
        agent.try_wait().unwrap().is_none(),
        "the agent is still running"
    );
    // kill -9
    agent.kill().unwrap();
    agent.wait().unwrap();
    let status = common::wait(&mut sim, Duration::from_secs(60));
    let text = sim.wait_with_output().unwrap();
    assert!(status.success(), "{text:?}");
    let stdout = String::from_utf8_lossy(&text.stdout);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(
        s["simulated_s"].as_f64().unwrap(),
        120.0,
        "the run finished"
    );
    let ag = &s["agents"]["agents"][0];
    let events: Vec<&str> = ag["events"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["what"].as_str().unwrap())
        .collect();
    assert_eq!(events[0], "attached");
    assert!(
        events.contains(&"gone"),
        "the dead agent is detected: {events:?}"
    );
    assert!(
        stdout.contains("gone"),
        "the printed summary says so:\n{stdout}"
    );
    // After the kill the vehicle is in fallback for the rest of the run.
    let t_gone = ag["events"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["what"] == "gone" || e["what"] == "hung")
        .unwrap()["t"]
        .as_f64()
        .unwrap();
    assert!(
        t_gone >= driven.t,
        "gone at {t_gone} s, alive at {} s",
        driven.t
    );
    let fb = ag["fallback_ticks"].as_u64().unwrap() as f64;
    let expected = (120.0 - t_gone) / 0.05;
    assert!(
        (fb - expected).abs() <= 3.0,
        "{fb} fallback ticks, expected ≈ {expected}"
    );
    assert!(!ag["attached_at_end"].as_bool().unwrap());
    // Holding: the depth at the end equals the depth when the agent died (± 5 cm).
    let mut r = csv::Reader::from_path(out.join("trajectories.csv")).unwrap();
    let h = r.headers().unwrap().clone();
    let (ct, cz) = (
        h.iter().position(|c| c == "t_s").unwrap(),
        h.iter().position(|c| c == "depth_reading_m").unwrap(),
    );
    let rows: Vec<(f64, f64)> = r
        .records()
        .map(|x| {
            let x = x.unwrap();
            (x[ct].parse().unwrap(), x[cz].parse().unwrap())
        })
        .collect();
    let at = |t: f64| rows.iter().find(|(tt, _)| *tt >= t).unwrap().1;
    let (z_gone, z_end) = (at(t_gone), rows.last().unwrap().1);
    assert!((z_end - z_gone).abs() < 0.05, "held {z_gone} m → {z_end} m");
    // Nothing left in shared memory by the world or the killed agent.
    let after = shm();
    let left: Vec<&String> = after.difference(&before).collect();
    assert!(left.is_empty(), "left in /dev/shm: {left:?}");
}

#[test]
fn world_interrupted_with_ctrl_c_tells_its_agent_and_leaves_nothing() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let before = shm();
    // 600 s (12,000 ticks) at 2 ms per tick would take ≈ 25 s.
    let (mut sim, mut agent, out, log) = start("ctrlc", 600.0);
    // Interrupted once the run is under way with its agent (2 s simulated).
    common::wait_logged(&log, 2.0);
    assert!(sim.try_wait().unwrap().is_none(), "the world still runs");
    let int = Command::new("kill")
        .args(["-INT", &sim.id().to_string()])
        .status()
        .unwrap();
    assert!(int.success());
    let status = common::wait(&mut sim, Duration::from_secs(30));
    let text = sim.wait_with_output().unwrap();
    assert_eq!(status.code(), Some(130), "{text:?}");
    // The agent got the END of the run and left by itself, successfully.
    let agent_status = common::wait(&mut agent, Duration::from_secs(15));
    assert!(agent_status.success(), "agent: {agent_status}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["interrupted"], true);
    let t = s["simulated_s"].as_f64().unwrap();
    assert!(t > 1.0 && t < 600.0, "interrupted at {t} s");
    assert!(String::from_utf8_lossy(&text.stdout).contains("INTERRUPTED"));
    let left: Vec<String> = shm().difference(&before).cloned().collect();
    assert!(left.is_empty(), "left in /dev/shm: {left:?}");
}
