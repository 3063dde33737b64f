//! Agent faults and timing modes with real processes (the goto example agent, no mocks): a
//! hung agent is declared hung after the timeout, its vehicle falls back, and it is taken back
//! when it answers again; the fallback `stop` ends the run (exit 3, the summary says why); the
//! fallback `surface` brings the vehicle up; a free-running world never waits for a slow
//! agent and keeps its last command in force; a killed agent of a free-running world is
//! noticed and a new process can take its place.

mod common;

use common::wait;

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::OnceLock;
use std::time::Duration;

fn agent_bin() -> &'static Path {
    static BIN: OnceLock<PathBuf> = OnceLock::new();
    BIN.get_or_init(|| common::example_agent("goto_agent"))
}

/// One μAUV² at 0.5 m, heading 0, driven by agent `pilot` (the first vehicle), and
/// `more_vehicles` (world-file text); `agents` is the body of the `[agents]` table.
fn world_with(dir: &Path, duration: f64, agents: &str, more_vehicles: &str) -> PathBuf {
    let p = dir.join("world.toml");
    std::fs::write(
        &p,
        format!(
            "name = \"faults\"\nduration = {duration}\n[pool]\nsize = [10.0, 10.0, 3.0]\n\
             [agents]\nattach_timeout = 20.0\n{agents}\n\
             [[vehicles]]\nname = \"auv\"\nposition = [5.0, 5.0, 0.5]\nagent = \"pilot\"\n\
             {more_vehicles}"
        ),
    )
    .unwrap();
    p
}

fn world(dir: &Path, duration: f64, agents: &str) -> PathBuf {
    world_with(dir, duration, agents, "")
}

fn spawn_world(world: &Path, out: &Path, prefix: &str) -> Child {
    // The agent is built first: a world waits only `attach_timeout` for it.
    agent_bin();
    Command::new(env!("CARGO_BIN_EXE_shoal"))
        .args(["run", "--no-plots", "--prefix", prefix, "--out"])
        .arg(out)
        .arg(world)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap()
}

fn spawn_agent(prefix: &str, args: &[&str]) -> Child {
    spawn_named(prefix, "pilot", args)
}

fn spawn_named(prefix: &str, name: &str, args: &[&str]) -> Child {
    Command::new(agent_bin())
        .args([prefix, name])
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap()
}

/// The world's exit status, printed summary, summary.json and (t, depth reading, heading)
/// rows of the pilot's vehicle.
struct Finished {
    status: ExitStatus,
    stdout: String,
    summary: Value,
    rows: Vec<(f64, f64, f64)>,
}

impl Finished {
    /// The report of agent `pilot`.
    fn agent(&self) -> &Value {
        self.summary["agents"]["agents"]
            .as_array()
            .unwrap()
            .iter()
            .find(|a| a["name"] == "pilot")
            .unwrap()
    }
    fn events(&self) -> Vec<(String, f64)> {
        self.agent()["events"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| {
                (
                    e["what"].as_str().unwrap().to_string(),
                    e["t"].as_f64().unwrap(),
                )
            })
            .collect()
    }
    fn last(&self) -> (f64, f64, f64) {
        *self.rows.last().unwrap()
    }
    /// Depth reading at the first sample at or after `t`.
    fn depth_at(&self, t: f64) -> f64 {
        self.rows.iter().find(|r| r.0 >= t).unwrap().1
    }
}

fn finish(mut world: Child, out: &Path) -> Finished {
    let status = wait(&mut world, Duration::from_secs(120));
    let mut stdout = String::new();
    std::io::Read::read_to_string(world.stdout.as_mut().unwrap(), &mut stdout).unwrap();
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let mut r = csv::Reader::from_path(out.join("trajectories.csv")).unwrap();
    let h = r.headers().unwrap().clone();
    let col = |n: &str| h.iter().position(|c| c == n).unwrap();
    let (ct, cv, cz, cy) = (
        col("t_s"),
        col("vehicle"),
        col("depth_reading_m"),
        col("yaw_rad"),
    );
    let records: Vec<csv::StringRecord> = r.records().map(|x| x.unwrap()).collect();
    // The pilot's vehicle is the first.
    let pilot = records[0][cv].to_string();
    let rows = records
        .iter()
        .filter(|x| x[cv] == pilot)
        .map(|x| {
            (
                x[ct].parse().unwrap(),
                x[cz].parse().unwrap(),
                x[cy].parse().unwrap(),
            )
        })
        .collect();
    Finished {
        status,
        stdout,
        summary,
        rows,
    }
}

fn assert_on_target(f: &Finished, depth: f64, heading_deg: f64) {
    let (_, z, yaw) = f.last();
    assert!((z - depth).abs() < 0.05, "depth {z}, wanted {depth}");
    assert!(
        (yaw - heading_deg.to_radians()).abs() < 1f64.to_radians(),
        "heading {yaw}, wanted {heading_deg}°"
    );
}

#[test]
fn hung_agent_falls_back_and_is_taken_back_when_it_answers_again() {
    let dir = common::tmp("faults", "hung");
    let prefix = format!("f{}-hung", std::process::id());
    // A second vehicle far off, driven by agent `pacer`, which takes 5 ms per tick: the
    // lock-step world waits for it, so it runs at ≈ 10× real time while `pilot` hangs.
    let w = world_with(
        &dir,
        60.0,
        "timing = \"lockstep\"\ntimeout = 0.5\nfallback = \"hold\"",
        "[[vehicles]]\nname = \"pace\"\nposition = [2.0, 2.0, 0.5]\nagent = \"pacer\"\n",
    );
    let out = dir.join("out");
    let sim = spawn_world(&w, &out, &prefix);
    let mut pacer = spawn_named(&prefix, "pacer", &["1.0", "0", "--slow", "5"]);
    // At its 40th tick (t = 2 s) the pilot stalls for 2 s, four times the timeout.
    let mut agent = spawn_agent(&prefix, &["1.5", "90", "--stall", "40:2000"]);
    let f = finish(sim, &out);
    assert!(wait(&mut agent, Duration::from_secs(30)).success());
    assert!(wait(&mut pacer, Duration::from_secs(30)).success());
    assert!(f.status.success(), "{}", f.stdout);
    let ev = f.events();
    let names: Vec<&str> = ev.iter().map(|e| e.0.as_str()).collect();
    assert_eq!(names, ["attached", "hung", "reattached"], "{ev:?}");
    // Declared hung on the tick it stalled on (t = 2.00 s, its 40th answered tick)…
    assert!((ev[1].1 - 2.0).abs() < 0.051, "hung at {}", ev[1].1);
    // …and taken back once it answered again, ≈ 1.5 s of wall time later (≈ 15 s simulated
    // at the pacer's speed; the bound only says "later, and well before the end").
    assert!(ev[2].1 > ev[1].1 && ev[2].1 < 50.0, "{ev:?}");
    // Under the fallback from the tick after the hang until its first command after
    // re-attaching (one or two ticks after that event).
    let fallback = f.agent()["fallback_ticks"].as_u64().unwrap() as f64;
    let expected = (ev[2].1 - ev[1].1) / 0.05;
    assert!(
        fallback >= expected - 0.5 && fallback <= expected + 3.0,
        "{fallback} fallback ticks, expected ≈ {expected}"
    );
    assert!(f.agent()["attached_at_end"].as_bool().unwrap());
    assert!(f.stdout.contains("hung"), "{}", f.stdout);
    // The other agent was not disturbed: attached once, never in fallback after its first command.
    let p = &f.summary["agents"]["agents"];
    let pacer_report = p
        .as_array()
        .unwrap()
        .iter()
        .find(|a| a["name"] == "pacer")
        .unwrap();
    assert_eq!(pacer_report["events"].as_array().unwrap().len(), 1);
    // (Its one fallback tick is the first: observed before its first command.)
    assert_eq!(pacer_report["fallback_ticks"], 1);
    // Back under the pilot's control: on target at the end.
    assert_on_target(&f, 1.5, 90.0);
}

#[test]
fn fallback_stop_ends_the_run_early_and_says_why() {
    let dir = common::tmp("faults", "stop");
    let prefix = format!("f{}-stop", std::process::id());
    let w = world(
        &dir,
        60.0,
        "timing = \"lockstep\"\ntimeout = 0.5\nfallback = \"stop\"",
    );
    let out = dir.join("out");
    let sim = spawn_world(&w, &out, &prefix);
    // Stalls 2 s at t = 1 s: hung after 0.5 s, the run stops; the agent wakes after the
    // world has gone and still finds the END of the run (exit 0).
    let mut agent = spawn_agent(&prefix, &["1.5", "90", "--stall", "20:2000"]);
    let f = finish(sim, &out);
    assert!(wait(&mut agent, Duration::from_secs(30)).success());
    assert_eq!(f.status.code(), Some(3), "{}", f.stdout);
    let stopped = f.summary["agents"]["stopped"].as_str().unwrap();
    assert!(
        stopped.contains("pilot") && stopped.contains("hung") && stopped.contains("stop"),
        "{stopped}"
    );
    assert!(f.stdout.contains("STOPPED"), "{}", f.stdout);
    // It stopped at the hang (t = 1 s), with the outputs written up to there.
    let t_end = f.summary["simulated_s"].as_f64().unwrap();
    assert!((t_end - 1.0).abs() < 0.06, "stopped at t = {t_end} s");
    assert!(f.last().0 <= t_end + 1e-9 && f.last().0 > 0.7);
}

#[test]
fn fallback_surface_brings_the_vehicle_up_after_its_agent_is_killed() {
    let dir = common::tmp("faults", "surface");
    let prefix = format!("f{}-surface", std::process::id());
    let w = world(
        &dir,
        90.0,
        "timing = \"lockstep\"\ntimeout = 2.0\nfallback = \"surface\"",
    );
    let out = dir.join("out");
    let sim = spawn_world(&w, &out, &prefix);
    // 10 ms per tick: 30 s simulated (600 ticks) take 6 s of wall time.
    let mut agent = spawn_agent(&prefix, &["1.5", "0", "--slow", "10"]);
    std::thread::sleep(Duration::from_millis(6000));
    agent.kill().unwrap(); // kill -9
    agent.wait().unwrap();
    let f = finish(sim, &out);
    assert!(f.status.success());
    let ev = f.events();
    let gone = ev.iter().find(|e| e.0 == "gone").expect("gone event").1;
    assert!(
        gone > 15.0,
        "killed at t = {gone} s: too early to have dived"
    );
    // It had dived (1.5 m, its pressure port reads 0.09 m less), and surfaced afterwards.
    assert!(f.depth_at(gone) > 1.2, "{} m at the kill", f.depth_at(gone));
    let (_, z_end, _) = f.last();
    assert!(z_end < 0.05, "at the end {z_end} m");
    assert_eq!(f.summary["simulated_s"].as_f64().unwrap(), 90.0);
}

#[test]
fn free_running_world_never_waits_and_keeps_the_last_command() {
    let dir = common::tmp("faults", "free");
    let prefix = format!("f{}-free", std::process::id());
    // 60 s simulated at 20× real time: 3 s of wall time, 1200 control ticks.
    let w = world(
        &dir,
        60.0,
        "timing = \"free\"\npace = 20.0\ntimeout = 0.3\nfallback = \"hold\"",
    );
    let out = dir.join("out");
    let sim = spawn_world(&w, &out, &prefix);
    // The agent needs 300 ms per tick: a lock-step world would take 1200 × 0.3 s = 6 min.
    let mut agent = spawn_agent(&prefix, &["1.5", "90", "--slow", "300"]);
    let f = finish(sim, &out);
    assert!(wait(&mut agent, Duration::from_secs(30)).success());
    assert!(f.status.success());
    let a = f.agent();
    assert_eq!(f.summary["agents"]["timing"], "free");
    // The world stepped through all 1,200 ticks while the agent answered a few: it did not
    // wait for the replies.
    let applied = a["commands_applied"].as_u64().unwrap();
    assert!(
        (1..100).contains(&applied),
        "{applied} commands for 1200 ticks"
    );
    assert_eq!(f.summary["simulated_s"].as_f64().unwrap(), 60.0);
    // No hang is declared in free-running mode, and nothing is timed.
    let names: Vec<String> = f.events().into_iter().map(|e| e.0).collect();
    assert_eq!(names, ["attached"]);
    assert_eq!(a["round_trip"]["count"], 0);
    // The vehicle holds (fallback) until the first command arrives, 0.3 s of wall time = 6 s
    // simulated after the agent attached; from then on the last command stays in force: no
    // fallback between the rare commands (that would be ≈ 1,200 − 20 ticks).
    let fallback = a["fallback_ticks"].as_u64().unwrap();
    assert!((1..400).contains(&fallback), "{fallback} fallback ticks");
    assert_on_target(&f, 1.5, 90.0);
}

#[test]
fn free_running_world_notices_a_killed_agent_and_takes_a_new_one() {
    let dir = common::tmp("faults", "replace");
    let prefix = format!("f{}-replace", std::process::id());
    // 120 s simulated at 20× real time: 6 s of wall time.
    let w = world(
        &dir,
        120.0,
        "timing = \"free\"\npace = 20.0\ntimeout = 0.3\nfallback = \"hold\"",
    );
    let out = dir.join("out");
    let sim = spawn_world(&w, &out, &prefix);
    let mut first = spawn_agent(&prefix, &["1.5", "0"]);
    std::thread::sleep(Duration::from_millis(2000));
    first.kill().unwrap(); // kill -9
    first.wait().unwrap();
    std::thread::sleep(Duration::from_millis(1000));
    let mut second = spawn_agent(&prefix, &["1.0", "90"]);
    let f = finish(sim, &out);
    assert!(wait(&mut second, Duration::from_secs(30)).success());
    assert!(f.status.success());
    let ev = f.events();
    let names: Vec<&str> = ev.iter().map(|e| e.0.as_str()).collect();
    assert_eq!(names, ["attached", "gone", "reattached"], "{ev:?}");
    // Between the two the vehicle held the depth it had when the first agent died.
    let (gone, back) = (ev[1].1, ev[2].1);
    assert!(back - gone > 5.0, "gone at {gone} s, back at {back} s");
    let (z0, z1) = (f.depth_at(gone), f.depth_at(back - 0.5));
    assert!((z1 - z0).abs() < 0.05, "held {z0} → {z1}");
    // The second agent's target at the end.
    assert_on_target(&f, 1.0, 90.0);
    assert!(f.agent()["attached_at_end"].as_bool().unwrap());
}

#[test]
fn rust_agent_interrupted_with_ctrl_c_says_goodbye() {
    let dir = common::tmp("faults", "ctrl-c");
    let prefix = format!("f{}-ctrl-c", std::process::id());
    // Free-running at 10× real time: 60 s simulated take 6 s.
    let w = world(
        &dir,
        60.0,
        "timing = \"free\"\npace = 10.0\nfallback = \"hold\"",
    );
    let out = dir.join("out");
    let sim = spawn_world(&w, &out, &prefix);
    let agent = spawn_agent(&prefix, &["1.5", "90"]);
    std::thread::sleep(Duration::from_millis(2000));
    let int = Command::new("kill")
        .args(["-INT", &agent.id().to_string()])
        .status()
        .unwrap();
    assert!(int.success());
    let mut agent = agent;
    let status = wait(&mut agent, Duration::from_secs(30));
    // iceoryx2 catches the signal; the agent API turns it into `Interrupted`, the example
    // exits 130 and the link says goodbye on the way out.
    assert_eq!(status.code(), Some(130));
    let f = finish(sim, &out);
    assert!(f.status.success());
    let names: Vec<String> = f.events().into_iter().map(|e| e.0).collect();
    assert_eq!(names, ["attached", "left"]);
    assert!(!f.agent()["attached_at_end"].as_bool().unwrap());
}

#[test]
fn rust_agent_waiting_for_its_world_stops_on_ctrl_c() {
    agent_bin();
    // No world with this prefix: the agent waits for it (up to 60 s).
    let mut agent = spawn_agent(&format!("f{}-nowhere", std::process::id()), &["1", "0"]);
    std::thread::sleep(Duration::from_millis(1000));
    let int = Command::new("kill")
        .args(["-INT", &agent.id().to_string()])
        .status()
        .unwrap();
    assert!(int.success());
    // Ended by the API (`Interrupted` → exit 130), not by the signal's default action.
    let status = wait(&mut agent, Duration::from_secs(10));
    assert_eq!(status.code(), Some(130), "{status}");
}
