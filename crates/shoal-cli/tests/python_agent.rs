//! The Python agent package (`shoal.agent`, in `python/shoal/agent`) against the Rust side: its
//! generated ctypes structs have the Rust layout field by field and equal the generator's
//! output, and the Python `school` example drives `worlds/agents_school.toml` in lock-step —
//! reproducibly, and to the same state digest as the Rust `school_agent` example.
//!
//! These tests need `python3` on the PATH with its `venv` module and pip (Debian:
//! `python3-venv`), cargo and PyPI: they use the project's venv (`.venv`), which
//! `scripts/python-env.sh` creates and keeps current (the `shoal` package of this checkout with
//! iceoryx2 0.10; it builds the extension module with cargo the first time, which takes
//! minutes). Without python3, venv or PyPI they fail and say which is missing: they never pass
//! unrun. The script holds an exclusive lock meanwhile, so test processes started side by side
//! do not build it twice or use it half-built.

mod common;

use serde_json::Value;
use shoal_bridge::protocol::{self, CType, flags, frame_flags, kind, mode};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// Simulated seconds per school run.
const SCHOOL_S: f64 = 10.0;
/// Vehicles of the school world's agent.
const SCHOOL_VEHICLES: u64 = 8;
/// Longest a world with its agent may take before both are killed.
const RUN_TIMEOUT: Duration = Duration::from_secs(120);

use common::repo;

/// `python3`; fails the test (with what to install) when it does not run.
fn python3() -> &'static str {
    match Command::new("python3").arg("--version").output() {
        Ok(o) if o.status.success() => "python3",
        Ok(o) => panic!(
            "`python3 --version` failed ({}): {}\nThe Python agent tests need python3 with venv and \
             pip (Debian: apt-get install python3 python3-venv) and PyPI access.",
            o.status,
            String::from_utf8_lossy(&o.stderr)
        ),
        Err(e) => panic!(
            "no python3 on the PATH ({e}).\nThe Python agent tests need python3 with venv and pip \
             (Debian: apt-get install python3 python3-venv) and PyPI access; scripts/test.sh \
             installs them where it can."
        ),
    }
}

fn tmp(name: &str) -> PathBuf {
    common::tmp("python-agent", name)
}

use common::read_log as read;

/// Prints the Python layout of the generated module (loaded by path: no iceoryx2 needed).
const LAYOUT_PY: &str = r#"
import ctypes, importlib.util, json, sys
spec = importlib.util.spec_from_file_location("shoal_protocol", sys.argv[1])
m = importlib.util.module_from_spec(spec)
spec.loader.exec_module(m)

def element(t):
    if issubclass(t, ctypes.Structure):
        return t.__name__
    code = t._type_
    return ("f" if code in "fd" else "i" if code in "bhilq" else "u") + str(ctypes.sizeof(t))

structs = {}
for name in ("Frame", "Outcome", "Observation", "Command"):
    s = getattr(m, name)
    fields = []
    for f in s._fields_:
        t = f[1]
        array = issubclass(t, ctypes.Array)
        fields.append({
            "name": f[0],
            "offset": getattr(s, f[0]).offset,
            "size": ctypes.sizeof(t),
            "count": t._length_ if array else 1,
            "element": element(t._type_ if array else t),
        })
    structs[name] = {"size": ctypes.sizeof(s), "align": ctypes.alignment(s),
                     "type_name": s.type_name(), "fields": fields}
consts = {k: v for k, v in vars(m).items() if k.isupper() and isinstance(v, int)}
for ns in ("flags", "frame_flags", "kind", "mode"):
    consts.update({ns + "." + k: v for k, v in vars(getattr(m, ns)).items() if k.isupper()})
print(json.dumps({"structs": structs, "consts": consts}))
"#;

fn element(t: CType) -> String {
    match t {
        CType::U8 => "u1".into(),
        CType::U16 => "u2".into(),
        CType::U32 => "u4".into(),
        CType::I32 => "i4".into(),
        CType::U64 => "u8".into(),
        CType::F64 => "f8".into(),
        CType::Frame => "Frame".into(),
        CType::Outcome => "Outcome".into(),
    }
}

#[test]
fn python_protocol_matches_rust_layout() {
    let py = python3();
    let module = repo().join("python/shoal/agent/protocol.py");
    let o = Command::new(py)
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .arg("-c")
        .arg(LAYOUT_PY)
        .arg(&module)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "python3 failed: {stderr}");
    let py: Value = serde_json::from_slice(&o.stdout).unwrap();

    let layout = protocol::layout();
    assert_eq!(py["structs"].as_object().unwrap().len(), layout.len());
    for s in &layout {
        let p = &py["structs"][s.name];
        assert_eq!(p["size"], s.size, "{} size", s.name);
        assert_eq!(p["align"], s.align, "{} alignment", s.name);
        assert_eq!(p["type_name"], s.type_name, "{} type name", s.name);
        let fields = p["fields"].as_array().unwrap();
        let names: Vec<&str> = fields.iter().map(|f| f["name"].as_str().unwrap()).collect();
        let rust: Vec<&str> = s.fields.iter().map(|f| f.name).collect();
        assert_eq!(names, rust, "{} fields", s.name);
        for (f, pf) in s.fields.iter().zip(fields) {
            let at = format!("{}.{}", s.name, f.name);
            assert_eq!(pf["offset"], f.offset, "{at} offset");
            assert_eq!(pf["count"], f.count, "{at} count");
            assert_eq!(pf["size"], f.count * f.ty.size(), "{at} size");
            assert_eq!(pf["element"], element(f.ty), "{at} element type");
        }
    }

    let expected: Vec<(&str, u64)> = vec![
        ("PROTOCOL_VERSION", protocol::PROTOCOL_VERSION.into()),
        ("FRAME_BYTES", protocol::FRAME_BYTES as u64),
        ("MAX_RX_FRAMES", protocol::MAX_RX_FRAMES as u64),
        ("MAX_TX_FRAMES", protocol::MAX_TX_FRAMES as u64),
        ("MAX_THRUSTERS", protocol::MAX_THRUSTERS as u64),
        ("MAX_TILTS", protocol::MAX_TILTS as u64),
        ("ALL_MODEMS", protocol::ALL_MODEMS.into()),
        ("BROADCAST", protocol::BROADCAST.into()),
        ("MAX_OUTCOMES", protocol::MAX_OUTCOMES as u64),
        ("flags.POSITION", flags::POSITION.into()),
        ("flags.TANK_FULL", flags::TANK_FULL.into()),
        ("flags.FALLBACK", flags::FALLBACK.into()),
        ("flags.END", flags::END.into()),
        ("frame_flags.ACK", frame_flags::ACK.into()),
        ("frame_flags.UNICAST", frame_flags::UNICAST.into()),
        ("kind.KEEP", kind::KEEP.into()),
        ("kind.MODE", kind::MODE.into()),
        ("kind.RAW", kind::RAW.into()),
        ("kind.LEAVE", kind::LEAVE.into()),
        ("mode.OFF", mode::OFF.into()),
        ("mode.DIVING", mode::DIVING.into()),
        ("mode.BUOYANCY", mode::BUOYANCY.into()),
        ("mode.TURNING", mode::TURNING.into()),
        ("mode.DRIFT", mode::DRIFT.into()),
        ("mode.AUTO", mode::AUTO.into()),
    ];
    let consts = py["consts"].as_object().unwrap();
    for (name, v) in &expected {
        assert_eq!(consts.get(*name), Some(&Value::from(*v)), "constant {name}");
    }
    assert_eq!(consts.len(), expected.len(), "constants: {consts:?}");

    // The committed module is the generator's output (regenerate it after changing the
    // protocol: `cargo run -p shoal-bridge --example gen_python -- python/shoal/agent/protocol.py`).
    // Built with `--workspace` like the other example agents (common::example_agent).
    let o = Command::new(common::example_agent("gen_python"))
        .current_dir(repo())
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "gen_python failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let generated = String::from_utf8(o.stdout).unwrap();
    assert!(
        generated == read(&module),
        "python/shoal/agent/protocol.py is stale: regenerate it with \
         `cargo run -p shoal-bridge --example gen_python -- python/shoal/agent/protocol.py`"
    );
}

/// The project venv's interpreter, made current by `scripts/python-env.sh` (which prints it).
fn venv() -> PathBuf {
    let t = Instant::now();
    let o = Command::new(repo().join("scripts/python-env.sh"))
        .current_dir(repo())
        .stdin(Stdio::null())
        .output()
        .unwrap_or_else(|e| panic!("cannot run scripts/python-env.sh: {e}"));
    assert!(
        o.status.success(),
        "scripts/python-env.sh failed (the Python agent tests need python3 with venv and pip — \
         Debian: apt-get install python3-venv — cargo, and PyPI access):\n{}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    let python = PathBuf::from(String::from_utf8_lossy(&o.stdout).trim());
    let agent = Command::new(&python)
        .args([
            "-c",
            "import importlib.metadata as m, shoal.agent; print(m.version('iceoryx2'))",
        ])
        .output()
        .unwrap();
    let version = String::from_utf8_lossy(&agent.stdout);
    assert!(
        agent.status.success() && version.trim().starts_with("0.10."),
        "{}: shoal.agent with iceoryx2 0.10 expected, got {version:?}: {}",
        python.display(),
        String::from_utf8_lossy(&agent.stderr)
    );
    println!(
        "venv {} ready in {:.1} s",
        python.display(),
        t.elapsed().as_secs_f64()
    );
    python
}

/// The Rust `school_agent` example.
fn rust_school_agent() -> PathBuf {
    common::example_agent("school_agent")
}

/// The venv, made current once per test process (the tests run in parallel). Checks first
/// that python3 runs, for a clear message when it is missing.
fn shared_venv() -> PathBuf {
    python3();
    static VENV: std::sync::Mutex<Option<PathBuf>> = std::sync::Mutex::new(None);
    let mut v = VENV.lock().unwrap_or_else(|e| e.into_inner());
    v.get_or_insert_with(venv).clone()
}

/// The first vehicle's last depth reading [m] and heading [rad] in a trajectories.csv.
fn final_pose(csv_path: &Path) -> (f64, f64) {
    let mut r = csv::Reader::from_path(csv_path).unwrap();
    let h = r.headers().unwrap().clone();
    let col = |n: &str| h.iter().position(|c| c == n).unwrap();
    let (id, z, yaw) = (col("vehicle"), col("depth_reading_m"), col("yaw_rad"));
    let rows: Vec<csv::StringRecord> = r.records().map(|x| x.unwrap()).collect();
    let first = rows[0][id].to_string();
    let last = rows.iter().rev().find(|x| x[id] == first).unwrap();
    (last[z].parse().unwrap(), last[yaw].parse().unwrap())
}

/// Waits for every child, polling; after `timeout` kills them all and panics.
fn wait_all(children: &mut [(&str, Child)], timeout: Duration) -> Vec<ExitStatus> {
    let start = Instant::now();
    let mut done: Vec<Option<ExitStatus>> = vec![None; children.len()];
    while done.iter().any(Option::is_none) {
        for ((_, c), d) in children.iter_mut().zip(done.iter_mut()) {
            if d.is_none() {
                *d = c.try_wait().unwrap();
            }
        }
        if start.elapsed() > timeout {
            let mut hung = Vec::new();
            for ((name, c), d) in children.iter_mut().zip(&done) {
                if d.is_none() {
                    let _ = c.kill();
                    let _ = c.wait();
                    hung.push(*name);
                }
            }
            panic!("killed after {timeout:?}: {}", hung.join(", "));
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    done.into_iter().map(Option::unwrap).collect()
}

/// One run of a world with one agent process.
struct Run {
    summary: Value,
    /// Vehicle 0's last depth reading [m] and heading [rad].
    final_pose: (f64, f64),
    agent_log: String,
    wall: Duration,
}

impl Run {
    fn digest(&self) -> &str {
        self.summary["digest"].as_str().unwrap()
    }
    fn agent(&self) -> &Value {
        &self.summary["agents"]["agents"][0]
    }
}

/// Runs `worlds/<world>.toml` for `duration` s with `agent` (a command, completed with the
/// prefix and `agent_args`); its `vehicles` must have answered every control tick but the
/// first two (at 0.05 s).
fn run_world(
    world: &str,
    duration: f64,
    vehicles: u64,
    label: &str,
    mut agent: Command,
    agent_args: &[&str],
) -> Run {
    let dir = tmp(label);
    let out = dir.join("out");
    let prefix = format!("pytest-{}-{label}", std::process::id());
    let log = |name: &str| std::fs::File::create(dir.join(name)).unwrap();
    let t = Instant::now();
    let world = Command::new(env!("CARGO_BIN_EXE_shoal"))
        .arg("run")
        .arg(repo().join(format!("worlds/{world}.toml")))
        .args(["--quiet", "--no-plots", "--duration"])
        .arg(duration.to_string())
        .args(["--prefix", &prefix, "--out"])
        .arg(&out)
        .stdin(Stdio::null())
        .stdout(log("world.out"))
        .stderr(log("world.err"))
        .spawn()
        .unwrap();
    let agent = agent
        .arg(&prefix)
        .args(agent_args)
        .current_dir(repo())
        .stdin(Stdio::null())
        .stdout(log("agent.out"))
        .stderr(log("agent.err"))
        .spawn()
        .unwrap();
    let mut children = [("world", world), ("agent", agent)];
    let status = wait_all(&mut children, RUN_TIMEOUT);
    let wall = t.elapsed();
    let logs = format!(
        "world:\n{}{}\nagent:\n{}{}",
        read(&dir.join("world.out")),
        read(&dir.join("world.err")),
        read(&dir.join("agent.out")),
        read(&dir.join("agent.err"))
    );
    assert!(status[0].success(), "{label}: world {}\n{logs}", status[0]);
    assert!(status[1].success(), "{label}: agent {}\n{logs}", status[1]);
    let summary: Value =
        serde_json::from_str(&read(&out.join("summary.json"))).expect("summary.json");
    let run = Run {
        summary,
        final_pose: final_pose(&out.join("trajectories.csv")),
        agent_log: read(&dir.join("agent.err")),
        wall,
    };
    let a = run.agent();
    let applied = a["commands_applied"].as_u64().unwrap();
    let ticks = (duration / 0.05).round() as u64;
    assert!(
        applied >= vehicles * (ticks - 2),
        "{label}: {applied} commands applied\n{logs}"
    );
    let rejected: u64 = a["rejections"]
        .as_object()
        .unwrap()
        .values()
        .map(|v| v.as_u64().unwrap())
        .sum();
    assert_eq!(rejected, 0, "{label}: rejections {}", a["rejections"]);
    assert!(
        a["round_trip"]["count"].as_u64().unwrap() > 0,
        "{label}: no round trip measured"
    );
    println!(
        "{label}: digest {}, {applied} commands applied, round trip {}, {:.2} s wall; agent: {}",
        run.digest(),
        a["round_trip"],
        wall.as_secs_f64(),
        run.agent_log.trim().replace('\n', " | ")
    );
    let _ = std::fs::remove_dir_all(&dir);
    run
}

#[test]
fn python_agent_drives_the_school_in_lockstep() {
    let t = Instant::now();
    let python = shared_venv();
    println!("venv ready in {:.1} s", t.elapsed().as_secs_f64());
    let school_py = || {
        let mut c = Command::new(&python);
        c.arg(repo().join("python/examples/school.py"))
            .env("PYTHONDONTWRITEBYTECODE", "1");
        c
    };
    let school = |label: &str, agent: Command| {
        run_world(
            "agents_school",
            SCHOOL_S,
            SCHOOL_VEHICLES,
            label,
            agent,
            &[],
        )
    };
    let py1 = school("py1", school_py());
    let py2 = school("py2", school_py());
    // The agent's log says how many ticks it answered: 200 and 199 mean that one run's agent
    // saw the first tick and the other's did not — the world did not wait for the reply on
    // the tick it noticed the agent (it only attaches it then), so the stateful school agent
    // (its beacon schedule starts at its first tick) diverges. That is the world's
    // reproducibility, not Python's: the Rust agent shows the same.
    assert_eq!(
        py1.digest(),
        py2.digest(),
        "two lock-step runs with the Python agent differ\nrun 1: {}\nrun 2: {}",
        py1.agent_log,
        py2.agent_log
    );

    // The Rust example agent must give the very same run: the Python agent decodes the
    // float32 beacons exactly, sums in the same order and uses the same libm functions, so
    // its commands are bit-identical.
    let rs = school("rust", Command::new(rust_school_agent()));
    assert_eq!(
        py1.digest(),
        rs.digest(),
        "the Python and Rust school agents give different runs\nPython: {}\nRust: {}",
        py1.agent_log,
        rs.agent_log
    );
    println!(
        "Python round trip {} vs Rust {}; walls {:.2} s, {:.2} s, {:.2} s",
        py1.agent()["round_trip"],
        rs.agent()["round_trip"],
        py1.wall.as_secs_f64(),
        py2.wall.as_secs_f64(),
        rs.wall.as_secs_f64()
    );
}

#[test]
fn python_agent_drives_a_vehicle_to_depth_and_heading_reproducibly() {
    let python = shared_venv();
    let goto_py = || {
        let mut c = Command::new(&python);
        c.arg(repo().join("python/examples/goto.py"))
            .env("PYTHONDONTWRITEBYTECODE", "1");
        c
    };
    let target = ["pilot", "1.5", "90"];
    let goto =
        |label: &str, agent: Command| run_world("agents_goto", 60.0, 1, label, agent, &target);
    let a = goto("goto-py1", goto_py());
    let b = goto("goto-py2", goto_py());
    // From 0.5 m and heading 0 the auto mode reaches the target well within 60 s (heading
    // time constant ≈ 6 s): within 5 cm and 1°.
    let (z, yaw) = a.final_pose;
    assert!((z - 1.5).abs() < 0.05, "depth {z}");
    assert!(
        (yaw - 90f64.to_radians()).abs() < 1f64.to_radians(),
        "heading {yaw}"
    );
    assert_eq!(a.agent()["events"][0]["what"], "attached");
    assert_eq!(a.digest(), b.digest(), "two lock-step Python runs differ");
    assert_eq!(a.final_pose, b.final_pose);
    // The Rust goto agent sends the same commands: the same run, bit for bit.
    let rs = goto(
        "goto-rust",
        Command::new(common::example_agent("goto_agent")),
    );
    assert_eq!(
        a.digest(),
        rs.digest(),
        "Python and Rust goto agents differ"
    );
}

#[test]
fn bench_measures_the_round_trip_to_a_python_agent() {
    let python = shared_venv();
    common::check_agent_bench("python", &["--python".as_ref(), python.as_os_str()]);
}

#[test]
fn python_agent_interrupted_with_ctrl_c_says_goodbye() {
    let python = shared_venv();
    let dir = tmp("ctrl-c");
    let prefix = format!("pytest-{}-ctrl-c", std::process::id());
    // Free-running at 10× real time: 60 s simulated take 6 s.
    let world = dir.join("world.toml");
    std::fs::write(
        &world,
        "name = \"ctrl-c\"\nduration = 60.0\n[pool]\nsize = [10.0, 10.0, 3.0]\n\
         [agents]\ntiming = \"free\"\npace = 10.0\nattach_timeout = 60.0\nfallback = \"hold\"\n\
         [[vehicles]]\nname = \"auv\"\nposition = [5.0, 5.0, 0.5]\nagent = \"pilot\"\n",
    )
    .unwrap();
    let out = dir.join("out");
    let log = |name: &str| std::fs::File::create(dir.join(name)).unwrap();
    let world_proc = Command::new(env!("CARGO_BIN_EXE_shoal"))
        .args(["run", "--quiet", "--no-plots", "--prefix", &prefix, "--out"])
        .arg(&out)
        .arg(&world)
        .stdout(log("world.out"))
        .stderr(log("world.err"))
        .spawn()
        .unwrap();
    let agent_err = dir.join("agent.err");
    let agent = Command::new(&python)
        .arg(repo().join("python/examples/goto.py"))
        .args([&prefix, "pilot", "1.5", "90", "--log"])
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .stdout(log("agent.out"))
        .stderr(log("agent.err"))
        .spawn()
        .unwrap();
    // Once it has driven a while (its log says what it observed at 10 s simulated), Ctrl-C.
    common::wait_attached(&agent_err);
    let driven = common::wait_logged(&agent_err, 10.0);
    let interrupted = Command::new("kill")
        .args(["-INT", &agent.id().to_string()])
        .status()
        .unwrap();
    assert!(interrupted.success());
    let mut children = [("world", world_proc), ("agent", agent)];
    let status = wait_all(&mut children, RUN_TIMEOUT);
    let logs = format!(
        "world: {}\nagent: {}",
        read(&dir.join("world.err")),
        read(&dir.join("agent.err"))
    );
    assert!(status[0].success(), "{logs}");
    assert_eq!(status[1].code(), Some(130), "{logs}");
    let s: Value = serde_json::from_str(&read(&out.join("summary.json"))).unwrap();
    let a = &s["agents"]["agents"][0];
    let events: Vec<&str> = a["events"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["what"].as_str().unwrap())
        .collect();
    // A goodbye the world acknowledged: `left`, not `gone`.
    assert_eq!(events, ["attached", "left"], "{logs}");
    let t_left = a["events"][1]["t"].as_f64().unwrap();
    assert!(t_left >= driven.t && t_left < 60.0, "left at {t_left} s");
    assert!(!a["attached_at_end"].as_bool().unwrap());
    // From then on its vehicle held (fallback) to the end; before, only the ticks until its
    // first command (a few: the world paces 5 ms of wall time per tick).
    let fallback = a["fallback_ticks"].as_u64().unwrap() as f64;
    let expected = (60.0 - t_left) / 0.05;
    assert!(
        fallback >= expected - 1.0 && fallback <= expected + 10.0,
        "{fallback} fallback ticks, ≈ {expected} expected"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
