//! The run's external agents, over both transports: iceoryx2 agents (`shoal-bridge`, one
//! agent index per name) and the ROS 2 bridge (`shoal-ros2`, the group named `ros2`, the last
//! agent index). Each exchange runs the iceoryx2 one first, then the ROS 2 one; each takes
//! only its own vehicles' observations, so neither sees the other's frames.

use crate::exit::Failure;
use anyhow::Context;
use shoal_bridge::host::Host;
use shoal_ros2::Ros2Host;
use shoal_sim::agents::{AgentHost, AgentReport, Flow};
use shoal_sim::sim::Sim;
use shoal_world::cancel::Cancel;
use shoal_world::desc::{AgentsDesc, WorldDesc};
use std::sync::Arc;
use std::time::Duration;

/// The hosts of a run's agents.
pub struct Agents {
    ipc: Option<Host>,
    ros2: Option<Ros2Host>,
    /// How to wait for the iceoryx2 agents to attach when the run starts.
    attach: Attach,
}

/// The wait for iceoryx2 agents to attach, and what it says.
struct Attach {
    wait: Duration,
    quiet: bool,
    cancel: Arc<Cancel>,
}

impl AgentHost for Agents {
    fn start(&mut self) -> Result<(), Box<dyn std::error::Error + Send + Sync>> {
        let Some(host) = self.ipc.as_mut() else {
            return Ok(());
        };
        let Attach {
            wait,
            quiet,
            ref cancel,
        } = self.attach;
        let mut shown = false;
        let missing = host.wait_for_agents(wait, &mut |missing| {
            if !quiet && !shown {
                eprintln!(
                    "shoal: waiting up to {:.0} s for {} to attach (Ctrl-C to stop; \
                     `--wait-agents SECONDS` waits longer — an agent built for the first time \
                     can take minutes to compile, so build it before starting the world)",
                    wait.as_secs_f64(),
                    missing.join(", ")
                );
                shown = true;
            }
            !cancel.is_requested()
        });
        if !missing.is_empty() && !quiet {
            eprintln!(
                "shoal: starting without {}: their vehicles hold depth and heading until they attach",
                missing.join(", ")
            );
        }
        Ok(())
    }

    /// The exchange before a physics step, on both transports.
    fn before_step(
        &mut self,
        sim: &mut Sim,
    ) -> Result<Flow, Box<dyn std::error::Error + Send + Sync>> {
        let mut flow = Flow::Continue;
        if let Some(h) = self.ipc.as_mut() {
            flow = h.before_step(sim).context("external agents (iceoryx2)")?;
            if flow != Flow::Continue {
                return Ok(flow);
            }
        }
        if let Some(h) = self.ros2.as_mut() {
            flow = h.before_step(sim).context("external agents (ROS 2)")?;
        }
        Ok(flow)
    }

    /// Ends both exchanges; the reports, iceoryx2 agents first.
    fn finish(&mut self, sim: &mut Sim, grace: Duration) -> Vec<AgentReport> {
        let mut reports = match self.ipc.as_mut() {
            Some(h) => h.finish(sim, grace),
            None => Vec::new(),
        };
        if let Some(h) = self.ros2.as_mut() {
            reports.push(h.finish(sim));
        }
        reports
    }
}

/// The iceoryx2 agents' part of the world's agent settings: every name but the ROS 2 bridge's
/// (which is the last index).
fn ipc_part(desc: &WorldDesc) -> AgentsDesc {
    let mut a = desc.agents.clone();
    if let Some(r) = &a.ros2 {
        a.names.truncate(r.agent);
    }
    a
}

/// Opens the world's agent services (when a vehicle group names an agent), printing where the
/// iceoryx2 agents attach; the run waits for them when it starts ([`AgentHost::start`]). The
/// ROS 2 bridge's nodes are waited for on the first control tick (lock-step) instead, as DDS
/// discovery takes its time.
pub fn open_agents(
    desc: &WorldDesc,
    quiet: bool,
    cancel: &Arc<Cancel>,
) -> Result<Option<Agents>, Failure> {
    if desc.agents.names.is_empty() {
        return Ok(None);
    }
    let ros2 = match &desc.agents.ros2 {
        None => None,
        Some(_) => {
            let mut h =
                Ros2Host::open(desc).map_err(|e| Failure::Input(format!("ROS 2 bridge: {e}")))?;
            h.stop_on(cancel.clone());
            if !quiet {
                h.announce_waits(|text| eprintln!("shoal: {text}"));
                eprintln!(
                    "shoal: ROS 2 nodes ({}) drive their vehicles on {}",
                    if desc.agents.lockstep {
                        "lock-step"
                    } else {
                        "free-running"
                    },
                    h.describe()
                );
            }
            Some(h)
        }
    };
    let cfg = ipc_part(desc);
    let attach = Attach {
        wait: Duration::from_secs_f64(cfg.attach_timeout),
        quiet,
        cancel: cancel.clone(),
    };
    if cfg.names.is_empty() {
        return Ok(Some(Agents {
            ipc: None,
            ros2,
            attach,
        }));
    }
    let counts: Vec<usize> = cfg
        .names
        .iter()
        .map(|n| {
            desc.vehicles
                .iter()
                .filter(|v| v.agent.as_deref() == Some(n))
                .count()
        })
        .collect();
    let mut host = Host::open(&cfg, &counts).map_err(|e| Failure::Input(e.to_string()))?;
    host.stop_on(cancel.clone());
    if !quiet {
        eprintln!(
            "shoal: agents ({}) attach with prefix `{}`: {}",
            if cfg.lockstep {
                "lock-step"
            } else {
                "free-running"
            },
            cfg.prefix,
            cfg.names
                .iter()
                .zip(&counts)
                .map(|(n, c)| format!("`{n}` ({})", shoal_output::words::count(*c, "vehicle")))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    Ok(Some(Agents {
        ipc: Some(host),
        ros2,
        attach,
    }))
}
