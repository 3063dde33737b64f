//! Helpers shared by the agent tests: the repository root, the example agents of
//! shoal-bridge (built with cargo like the binary under test), and polling for what a running
//! process has logged — that it attached, how far its world has run — instead of sleeping a
//! fixed time and assuming it.

#![allow(dead_code)]

#[path = "../../../shoal-record/tests/support/cargo_example.rs"]
mod cargo_example;

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
    cargo_example::build_example(&repo(), bin_dir, name)
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

/// Checks that the CSV table `path` is whole: it ends with a newline and every row has as
/// many fields as the header. Returns the number of rows (without the header).
pub fn whole_csv_rows(path: &Path) -> usize {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(
        text.ends_with('\n'),
        "{} does not end with a newline",
        path.display()
    );
    let mut r = csv::ReaderBuilder::new()
        .flexible(true)
        .from_reader(text.as_bytes());
    let width = r.headers().unwrap().len();
    assert!(width > 1, "{}: header of {width} field(s)", path.display());
    let mut rows = 0;
    for (i, rec) in r.records().enumerate() {
        let rec = rec.unwrap();
        assert_eq!(
            rec.len(),
            width,
            "{}: row {} has {} fields, the header {width}",
            path.display(),
            i + 1,
            rec.len()
        );
        rows += 1;
    }
    rows
}

/// The names of the files in `dir` that end with `suffix`.
pub fn files_ending(dir: &Path, suffix: &str) -> Vec<String> {
    std::fs::read_dir(dir)
        .map(|d| {
            d.filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| n.ends_with(suffix))
                .collect()
        })
        .unwrap_or_default()
}

/// Starts `shoal run ARGS… --out OUT WORLD` with stdout and stderr piped. With `shell`
/// (e.g. `trap '' HUP;`), `sh` runs that first and then becomes shoal (`exec`).
pub fn start_run(args: &[&str], out: &Path, world: &Path, shell: Option<&str>) -> Child {
    run_command(args, out, world, shell).spawn().unwrap()
}

/// The command of [`start_run`], to add to (an environment variable) before it is spawned.
pub fn run_command(args: &[&str], out: &Path, world: &Path, shell: Option<&str>) -> Command {
    let mut c = match shell {
        None => Command::new(env!("CARGO_BIN_EXE_shoal")),
        Some(pre) => {
            let mut c = Command::new("sh");
            c.args(["-c", &format!("{pre} exec \"$@\""), "sh"])
                .arg(env!("CARGO_BIN_EXE_shoal"));
            c
        }
    };
    c.arg("run")
        .args(args)
        .arg("--out")
        .arg(out)
        .arg(world)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped());
    c
}

/// Polls (bounded by [`POLL_LIMIT`], a hang guard) until `path` holds more than `bytes`
/// bytes; fails when `child` ends first.
pub fn wait_for_size(path: &Path, bytes: u64, child: &mut Child) {
    let start = Instant::now();
    while !path.metadata().is_ok_and(|m| m.len() > bytes) {
        assert!(
            child.try_wait().unwrap().is_none(),
            "shoal ended before writing {}",
            path.display()
        );
        assert!(
            start.elapsed() < POLL_LIMIT,
            "{} did not grow past {bytes} bytes",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Sends `signal` (a name such as `TERM`) to `child` with `kill`.
pub fn kill(child: &Child, signal: &str) {
    let status = Command::new("kill")
        .args([format!("-{signal}"), child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success(), "kill -{signal}");
}

/// A child's standard error, read line by line on a thread of its own, so a test can wait
/// for a line (a progress marker) while the child goes on.
pub struct StderrLines {
    rx: std::sync::mpsc::Receiver<String>,
    reader: std::thread::JoinHandle<()>,
    seen: Vec<String>,
}

impl StderrLines {
    /// Takes `child`'s piped standard error.
    pub fn take(child: &mut Child) -> Self {
        use std::io::BufRead;
        let (tx, rx) = std::sync::mpsc::channel();
        let stderr = std::io::BufReader::new(child.stderr.take().expect("piped stderr"));
        let reader = std::thread::spawn(move || {
            for line in stderr.lines().map_while(Result::ok) {
                let _ = tx.send(line);
            }
        });
        Self {
            rx,
            reader,
            seen: Vec::new(),
        }
    }

    /// Waits (at most `limit`, a hang guard) for a line that contains `marker`; kills
    /// `child` and fails the test when none comes.
    pub fn wait_for(&mut self, marker: &str, limit: Duration, child: &mut Child) {
        let start = Instant::now();
        loop {
            match self.rx.recv_timeout(limit.saturating_sub(start.elapsed())) {
                Ok(line) => {
                    let found = line.contains(marker);
                    self.seen.push(line);
                    if found {
                        return;
                    }
                }
                Err(e) => {
                    let _ = child.kill();
                    panic!(
                        "no `{marker}` line on stderr ({e}); it said:\n{}",
                        self.seen.join("\n")
                    );
                }
            }
        }
    }

    /// Every line, once the child has closed its standard error (it has ended).
    pub fn finish(mut self) -> String {
        self.reader.join().unwrap();
        self.seen.extend(self.rx.try_iter());
        self.seen.join("\n")
    }
}

/// The CSV table `path`: its header, and its rows as column → text.
pub fn read_table(path: &Path) -> (Vec<String>, Vec<std::collections::BTreeMap<String, String>>) {
    let mut r = csv::Reader::from_path(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let header: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    let rows = r
        .records()
        .map(|rec| {
            let rec = rec.unwrap();
            header
                .iter()
                .cloned()
                .zip(rec.iter().map(String::from))
                .collect()
        })
        .collect();
    (header, rows)
}

/// The files a summary.json lists.
pub fn summary_files(summary: &serde_json::Value) -> Vec<PathBuf> {
    summary["files"]
        .as_array()
        .expect("`files` in the summary")
        .iter()
        .map(|f| PathBuf::from(f.as_str().expect("a file name")))
        .collect()
}

/// Calls `ready` every 10 ms until it gives a value. `limit` is a hang guard, not a timing
/// assertion: only a process that never gets there takes that long, and the test then fails
/// with `what`.
pub fn poll<T>(limit: Duration, what: &str, mut ready: impl FnMut() -> Option<T>) -> T {
    let start = Instant::now();
    loop {
        if let Some(v) = ready() {
            return v;
        }
        assert!(start.elapsed() < limit, "{what}: not within {limit:?}");
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// What a running process has written to its log file so far (empty before it exists).
pub fn read_log(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_default()
}

/// A log file for a child's stderr (or stdout).
pub fn log_file(path: &Path) -> std::process::Stdio {
    std::fs::File::create(path)
        .unwrap_or_else(|e| panic!("cannot create {}: {e}", path.display()))
        .into()
}

/// Hang guard of the polls below.
pub const POLL_LIMIT: Duration = Duration::from_secs(60);

/// Waits until the agent logging to `log` says it attached (the Rust and Python example
/// agents print `…: attached to `PREFIX` as `NAME``).
pub fn wait_attached(log: &Path) {
    poll(
        POLL_LIMIT,
        &format!("attach logged in {}", log.display()),
        || read_log(log).contains("attached").then_some(()),
    )
}

/// One line of a goto agent's `--log` output: what its first vehicle observed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Logged {
    /// Simulated time of the observation [s].
    pub t: f64,
    /// Depth reading [m].
    pub depth: f64,
    /// Heading [°].
    pub yaw_deg: f64,
    /// The world held the vehicle under its fallback.
    pub fallback: bool,
}

/// Every complete line of a goto agent's `--log` output
/// (`goto_agent: t = 12.00 s, depth 1.234 m, yaw 45.0°[ (fallback)]`, the same from goto.py;
/// a line still being written is left out).
pub fn logged(log: &str) -> Vec<Logged> {
    log.split_inclusive('\n')
        .filter_map(|l| {
            let l = l.strip_suffix('\n')?;
            let rest = l.split_once(": t = ")?.1;
            let (t, rest) = rest.split_once(" s, depth ")?;
            let (depth, rest) = rest.split_once(" m, yaw ")?;
            let (yaw, rest) = rest.split_once('°')?;
            Some(Logged {
                t: t.parse().ok()?,
                depth: depth.parse().ok()?,
                yaw_deg: yaw.parse().ok()?,
                fallback: rest.contains("(fallback)"),
            })
        })
        .collect()
}

/// Waits until the goto agent logging to `log` (with `--log`) has observed simulated time
/// `t` or later; returns that line.
pub fn wait_logged(log: &Path, t: f64) -> Logged {
    poll(
        POLL_LIMIT,
        &format!("simulated t = {t} s logged in {}", log.display()),
        || logged(&read_log(log)).into_iter().find(|l| l.t >= t),
    )
}

/// A line the goto agent logging to `log` prints after this call began: the world has run at
/// least to its `t` since then, whatever the test did just before (a signal, a kill). (Two
/// simulated seconds past the last complete line, so that a line being written meanwhile
/// does not count.)
pub fn logged_from_now(log: &Path) -> Logged {
    let last = logged(&read_log(log))
        .last()
        .map_or(f64::NEG_INFINITY, |l| l.t);
    poll(
        POLL_LIMIT,
        &format!("a new line logged in {}", log.display()),
        || {
            logged(&read_log(log))
                .into_iter()
                .find(|l| l.t >= last + 1.5)
        },
    )
}

/// The shared-memory segments process `pid` has mapped (its iceoryx2 services' memory).
pub fn mapped_shm(pid: u32) -> std::collections::BTreeSet<PathBuf> {
    std::fs::read_to_string(format!("/proc/{pid}/maps"))
        .unwrap_or_default()
        .lines()
        .filter_map(|l| l.split_whitespace().nth(5))
        .filter(|p| p.starts_with("/dev/shm/"))
        .map(PathBuf::from)
        .collect()
}

/// iceoryx2's records (service and node files under /tmp/iceoryx2) that name `prefix`.
pub fn ipc_records(prefix: &str) -> Vec<PathBuf> {
    fn walk(dir: &Path, prefix: &str, found: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.filter_map(|e| e.ok()) {
            let p = e.path();
            if p.is_dir() {
                walk(&p, prefix, found);
            } else if std::fs::read(&p).is_ok_and(|b| String::from_utf8_lossy(&b).contains(prefix))
            {
                found.push(p);
            }
        }
    }
    let mut found = Vec::new();
    walk(Path::new("/tmp/iceoryx2"), prefix, &mut found);
    found
}
