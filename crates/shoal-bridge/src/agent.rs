//! The agent side: attach to a running world as agent `name`, receive each control tick's
//! observations of its vehicles, answer with one command per vehicle.
//!
//! ```no_run
//! use shoal_bridge::agent::{Agent, AgentLink};
//! use shoal_bridge::protocol::{Command, Observation, mode};
//!
//! /// Every vehicle dives to 1.5 m and turns north-east.
//! struct Dive;
//! impl Agent for Dive {
//!     fn tick(&mut self, obs: &Observation, cmd: &mut Command) {
//!         cmd.set_mode(mode::AUTO, 1.5, 0.785, 0.0, 0.0);
//!     }
//! }
//!
//! let mut link = AgentLink::attach("my-world", "divers", std::time::Duration::from_secs(30))?;
//! link.run(&mut Dive)?;
//! # Ok::<(), shoal_bridge::BridgeError>(())
//! ```
//!
//! Frames: [`Command::send`] broadcasts; [`Command::send_to`] addresses one vehicle, with
//! or without acknowledgement. A received [`Frame`](crate::protocol::Frame) names its sender
//! (`peer`) and whether it was for this vehicle alone
//! ([`is_unicast`](crate::protocol::Frame::is_unicast)); what became of each acknowledged
//! frame comes back with its tag in a later [`Observation::outcomes`]:
//!
//! ```no_run
//! # use shoal_bridge::agent::Agent;
//! # use shoal_bridge::protocol::{ALL_MODEMS, Command, Observation};
//! /// Vehicle 0 asks vehicle 1 for a confirmation once; vehicle 1 notes who wrote to it.
//! struct Ping;
//! impl Agent for Ping {
//!     fn tick(&mut self, obs: &Observation, cmd: &mut Command) {
//!         for f in obs.received().iter().filter(|f| f.is_unicast()) {
//!             eprintln!("{} got {:?} from {}", obs.vehicle, f.payload(), f.peer);
//!         }
//!         for o in obs.outcomes() {
//!             let (tag, ok, n) = (o.tag, o.is_acknowledged(), o.transmissions);
//!             eprintln!("frame {tag}: acknowledged {ok} after {n} transmissions");
//!         }
//!         if obs.vehicle == 0 && obs.step == 100 {
//!             cmd.send_to(1, ALL_MODEMS, b"ping", 0.0, true, 7);
//!         }
//!     }
//! }
//! ```

use crate::protocol::{Command, Observation, flags};
use crate::{BridgeError, IpcOp, ipc, service_name};
use iceoryx2::node::NodeWaitFailure;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;
use std::time::{Duration, Instant};

type Ipc = ipc::Service;

/// A swarm behaviour run by [`AgentLink::run`]: called once per vehicle and tick.
pub trait Agent {
    /// Fill `cmd` (pre-set to "keep", for `obs.vehicle` and `obs.step`) from `obs`.
    fn tick(&mut self, obs: &Observation, cmd: &mut Command);
}

/// What ended [`AgentLink::run`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ended {
    /// The world said the run is over.
    WorldEnded,
    /// No observation arrived for the idle timeout (the world died or stalled).
    Silent,
}

/// An attached agent.
pub struct AgentLink {
    node: Node<Ipc>,
    obs: Subscriber<Ipc, [Observation], ()>,
    cmd: Publisher<Ipc, [Command], ()>,
    /// Longest wait for the next observation before [`Ended::Silent`].
    pub idle_timeout: Duration,
    /// Ticks answered.
    pub ticks: u64,
    /// The world ended the run (no goodbye needed).
    ended: bool,
    /// Last look for a termination request.
    signal_checked: Instant,
}

/// Longest wait for the world to acknowledge a LEAVE.
const LEAVE_ACK: Duration = Duration::from_millis(500);
/// Longest time between two looks for Ctrl-C / SIGTERM while ticks keep coming.
const SIGNAL_CHECK: Duration = Duration::from_millis(10);

impl Drop for AgentLink {
    /// Detaches: unless the world ended the run, says LEAVE and waits (at most 0.5 s) for the
    /// world's acknowledgement, so the world records `left` rather than `gone`.
    fn drop(&mut self) {
        if self.ended || self.send(&[Command::leave()]).is_err() {
            return;
        }
        let start = Instant::now();
        while start.elapsed() < LEAVE_ACK {
            // (Without looking for signals: after Ctrl-C the goodbye still completes.)
            match self.poll(LEAVE_ACK.saturating_sub(start.elapsed()), false) {
                Ok(Some(_)) if self.ended => return,
                Ok(Some(_)) => {}
                _ => return,
            }
        }
    }
}

/// Sleeps `d` on `node`, looking for Ctrl-C and SIGTERM (iceoryx2 catches them): they end
/// the wait with [`BridgeError::Interrupted`]. A sleep cut short by any other signal — the
/// SIGCONT that resumes a process stopped with SIGSTOP or Ctrl-Z, which Linux lets interrupt
/// the sleep without a handler — is not a termination request: it only ends the nap early.
fn nap(node: &Node<Ipc>, d: Duration) -> Result<(), BridgeError> {
    match node.wait(d) {
        Ok(()) => Ok(()),
        // Was it Ctrl-C? Then the handler has recorded it, and this look reports it.
        Err(NodeWaitFailure::Interrupt) => node
            .wait(Duration::ZERO)
            .map_err(|_| BridgeError::Interrupted),
        Err(NodeWaitFailure::TerminationRequest) => Err(BridgeError::Interrupted),
    }
}

impl AgentLink {
    /// Attaches as `agent` to the world with `prefix`, waiting up to `wait` for the world to
    /// appear.
    pub fn attach(prefix: &str, agent: &str, wait: Duration) -> Result<AgentLink, BridgeError> {
        let config = Config::default();
        let node = NodeBuilder::new()
            .name(&NodeName::new(&format!("shoal-agent.{agent}")).map_err(ipc(IpcOp::NodeName))?)
            .config(&config)
            .create::<Ipc>()
            .map_err(ipc(IpcOp::Node))?;
        // The first look for a termination request installs iceoryx2's Ctrl-C / SIGTERM
        // handler (it is installed lazily): from here on they end the wait cleanly.
        nap(&node, Duration::ZERO)?;
        let start = Instant::now();
        let (obs_svc, cmd_svc) = loop {
            let o = node
                .service_builder(
                    &ServiceName::new(&service_name(prefix, agent, "obs"))
                        .map_err(ipc(IpcOp::ServiceName))?,
                )
                .publish_subscribe::<[Observation]>()
                .open();
            let c = node
                .service_builder(
                    &ServiceName::new(&service_name(prefix, agent, "cmd"))
                        .map_err(ipc(IpcOp::ServiceName))?,
                )
                .publish_subscribe::<[Command]>()
                .open();
            match (o, c) {
                (Ok(o), Ok(c)) => break (o, c),
                _ if start.elapsed() < wait => {
                    // Sleeps, and notices Ctrl-C / SIGTERM (iceoryx2 catches them).
                    nap(&node, Duration::from_millis(20))?;
                }
                _ => {
                    return Err(BridgeError::NoWorld {
                        prefix: prefix.into(),
                        agent: agent.into(),
                        secs: wait.as_secs_f64(),
                    });
                }
            }
        };
        let cmd = cmd_svc
            .publisher_builder()
            .initial_max_slice_len(64)
            .allocation_strategy(AllocationStrategy::PowerOfTwo)
            .create()
            .map_err(|_| BridgeError::AgentTaken(agent.into()))?;
        let obs = obs_svc
            .subscriber_builder()
            .buffer_size(2)
            .create()
            .map_err(|_| BridgeError::AgentTaken(agent.into()))?;
        Ok(AgentLink {
            node,
            obs,
            cmd,
            idle_timeout: Duration::from_secs(10),
            ticks: 0,
            ended: false,
            signal_checked: Instant::now(),
        })
    }

    /// The next observation slice (busy-polls briefly, then naps), or `None` after
    /// `timeout`. The slice of the world's last tick has [`flags::END`] set. (Dropping the
    /// link detaches with a goodbye the world acknowledges.)
    ///
    /// Ctrl-C and SIGTERM are caught (by iceoryx2's node) and end the wait with
    /// [`BridgeError::Interrupted`]; they are looked for at least every 10 ms.
    pub fn receive(&mut self, timeout: Duration) -> Result<Option<Vec<Observation>>, BridgeError> {
        self.poll(timeout, true)
    }

    /// [`AgentLink::receive`], with or without looking for termination requests.
    fn poll(
        &mut self,
        timeout: Duration,
        signals: bool,
    ) -> Result<Option<Vec<Observation>>, BridgeError> {
        let start = Instant::now();
        if signals && self.signal_checked.elapsed() >= SIGNAL_CHECK {
            self.signal_checked = Instant::now();
            nap(&self.node, Duration::ZERO)?;
        }
        loop {
            // Take the newest slice if several are queued.
            let mut newest = None;
            while let Some(s) = self
                .obs
                .receive()
                .map_err(ipc(IpcOp::ReceiveObservations))?
            {
                newest = Some(s.payload().to_vec());
            }
            if let Some(obs) = &newest {
                self.ended |= obs.iter().any(|o| o.flags & flags::END != 0);
                return Ok(newest);
            }
            let waited = start.elapsed();
            if waited >= timeout {
                return Ok(None);
            }
            if waited < Duration::from_micros(50) {
                std::hint::spin_loop();
            } else if waited < Duration::from_millis(1) {
                std::thread::yield_now();
            } else if signals {
                nap(&self.node, Duration::from_micros(50))?;
            } else {
                std::thread::sleep(Duration::from_micros(50));
            }
        }
    }

    /// Sends one reply slice (at least one command; all for the same step).
    pub fn send(&mut self, cmds: &[Command]) -> Result<(), BridgeError> {
        if cmds.is_empty() {
            return Ok(());
        }
        let s = self
            .cmd
            .loan_slice_uninit(cmds.len())
            .map_err(ipc(IpcOp::Loan))?;
        s.write_from_fn(|i| cmds[i])
            .send()
            .map_err(ipc(IpcOp::SendCommands))?;
        Ok(())
    }

    /// Runs `agent` until the world ends the run or falls silent.
    pub fn run(&mut self, agent: &mut dyn Agent) -> Result<Ended, BridgeError> {
        let mut cmds = Vec::new();
        loop {
            let Some(obs) = self.receive(self.idle_timeout)? else {
                self.node.try_cleanup_dead_nodes();
                return Ok(Ended::Silent);
            };
            if obs.iter().any(|o| o.flags & flags::END != 0) {
                return Ok(Ended::WorldEnded);
            }
            cmds.clear();
            for o in &obs {
                let mut c = Command::keep(o);
                agent.tick(o, &mut c);
                cmds.push(c);
            }
            self.send(&cmds)?;
            self.ticks += 1;
        }
    }
}
