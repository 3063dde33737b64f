//! The world side of the bridge: one pair of services per agent (`…/obs`, `…/cmd`, created
//! by the world with one publisher each, so a second world with the same prefix or a second
//! process with the same agent name is refused), and the exchange on every control tick.
//!
//! **Lock-step**: the world publishes the observations and waits for each attached agent's
//! reply to this very step (busy-polling for the first 50 µs, then yielding, then sleeping in
//! 50 µs naps), at most `timeout` of wall time. Replies are applied in agent order, so the
//! run is reproducible. **Free-running**: the world publishes and applies whatever replies
//! have arrived (the last command per vehicle stays in force), never waiting.
//!
//! **Faults**: an agent that misses the timeout is *hung*: its vehicles fall back and the
//! world stops waiting for it; any reply to a step since it hung re-attaches it (its vehicles
//! leave the fallback with its next command). While waiting, and every 64 steps otherwise,
//! dead nodes are cleaned up (`try_cleanup_dead_nodes`), so a killed agent's ports vanish
//! and it counts as *gone*. An agent that closes properly says so first
//! ([`protocol::kind::LEAVE`], acknowledged with [`flags::END`]) and counts as *left*. A new
//! process may then attach under the same name (*reattached*). Every command is validated
//! (see [`shoal_sim::agents`]); protocol errors are counted as malformed. The first 1,000
//! events per agent are kept for the summary, later ones counted.
//!
//! **Shutdown**: the last observation carries [`flags::END`]; the world waits up to 1 s for
//! its agents to leave before removing its services, so no shared memory is left behind.

pub use crate::convert::{decode, encode};
use crate::protocol::{self, Command, Observation, flags};
use crate::{BridgeError, IpcOp, ipc, service_name};
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;
use iceoryx2::service::port_factory::PortFactory as _;
use iceoryx2::service::port_factory::publish_subscribe::PortFactory;
pub use shoal_sim::agents::Flow;
use shoal_sim::agents::{self, AgentReport, RoundTrip};
use shoal_sim::sim::Sim;
use shoal_world::cancel::Cancel;
use shoal_world::desc::AgentsDesc;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Largest number of vehicles one agent's slice is prepared for; more are allocated on demand.
const INITIAL_SLICE: usize = 1024;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum State {
    Absent,
    Attached,
    Hung,
}

type Ipc = ipc::Service;

struct Port {
    obs_svc: PortFactory<Ipc, [Observation], ()>,
    cmd_svc: PortFactory<Ipc, [Command], ()>,
    obs_pub: Publisher<Ipc, [Observation], ()>,
    cmd_sub: Subscriber<Ipc, [Command], ()>,
    state: State,
    report: AgentReport,
    rtt: Vec<f64>,
    /// Step of the tick on which it was declared hung.
    hung_step: u64,
    /// It said LEAVE and has not closed its ports yet (it is not re-attached meanwhile).
    leaving: bool,
}

impl Port {
    /// Whether an agent process holds both ends.
    fn connected(&self) -> bool {
        self.obs_svc.dynamic_config().number_of_subscribers() > 0
            && self.cmd_svc.dynamic_config().number_of_publishers() > 0
    }

    fn event(&mut self, t: f64, step: u64, what: &'static str, detail: String) {
        self.report.event(t, step, what, detail);
    }

    /// The agent said LEAVE: record it, put its vehicles under the fallback and acknowledge
    /// with an [`flags::END`] slice (it waits for that before closing its ports).
    fn leave(
        &mut self,
        sim: &mut Sim,
        a: usize,
        cfg: &AgentsDesc,
        t: f64,
        step: u64,
        flow: Flow,
    ) -> Flow {
        self.state = State::Absent;
        self.leaving = true;
        self.event(t, step, "left", "the agent detached".into());
        sim.set_fallback(a, cfg.fallback);
        let _ = publish(&self.obs_pub, &[end_marker(step, t)], flags::END);
        lost(cfg, &self.report.name, "left", flow)
    }
}

/// An observation slice element that only carries [`flags::END`] (no vehicle).
fn end_marker(step: u64, t: f64) -> agents::Observation {
    agents::Observation {
        id: u32::MAX,
        step,
        t,
        sensors: shoal_model::control::SensorReadings::zeros(0),
        position: None,
        frames: Vec::new(),
        outcomes: Vec::new(),
        fallback: true,
    }
}

/// The world's end of the bridge.
pub struct Host {
    node: Node<Ipc>,
    ports: Vec<Port>,
    cfg: AgentsDesc,
    wall0: Option<Instant>,
    cancel: Option<Arc<Cancel>>,
}

impl Host {
    /// Creates the services of every agent named in `cfg` (`vehicles[i]`: how many vehicles
    /// agent `i` drives).
    pub fn open(cfg: &AgentsDesc, vehicles: &[usize]) -> Result<Host, BridgeError> {
        let config = Config::default();
        let node = NodeBuilder::new()
            .name(
                &NodeName::new(&format!("shoal-world.{}", cfg.prefix))
                    .map_err(ipc(IpcOp::NodeName))?,
            )
            .config(&config)
            // The program owns its signals (the `shoal` binary has its own Ctrl-C handler).
            .signal_handling_mode(SignalHandlingMode::Disabled)
            .create::<Ipc>()
            .map_err(ipc(IpcOp::Node))?;
        let mut ports = Vec::new();
        for (i, name) in cfg.names.iter().enumerate() {
            let svc = |leaf: &str| {
                ServiceName::new(&service_name(&cfg.prefix, name, leaf))
                    .map_err(ipc(IpcOp::ServiceName))
            };
            let in_use = |e: &dyn std::fmt::Debug| {
                if format!("{e:?}").contains("AlreadyExists") {
                    BridgeError::PrefixInUse(cfg.prefix.clone())
                } else {
                    BridgeError::Ipc {
                        op: IpcOp::Services,
                        detail: format!("agent `{name}`: {e:?}"),
                    }
                }
            };
            let obs_svc = node
                .service_builder(&svc("obs")?)
                .publish_subscribe::<[Observation]>()
                .max_publishers(1)
                .max_subscribers(2)
                .subscriber_max_buffer_size(2)
                .history_size(0)
                .enable_safe_overflow(true)
                .create()
                .map_err(|e| in_use(&e))?;
            let cmd_svc = node
                .service_builder(&svc("cmd")?)
                .publish_subscribe::<[Command]>()
                .max_publishers(1)
                .max_subscribers(1)
                .subscriber_max_buffer_size(4)
                .history_size(0)
                .enable_safe_overflow(true)
                .create()
                .map_err(|e| in_use(&e))?;
            let obs_pub = obs_svc
                .publisher_builder()
                .initial_max_slice_len(
                    vehicles
                        .get(i)
                        .copied()
                        .unwrap_or(1)
                        .clamp(1, INITIAL_SLICE),
                )
                .allocation_strategy(AllocationStrategy::PowerOfTwo)
                .create()
                .map_err(ipc(IpcOp::ObservationPublisher))?;
            let cmd_sub = cmd_svc
                .subscriber_builder()
                .buffer_size(4)
                .create()
                .map_err(ipc(IpcOp::CommandSubscriber))?;
            ports.push(Port {
                obs_svc,
                cmd_svc,
                obs_pub,
                cmd_sub,
                state: State::Absent,
                report: AgentReport::new(name, vehicles.get(i).copied().unwrap_or(0)),
                rtt: Vec::new(),
                hung_step: 0,
                leaving: false,
            });
        }
        Ok(Host {
            node,
            ports,
            cfg: cfg.clone(),
            wall0: None,
            cancel: None,
        })
    }

    /// Makes the exchange give up its waits (lock-step replies, free-running pace) within
    /// about 10 ms once `cancel` asks for a stop; [`Host::before_step`] then says
    /// [`Flow::Interrupted`]. The services are removed when the host is dropped, as always.
    pub fn stop_on(&mut self, cancel: Arc<Cancel>) {
        self.cancel = Some(cancel);
    }

    /// Service names agents attach to, one line per agent.
    pub fn services(&self) -> Vec<String> {
        self.cfg
            .names
            .iter()
            .map(|n| service_name(&self.cfg.prefix, n, "{obs,cmd}"))
            .collect()
    }

    /// Waits up to `timeout` (wall time) until every agent is attached; `tick` is called about
    /// every 100 ms with the names still missing and stops the wait by returning `false`.
    /// Returns the names still missing.
    pub fn wait_for_agents(
        &mut self,
        timeout: Duration,
        tick: &mut dyn FnMut(&[String]) -> bool,
    ) -> Vec<String> {
        let start = Instant::now();
        let mut last = Instant::now();
        loop {
            self.node.try_cleanup_dead_nodes();
            let missing: Vec<String> = self
                .ports
                .iter()
                .filter(|p| !p.connected())
                .map(|p| p.report.name.clone())
                .collect();
            if missing.is_empty() || start.elapsed() >= timeout {
                return missing;
            }
            if last.elapsed() >= Duration::from_millis(100) {
                if !tick(&missing) {
                    return missing;
                }
                last = Instant::now();
            }
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    /// The exchange before a physics step: on a control tick of agent-driven vehicles,
    /// publish observations, collect (lock-step: wait for) replies, validate and apply them,
    /// handle attach, detach, hang and death.
    pub fn before_step(&mut self, sim: &mut Sim) -> Result<Flow, BridgeError> {
        if self.ports.is_empty() || !sim.agent_tick_due() {
            return Ok(Flow::Continue);
        }
        let wall0 = *self.wall0.get_or_insert_with(Instant::now);
        let step = sim.step_count();
        let t = sim.time();
        let obs = sim.observe_agents(self.ports.len(), self.cfg.grant_position);
        let mut flow = Flow::Continue;
        let mut sent_at = vec![None; self.ports.len()];
        for (a, port) in self.ports.iter_mut().enumerate() {
            if !port.connected() {
                // Ports vanished without a LEAVE: the process was killed or crashed (its
                // dead node was cleaned up, by us or by another process).
                if port.state != State::Absent {
                    port.state = State::Absent;
                    port.event(
                        t,
                        step,
                        "gone",
                        "the agent's process vanished without detaching (killed or crashed)".into(),
                    );
                    sim.set_fallback(a, self.cfg.fallback);
                    flow = lost(&self.cfg, &port.report.name, "died", flow);
                }
                port.leaving = false;
            } else if port.state == State::Absent && !port.leaving {
                // An agent that attached since the last tick answers this very tick
                // (lock-step waits for it), so runs do not depend on how fast it was. Older
                // replies go.
                let again = port.report.events.iter().any(|e| e.what == "attached");
                port.state = State::Attached;
                port.event(
                    t,
                    step,
                    if again { "reattached" } else { "attached" },
                    String::new(),
                );
                let _ = drain(port);
            }
        }
        for (a, port) in self.ports.iter_mut().enumerate() {
            let fallback_ticks = obs[a].iter().filter(|o| o.fallback).count() as u64;
            port.report.fallback_ticks += fallback_ticks;
            publish(&port.obs_pub, &obs[a], 0).map_err(ipc(IpcOp::PublishObservations))?;
            sent_at[a] = Some(Instant::now());
        }
        if step.is_multiple_of(64) {
            // Nothing waits for an absent, hung or free-running agent: look for dead ones
            // now and then (a lock-step wait looks every 10 ms).
            self.node.try_cleanup_dead_nodes();
        }
        for (a, sent) in sent_at.into_iter().enumerate() {
            let Some(sent) = sent else { continue };
            let lockstep = self.cfg.lockstep;
            let timeout = Duration::from_secs_f64(self.cfg.timeout);
            let port = &mut self.ports[a];
            match port.state {
                State::Attached if lockstep => {
                    match wait_reply(
                        &self.node,
                        port,
                        step,
                        sent,
                        timeout,
                        self.cancel.as_deref(),
                    ) {
                        Reply::Interrupted => return Ok(Flow::Interrupted),
                        Reply::Got(cmds) => {
                            port.rtt.push(sent.elapsed().as_secs_f64() * 1e6);
                            apply(sim, a, port, &cmds);
                        }
                        Reply::Leave => {
                            flow = port.leave(sim, a, &self.cfg, t, step, flow);
                        }
                        Reply::Timeout => {
                            port.state = State::Hung;
                            port.hung_step = step;
                            port.event(
                                t,
                                step,
                                "hung",
                                format!("no reply within {} s", self.cfg.timeout),
                            );
                            sim.set_fallback(a, self.cfg.fallback);
                            flow = lost(&self.cfg, &port.report.name, "hung", flow);
                        }
                        Reply::Gone => {
                            port.state = State::Absent;
                            port.event(
                                t,
                                step,
                                "gone",
                                "the agent's process died (its dead node was cleaned up)".into(),
                            );
                            sim.set_fallback(a, self.cfg.fallback);
                            flow = lost(&self.cfg, &port.report.name, "died", flow);
                        }
                    }
                }
                State::Attached => {
                    // Free-running: whatever has arrived, in order; the last one wins.
                    for cmds in drain(port) {
                        if is_leave(&cmds) {
                            flow = port.leave(sim, a, &self.cfg, t, step, flow);
                            break;
                        }
                        apply(sim, a, port, &cmds);
                    }
                }
                State::Hung => {
                    // Back as soon as it answers any step since it hung (it woke up); its
                    // vehicles stay under the fallback until its next command.
                    let replies = drain(port);
                    if replies.iter().any(|c| is_leave(c)) {
                        flow = port.leave(sim, a, &self.cfg, t, step, flow);
                    } else if replies
                        .iter()
                        .any(|c| c.first().is_some_and(|c| c.step >= port.hung_step))
                    {
                        port.state = State::Attached;
                        port.event(t, step, "reattached", "answering again".into());
                    }
                }
                // (Attaching is handled before publishing, above.)
                State::Absent => {}
            }
        }
        if !self.cfg.lockstep && self.cfg.pace > 0.0 {
            // Sleep until the wall clock catches up, in naps short enough to answer a stop.
            loop {
                let ahead = t / self.cfg.pace - wall0.elapsed().as_secs_f64();
                if ahead <= 0.0 {
                    break;
                }
                if self.cancel.as_deref().is_some_and(Cancel::is_requested) {
                    return Ok(Flow::Interrupted);
                }
                std::thread::sleep(Duration::from_secs_f64(ahead.min(0.01)));
            }
        }
        Ok(flow)
    }

    /// Round-trip statistics of every agent since the start or the last call, clearing them
    /// (the report of [`Host::finish`] then covers only what came after): a benchmark takes
    /// them once after its warm-up and once at the end.
    pub fn take_round_trips(&mut self) -> Vec<RoundTrip> {
        self.ports
            .iter_mut()
            .map(|p| {
                let r = RoundTrip::of(&mut p.rtt);
                p.rtt.clear();
                r
            })
            .collect()
    }

    /// Ends the exchange: tells attached agents the run is over (observations with
    /// [`flags::END`]), waits up to `grace` for them to leave, and returns the reports. The
    /// services disappear when the host is dropped.
    pub fn finish(&mut self, sim: &mut Sim, grace: Duration) -> Vec<AgentReport> {
        let step = sim.step_count();
        let t = sim.time();
        let obs = sim.observe_agents(self.ports.len(), false);
        for (a, port) in self.ports.iter_mut().enumerate() {
            port.report.attached_at_end = port.state == State::Attached && port.connected();
            let mut end: Vec<agents::Observation> = obs[a].clone();
            if end.is_empty() {
                end.push(end_marker(step, t));
            }
            let _ = publish(&port.obs_pub, &end, flags::END);
        }
        let start = Instant::now();
        while start.elapsed() < grace
            && self
                .ports
                .iter()
                .any(|p| p.obs_svc.dynamic_config().number_of_subscribers() > 0)
        {
            self.node.try_cleanup_dead_nodes();
            std::thread::sleep(Duration::from_millis(2));
        }
        self.ports
            .iter_mut()
            .map(|p| {
                p.report.round_trip = RoundTrip::of(&mut p.rtt);
                p.report.clone()
            })
            .collect()
    }
}

fn lost(cfg: &AgentsDesc, name: &str, how: &str, flow: Flow) -> Flow {
    agents::lost_agent(cfg.fallback, name, how, flow)
}

enum Reply {
    Got(Vec<Command>),
    Leave,
    Timeout,
    Gone,
    Interrupted,
}

/// Whether a reply slice is the agent's goodbye ([`protocol::kind::LEAVE`]).
fn is_leave(cmds: &[Command]) -> bool {
    cmds.first()
        .is_some_and(|c| c.version == protocol::PROTOCOL_VERSION && c.kind == protocol::kind::LEAVE)
}

/// Waits for `port`'s reply to `step`.
fn wait_reply(
    node: &Node<Ipc>,
    port: &mut Port,
    step: u64,
    sent: Instant,
    timeout: Duration,
    cancel: Option<&Cancel>,
) -> Reply {
    let mut last_check = Instant::now();
    loop {
        loop {
            match port.cmd_sub.receive() {
                Ok(Some(s)) => {
                    port.report.replies += 1;
                    let cmds = s.payload();
                    if is_leave(cmds) {
                        return Reply::Leave;
                    }
                    if cmds.first().is_some_and(|c| c.step == step) {
                        return Reply::Got(cmds.to_vec());
                    }
                    port.report.late_replies += 1;
                }
                Ok(None) => break,
                Err(_) => {
                    port.report.rejections.malformed += 1;
                    break;
                }
            }
        }
        let waited = sent.elapsed();
        if waited >= timeout {
            return Reply::Timeout;
        }
        if last_check.elapsed() >= Duration::from_millis(10) {
            if cancel.is_some_and(Cancel::is_requested) {
                return Reply::Interrupted;
            }
            node.try_cleanup_dead_nodes();
            if !port.connected() {
                return Reply::Gone;
            }
            last_check = Instant::now();
        }
        if waited < Duration::from_micros(50) {
            std::hint::spin_loop();
        } else if waited < Duration::from_millis(1) {
            std::thread::yield_now();
        } else {
            std::thread::sleep(Duration::from_micros(50));
        }
    }
}

/// Every reply that has arrived, oldest first.
fn drain(port: &mut Port) -> Vec<Vec<Command>> {
    let mut out = Vec::new();
    loop {
        match port.cmd_sub.receive() {
            Ok(Some(s)) => {
                port.report.replies += 1;
                out.push(s.payload().to_vec());
            }
            Ok(None) => break,
            Err(_) => {
                port.report.rejections.malformed += 1;
                break;
            }
        }
    }
    out
}

/// Validates and applies one reply slice.
fn apply(sim: &mut Sim, agent: usize, port: &mut Port, cmds: &[Command]) {
    for c in cmds {
        let rej = &mut port.report.rejections;
        if let Some(cmd) = decode(c, rej)
            && sim.command_vehicle(agent, &cmd, rej)
        {
            port.report.commands_applied += 1;
        }
    }
}

/// Encodes observations (with extra `flags`) and sends them as one slice.
fn publish(
    p: &Publisher<Ipc, [Observation], ()>,
    obs: &[agents::Observation],
    extra: u32,
) -> Result<usize, String> {
    if obs.is_empty() {
        return Ok(0);
    }
    let sample = p
        .loan_slice_uninit(obs.len())
        .map_err(|e| format!("{e:?}"))?;
    let sample = sample.write_from_fn(|i| encode(&obs[i], extra));
    sample.send().map_err(|e| format!("{e:?}"))
}
