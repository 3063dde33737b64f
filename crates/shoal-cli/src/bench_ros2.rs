//! The ROS 2 rows of `shoal bench --agents ros2`: the lock-step round trip per control period
//! of the same benchmark swarm as the iceoryx2 rows (`shoal_sim::bench::agent_swarm_text`),
//! its group on the ROS 2 bridge (`agent = "ros2"`, its own namespace and DDS domain), driven
//! by one Python process on Cyclone DDS (`python/bench/ros2_hold.py`: auto mode to 1.3 m and
//! 45°, as the iceoryx2 rows' `pilot 1.3 45`). Publish imu and pressure → every vehicle's
//! setpoint back, wall time, measured by the bridge.

use crate::bench_agent::{AgentCell, AgentProcess, Exchange, checkout, python, time_exchange};
use anyhow::Context;
use shoal_ros2::Ros2Host;
use shoal_sim::agents::Flow;
use shoal_sim::prelude::*;
use std::path::Path;
use std::process::Stdio;
use std::time::Duration;

impl Exchange for Ros2Host {
    fn exchange(&mut self, sim: &mut Sim) -> anyhow::Result<Flow> {
        Ok(self.before_step(sim)?)
    }
    fn round_trips(&mut self) -> shoal_sim::agents::RoundTrip {
        self.take_round_trips()
    }
}

/// One row: `n` vehicles on the ROS 2 bridge.
/// `python`: the interpreter (default: the checkout's venv), `seconds`: the least wall time
/// measured \[s\].
pub fn measure(python_exe: Option<&Path>, seconds: f64, n: usize) -> anyhow::Result<AgentCell> {
    let pid = std::process::id();
    let namespace = format!("bench_{pid}_{n}");
    // A domain of its own (1 … 200) so that other runs on the machine do not answer.
    let domain = 1 + (pid as usize * 7 + n) % 200;
    let text = shoal_sim::bench::agent_swarm_text(n, &namespace)
        .replace("agent = \"pilot\"", "agent = \"ros2\"")
        + &format!(
            "[ros2]\nnamespace = \"{namespace}\"\ndomain_id = {domain}\nlocalhost_only = true\n"
        );
    let desc = shoal_world::load::load_str(&text, Path::new("<ros2 bench swarm>"))
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
    let mut child = AgentProcess(
        std::process::Command::new(python(python_exe, &repo))
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
    // The first ticks wait for DDS discovery: in the warm-up, not measured.
    let (wall, sim_s) = time_exchange(seconds, &mut sim, &mut host)?;
    let rt = host.round_trips();
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
