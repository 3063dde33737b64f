//! `kill -9` of an agent in the middle of a lock-step run: the world notices (timeout, then
//! the dead node is cleaned up), the vehicle falls back to holding depth and heading, the run
//! finishes normally, the summary says what happened, and no shared memory is left behind.
//! Ctrl-C of the world: it ends the run, its agent is told and leaves, nothing is left.
//!
//! "Nothing left" is checked on what these processes themselves held — the shared-memory
//! segments the world and the agent have mapped while they run (`/proc/<pid>/maps`) and
//! iceoryx2's records naming the world's prefix — so other worlds and agents running beside
//! the test (the test runner runs tests side by side) neither hide nor fake a leak.

mod common;

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::process::{Child, Command};
use std::time::Duration;

/// What a running world and its agent hold in shared memory: the segments either maps, and
/// iceoryx2's records that name the world's prefix.
struct Held {
    segments: BTreeSet<PathBuf>,
    prefix: String,
}

impl Held {
    /// Read while both run (the agent attached).
    fn of(world: &Child, agent: &Child, prefix: &str) -> Held {
        let mut segments = common::mapped_shm(world.id());
        segments.extend(common::mapped_shm(agent.id()));
        assert!(
            !segments.is_empty(),
            "the world and its agent map no shared memory"
        );
        assert!(
            !common::ipc_records(prefix).is_empty(),
            "no iceoryx2 service names `{prefix}`"
        );
        Held {
            segments,
            prefix: prefix.to_string(),
        }
    }

    /// Fails with what is left once both have exited.
    fn assert_released(&self) {
        let left: Vec<&PathBuf> = self.segments.iter().filter(|p| p.exists()).collect();
        assert!(left.is_empty(), "left in /dev/shm: {left:?}");
        assert_eq!(common::ipc_records(&self.prefix), Vec::<PathBuf>::new());
    }
}

/// A lock-step world of `duration` s with one vehicle driven by a goto agent that takes 2 ms
/// per tick (so the run lasts a while), both started. Returns the world, the agent, the
/// output directory and the agent's log (`--log`: what it observes each simulated second).
fn start(name: &str, duration: f64) -> (Child, Child, PathBuf, PathBuf, String) {
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
    (sim, agent, out, log, prefix)
}

#[test]
fn killed_agent_is_detected_its_vehicle_falls_back_and_nothing_is_left() {
    // 120 s at 2 ms per tick: ≈ 5 s of wall time.
    let (mut sim, mut agent, out, log, prefix) = start("kill", 120.0);
    // Killed once it has driven 20 s (simulated) towards its target.
    let driven = common::wait_logged(&log, 20.0);
    let held = Held::of(&sim, &agent, &prefix);
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
    held.assert_released();
}

#[test]
fn world_interrupted_with_ctrl_c_tells_its_agent_and_leaves_nothing() {
    // 600 s (12,000 ticks) at 2 ms per tick would take ≈ 25 s.
    let (mut sim, mut agent, out, log, prefix) = start("ctrlc", 600.0);
    // Interrupted once the run is under way with its agent (2 s simulated).
    common::wait_logged(&log, 2.0);
    let held = Held::of(&sim, &agent, &prefix);
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
    held.assert_released();
}
