//! `shoal bench`'s scaling rows, each measured in a fresh child process (so that each row's
//! peak resident memory is its own), optionally side by side with another shoal binary
//! (`--compare OTHER`): for every vehicle count and thread count the two binaries run one
//! after the other, so both see the same machine load, and the table prints their ratio.
//!
//! A child is `EXE bench --vehicles N --threads T --seconds S --json [--no-comm]` with
//! [`CHILD_ENV`] set, which every shoal binary since the first `bench` understands (older ones
//! measure in their own process anyway; newer ones see the variable and never start children
//! of their own); its JSON rows are read back from its standard output and its peak resident
//! memory from the kernel (`wait4`'s `ru_maxrss`) unless it reports it.

use anyhow::Context;
use serde::Serialize;
use shoal_sim::phases::{ByPhase, Phase};
use std::io::Read;
use std::path::PathBuf;
use std::process::{Command, Stdio};

/// One row of the scaling table.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// Which binary measured it: `this` or `other`.
    pub binary: &'static str,
    /// Vehicles in the world.
    pub vehicles: usize,
    /// Working threads.
    pub threads: usize,
    /// Whether every vehicle beacons through four modems (the traffic table).
    pub traffic: bool,
    /// Vehicle-steps per wall-clock second \[1/s\].
    pub vehicle_steps_per_s: f64,
    /// Simulated seconds per wall-clock second.
    pub realtime_factor: f64,
    /// Share of the step spent on the optical medium, 1 − rate / rate of the same swarm
    /// without traffic (traffic rows only).
    pub medium_share: Option<f64>,
    /// Peak resident memory of the measuring process \[bytes\].
    pub peak_rss_bytes: Option<u64>,
    /// CPU cycles per vehicle-step on the threads used: clock × threads / rate (when the clock
    /// frequency is known).
    pub cycles_per_vehicle_step: Option<f64>,
    /// Memory allocated per vehicle while building the world \[bytes\] (when reported).
    pub bytes_per_vehicle: Option<f64>,
    /// Loops split over the thread pool during the measured steps (when reported; zero on
    /// one thread and below [`shoal_sim::parallel::MIN_PARALLEL`] vehicles).
    pub parallel_dispatches: Option<u64>,
    /// Share of the step's wall time in each phase, in the order of
    /// [`Phase::ALL`] (when reported); in JSON an object keyed by phase
    /// name.
    pub phase_shares: Option<ByPhase>,
    /// Reception attempts per step (frames ended × candidate receivers; when reported).
    pub attempts_per_step: Option<f64>,
    /// Wall time of the delivery phase per reception attempt \[ns\] (when reported).
    pub delivery_ns_per_attempt: Option<f64>,
}

/// What the machine is, for the table's head and the JSON file.
#[derive(Clone, Debug, Serialize)]
pub struct Machine {
    /// CPU model (`/proc/cpuinfo`).
    pub cpu: String,
    /// Cores available to this process.
    pub cores: usize,
    /// Clock frequency the kernel reports \[Hz\].
    pub clock_hz: Option<f64>,
}

impl Machine {
    /// This machine.
    pub fn here() -> Self {
        let info = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
        let field = |name: &str| {
            info.lines()
                .filter_map(|l| l.split_once(':'))
                .find(|(k, _)| k.trim() == name)
                .map(|(_, v)| v.trim().to_string())
        };
        Self {
            cpu: field("model name").unwrap_or_else(|| "unknown CPU".into()),
            cores: shoal_sim::parallel::all_cores(),
            clock_hz: field("cpu MHz")
                .and_then(|v| v.parse::<f64>().ok())
                .map(|mhz| mhz * 1e6),
        }
    }
}

/// Set (to 1) in the environment of a row's child process: it measures in its own process
/// and starts no children.
pub const CHILD_ENV: &str = "SHOAL_BENCH_CHILD";

/// A shoal binary that measures rows.
pub struct Bench {
    exe: PathBuf,
    binary: &'static str,
}

impl Bench {
    /// The binary `exe`, labelled `binary` (`this` or `other`) in the rows.
    pub fn new(exe: PathBuf, binary: &'static str) -> anyhow::Result<Self> {
        anyhow::ensure!(
            exe.is_file(),
            "--compare {}: no such file (give the path of another `shoal` binary)",
            exe.display()
        );
        Ok(Self { exe, binary })
    }

    /// The rows of `vehicles` on `threads`: the quiet row, and with `traffic` the traffic row
    /// (a second child, so each row's peak memory is its own).
    pub fn rows(
        &self,
        vehicles: usize,
        threads: usize,
        seconds: f64,
        traffic: bool,
        machine: &Machine,
    ) -> anyhow::Result<Vec<Row>> {
        let mut rows = self.child(vehicles, threads, seconds, false, machine)?;
        if traffic {
            rows.extend(
                self.child(vehicles, threads, seconds, true, machine)?
                    .into_iter()
                    .filter(|r| r.traffic),
            );
        }
        Ok(rows)
    }

    fn child(
        &self,
        vehicles: usize,
        threads: usize,
        seconds: f64,
        traffic: bool,
        machine: &Machine,
    ) -> anyhow::Result<Vec<Row>> {
        let mut cmd = Command::new(&self.exe);
        cmd.args(["bench", "--vehicles", &vehicles.to_string()])
            .args(["--threads", &threads.to_string()])
            .args(["--seconds", &seconds.to_string(), "--json"]);
        if !traffic {
            cmd.arg("--no-comm");
        }
        cmd.env(CHILD_ENV, "1");
        let what = format!(
            "{} bench ({vehicles} vehicles, {threads} threads)",
            self.exe.display()
        );
        let mut child = cmd
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .with_context(|| format!("cannot start {what}"))?;
        let mut out = String::new();
        child
            .stdout
            .take()
            .context("no pipe")?
            .read_to_string(&mut out)
            .with_context(|| format!("cannot read {what}"))?;
        let (ok, max_rss) = wait_with_rusage(child.id())?;
        anyhow::ensure!(ok, "{what} failed");
        let at = out
            .find("\n[")
            .map(|i| i + 1)
            .or_else(|| out.starts_with('[').then_some(0))
            .with_context(|| format!("{what} printed no JSON rows"))?;
        let cells: Vec<serde_json::Value> = serde_json::from_str(out[at..].trim())
            .with_context(|| format!("{what}: its JSON rows do not parse"))?;
        Ok(cells
            .iter()
            .map(|c| {
                let f = |k: &str| c.get(k).and_then(serde_json::Value::as_f64);
                let rate = f("vehicle_steps_per_s").unwrap_or(0.0);
                let threads = c["threads"].as_u64().unwrap_or(threads as u64) as usize;
                Row {
                    binary: self.binary,
                    vehicles: c["vehicles"].as_u64().unwrap_or(vehicles as u64) as usize,
                    threads,
                    traffic: c["table"] == "traffic",
                    vehicle_steps_per_s: rate,
                    realtime_factor: f("real_time_factor")
                        .or(f("realtime_factor"))
                        .unwrap_or(0.0),
                    medium_share: f("medium_share"),
                    peak_rss_bytes: c
                        .get("peak_rss_bytes")
                        .and_then(serde_json::Value::as_u64)
                        .or(max_rss),
                    cycles_per_vehicle_step: machine
                        .clock_hz
                        .filter(|_| rate > 0.0)
                        .map(|hz| hz * threads as f64 / rate),
                    bytes_per_vehicle: f("bytes_per_vehicle"),
                    parallel_dispatches: c
                        .get("parallel_dispatches")
                        .and_then(serde_json::Value::as_u64),
                    phase_shares: phase_shares(c),
                    attempts_per_step: f("attempts_per_step"),
                    delivery_ns_per_attempt: f("delivery_ns_per_attempt"),
                }
            })
            .collect())
    }
}

/// The phase shares of a child's row (`phase_shares`: an object keyed by phase name), when it
/// reports every phase.
fn phase_shares(row: &serde_json::Value) -> Option<ByPhase> {
    let shares = row.get("phase_shares")?;
    let mut out = [0.0; 6];
    for (o, p) in out.iter_mut().zip(Phase::ALL) {
        *o = shares.get(p.name())?.as_f64()?;
    }
    Some(ByPhase(out))
}

/// Waits for the child `pid`: whether it exited with 0, and its peak resident memory
/// \[bytes\].
#[expect(
    unsafe_code,
    reason = "wait4 is the one call that returns one child's peak memory; std has no wrapper"
)]
fn wait_with_rusage(pid: u32) -> anyhow::Result<(bool, Option<u64>)> {
    let mut status = 0;
    // SAFETY: an all-zero rusage is a valid value of this plain C struct.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let pid = libc::pid_t::try_from(pid).context("process id out of range")?;
    // SAFETY: `status` and `usage` are valid for writes; `pid` is our own child, not yet
    // waited for (std's `Child` is never waited on after this).
    let r = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
    anyhow::ensure!(r == pid, "cannot wait for the bench child {pid}");
    let ok = libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0;
    // ru_maxrss is in KiB on Linux.
    let rss = u64::try_from(usage.ru_maxrss).ok().map(|k| k * 1024);
    Ok((ok, rss))
}
