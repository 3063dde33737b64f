//! Agent faults and timing modes with real processes (the goto example agent, no mocks), each
//! checked on what the run shows — the summary's events and counts, and the vehicle's mode,
//! setpoints and motion in trajectories.csv:
//!
//! - lock-step: an agent that stalls, or is stopped with SIGSTOP, is declared hung after the
//!   timeout, its vehicle holds depth and heading, and it is taken back when it answers again
//!   (SIGCONT), or a new process takes its place after the stopped one is killed;
//! - the fallback `stop` ends the run (exit 3, the summary says why) when an agent hangs, and
//!   when a free-running agent is killed; the fallback `surface` brings the vehicle up;
//! - free-running: an agent gets observations of the vehicle as it is and its commands take
//!   effect; the world never waits for a slow agent and keeps its last command in force; a
//!   killed agent is noticed, the world goes on with the vehicle holding, and a new process
//!   can take its place;
//! - Ctrl-C of an agent says goodbye.
//!
//! The tests follow a run through the agents' `--log` lines (what each observed, once per
//! simulated second) instead of sleeping and assuming where the run is.

mod common;

use common::{Logged, wait, wait_attached, wait_logged};

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

/// A second vehicle far off, driven by agent `name`.
fn second_vehicle(name: &str) -> String {
    format!("[[vehicles]]\nname = \"{name}\"\nposition = [2.0, 2.0, 0.5]\nagent = \"{name}\"\n")
}

/// A test's folder, its agents' service prefix, the run's output folder and the running
/// world.
struct Started {
    dir: PathBuf,
    prefix: String,
    out: PathBuf,
    world: Child,
}

/// Starts the world of test `name` ([`world_with`]) in a fresh folder, with its own prefix.
fn start(name: &str, duration: f64, agents: &str, more_vehicles: &str) -> Started {
    let dir = common::tmp("faults", name);
    let prefix = format!("f{}-{name}", std::process::id());
    let w = world_with(&dir, duration, agents, more_vehicles);
    let out = dir.join("out");
    let world = spawn_world(&w, &out, &prefix);
    Started {
        dir,
        prefix,
        out,
        world,
    }
}

impl Started {
    /// The goto agent `pilot` with `args` ([`spawn_agent`], logging to `pilot.err`).
    fn pilot(&self, args: &[&str]) -> (Child, PathBuf) {
        spawn_agent(&self.dir, "pilot", &self.prefix, "pilot", args)
    }
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

/// A goto agent `name` with `args`, logging what it observes (`--log`) to `dir/<log>.err`;
/// returns the process and its log.
fn spawn_agent(dir: &Path, log: &str, prefix: &str, name: &str, args: &[&str]) -> (Child, PathBuf) {
    let path = dir.join(format!("{log}.err"));
    let child = Command::new(agent_bin())
        .args([prefix, name])
        .args(args)
        .arg("--log")
        .stdout(Stdio::null())
        .stderr(common::log_file(&path))
        .spawn()
        .unwrap();
    (child, path)
}

/// Sends `signal` (`STOP`, `CONT`, `INT`) to `child`.
fn signal(child: &Child, signal: &str) {
    let ok = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(ok.success(), "kill -{signal}");
}

/// One recorded row of the pilot's vehicle.
#[derive(Clone, Debug)]
struct Row {
    t: f64,
    depth: f64,
    yaw: f64,
    mode: String,
    depth_sp: f64,
    yaw_sp: f64,
}

/// The world's exit status, printed summary, summary.json and the rows of the pilot's
/// vehicle.
struct Finished {
    status: ExitStatus,
    stdout: String,
    summary: Value,
    rows: Vec<Row>,
}

impl Finished {
    /// The report of agent `name`.
    fn agent_named(&self, name: &str) -> &Value {
        self.summary["agents"]["agents"]
            .as_array()
            .unwrap()
            .iter()
            .find(|a| a["name"] == name)
            .unwrap()
    }
    /// The report of agent `pilot`.
    fn agent(&self) -> &Value {
        self.agent_named("pilot")
    }
    fn events_of(&self, name: &str) -> Vec<(String, f64)> {
        self.agent_named(name)["events"]
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
    fn events(&self) -> Vec<(String, f64)> {
        self.events_of("pilot")
    }
    fn names(&self) -> Vec<String> {
        self.events().into_iter().map(|e| e.0).collect()
    }
    fn last(&self) -> &Row {
        self.rows.last().unwrap()
    }
    /// The first row at or after `t`.
    fn at(&self, t: f64) -> &Row {
        self.rows.iter().find(|r| r.t >= t - 1e-9).unwrap()
    }
    /// Depth reading at the first sample at or after `t`.
    fn depth_at(&self, t: f64) -> f64 {
        self.at(t).depth
    }
    /// The rows in `from … to` (both included).
    fn between(&self, from: f64, to: f64) -> Vec<&Row> {
        let rows: Vec<&Row> = self
            .rows
            .iter()
            .filter(|r| r.t >= from - 1e-9 && r.t <= to + 1e-9)
            .collect();
        assert!(!rows.is_empty(), "no rows in {from} … {to} s");
        rows
    }
}

fn finish(mut world: Child, out: &Path) -> Finished {
    // (A hang guard: a run that never ends fails the test.)
    let status = wait(&mut world, Duration::from_secs(120));
    let mut stdout = String::new();
    std::io::Read::read_to_string(world.stdout.as_mut().unwrap(), &mut stdout).unwrap();
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let mut r = csv::Reader::from_path(out.join("trajectories.csv")).unwrap();
    let h = r.headers().unwrap().clone();
    let col = |n: &str| h.iter().position(|c| c == n).unwrap();
    let (ct, cv, cz, cy, cm, czs, cys) = (
        col("t_s"),
        col("vehicle"),
        col("depth_reading_m"),
        col("yaw_rad"),
        col("mode"),
        col("depth_setpoint_m"),
        col("yaw_setpoint_rad"),
    );
    let records: Vec<csv::StringRecord> = r.records().map(|x| x.unwrap()).collect();
    // The pilot's vehicle is the first.
    let pilot = records[0][cv].to_string();
    let rows = records
        .iter()
        .filter(|x| x[cv] == pilot)
        .map(|x| Row {
            t: x[ct].parse().unwrap(),
            depth: x[cz].parse().unwrap(),
            yaw: x[cy].parse().unwrap(),
            mode: x[cm].to_string(),
            depth_sp: x[czs].parse().unwrap(),
            yaw_sp: x[cys].parse().unwrap(),
        })
        .collect();
    Finished {
        status,
        stdout,
        summary,
        rows,
    }
}

/// |a − b| for headings [rad], wrapped to [0, π].
fn angle(a: f64, b: f64) -> f64 {
    (a - b).sin().atan2((a - b).cos()).abs()
}

fn assert_on_target(f: &Finished, depth: f64, heading_deg: f64) {
    let r = f.last();
    assert!(
        (r.depth - depth).abs() < 0.05,
        "depth {}, wanted {depth}",
        r.depth
    );
    assert!(
        angle(r.yaw, heading_deg.to_radians()) < 1f64.to_radians(),
        "heading {}, wanted {heading_deg}°",
        r.yaw
    );
}

/// Time of the first row under a command to `depth`.
fn first_command(f: &Finished, depth: f64) -> f64 {
    f.rows
        .iter()
        .find(|r| (r.depth_sp - depth).abs() < 1e-6)
        .expect("a command took effect")
        .t
}

/// In `from … to` the vehicle was under the agent's command: auto mode to `depth` and
/// `heading_deg` (to the 6 decimals trajectories.csv has).
fn assert_commanded(f: &Finished, from: f64, to: f64, depth: f64, heading_deg: f64) {
    for r in f.between(from, to) {
        assert!(
            r.mode == "auto"
                && (r.depth_sp - depth).abs() < 1e-6
                && angle(r.yaw_sp, heading_deg.to_radians()) < 1e-6,
            "not under the command ({depth} m, {heading_deg}°) at {r:?}"
        );
    }
}

/// The recorded depth reading and heading at `t`, interpolated between the rows around it.
fn state_at(f: &Finished, t: f64) -> (f64, f64) {
    let i = f.rows.iter().position(|r| r.t >= t - 1e-9).unwrap();
    if i == 0 || f.rows[i].t <= t + 1e-9 {
        return (f.rows[i].depth, f.rows[i].yaw);
    }
    let (a, b) = (&f.rows[i - 1], &f.rows[i]);
    let w = (t - a.t) / (b.t - a.t);
    let dyaw = (b.yaw - a.yaw).sin().atan2((b.yaw - a.yaw).cos());
    (a.depth + w * (b.depth - a.depth), a.yaw + w * dyaw)
}

/// From `since` (when the fallback `hold` began) to `to` the vehicle held: auto mode with the
/// depth reading and heading it had at `since` as its setpoints throughout, and it stayed
/// there. Returns the held heading.
fn assert_holds(f: &Finished, since: f64, to: f64) -> f64 {
    let rows = f.between(since + 0.1, to);
    let held = rows[0];
    // The setpoints are the sensors' values on the tick the fallback began: the depth reading
    // (1.8 mm steps, 0.5 mm noise) and the IMU's heading (0.5° noise), against the record
    // interpolated to that tick.
    let (depth, yaw) = state_at(f, since);
    assert!(
        (held.depth_sp - depth).abs() < 0.01 && angle(held.yaw_sp, yaw) < 2f64.to_radians(),
        "holds what it had at {since} s ({depth} m, {yaw} rad): {held:?}"
    );
    for r in &rows {
        assert!(
            r.mode == "auto" && r.depth_sp == held.depth_sp && r.yaw_sp == held.yaw_sp,
            "the fallback's setpoints throughout: {r:?} vs {held:?}"
        );
    }
    // It was moving when the fallback began; by the end of the hold it is back at the held
    // values (measured: within 2 cm and 1.5° after 8 s or more).
    let end = rows.last().unwrap();
    assert!(
        (end.depth - held.depth_sp).abs() < 0.05 && angle(end.yaw, held.yaw_sp) < 0.05,
        "stayed at the held depth and heading: {end:?} vs {held:?}"
    );
    held.yaw_sp
}

/// [`assert_holds`], and the heading held is more than 5° short of the commanded
/// `heading_deg` (the vehicle was still turning when it lost its agent): the hold shows as
/// such, not as the last command still in force.
fn assert_holds_short_of(f: &Finished, since: f64, to: f64, heading_deg: f64) {
    let held = assert_holds(f, since, to);
    assert!(
        angle(held, heading_deg.to_radians()) > 5f64.to_radians(),
        "it held heading {}°, not short of the commanded {heading_deg}°",
        held.to_degrees()
    );
}

#[test]
fn hung_agent_falls_back_and_is_taken_back_when_it_answers_again() {
    // A second vehicle far off, driven by agent `pacer`, which takes 5 ms per tick: the
    // lock-step world waits for it, so it runs at ≈ 10× real time while `pilot` hangs.
    let s = start(
        "hung",
        60.0,
        "timing = \"lockstep\"\ntimeout = 0.5\nfallback = \"hold\"",
        &second_vehicle("pacer"),
    );
    let (mut pacer, _) = spawn_agent(
        &s.dir,
        "pacer",
        &s.prefix,
        "pacer",
        &["1.0", "0", "--slow", "5"],
    );
    // At its 40th tick (t = 2 s) the pilot stops answering for 12 s of simulated time (at the
    // pacer's speed ≈ 1.2 s of wall time, more than twice the timeout; on a loaded machine
    // longer, but the same 12 s simulated: long enough for the hold to settle).
    let (mut agent, _) = s.pilot(&["1.5", "90", "--stall", "40:12"]);
    let f = finish(s.world, &s.out);
    assert!(wait(&mut agent, Duration::from_secs(30)).success());
    assert!(wait(&mut pacer, Duration::from_secs(30)).success());
    assert!(f.status.success(), "{}", f.stdout);
    let ev = f.events();
    assert_eq!(f.names(), ["attached", "hung", "reattached"], "{ev:?}");
    // Declared hung on the tick it stalled on (t = 2.00 s, its 40th answered tick)…
    assert!((ev[1].1 - 2.0).abs() < 0.051, "hung at {}", ev[1].1);
    // …and taken back once it answered again, 12 s simulated later (a tick or a few more if
    // the world ran on while its answer was on the way).
    assert!(ev[2].1 >= 14.0 - 1e-9 && ev[2].1 < 14.5, "{ev:?}");
    // Under the fallback from the tick after the hang until its first command after
    // re-attaching (one or two ticks after that event).
    let fallback = f.agent()["fallback_ticks"].as_u64().unwrap() as f64;
    let expected = (ev[2].1 - ev[1].1) / 0.05;
    assert!(
        fallback >= expected - 0.5 && fallback <= expected + 3.0,
        "{fallback} fallback ticks, expected ≈ {expected}"
    );
    // In the run: its command before, holding while hung, its command again after.
    assert_commanded(&f, 0.2, ev[1].1 - 0.05, 1.5, 90.0);
    assert_holds(&f, ev[1].1, ev[2].1 - 0.05);
    assert_commanded(&f, ev[2].1 + 0.15, 60.0, 1.5, 90.0);
    assert!(f.agent()["attached_at_end"].as_bool().unwrap());
    assert!(f.stdout.contains("hung"), "{}", f.stdout);
    // The other agent was not disturbed: attached once, never in fallback after its first command.
    let pacer_report = f.agent_named("pacer");
    assert_eq!(pacer_report["events"].as_array().unwrap().len(), 1);
    // (Its one fallback tick is the first: observed before its first command.)
    assert_eq!(pacer_report["fallback_ticks"], 1);
    // Back under the pilot's control: on target at the end.
    assert_on_target(&f, 1.5, 90.0);
}

/// A lock-step world of 60 s (`fallback = "hold"`, timeout 0.5 s) whose pilot (sent to 1.5 m,
/// heading 180°) is stopped with SIGSTOP at 3 s simulated, beside agent `pacer` (5 ms per
/// tick) on a second vehicle. Returns the world, the stopped pilot and its log, the pacer and
/// its log, and the pilot's last logged observation before the stop.
struct Stopped {
    dir: PathBuf,
    prefix: String,
    out: PathBuf,
    world: Child,
    pilot: Child,
    pilot_log: PathBuf,
    pacer: Child,
    pacer_log: PathBuf,
    stopped_after: Logged,
    /// A line the pacer logged after the pilot was stopped.
    stopped: Logged,
}

fn stop_the_pilot(name: &str) -> Stopped {
    let Started {
        dir,
        prefix,
        out,
        world,
    } = start(
        name,
        60.0,
        "timing = \"lockstep\"\ntimeout = 0.5\nfallback = \"hold\"",
        &second_vehicle("pacer"),
    );
    let (pacer, pacer_log) = spawn_agent(
        &dir,
        "pacer",
        &prefix,
        "pacer",
        &["1.0", "0", "--slow", "5"],
    );
    // Heading 180° takes the paper's overdamped yaw loop well over 20 s: at 3 s the vehicle is
    // still turning, so what it holds differs from where it was sent.
    let (pilot, pilot_log) = spawn_agent(&dir, "pilot", &prefix, "pilot", &["1.5", "180"]);
    let stopped_after = wait_logged(&pilot_log, 3.0);
    signal(&pilot, "STOP");
    let stopped = common::logged_from_now(&pacer_log);
    Stopped {
        dir,
        prefix,
        out,
        world,
        pilot,
        pilot_log,
        pacer,
        pacer_log,
        stopped_after,
        stopped,
    }
}

#[test]
fn stopped_agent_is_declared_hung_and_taken_back_when_continued() {
    let s = stop_the_pilot("sigstop");
    // The world cannot pass the pilot's stalled tick before declaring it hung (lock-step):
    // once the pacer has seen 8 s more, the pilot has been hung for most of them.
    let later = wait_logged(&s.pacer_log, s.stopped.t + 8.0);
    signal(&s.pilot, "CONT");
    let (mut pilot, mut pacer) = (s.pilot, s.pacer);
    let f = finish(s.world, &s.out);
    let status = wait(&mut pilot, Duration::from_secs(30));
    assert!(
        status.success(),
        "pilot: {status}\n{}",
        common::read_log(&s.pilot_log)
    );
    assert!(wait(&mut pacer, Duration::from_secs(30)).success());
    assert!(f.status.success(), "{}", f.stdout);
    let ev = f.events();
    assert_eq!(f.names(), ["attached", "hung", "reattached"], "{ev:?}");
    let (hung, back) = (ev[1].1, ev[2].1);
    // Stopped after its last log line, declared hung before the pacer's line that preceded
    // SIGCONT, and continued after that.
    assert!(
        hung >= s.stopped_after.t && hung < later.t,
        "hung at {hung} s, last seen at {} s, the pacer at {} s",
        s.stopped_after.t,
        later.t
    );
    assert!(
        back >= later.t,
        "back at {back} s, the pacer was at {} s",
        later.t
    );
    assert_commanded(&f, 0.2, hung - 0.05, 1.5, 180.0);
    assert_holds_short_of(&f, hung, back - 0.05, 180.0);
    assert_commanded(&f, back + 0.15, 60.0, 1.5, 180.0);
    // The pilot was told: its first observation after waking carried the fallback flag.
    let woke = common::logged(&common::read_log(&s.pilot_log));
    assert!(
        woke.iter().any(|l| l.t >= hung && l.fallback),
        "no fallback observation logged: {woke:?}"
    );
    let fallback = f.agent()["fallback_ticks"].as_u64().unwrap() as f64;
    let expected = (back - hung) / 0.05;
    assert!(
        fallback >= expected - 0.5 && fallback <= expected + 3.0,
        "{fallback} fallback ticks, expected ≈ {expected}"
    );
    assert!(f.agent()["attached_at_end"].as_bool().unwrap());
    assert_eq!(f.events_of("pacer").len(), 1);
    // The 180° turn is overdamped (paper gains): closer than 45° to it after 40 s.
    assert!(angle(f.last().yaw, std::f64::consts::PI) < 45f64.to_radians());
    assert!((f.last().depth - 1.5).abs() < 0.05, "{:?}", f.last());
    let _ = std::fs::remove_dir_all(&s.dir);
}

#[test]
fn stopped_agent_killed_and_replaced_by_a_new_process() {
    let s = stop_the_pilot("replace-hung");
    let hung_seen = wait_logged(&s.pacer_log, s.stopped.t + 4.0);
    // kill -9 of the stopped process; the world finds its node dead (it looks every 64
    // steps) and the name free for a new process once some simulated seconds have passed.
    let mut pilot = s.pilot;
    pilot.kill().unwrap();
    pilot.wait().unwrap();
    let killed = common::logged_from_now(&s.pacer_log);
    let dead_seen = wait_logged(&s.pacer_log, killed.t + 4.0);
    let (mut second, second_log) = spawn_agent(&s.dir, "pilot2", &s.prefix, "pilot", &["1.0", "0"]);
    wait_attached(&second_log);
    let mut pacer = s.pacer;
    let f = finish(s.world, &s.out);
    assert!(wait(&mut second, Duration::from_secs(30)).success());
    assert!(wait(&mut pacer, Duration::from_secs(30)).success());
    assert!(f.status.success(), "{}", f.stdout);
    let ev = f.events();
    assert_eq!(
        f.names(),
        ["attached", "hung", "gone", "reattached"],
        "{ev:?}"
    );
    let (hung, gone, back) = (ev[1].1, ev[2].1, ev[3].1);
    assert!(hung <= hung_seen.t && gone >= hung_seen.t && gone <= dead_seen.t);
    assert!(back >= dead_seen.t, "back at {back} s");
    // Held from the hang until the new process's first command, through the death.
    assert_commanded(&f, 0.2, hung - 0.05, 1.5, 180.0);
    assert_holds(&f, hung, back - 0.05);
    assert_commanded(&f, back + 0.15, 60.0, 1.0, 0.0);
    assert_on_target(&f, 1.0, 0.0);
    assert!(f.agent()["attached_at_end"].as_bool().unwrap());
    assert_eq!(f.events_of("pacer").len(), 1);
    let _ = std::fs::remove_dir_all(&s.dir);
}

#[test]
fn fallback_stop_ends_the_run_early_and_says_why() {
    let s = start(
        "stop",
        60.0,
        "timing = \"lockstep\"\ntimeout = 0.5\nfallback = \"stop\"",
        "",
    );
    // Stops answering at t = 1 s for 2 s simulated: hung after 0.5 s of wall time, the run
    // stops; the waiting agent finds the END of the run (exit 0).
    let (mut agent, _) = s.pilot(&["1.5", "90", "--stall", "20:2"]);
    let f = finish(s.world, &s.out);
    assert!(wait(&mut agent, Duration::from_secs(30)).success());
    assert_eq!(f.status.code(), Some(3), "{}", f.stdout);
    let stopped = f.summary["agents"]["stopped"].as_str().unwrap();
    assert!(
        stopped.contains("pilot") && stopped.contains("hung") && stopped.contains("stop"),
        "{stopped}"
    );
    assert!(f.stdout.contains("STOPPED"), "{}", f.stdout);
    assert_eq!(f.names(), ["attached", "hung"]);
    // It stopped at the hang (t = 1 s), with the outputs written up to there, and under the
    // agent's command to the end: no fallback ran.
    let t_end = f.summary["simulated_s"].as_f64().unwrap();
    assert!((t_end - 1.0).abs() < 0.06, "stopped at t = {t_end} s");
    assert!((f.events()[1].1 - t_end).abs() < 1e-9);
    assert!(f.last().t <= t_end + 1e-9 && f.last().t > 0.7);
    assert_commanded(&f, 0.2, t_end, 1.5, 90.0);
}

#[test]
fn fallback_stop_ends_a_free_running_run_when_its_agent_is_killed() {
    // 600 s simulated at 20× real time (30 s of wall time): the kill lands long before the
    // end even when a loaded machine lets the test thread lag the world by seconds.
    let s = start(
        "stop-killed",
        600.0,
        "timing = \"free\"\npace = 20.0\nfallback = \"stop\"",
        "",
    );
    let (mut agent, log) = s.pilot(&["1.5", "90"]);
    let alive = wait_logged(&log, 5.0);
    agent.kill().unwrap(); // kill -9
    agent.wait().unwrap();
    let f = finish(s.world, &s.out);
    assert_eq!(f.status.code(), Some(3), "{}", f.stdout);
    let stopped = f.summary["agents"]["stopped"].as_str().unwrap();
    assert!(
        stopped.contains("pilot") && stopped.contains("died") && stopped.contains("stop"),
        "{stopped}"
    );
    let ev = f.events();
    assert_eq!(f.names(), ["attached", "gone"], "{ev:?}");
    // The run ended on the tick the death was noticed, long before its 600 s.
    let t_end = f.summary["simulated_s"].as_f64().unwrap();
    assert!(
        ev[1].1 >= alive.t && (ev[1].1 - t_end).abs() < 1e-9,
        "{ev:?}, end {t_end}"
    );
    assert!(t_end < 600.0);
    assert!(f.last().t <= t_end + 1e-9);
    // Its last command was in force to the end.
    let first_cmd = first_command(&f, 1.5);
    assert_commanded(&f, first_cmd, t_end, 1.5, 90.0);
}

#[test]
fn fallback_surface_brings_the_vehicle_up_after_its_agent_is_killed() {
    let s = start(
        "surface",
        90.0,
        "timing = \"lockstep\"\ntimeout = 2.0\nfallback = \"surface\"",
        "",
    );
    // 10 ms per tick: the run lasts a while.
    let (mut agent, log) = s.pilot(&["1.5", "0", "--slow", "10"]);
    // Killed once it has dived (its pressure port reads 0.09 m less than the 1.5 m).
    let dived = common::poll(common::POLL_LIMIT, "the vehicle dived", || {
        common::logged(&common::read_log(&log))
            .into_iter()
            .find(|l| l.depth > 1.3)
    });
    agent.kill().unwrap(); // kill -9
    agent.wait().unwrap();
    let f = finish(s.world, &s.out);
    assert!(f.status.success());
    let ev = f.events();
    let gone = ev.iter().find(|e| e.0 == "gone").expect("gone event").1;
    assert!(gone >= dived.t, "gone at {gone} s, dived at {} s", dived.t);
    assert!(f.depth_at(gone) > 1.2, "{} m at the kill", f.depth_at(gone));
    // Surfaced afterwards: the fallback's setpoint is the surface.
    for r in f.between(gone + 0.1, 90.0) {
        assert!(r.mode == "auto" && r.depth_sp == 0.0, "{r:?}");
    }
    assert!(f.last().depth < 0.05, "at the end {} m", f.last().depth);
    assert_eq!(f.summary["simulated_s"].as_f64().unwrap(), 90.0);
}

#[test]
fn free_running_agent_gets_observations_and_its_commands_take_effect() {
    // 60 s simulated at 20× real time: 1,200 control ticks in 3 s of wall time.
    let s = start(
        "free-obs",
        60.0,
        "timing = \"free\"\npace = 20.0\ntimeout = 0.3\nfallback = \"hold\"",
        "",
    );
    let (mut agent, log) = s.pilot(&["1.5", "90"]);
    let f = finish(s.world, &s.out);
    assert!(wait(&mut agent, Duration::from_secs(30)).success());
    assert!(f.status.success(), "{}", f.stdout);
    assert_eq!(f.summary["agents"]["timing"], "free");
    assert_eq!(f.names(), ["attached"]);
    let a = f.agent();
    assert_eq!(
        a["round_trip"]["count"], 0,
        "free-running: nothing is timed"
    );
    // Observations: the vehicle's own sensors, from its attach to the end of the run. Each
    // logged reading is the recorded one at that time (the reading is quantised and noisy
    // and the record is 0.1 s apart: within 3 cm and 2°).
    let seen = common::logged(&common::read_log(&log));
    assert!(seen.len() >= 10, "{} observations logged", seen.len());
    assert!(seen.windows(2).all(|w| w[1].t > w[0].t), "{seen:?}");
    assert!(seen.last().unwrap().t >= 59.0, "{:?}", seen.last());
    for l in &seen {
        let r = f.at(l.t);
        assert!(
            (l.depth - r.depth).abs() < 0.03
                && angle(l.yaw_deg.to_radians(), r.yaw) < 2f64.to_radians(),
            "observed {l:?}, recorded {r:?}"
        );
    }
    // Commands: from the first, the vehicle is under them to the end (the last command stays
    // in force between replies); before it, it held (fallback) — as many ticks as the
    // summary counts.
    let first_cmd = first_command(&f, 1.5);
    assert_commanded(&f, first_cmd, 60.0, 1.5, 90.0);
    if first_cmd > 0.15 {
        assert_holds(&f, 0.0, first_cmd - 0.1);
    }
    let fallback = a["fallback_ticks"].as_u64().unwrap() as f64;
    assert!(
        (fallback - first_cmd / 0.05).abs() <= 2.0,
        "{fallback} fallback ticks, first command recorded at {first_cmd} s"
    );
    let applied = a["commands_applied"].as_u64().unwrap();
    assert!((1..=1200).contains(&applied), "{applied} commands applied");
    assert_on_target(&f, 1.5, 90.0);
    // The agent saw it get there.
    let last = seen.last().unwrap();
    assert!(
        (last.depth - 1.5).abs() < 0.05 && (last.yaw_deg - 90.0).abs() < 1.5,
        "{last:?}"
    );
}

#[test]
fn free_running_world_never_waits_and_keeps_the_last_command() {
    // 60 s simulated at 20× real time: 3 s of wall time, 1200 control ticks.
    let s = start(
        "free",
        60.0,
        "timing = \"free\"\npace = 20.0\ntimeout = 0.3\nfallback = \"hold\"",
        "",
    );
    // The agent needs 300 ms per tick: a lock-step world would take 1200 × 0.3 s = 6 min.
    let (mut agent, _) = s.pilot(&["1.5", "90", "--slow", "300"]);
    let f = finish(s.world, &s.out);
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
    assert_eq!(f.names(), ["attached"]);
    assert_eq!(a["round_trip"]["count"], 0);
    // The vehicle holds (fallback) until the first command arrives, 0.3 s of wall time = 6 s
    // simulated after the agent attached; from then on the last command stays in force: no
    // fallback between the rare commands (that would be ≈ 1,200 − 20 ticks).
    let fallback = a["fallback_ticks"].as_u64().unwrap();
    assert!((1..400).contains(&fallback), "{fallback} fallback ticks");
    let first_cmd = first_command(&f, 1.5);
    assert_commanded(&f, first_cmd, 60.0, 1.5, 90.0);
    assert_on_target(&f, 1.5, 90.0);
}

#[test]
fn free_running_world_notices_a_killed_agent_and_takes_a_new_one() {
    // 120 s simulated at 10× real time; agent `watch` on a second vehicle shows how far the
    // world has run.
    let s = start(
        "replace",
        120.0,
        "timing = \"free\"\npace = 10.0\ntimeout = 0.3\nfallback = \"hold\"",
        &second_vehicle("watch"),
    );
    let (mut watch, watch_log) = spawn_agent(&s.dir, "watch", &s.prefix, "watch", &["1.0", "0"]);
    // Sent to 180°, which the paper's overdamped yaw loop takes well over 20 s to reach:
    // killed at 3 s, the vehicle holds a heading far from it.
    let (mut first, first_log) = s.pilot(&["1.5", "180"]);
    let alive = wait_logged(&first_log, 3.0);
    first.kill().unwrap(); // kill -9
    first.wait().unwrap();
    // The world goes on (it does not hang on the dead agent), finds it dead (it looks every
    // 64 steps) and frees its name: 10 s simulated later a new process attaches.
    let killed = common::logged_from_now(&watch_log);
    let later = wait_logged(&watch_log, killed.t + 10.0);
    let (mut second, second_log) =
        spawn_agent(&s.dir, "pilot2", &s.prefix, "pilot", &["1.0", "90"]);
    wait_attached(&second_log);
    let f = finish(s.world, &s.out);
    assert!(wait(&mut second, Duration::from_secs(30)).success());
    assert!(wait(&mut watch, Duration::from_secs(30)).success());
    assert!(f.status.success());
    assert_eq!(f.summary["simulated_s"].as_f64().unwrap(), 120.0);
    let ev = f.events();
    assert_eq!(f.names(), ["attached", "gone", "reattached"], "{ev:?}");
    let (gone, back) = (ev[1].1, ev[2].1);
    assert!(gone >= alive.t && gone <= later.t, "gone at {gone} s");
    assert!(back >= later.t, "back at {back} s");
    // Between the two the vehicle held the depth and heading it had when the first agent
    // died (not the 180° it was sent to), then followed the second agent.
    assert_commanded(&f, 0.5, gone - 0.05, 1.5, 180.0);
    assert_holds_short_of(&f, gone, back - 0.05, 180.0);
    // The new agent's first command takes over once its process gets to send it: free-running,
    // the world does not wait for it, so how much simulated time passes first is the agent's
    // scheduling delay × 10 (the pace) — a few ticks on an idle machine, more beside CPU-bound
    // tests; within 3 s simulated (0.3 s of wall time). From then on it is in force.
    let took = first_command(&f, 1.0);
    assert!(
        took >= back && took <= back + 3.0,
        "back at {back} s, first command at {took} s"
    );
    assert_commanded(&f, took, 120.0, 1.0, 90.0);
    assert_on_target(&f, 1.0, 90.0);
    assert!(f.agent()["attached_at_end"].as_bool().unwrap());
    // The other agent was not disturbed.
    assert_eq!(f.events_of("watch").len(), 1);
}

#[test]
fn rust_agent_interrupted_with_ctrl_c_says_goodbye() {
    // Free-running at 10× real time: 60 s simulated take 6 s.
    let s = start(
        "ctrl-c",
        60.0,
        "timing = \"free\"\npace = 10.0\nfallback = \"hold\"",
        "",
    );
    let (mut agent, log) = s.pilot(&["1.5", "90"]);
    // Interrupted once it has observations (the world has it attached) and has driven 5 s.
    let driven = wait_logged(&log, 5.0);
    signal(&agent, "INT");
    let status = wait(&mut agent, Duration::from_secs(30));
    // iceoryx2 catches the signal; the agent API turns it into `Interrupted`, the example
    // exits 130 and the link says goodbye on the way out.
    assert_eq!(status.code(), Some(130));
    let f = finish(s.world, &s.out);
    assert!(f.status.success());
    let ev = f.events();
    assert_eq!(f.names(), ["attached", "left"]);
    assert!(ev[1].1 >= driven.t);
    assert!(!f.agent()["attached_at_end"].as_bool().unwrap());
    // Holding from its goodbye to the end.
    assert_holds(&f, ev[1].1, 60.0);
}

#[test]
fn rust_agent_waiting_for_its_world_stops_on_ctrl_c() {
    agent_bin();
    // No world with this prefix: the agent waits for it (up to 60 s).
    let dir = common::tmp("faults", "nowhere");
    let (mut agent, _) = spawn_agent(
        &dir,
        "pilot",
        &format!("f{}-nowhere", std::process::id()),
        "pilot",
        &["1", "0"],
    );
    // Nothing to observe while it waits: give it time to start and install its handler (the
    // signal's default action would end it with no exit code).
    std::thread::sleep(Duration::from_millis(1000));
    signal(&agent, "INT");
    // Ended by the API (`Interrupted` → exit 130), not by the signal's default action.
    let status = wait(&mut agent, Duration::from_secs(10));
    assert_eq!(status.code(), Some(130), "{status}");
}
