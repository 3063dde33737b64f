//! `shoal bench`: the scaling table. Every figure comes from one process in one run, so the
//! ratios between rows (thread speed-up, cost of the optical medium, memory per vehicle) are
//! comparable even on a noisy machine; absolute numbers are not.
//!
//! `shoal bench --agents rust,python`: the lock-step round trip per control period with 1, 100
//! and 1,000 vehicles in one external agent process (the goto example agents), measured by
//! the world's end of the bridge.

use crate::bench_agent::{AgentCell, AgentProcess, Exchange, checkout, python, time_exchange};
use crate::bench_measure::measure;
use crate::bench_rows::{Bench, Machine, Row};
use anyhow::Context;
use shoal_bridge::host::Host;
use shoal_sim::bench::{SPACING, TRAFFIC_SPACING, swarm_spaced};
use shoal_sim::phases::{ByPhase, Phase};
use shoal_sim::prelude::*;
use std::path::{Path, PathBuf};
use std::process::Stdio;
use std::time::Duration;

/// 1, 2, 4, … below `cores`, then `cores`: the scaling from one thread to every core.
fn default_threads(cores: usize) -> Vec<usize> {
    let mut t: Vec<usize> = std::iter::successors(Some(1usize), |&k| Some(k * 2))
        .take_while(|&k| k < cores)
        .collect();
    t.push(cores.max(1));
    t
}

/// Arguments of `shoal bench`.
#[derive(clap::Args, Debug)]
pub struct BenchArgs {
    /// Vehicle counts [default: 1,10,100,1000,10000; with --agents 1,100,1000].
    #[arg(long, value_delimiter = ',')]
    pub vehicles: Option<Vec<usize>>,
    /// Thread counts [default: 1, 2, 4, … up to every core of this machine, and that
    /// count].
    #[arg(long, value_delimiter = ',')]
    pub threads: Option<Vec<usize>>,
    /// Least wall time measured per cell [s].
    #[arg(long, default_value_t = 1.0)]
    pub seconds: f64,
    /// Skip the second table (optical traffic).
    #[arg(long)]
    pub no_comm: bool,
    /// Write the rows as JSON to FILE (`-` or no FILE: print them after the table). Per row:
    /// vehicles, threads, traffic, vehicle_steps_per_s, realtime_factor, medium_share,
    /// peak_rss_bytes, cycles_per_vehicle_step (when the CPU clock is known), phase_shares
    /// (ingest, vehicles, medium_snapshot, medium_transmit, medium_delivery, recorder: shares
    /// of the step's wall time), attempts_per_step and delivery_ns_per_attempt (reception
    /// attempts per step, the delivery phase's wall time per attempt; rows with traffic).
    #[arg(long, value_name = "FILE", num_args = 0..=1, default_missing_value = "-")]
    pub json: Option<PathBuf>,
    /// Medium-access protocols to measure the traffic table with, each a world file's
    /// `access` value (`aloha`, `carrier_sense`, `slotted_aloha`, `tdma`, `csma_ca`,
    /// `p_persistent`); every row then also gives its step's cost against unslotted ALOHA's,
    /// measured in the same run.
    #[arg(long, value_delimiter = ',')]
    pub access: Option<Vec<String>>,
    /// Measure every row of this binary and of OTHER (another `shoal` binary, e.g. an older
    /// build) one after the other, and print their ratio.
    #[arg(long, value_name = "OTHER")]
    pub compare: Option<PathBuf>,

    /// Instead of the scaling tables: the lock-step round trip to an external agent process
    /// written in these languages (`rust`: the goto_agent example; `python`:
    /// python/examples/goto.py).
    #[arg(long, value_delimiter = ',', value_parser = ["rust", "python", "ros2"])]
    pub agents: Vec<String>,
    /// The Rust agent executable [default: examples/goto_agent next to this binary].
    #[arg(long, value_name = "PATH")]
    pub rust_agent: Option<PathBuf>,
    /// The Python interpreter with the `shoal` package installed [default: .venv/bin/python
    /// of the checkout (made by scripts/python-env.sh) if it exists, else python3].
    #[arg(long, value_name = "PATH")]
    pub python: Option<PathBuf>,
}

/// Runs the tables.
pub fn bench(a: &BenchArgs) -> anyhow::Result<()> {
    anyhow::ensure!(
        a.seconds > 0.0 && a.seconds.is_finite(),
        "--seconds must be > 0"
    );
    anyhow::ensure!(
        a.vehicles
            .iter()
            .flatten()
            .all(|n| (1..=1_000_000).contains(n)),
        "--vehicles: each 1 … 1000000"
    );
    anyhow::ensure!(
        a.threads.iter().flatten().all(|t| (1..=256).contains(t)),
        "--threads: each 1 … 256"
    );
    if cfg!(debug_assertions) {
        eprintln!(
            "warning: this is a debug build; benchmark a release build (cargo run --release -- bench)"
        );
    }
    if !a.agents.is_empty() {
        return agents(a);
    }
    let vehicles = a
        .vehicles
        .clone()
        .unwrap_or_else(|| vec![1, 10, 100, 1000, 10000]);
    let threads = a
        .threads
        .clone()
        .unwrap_or_else(|| default_threads(shoal_sim::parallel::all_cores()));
    if let Some(access) = &a.access {
        let mut json = Vec::new();
        crate::bench_access::access_table((&vehicles, &threads), access, a.seconds, &mut json)?;
        if let Some(path) = &a.json {
            write_json(path, &serde_json::to_string_pretty(&json)?)?;
        }
        return Ok(());
    }
    // A row's child (the variable is set) measures here; anyone else measures each row in a
    // child process of its own.
    if std::env::var_os(crate::bench_rows::CHILD_ENV).is_none() {
        return scaling(a, &vehicles, &threads);
    }
    let mut json = Vec::new();
    println!(
        "shoal bench — μAUV² swarm on a 0.6 m grid in auto mode, dt = 0.01 s, RK4, recording off"
    );
    println!(
        "{:>8} {:>7} {:>7} {:>9} {:>16} {:>12} {:>9} {:>14}",
        "vehicles",
        "threads",
        "steps",
        "wall s",
        "vehicle-steps/s",
        "real-time ×",
        "speed-up",
        "bytes/vehicle"
    );
    for &n in &vehicles {
        let desc = swarm_spaced(n, 1, SPACING, false);
        let mut base: Option<f64> = None;
        for &t in &threads {
            let c = measure(&desc, t, a.seconds, 20);
            let speedup = base.map_or(1.0, |b| c.vehicle_steps_per_s / b);
            base.get_or_insert(c.vehicle_steps_per_s);
            println!(
                "{:>8} {:>7} {:>7} {:>9.3} {:>16.0} {:>12.2} {:>9.2} {:>14.0}",
                n,
                t,
                c.steps,
                c.wall_s,
                c.vehicle_steps_per_s,
                c.real_time,
                speedup,
                c.bytes_per_vehicle
            );
            json.push(serde_json::json!({
                "table": "quiet", "vehicles": n, "threads": t, "steps": c.steps, "wall_s": c.wall_s,
                "vehicle_steps_per_s": c.vehicle_steps_per_s, "real_time_factor": c.real_time,
                "speed_up": speedup, "bytes_per_vehicle": c.bytes_per_vehicle,
                "parallel_dispatches": c.parallel_dispatches,
                "phase_shares": ByPhase(c.phase_shares),
                "attempts_per_step": c.attempts.map(|a| a.0),
                "delivery_ns_per_attempt": c.attempts.map(|a| a.1),
                "peak_rss_bytes": shoal_record::output::peak_memory_bytes()
            }));
        }
    }
    if !a.no_comm {
        println!(
            "\nwith optical traffic — a {TRAFFIC_SPACING} m grid, every vehicle with 4 modems beaconing a 32-byte frame once a second;\nmedium share = 1 − rate with traffic / rate of the same swarm without"
        );
        println!(
            "{:>8} {:>7} {:>7} {:>9} {:>16} {:>12} {:>10} {:>12} {:>14}",
            "vehicles",
            "threads",
            "steps",
            "wall s",
            "vehicle-steps/s",
            "real-time ×",
            "frames/s",
            "delivered/s",
            "medium share"
        );
        for &n in &vehicles {
            let desc = swarm_spaced(n, 1, TRAFFIC_SPACING, true);
            let silent = swarm_spaced(n, 1, TRAFFIC_SPACING, false);
            for &t in &threads {
                // 1.5 s of warm-up: every beacon has started.
                let c = measure(&desc, t, a.seconds, 150);
                let q = measure(&silent, t, a.seconds, 150).vehicle_steps_per_s;
                // Share of a step's time spent on the medium: 1 − (rate with traffic / quiet rate).
                let share = 1.0 - c.vehicle_steps_per_s / q;
                println!(
                    "{:>8} {:>7} {:>7} {:>9.3} {:>16.0} {:>12.2} {:>10.0} {:>12.0} {:>13.0}%",
                    n,
                    t,
                    c.steps,
                    c.wall_s,
                    c.vehicle_steps_per_s,
                    c.real_time,
                    c.frames_per_s,
                    c.deliveries_per_s,
                    100.0 * share
                );
                json.push(serde_json::json!({
                    "table": "traffic", "vehicles": n, "threads": t, "steps": c.steps, "wall_s": c.wall_s,
                    "vehicle_steps_per_s": c.vehicle_steps_per_s, "real_time_factor": c.real_time,
                    "frames_per_s": c.frames_per_s, "deliveries_per_s": c.deliveries_per_s, "medium_share": share,
                    "bytes_per_vehicle": c.bytes_per_vehicle, "parallel_dispatches": c.parallel_dispatches,
                    "phase_shares": ByPhase(c.phase_shares),
                    "attempts_per_step": c.attempts.map(|a| a.0),
                    "delivery_ns_per_attempt": c.attempts.map(|a| a.1),
                    "peak_rss_bytes": shoal_record::output::peak_memory_bytes()
                }));
            }
        }
    }
    if let Some(path) = &a.json {
        write_json(path, &serde_json::to_string_pretty(&json)?)?;
    }
    Ok(())
}

/// The second table: the share of each phase of the step in this binary's rows.
fn print_phases(rows: &[Row]) {
    let mine: Vec<(&Row, &[f64; 6])> = rows
        .iter()
        .filter(|r| r.binary == "this")
        .filter_map(|r| r.phase_shares.as_ref().map(|s| (r, &s.0)))
        .collect();
    if mine.is_empty() {
        return;
    }
    println!(
        "\nwhere the time goes — share of the step's wall time per phase (medium: snapshot, transmit, delivery)"
    );
    let mut head = format!("{:>8} {:>7} {:>7}", "vehicles", "threads", "traffic");
    for p in Phase::ALL {
        head += &format!(" {:>9}", p.name().trim_start_matches("medium_"));
    }
    head += &format!(" {:>13} {:>11}", "attempts/step", "ns/attempt");
    println!("{head}");
    for (r, shares) in mine {
        let mut line = format!(
            "{:>8} {:>7} {:>7}",
            r.vehicles,
            r.threads,
            if r.traffic { "yes" } else { "no" }
        );
        for s in shares {
            line += &format!(" {:>8.1}%", 100.0 * s);
        }
        match (r.attempts_per_step, r.delivery_ns_per_attempt) {
            (Some(a), Some(ns)) => line += &format!(" {a:>13.0} {ns:>11.0}"),
            _ => line += &format!(" {:>13} {:>11}", "—", "—"),
        }
        println!("{line}");
    }
}

/// Prints `text` (`-`) or writes it whole to `path`.
fn write_json(path: &Path, text: &str) -> anyhow::Result<()> {
    if path == Path::new("-") {
        println!("{text}");
        return Ok(());
    }
    shoal_output::files::write_whole(path, format!("{text}\n").as_bytes())?;
    eprintln!("shoal bench: wrote {}", path.display());
    Ok(())
}

/// The scaling table, each row measured in a child process of this binary (and of
/// `--compare OTHER` right after it).
fn scaling(a: &BenchArgs, vehicles: &[usize], threads: &[usize]) -> anyhow::Result<()> {
    let machine = Machine::here();
    let this = Bench::new(
        std::env::current_exe().context("cannot locate this binary")?,
        "this",
    )?;
    let other = a
        .compare
        .clone()
        .map(|p| Bench::new(p, "other"))
        .transpose()?;
    let clock = machine
        .clock_hz
        .map_or_else(String::new, |hz| format!(", {:.2} GHz", hz / 1e9));
    println!(
        "shoal bench — {}, {} cores{clock}; μAUV² swarms in auto mode, dt = 0.01 s, RK4, recording off",
        machine.cpu, machine.cores
    );
    println!(
        "quiet: a {SPACING} m grid; traffic: a {TRAFFIC_SPACING} m grid, every vehicle with 4 modems beaconing a 32-byte frame once a second;\nmedium = 1 − rate with traffic / rate of the same swarm without; each row in its own process"
    );
    let mut head = format!(
        "{:>8} {:>7} {:>7} {:>16} {:>12} {:>9} {:>8} {:>12} {:>14}",
        "vehicles",
        "threads",
        "traffic",
        "vehicle-steps/s",
        "real-time ×",
        "speed-up",
        "medium",
        "peak RSS MB",
        "cycles/v-step"
    );
    if other.is_some() {
        head += &format!(" {:>16} {:>12}", "other v-steps/s", "this/other");
    }
    println!("{head}");
    let mut rows: Vec<Row> = Vec::new();
    for &n in vehicles {
        for &t in threads {
            let mine = this.rows(n, t, a.seconds, !a.no_comm, &machine)?;
            let theirs = match &other {
                Some(o) => o.rows(n, t, a.seconds, !a.no_comm, &machine)?,
                None => Vec::new(),
            };
            for r in &mine {
                let first = rows
                    .iter()
                    .find(|b| b.binary == "this" && b.vehicles == n && b.traffic == r.traffic)
                    .map_or(r.vehicle_steps_per_s, |b| b.vehicle_steps_per_s);
                let mut line = format!(
                    "{:>8} {:>7} {:>7} {:>16.0} {:>12.2} {:>9.2} {:>8} {:>12} {:>14}",
                    r.vehicles,
                    r.threads,
                    if r.traffic { "yes" } else { "no" },
                    r.vehicle_steps_per_s,
                    r.realtime_factor,
                    r.vehicle_steps_per_s / first,
                    r.medium_share
                        .map_or_else(|| "—".into(), |m| format!("{:.0}%", 100.0 * m)),
                    r.peak_rss_bytes
                        .map_or_else(|| "—".into(), |b| format!("{:.0}", b as f64 / 1e6)),
                    r.cycles_per_vehicle_step
                        .map_or_else(|| "—".into(), |c| format!("{c:.0}")),
                );
                if other.is_some() {
                    match theirs.iter().find(|o| o.traffic == r.traffic) {
                        Some(o) => {
                            line += &format!(
                                " {:>16.0} {:>12.2}",
                                o.vehicle_steps_per_s,
                                r.vehicle_steps_per_s / o.vehicle_steps_per_s
                            );
                        }
                        None => line += &format!(" {:>16} {:>12}", "—", "—"),
                    }
                }
                println!("{line}");
            }
            rows.extend(mine);
            rows.extend(theirs);
        }
    }
    print_phases(&rows);
    if let Some(path) = &a.json {
        let doc = serde_json::json!({
            "machine": machine,
            "seconds_per_cell": a.seconds,
            "this": std::env::current_exe().ok(),
            "other": a.compare,
            "rows": rows,
        });
        write_json(path, &serde_json::to_string_pretty(&doc)?)?;
    }
    Ok(())
}

/// The command line of the goto agent in `lang`, without its arguments.
fn agent_command(a: &BenchArgs, lang: &str) -> anyhow::Result<std::process::Command> {
    if lang == "rust" {
        let exe = match &a.rust_agent {
            Some(p) => p.clone(),
            None => std::env::current_exe()
                .context("cannot locate this binary")?
                .parent()
                .context("cannot locate this binary's directory")?
                .join("examples")
                .join(format!("goto_agent{}", std::env::consts::EXE_SUFFIX)),
        };
        anyhow::ensure!(
            exe.is_file(),
            "the Rust agent {} does not exist: build it with `cargo build --release -p shoal-bridge --example goto_agent` or pass --rust-agent PATH",
            exe.display()
        );
        return Ok(std::process::Command::new(exe));
    }
    let repo = checkout().context(
        "cannot find the checkout's python/ directory (run from inside the shoal repository)",
    )?;
    let mut c = std::process::Command::new(python(a.python.as_deref(), &repo));
    c.arg(repo.join("python/examples/goto.py"))
        .env("PYTHONDONTWRITEBYTECODE", "1");
    Ok(c)
}

fn measure_agent(a: &BenchArgs, lang: &str, n: usize) -> anyhow::Result<AgentCell> {
    let prefix = format!("bench-{}-{lang}-{n}", std::process::id());
    let desc = shoal_sim::bench::agent_swarm(n, &prefix).map_err(anyhow::Error::msg)?;
    let mut host = Host::open(&desc.agents, &[n])?;
    let mut sim = Sim::new(
        &desc,
        SimOptions {
            threads: 1,
            record: false,
        },
    );
    let mut child = AgentProcess(
        agent_command(a, lang)?
            .args([prefix.as_str(), "pilot", "1.3", "45"])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .with_context(|| format!("cannot start the {lang} agent"))?,
    );
    let missing = host.wait_for_agents(Duration::from_secs(30), &mut |_| {
        matches!(child.0.try_wait(), Ok(None))
    });
    if !missing.is_empty() {
        child.wait(Duration::from_millis(500));
        anyhow::bail!(
            "the {lang} agent did not attach: {}{}",
            child.stderr(),
            if lang == "python" {
                "\n(the interpreter needs the shoal package with iceoryx2 0.10: scripts/python-env.sh makes .venv)"
            } else {
                ""
            }
        );
    }
    let (wall, sim_s) = time_exchange(a.seconds, &mut sim, &mut host)?;
    let rt = host.round_trips();
    let report = host.finish(&mut sim, Duration::from_secs(2));
    drop(host);
    let status = child.wait(Duration::from_secs(5));
    let hiccups: Vec<String> = report[0]
        .events
        .iter()
        .filter(|e| e.what != "attached")
        .map(|e| format!("{} at t = {:.2} s", e.what, e.t))
        .collect();
    anyhow::ensure!(
        hiccups.is_empty(),
        "the {lang} agent with {n} vehicles: {}",
        hiccups.join(", ")
    );
    anyhow::ensure!(
        status.is_some_and(|s| s.success()),
        "the {lang} agent did not end cleanly ({status:?}): {}",
        child.stderr()
    );
    Ok(AgentCell {
        ticks: rt.count,
        round_trip: rt,
        real_time: sim_s / wall,
    })
}

/// The agent round-trip table.
fn agents(a: &BenchArgs) -> anyhow::Result<()> {
    let ros2_only = a.agents.iter().all(|l| l == "ros2");
    let vehicles = a.vehicles.clone().unwrap_or_else(|| {
        if ros2_only {
            vec![1, 10, 100]
        } else {
            vec![1, 100, 1000]
        }
    });
    println!(
        "shoal bench --agents — lock-step round trip per control period (0.05 s) to one agent process\n\
         driving every vehicle (iceoryx2: the goto example; ros2: python/bench/ros2_hold.py on Cyclone\n\
         DDS, the same orders); publish observations → all commands back, wall time;\n\
         world on 1 thread, 20 ticks of warm-up not counted"
    );
    println!(
        "{:>8} {:>8} {:>7} {:>11} {:>11} {:>11} {:>13} {:>12}",
        "agent", "vehicles", "ticks", "median µs", "p99 µs", "max µs", "µs/vehicle", "real-time ×"
    );
    let mut json = Vec::new();
    for lang in &a.agents {
        for &n in &vehicles {
            let c = if lang == "ros2" {
                crate::bench_ros2::measure(a.python.as_deref(), a.seconds, n)?
            } else {
                measure_agent(a, lang, n)?
            };
            let r = c.round_trip;
            println!(
                "{:>8} {:>8} {:>7} {:>11.1} {:>11.1} {:>11.1} {:>13.3} {:>12.1}",
                lang,
                n,
                c.ticks,
                r.median_us,
                r.p99_us,
                r.max_us,
                r.median_us / n as f64,
                c.real_time
            );
            json.push(serde_json::json!({
                "table": "agents", "agent": lang, "vehicles": n, "ticks": c.ticks,
                "median_us": r.median_us, "p99_us": r.p99_us, "max_us": r.max_us,
                "median_us_per_vehicle": r.median_us / n as f64, "real_time_factor": c.real_time
            }));
        }
    }
    if let Some(path) = &a.json {
        write_json(path, &serde_json::to_string_pretty(&json)?)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::default_threads;

    #[test]
    fn the_default_threads_run_from_one_to_every_core() {
        assert_eq!(default_threads(1), [1]);
        assert_eq!(default_threads(2), [1, 2]);
        assert_eq!(default_threads(6), [1, 2, 4, 6]);
        assert_eq!(default_threads(8), [1, 2, 4, 8]);
    }
}
