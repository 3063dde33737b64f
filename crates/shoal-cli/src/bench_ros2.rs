//! The ROS 2 rows of `shoal bench --agents ros2`: the lock-step round trip per control period
//! of the same benchmark swarm as the iceoryx2 rows (`shoal_sim::bench::agent_swarm_text`),
//! its group on the ROS 2 bridge (`agent = "ros2"`, its own namespace and DDS domain), driven
//! by one Python process on Cyclone DDS (`python/bench/ros2_hold.py`: auto mode to 1.3 m and
//! 45°, as the iceoryx2 rows' `pilot 1.3 45`). Publish imu and pressure → every vehicle's
//! setpoint back, wall time, measured by the bridge.

use crate::bench::{AgentCell, AgentProcess, BenchArgs, checkout};
use anyhow::Context;
use shoal_ros2::Ros2Host;
use shoal_sim::agents::Flow;
use shoal_sim::prelude::*;
use std::path::PathBuf;
use std::process::Stdio;
use std::time::{Duration, Instant};

/// One row: `n` vehicles on the ROS 2 bridge.
pub fn measure(a: &BenchArgs, n: usize) -> anyhow::Result<AgentCell> {
    let pid = std::process::id();
    let namespace = format!("bench_{pid}_{n}");
    // A domain of its own (1 … 200) so that other runs on the machine do not answer.
    let domain = 1 + (pid as usize * 7 + n) % 200;
    let text = shoal_sim::bench::agent_swarm_text(n, &namespace)
        .replace("agent = \"pilot\"", "agent = \"ros2\"")
        + &format!(
            "[ros2]\nnamespace = \"{namespace}\"\ndomain_id = {domain}\nlocalhost_only = true\n"
        );
    let desc = shoal_world::load::load_str(&text, std::path::Path::new("<ros2 bench swarm>"))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let mut host = Ros2Host::open(&desc)?;
    let mut sim = Sim::new(
        &desc,
        SimOptions {
            threads: 1,
            record: false,
        },
    );
    let repo = checkout().context("cannot find the checkout's python/ directory")?;
    let python = a.python.clone().unwrap_or_else(|| {
        let venv = repo.join(".venv/bin/python");
        if venv.is_file() {
            venv
        } else {
            PathBuf::from("python3")
        }
    });
    let mut child = AgentProcess(
        std::process::Command::new(python)
            .arg(repo.join("python/bench/ros2_hold.py"))
            .args([namespace.clone(), domain.to_string()])
            .args(host.vehicle_names())
            .env("PYTHONDONTWRITEBYTECODE", "1")
            // DDS stays on this machine on both sides.
            .env("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .context("cannot start the ROS 2 agent (python/bench/ros2_hold.py)")?,
    );
    let step = |sim: &mut Sim, host: &mut Ros2Host| -> anyhow::Result<()> {
        match host.before_step(sim)? {
            Flow::Continue => {
                sim.step();
                Ok(())
            }
            Flow::Stop(why) => anyhow::bail!("{why}"),
            Flow::Interrupted => anyhow::bail!("interrupted"),
        }
    };
    // Warm-up: 20 control ticks (1 s simulated; the first waits for discovery), not measured.
    for _ in 0..100 {
        step(&mut sim, &mut host)?;
    }
    host.take_round_trips();
    let start = Instant::now();
    let t0 = sim.time();
    loop {
        for _ in 0..5 {
            step(&mut sim, &mut host)?;
        }
        if start.elapsed().as_secs_f64() >= a.seconds && sim.time() - t0 >= 1.0 {
            break;
        }
    }
    let wall = start.elapsed().as_secs_f64();
    let sim_s = sim.time() - t0;
    let rt = host.take_round_trips();
    let report = host.finish(&mut sim);
    drop(host);
    let status = child.wait(Duration::from_secs(15));
    let hiccups: Vec<String> = report
        .events
        .iter()
        .filter(|e| e.what != "attached")
        .map(|e| format!("{} at t = {:.2} s", e.what, e.t))
        .collect();
    anyhow::ensure!(
        hiccups.is_empty() && rt.count > 0,
        "the ROS 2 agent with {n} vehicles: {} ({} ticks measured): {}",
        hiccups.join(", "),
        rt.count,
        child.stderr()
    );
    anyhow::ensure!(
        status.is_some_and(|s| s.success()),
        "the ROS 2 agent did not end cleanly ({status:?}): {}",
        child.stderr()
    );
    Ok(AgentCell {
        ticks: rt.count,
        round_trip: rt,
        real_time: sim_s / wall,
    })
}
