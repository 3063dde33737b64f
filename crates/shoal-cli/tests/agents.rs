//! External agents as real processes over iceoryx2 (no mocks): a Rust agent drives a vehicle
//! in lock-step reproducibly, a killed agent is detected and its vehicle falls back, invalid
//! commands are rejected and counted without touching the run, and worlds with different
//! prefixes never see each other.
//!
//! The agent is `crates/shoal-bridge/examples/goto_agent.rs`, built by the test with cargo.

mod common;

use common::{summary, wait};

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::OnceLock;
use std::time::Duration;

/// The goto agent, built once per test process.
fn agent_bin() -> &'static Path {
    static BIN: OnceLock<PathBuf> = OnceLock::new();
    BIN.get_or_init(|| common::example_agent("goto_agent"))
}

/// A world with one μAUV² driven by agent `pilot`.
fn world(dir: &Path, duration: f64, extra_agents: &str) -> PathBuf {
    let p = dir.join("world.toml");
    std::fs::write(
        &p,
        format!(
            r#"name = "pilot-test"
duration = {duration}
[pool]
size = [10.0, 10.0, 3.0]
[agents]
timing = "lockstep"
timeout = 0.5
attach_timeout = 20.0
{extra_agents}
[[vehicles]]
name = "auv"
position = [5.0, 5.0, 0.5]
agent = "pilot"
"#
        ),
    )
    .unwrap();
    p
}

fn spawn_world(world: &Path, out: &Path, prefix: &str, extra: &[&str]) -> Child {
    // The agent is built first: a world waits only `attach_timeout` for it.
    agent_bin();
    Command::new(env!("CARGO_BIN_EXE_shoal"))
        .args(["run", "--quiet", "--no-plots", "--prefix", prefix, "--out"])
        .arg(out)
        .args(extra)
        .arg(world)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

fn spawn_agent(prefix: &str, name: &str, args: &[&str]) -> Child {
    Command::new(agent_bin())
        .args([prefix, name])
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Final depth reading [m] and heading [rad] of vehicle 0 from trajectories.csv.
fn final_pose(out: &Path) -> (f64, f64) {
    let mut r = csv::Reader::from_path(out.join("trajectories.csv")).unwrap();
    let h = r.headers().unwrap().clone();
    let col = |n: &str| h.iter().position(|c| c == n).unwrap();
    let (z, yaw) = (col("depth_reading_m"), col("yaw_rad"));
    let last = r.records().map(|x| x.unwrap()).last().unwrap();
    (last[z].parse().unwrap(), last[yaw].parse().unwrap())
}

fn run_pilot(dir: &Path, prefix: &str, duration: f64, agent_args: &[&str]) -> serde_json::Value {
    let w = world(dir, duration, "");
    let out = dir.join(format!("out-{prefix}"));
    let mut sim = spawn_world(&w, &out, prefix, &[]);
    let mut agent = spawn_agent(prefix, "pilot", agent_args);
    let a = wait(&mut agent, Duration::from_secs(120));
    let s = wait(&mut sim, Duration::from_secs(120));
    assert!(s.success(), "world: {s}");
    assert!(a.success(), "agent: {a}");
    let mut v = summary(&out);
    v["final_pose"] = serde_json::json!(final_pose(&out));
    v
}

#[test]
fn rust_agent_drives_a_vehicle_in_lockstep_reproducibly() {
    let dir = common::tmp("agents", "lockstep");
    let pfx = format!("t{}-lock", std::process::id());
    let a = run_pilot(&dir, &format!("{pfx}-a"), 60.0, &["1.5", "90"]);
    let b = run_pilot(&dir, &format!("{pfx}-b"), 60.0, &["1.5", "90"]);
    // The vehicle went where the agent sent it (from 0.5 m, heading 0; the heading loop
    // settles with a time constant of ≈ 6 s, so after 60 s it is there within a degree).
    let (z, yaw) = (
        a["final_pose"][0].as_f64().unwrap(),
        a["final_pose"][1].as_f64().unwrap(),
    );
    assert!((z - 1.5).abs() < 0.05, "depth {z}");
    assert!(
        (yaw - 90f64.to_radians()).abs() < 1f64.to_radians(),
        "heading {yaw}"
    );
    let ag = &a["agents"]["agents"][0];
    assert_eq!(ag["name"], "pilot");
    // 60 s at a 0.05 s control period: 1200 ticks; the first may precede the attach.
    let applied = ag["commands_applied"].as_u64().unwrap();
    assert!(applied >= 1198, "{applied} commands applied");
    assert_eq!(ag["rejections"]["non_finite"], 0);
    assert!(ag["round_trip"]["count"].as_u64().unwrap() >= 1198);
    assert_eq!(ag["events"][0]["what"], "attached");
    // Lock-step: bit-identical on repeat.
    assert_eq!(a["digest"], b["digest"]);
    assert_eq!(a["final_pose"], b["final_pose"]);
}

#[test]
fn invalid_commands_are_counted_and_leave_the_run_unaffected() {
    let dir = common::tmp("agents", "invalid");
    let pfx = format!("t{}-bad", std::process::id());
    let good = run_pilot(&dir, &format!("{pfx}-good"), 30.0, &["1.2", "-45"]);
    let bad = run_pilot(&dir, &format!("{pfx}-bad"), 30.0, &["1.2", "-45", "--bad"]);
    let r = &bad["agents"]["agents"][0]["rejections"];
    let ticks = bad["agents"]["agents"][0]["round_trip"]["count"]
        .as_u64()
        .unwrap();
    assert!(ticks >= 598);
    // Per tick: NaN depth and infinite heading; an unknown mode and an unknown kind; a
    // vehicle that is not the agent's; an old protocol version; and 9 bad frames: 5 beyond
    // the 4 a command holds, one longer than the buffer, one longer than the modem's 58-byte
    // payload, one for a modem the vehicle lacks, one empty.
    assert_eq!(r["non_finite"].as_u64().unwrap(), 2 * ticks, "{r}");
    assert_eq!(r["invalid"].as_u64().unwrap(), 2 * ticks, "{r}");
    assert_eq!(r["unknown_vehicle"].as_u64().unwrap(), ticks, "{r}");
    assert_eq!(r["malformed"].as_u64().unwrap(), ticks, "{r}");
    assert_eq!(r["bad_frames"].as_u64().unwrap(), 9 * ticks, "{r}");
    assert_eq!(r["clamped"], 0);
    // Nothing of it reached the world: bit-identical to the well-behaved agent's run.
    assert_eq!(good["digest"], bad["digest"]);
}

#[test]
fn two_worlds_with_different_prefixes_do_not_see_each_other() {
    let dir = common::tmp("agents", "isolation");
    let pfx = format!("t{}-iso", std::process::id());
    let (pa, pb) = (format!("{pfx}-a"), format!("{pfx}-b"));
    let w = world(&dir, 20.0, "");
    let (oa, ob) = (dir.join("a"), dir.join("b"));
    // A is not quiet: it says when its services exist ("… attach with prefix …"), then waits
    // up to its attach timeout (20 s) for its agent.
    agent_bin();
    let wa_err = dir.join("a.err");
    let mut wa = Command::new(env!("CARGO_BIN_EXE_shoal"))
        .args(["run", "--no-plots", "--prefix", &pa, "--out"])
        .arg(&oa)
        .arg(&w)
        .stdout(Stdio::null())
        .stderr(common::log_file(&wa_err))
        .spawn()
        .unwrap();
    let mut wb = spawn_world(&w, &ob, &pb, &["--wait-agents", "1.5"]);
    // A third world with A's prefix is refused while A runs.
    common::poll(common::POLL_LIMIT, "world A opened its services", || {
        common::read_log(&wa_err)
            .contains("attach with prefix")
            .then_some(())
    });
    let dup = Command::new(env!("CARGO_BIN_EXE_shoal"))
        .args(["run", "--quiet", "--no-plots", "--prefix", &pa, "--out"])
        .arg(dir.join("dup"))
        .arg(&w)
        .output()
        .unwrap();
    assert_eq!(dup.status.code(), Some(2), "{dup:?}");
    assert!(
        String::from_utf8_lossy(&dup.stderr).contains("in use"),
        "{dup:?}"
    );
    let mut agent = spawn_agent(&pa, "pilot", &["2.0", "0"]);
    assert!(wait(&mut agent, Duration::from_secs(120)).success());
    assert!(wait(&mut wa, Duration::from_secs(120)).success());
    assert!(wait(&mut wb, Duration::from_secs(120)).success());
    let (sa, sb) = (summary(&oa), summary(&ob));
    assert_eq!(sa["agents"]["agents"][0]["events"][0]["what"], "attached");
    assert!(
        sa["agents"]["agents"][0]["commands_applied"]
            .as_u64()
            .unwrap()
            >= 398
    );
    // B never saw A's agent: no events, no commands, its vehicle held depth throughout.
    assert_eq!(sb["agents"]["agents"][0]["events"], serde_json::json!([]));
    assert_eq!(sb["agents"]["agents"][0]["commands_applied"], 0);
    // (The pressure sensor sits above the body origin: at 0.5 m it reads 0.41 m.)
    let (zb, _) = final_pose(&ob);
    assert!((zb - 0.41).abs() < 0.03, "B held its depth: {zb}");
}

#[test]
fn bench_measures_the_round_trip_to_a_rust_agent() {
    let agent = agent_bin();
    common::check_agent_bench("rust", &["--rust-agent".as_ref(), agent.as_os_str()]);
}

#[test]
fn school_agent_aligns_the_school_using_only_what_it_senses_and_hears() {
    let school = common::example_agent("school_agent");
    agent_bin();
    let dir = common::tmp("agents", "school");
    let prefix = format!("t{}-school", std::process::id());
    let out = dir.join("out");
    let mut sim = spawn_world(
        &common::repo().join("worlds/agents_school.toml"),
        &out,
        &prefix,
        &[],
    );
    let mut agent = Command::new(school)
        .arg(&prefix)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    assert!(wait(&mut agent, Duration::from_secs(120)).success());
    assert!(wait(&mut sim, Duration::from_secs(120)).success());
    // Headings start up to 145° from their mean (random); by the end of the 60 s run the
    // agent has brought every vehicle within 5° of the mean, and all eight in optical contact.
    let mut r = csv::Reader::from_path(out.join("trajectories.csv")).unwrap();
    let h = r.headers().unwrap().clone();
    let col = |n: &str| h.iter().position(|c| c == n).unwrap();
    let (ct, cy) = (col("t_s"), col("yaw_rad"));
    let rows: Vec<(f64, f64)> = r
        .records()
        .map(|x| {
            let x = x.unwrap();
            (x[ct].parse().unwrap(), x[cy].parse().unwrap())
        })
        .collect();
    let spread = |t: f64| {
        let ys: Vec<f64> = rows
            .iter()
            .filter(|r| (r.0 - t).abs() < 1e-6)
            .map(|r| r.1)
            .collect();
        assert_eq!(ys.len(), 8, "samples at t = {t}");
        let (c, s) = ys
            .iter()
            .fold((0.0, 0.0), |(c, s), y| (c + y.cos(), s + y.sin()));
        let mean = s.atan2(c);
        ys.iter()
            .map(|y| (y - mean).sin().atan2((y - mean).cos()).abs())
            .fold(0.0, f64::max)
            .to_degrees()
    };
    let (start, end) = (spread(0.0), spread(60.0));
    assert!(start > 60.0, "the school starts scattered: {start}°");
    assert!(end < 5.0, "aligned within 5° at the end: {end}°");
    let s = summary(&out);
    let contact = s["comm"]["connectivity"].as_array().unwrap();
    assert_eq!(contact.last().unwrap()["largest"], 8);
    assert_eq!(s["agents"]["agents"][0]["rejections"]["non_finite"], 0);
}

// Addressed frames: worlds/agents_unicast.toml driven by the `unicast_agent` example, which
// logs what its vehicles sent, received and learnt of their acknowledged frames (JSON lines).

/// Physics step of worlds/agents_unicast.toml [s]: the link layer looks at its timers, and
/// acknowledgements leave, at the start of a step.
const DT: f64 = 0.01;
/// The delay after the tick the agent gives its frames [s] (off the step grid on purpose).
const DELAY: f64 = 0.013;
/// Airtime of the agent's frames: (8 payload + 6 header bytes) × 10 bits at 19,200 bit/s [s].
const AIRTIME: f64 = 14.0 * 10.0 / 19_200.0;
/// Airtime of an acknowledgement (the 6-byte header alone) [s].
const ACK_AIRTIME: f64 = 6.0 * 10.0 / 19_200.0;
/// `ack_timeout` of the world's modems [s].
const ACK_TIMEOUT: f64 = 0.05;
/// `arq_retries` of the world's modems.
const ARQ_RETRIES: u64 = 2;

/// The first step boundary at or after `t` [s].
fn next_step(t: f64) -> f64 {
    (t / DT - 1e-9).ceil() * DT
}

/// One run of worlds/agents_unicast.toml with the unicast agent sending `sends`
/// (`AT:FROM:TO:ACK:TAG`): the summary and the agent's log lines.
fn run_unicast(label: &str, sends: &[&str]) -> (serde_json::Value, Vec<serde_json::Value>) {
    let agent = common::example_agent("unicast_agent");
    let dir = common::tmp("agents", label);
    let prefix = format!("t{}-{label}", std::process::id());
    let out = dir.join("out");
    let mut sim = Command::new(env!("CARGO_BIN_EXE_shoal"))
        .args(["run", "--quiet", "--no-plots", "--prefix", &prefix, "--out"])
        .arg(&out)
        .arg(common::repo().join("worlds/agents_unicast.toml"))
        .stdout(common::log_file(&dir.join("world.out")))
        .stderr(common::log_file(&dir.join("world.err")))
        .spawn()
        .unwrap();
    let mut args = vec![prefix.as_str(), "link", "--delay", "0.013"];
    for s in sends {
        args.extend(["--send", s]);
    }
    let mut a = Command::new(agent)
        .args(&args)
        .stdout(common::log_file(&dir.join("agent.out")))
        .stderr(common::log_file(&dir.join("agent.err")))
        .spawn()
        .unwrap();
    let (sa, sw) = (
        wait(&mut a, Duration::from_secs(120)),
        wait(&mut sim, Duration::from_secs(120)),
    );
    let logs = || {
        ["world.err", "agent.err"]
            .map(|f| common::read_log(&dir.join(f)))
            .join("\n")
    };
    assert!(
        sa.success() && sw.success(),
        "agent {sa}, world {sw}\n{}",
        logs()
    );
    let lines = common::read_log(&dir.join("agent.out"))
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{l}: {e}")))
        .collect();
    (summary(&out), lines)
}

/// The log lines of `event` ("sent", "rx", "outcome") with `key` = `value`.
fn events<'a>(
    log: &'a [serde_json::Value],
    event: &str,
    key: &str,
    value: u64,
) -> Vec<&'a serde_json::Value> {
    log.iter()
        .filter(|l| l["event"] == event && l[key] == value)
        .collect()
}

/// The tag a received frame carries in its payload (the agent's first 4 bytes).
fn payload_tag(rx: &serde_json::Value) -> u64 {
    let b: Vec<u64> = rx["payload"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap())
        .collect();
    b[0] | b[1] << 8 | b[2] << 16 | b[3] << 24
}

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap()
}

#[test]
fn acknowledged_unicast_reaches_its_destination_alone_and_comes_back_with_its_tag() {
    // Vehicle 0 (`a`) sends: at 0.5 s an acknowledged unicast for 1 (`b`, 1.2 m ahead, facing
    // it) tagged 7; at 1.0 s one without acknowledgement tagged 8; at 1.5 s a broadcast tagged
    // 9, which shows that 2 (`c`, beside `b`) hears `a`.
    let (s, log) = run_unicast(
        "unicast",
        &["0.5:0:1:ack:7", "1.0:0:1:-:8", "1.5:0:all:-:9"],
    );
    let outcomes = events(&log, "outcome", "vehicle", 0);
    assert_eq!(
        outcomes.len(),
        1,
        "only the acknowledged frame ends: {log:?}"
    );
    let o = outcomes[0];
    assert_eq!((&o["tag"], &o["to"]), (&7.into(), &1.into()), "{o}");
    assert_eq!(o["acknowledged"], true, "{o}");
    assert_eq!(o["transmissions"], 1, "a 0.95-m link loses nothing: {o}");
    // Handed over at the tick plus the delay; on the air at once for AIRTIME; `b` decodes it
    // in that step and its acknowledgement leaves at the next step boundary, decoded by `a`
    // ACK_AIRTIME later.
    let sent = 0.5 + DELAY;
    assert!((f(&o["sent"]) - sent).abs() < 1e-9, "{o}");
    let acked = next_step(sent + AIRTIME) + ACK_AIRTIME;
    assert!((f(&o["t"]) - acked).abs() < 1e-9, "{o}: expected {acked}");
    // `b` got each of its frames once, from vehicle 0: the two unicasts flagged as such, with
    // the sequence number the outcome names for the acknowledged one; the broadcast not.
    let at_b = events(&log, "rx", "vehicle", 1);
    let tags: Vec<u64> = at_b.iter().map(|r| payload_tag(r)).collect();
    assert_eq!(tags, [7, 8, 9], "{at_b:?}");
    assert!(at_b.iter().all(|r| r["peer"] == 0 && f(&r["power"]) > 0.0));
    let unicast: Vec<bool> = at_b.iter().map(|r| r["unicast"] == true).collect();
    assert_eq!(unicast, [true, true, false]);
    assert_eq!(at_b[0]["seq"], o["seq"]);
    assert!(
        (f(&at_b[0]["t"]) - (sent + AIRTIME)).abs() < 1e-9,
        "{}",
        at_b[0]
    );
    // `c` hears `a` (the broadcast) but is handed neither unicast; `d` hears nothing.
    let at_c = events(&log, "rx", "vehicle", 2);
    let tags: Vec<u64> = at_c.iter().map(|r| payload_tag(r)).collect();
    assert_eq!(tags, [9], "{at_c:?}");
    assert_eq!(
        (&at_c[0]["peer"], &at_c[0]["unicast"]),
        (&0.into(), &false.into())
    );
    assert!(events(&log, "rx", "vehicle", 3).is_empty());
    // The world's side: one frame acknowledged, one acknowledgement sent, nothing refused.
    let ll = &s["comm"]["link_layer"];
    assert_eq!(
        (&ll["acknowledged"], &ll["gave_up"]),
        (&1.into(), &0.into()),
        "{ll}"
    );
    assert_eq!(ll["acks_sent"], 1, "{ll}");
    assert_eq!(s["agents"]["agents"][0]["rejections"]["bad_frames"], 0);
}

#[test]
fn acknowledged_unicast_to_a_vehicle_out_of_reach_is_given_up_after_its_retries() {
    // Vehicle 3 (`d`) is 8 m away and faces away: no copy reaches it, no acknowledgement comes.
    let (s, log) = run_unicast("give-up", &["1.0:0:3:ack:8"]);
    let outcomes = events(&log, "outcome", "vehicle", 0);
    assert_eq!(outcomes.len(), 1, "{log:?}");
    let o = outcomes[0];
    assert_eq!((&o["tag"], &o["to"]), (&8.into(), &3.into()), "{o}");
    assert_eq!(o["acknowledged"], false, "{o}");
    assert_eq!(o["transmissions"], 1 + ARQ_RETRIES, "{o}");
    // By hand: the first copy goes on the air when handed over; each wait ends ACK_TIMEOUT
    // after its copy ended and is noticed at the next step boundary, where the retransmission
    // starts; the last wait's end is the outcome.
    let sent = 1.0 + DELAY;
    assert!((f(&o["sent"]) - sent).abs() < 1e-9, "{o}");
    let mut start = sent;
    for _ in 0..ARQ_RETRIES {
        start = next_step(start + AIRTIME + ACK_TIMEOUT);
    }
    let last_end = start + AIRTIME;
    let gave_up = next_step(last_end + ACK_TIMEOUT);
    let t = f(&o["t"]);
    assert!((t - gave_up).abs() < 1e-9, "{o}: expected {gave_up}");
    assert!(
        t >= last_end + ACK_TIMEOUT && t < last_end + ACK_TIMEOUT + DT,
        "{o}: the last wait ends {ACK_TIMEOUT} s after the last copy ended at {last_end}"
    );
    assert!(events(&log, "rx", "vehicle", 3).is_empty(), "{log:?}");
    let ll = &s["comm"]["link_layer"];
    assert_eq!(
        (&ll["acknowledged"], &ll["gave_up"]),
        (&0.into(), &1.into()),
        "{ll}"
    );
    assert_eq!(ll["retransmissions"], ARQ_RETRIES, "{ll}");
}

#[test]
fn bad_unicasts_are_counted_and_never_sent() {
    // At 2.0 s vehicle 0 sends four frames in one command: acknowledged to itself, to vehicle
    // 99 (the world has 4), a broadcast asking for an acknowledgement — all refused — and a
    // good unicast to 1, which goes out: the command itself is applied.
    let (s, log) = run_unicast(
        "bad-unicast",
        &[
            "2.0:0:0:ack:11",
            "2.0:0:99:-:12",
            "2.0:0:all:ack:13",
            "2.0:0:1:-:14",
        ],
    );
    let sent = events(&log, "sent", "from", 0);
    assert!(sent.iter().all(|l| l["added"] == true), "{sent:?}");
    let a = &s["agents"]["agents"][0];
    let r = &a["rejections"];
    assert_eq!(r["bad_frames"], 3, "{r}");
    let total: u64 = r
        .as_object()
        .unwrap()
        .values()
        .map(|v| v.as_u64().unwrap())
        .sum();
    assert_eq!(total, 3, "nothing else refused: {r}");
    // 60 ticks of 4 vehicles, all applied but the first tick's (before the agent attached).
    assert!(a["commands_applied"].as_u64().unwrap() >= 59 * 4, "{a}");
    assert_eq!(s["comm"]["frames_sent"], 1, "{}", s["comm"]);
    let tags: Vec<u64> = log
        .iter()
        .filter(|l| l["event"] == "rx")
        .map(payload_tag)
        .collect();
    assert_eq!(tags, [14], "only the good frame arrived: {log:?}");
    assert!(log.iter().all(|l| l["event"] != "outcome"), "{log:?}");
}
