//! The world's end of the ROS 2 bridge: one DDS participant and node (`/shoal_world`), the
//! topics of every vehicle whose group says `agent = "ros2"`, and the exchange on each of
//! their control ticks.
//!
//! On a tick at simulated time T the world publishes, for each bridged vehicle, its IMU
//! readings and pressure (stamped T), its odometry when positions are granted, the frames it
//! received since its last tick (`modem/rx`) and what became of its acknowledged unicasts
//! that ended since then (`modem/outcome`), then `/tf` (granted) and `/clock` = T.
//!
//! * **Lock-step** (`[agents] timing = "lockstep"`): the world then waits, at most
//!   `[agents] timeout` of wall time (`attach_timeout` until the first command ever arrives:
//!   the nodes may still be discovering the world), for every vehicle's `setpoint` or
//!   `actuators` stamped exactly T and for as many `modem/tx` frames stamped T as that
//!   message's `frames` says. Commands stamped earlier are late and dropped (counted). A
//!   vehicle is answered by the newest command stamped T. A run is then as reproducible as one
//!   without agents: what reaches the world, and when in simulated time, does not depend on
//!   the wall clock.
//! * **Free-running**: nothing waits; whatever has arrived is applied (the newest command per
//!   vehicle, every frame), and the world keeps to `[ros2] rtf` × real time.
//!
//! A vehicle not answered in time falls back (`[agents] fallback`) with every other vehicle
//! of the bridge — the bridge is one agent, *hung* — until commands arrive again; `stop` ends
//! the run. Every command is checked by [`Sim::command_vehicle`] (the rules of iceoryx2
//! agents: a NaN rejects it, values out of range are clamped, both counted) and an unknown
//! `mode` or `pump` is counted as invalid, a frame to a name that is no vehicle's as a bad
//! frame; nothing unchecked reaches the world.

use crate::convert::{self, Answer, ns};
use crate::error::Ros2Error;
use crate::msgs::{Clock, FluidPressure, Imu, Odometry, OpticalFrame, TfMessage, Time, stamp};
use crate::names::Names;
use crate::topics::{VehicleTopics, WorldTopics};
use ros2_client::{Context, Node, NodeName, NodeOptions};
use shoal_sim::agents::{AgentReport, Flow, Observation, Rejections, RoundTrip, lost_agent};
use shoal_sim::sim::Sim;
use shoal_world::cancel::Cancel;
use shoal_world::desc::{AgentsDesc, Ros2Desc, WorldDesc};
use std::collections::HashMap;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// How often a lock-step wait publishes the sensors of vehicles not yet answered again.
const REPUBLISH: Duration = Duration::from_millis(200);

/// How long the first tick's wait for the nodes goes on before it is announced (nodes already
/// running answer within DDS discovery, well under it).
const ATTACH_NOTICE_AFTER: Duration = Duration::from_secs(1);

/// What the world says while it waits up to `wait` for the ROS 2 nodes of the vehicles
/// `missing` (their ROS names) to answer the first tick: the domain, the topics it listens
/// on, how long, and how to stop or wait longer.
pub fn attach_wait_notice(ros2: &Ros2Desc, missing: &[&str], wait: Duration) -> String {
    let names = if missing.len() == 1 {
        missing[0].to_string()
    } else {
        format!("{{{}}}", missing.join(","))
    };
    format!(
        "waiting up to {:.0} s for ROS 2 nodes (domain {}) to answer the first tick: \
         /{ns}/{names}/setpoint (shoal_msgs/Setpoint) or /{ns}/{names}/actuators \
         (shoal_msgs/Actuators) stamped with /clock (Ctrl-C to stop; `--wait-agents SECONDS` \
         or `[agents] attach_timeout` sets the wait; unanswered vehicles fall back)",
        wait.as_secs_f64(),
        ros2.domain_id,
        ns = ros2.namespace,
    )
}

/// Whether ROS 2's own switches keep DDS on this machine: `ROS_AUTOMATIC_DISCOVERY_RANGE=
/// LOCALHOST` (Iron and later) or `ROS_LOCALHOST_ONLY=1` (before).
pub fn localhost_from_env() -> bool {
    std::env::var("ROS_AUTOMATIC_DISCOVERY_RANGE")
        .is_ok_and(|v| v.eq_ignore_ascii_case("localhost"))
        || std::env::var("ROS_LOCALHOST_ONLY").is_ok_and(|v| v == "1")
}

/// The DDS participant of the bridge: in `[ros2] domain_id`, on the loopback interface only
/// when `[ros2] localhost_only` or ROS 2's environment says so (no discovery traffic leaves
/// the machine), else on every interface, as ROS 2's default.
fn participant(ros2: &Ros2Desc) -> Result<Context, Ros2Error> {
    use ros2_client::dds::rustdds::DomainParticipantBuilder;
    let fail =
        |e: String| Ros2Error::Dds(format!("DDS participant in domain {}: {e}", ros2.domain_id));
    let mut b = DomainParticipantBuilder::new(ros2.domain_id);
    if ros2.localhost_only || localhost_from_env() {
        b = b.with_only_networks([std::net::Ipv4Addr::LOCALHOST]);
    }
    let dp = b.build().map_err(|e| fail(format!("{e:?}")))?;
    Context::from_domain_participant(dp).map_err(|e| fail(format!("{e:?}")))
}

/// The world's end of the ROS 2 bridge.
pub struct Ros2Host {
    _context: Context,
    node: Node,
    world: WorldTopics,
    vehicles: Vec<VehicleTopics>,
    /// Vehicle id → index in `vehicles`.
    index: HashMap<u32, usize>,
    /// Every vehicle's ROS name (frames' senders and destinations).
    names: Names,
    agents: AgentsDesc,
    ros2: Ros2Desc,
    density: f64,
    gravity: f64,
    /// Frames to send, per vehicle, not yet claimed by a command.
    tx: Vec<Vec<OpticalFrame>>,
    answered_once: bool,
    /// The wait for the nodes to attach (the first tick's) is over.
    attach_waited: bool,
    hung: bool,
    /// Stamp of the tick on which the bridge was declared hung \[ns\].
    hung_stamp: i64,
    /// Newest stamp of any reply received \[ns\].
    newest_reply: i64,
    report: AgentReport,
    rtt: Vec<f64>,
    wall0: Option<Instant>,
    cancel: Option<Arc<Cancel>>,
    /// Told [`attach_wait_notice`] when the first tick's wait goes on (see
    /// [`Ros2Host::announce_waits`]).
    notice: Option<Notice>,
}

/// Where the host tells what a world waits for.
type Notice = Box<dyn FnMut(&str) + Send>;

impl Ros2Host {
    /// Opens the bridge for the world `desc` (which must have a `ros2` agent): the node in
    /// domain `[ros2] domain_id` and every bridged vehicle's topics.
    pub fn open(desc: &WorldDesc) -> Result<Ros2Host, Ros2Error> {
        let ros2 = desc.agents.ros2.clone().ok_or(Ros2Error::NotConfigured)?;
        let context = participant(&ros2)?;
        let mut node = context
            .new_node(
                NodeName::new("/", "shoal_world").map_err(|e| Ros2Error::Name(format!("{e:?}")))?,
                NodeOptions::new().enable_rosout(false),
            )
            .map_err(|e| Ros2Error::Dds(format!("node: {e:?}")))?;
        let grant = desc.agents.grant_position;
        let names = Names::new(
            desc.vehicles.iter().map(|v| v.name.as_str()),
            &ros2.namespace,
        )?;
        let mut vehicles = Vec::new();
        let mut index = HashMap::new();
        for (id, v) in desc.vehicles.iter().enumerate() {
            if v.agent.as_deref() != Some(shoal_world::spec::ROS2_AGENT) {
                continue;
            }
            index.insert(id as u32, vehicles.len());
            vehicles.push(VehicleTopics::open(
                &mut node,
                &ros2.namespace,
                id as u32,
                &v.name,
                grant,
            )?);
        }
        let world = WorldTopics::open(&mut node, grant)?;
        let n = vehicles.len();
        Ok(Ros2Host {
            _context: context,
            node,
            world,
            vehicles,
            index,
            names,
            agents: desc.agents.clone(),
            density: desc.env.density,
            gravity: desc.env.gravity,
            tx: vec![Vec::new(); n],
            answered_once: false,
            attach_waited: false,
            hung: false,
            hung_stamp: 0,
            newest_reply: i64::MIN,
            report: AgentReport::new(shoal_world::spec::ROS2_AGENT, n),
            rtt: Vec::new(),
            wall0: None,
            ros2,
            cancel: None,
            notice: None,
        })
    }

    /// Gives up waits within about 10 ms once `cancel` asks for a stop.
    pub fn stop_on(&mut self, cancel: Arc<Cancel>) {
        self.cancel = Some(cancel);
    }

    /// Has `notice` told what the world waits for ([`attach_wait_notice`]) once the first
    /// tick's lock-step wait for the nodes has gone on for a second.
    pub fn announce_waits(&mut self, notice: impl FnMut(&str) + Send + 'static) {
        self.notice = Some(Box::new(notice));
    }

    /// The topics' namespace and the vehicles' names, for the start-up line.
    pub fn describe(&self) -> String {
        format!(
            "ROS 2 domain {}, /{}/{{{}}}/…",
            self.ros2.domain_id,
            self.ros2.namespace,
            self.vehicles
                .iter()
                .map(|v| v.name.as_str())
                .collect::<Vec<_>>()
                .join(",")
        )
    }

    /// The bridged vehicles' ROS names (`/<namespace>/<name>/…`), in id order.
    pub fn vehicle_names(&self) -> Vec<String> {
        self.vehicles.iter().map(|v| v.name.clone()).collect()
    }

    fn event(&mut self, t: f64, step: u64, what: &'static str, detail: String) {
        self.report.event(t, step, what, detail);
    }

    fn stopping(&self) -> bool {
        self.cancel.as_deref().is_some_and(Cancel::is_requested)
    }

    /// The exchange before a physics step (see the module doc).
    pub fn before_step(&mut self, sim: &mut Sim) -> Result<Flow, Ros2Error> {
        if self.vehicles.is_empty() || !sim.agent_tick_due() {
            return Ok(Flow::Continue);
        }
        let obs = sim.observe_agent(self.ros2.agent, self.agents.grant_position);
        if obs.is_empty() {
            return Ok(Flow::Continue);
        }
        let wall0 = *self.wall0.get_or_insert_with(Instant::now);
        let (t, step) = (sim.time(), sim.step_count());
        let now = stamp(t);
        self.report.fallback_ticks += obs.iter().filter(|o| o.fallback).count() as u64;
        let sensors = self.publish_tick(&obs, now)?;
        let sent = Instant::now();
        let ids: Vec<u32> = obs.iter().map(|o| o.id).collect();
        let mut flow = Flow::Continue;
        if self.agents.lockstep {
            // Wait for the nodes to attach once (DDS discovery), then `timeout` per tick while
            // they answer; a bridge whose nodes are absent or hung is not waited for (its
            // vehicles are under the fallback) until a tick is answered in full again.
            let attaching = !self.answered_once && !self.attach_waited;
            let timeout = match (self.answered_once, self.attach_waited, self.hung) {
                (false, false, _) => self.agents.attach_timeout,
                (true, _, false) => self.agents.timeout,
                _ => 0.0,
            };
            self.attach_waited = true;
            let timeout = Duration::from_secs_f64(timeout);
            let answers = self.wait(&ids, now, timeout, attaching, &sensors)?;
            let Some(answers) = answers else {
                return Ok(Flow::Interrupted);
            };
            let complete = answers.len() == ids.len();
            if complete {
                self.rtt.push(sent.elapsed().as_secs_f64() * 1e6);
                if self.hung || !self.answered_once {
                    let what = if self.answered_once {
                        "reattached"
                    } else {
                        "attached"
                    };
                    self.event(t, step, what, String::new());
                }
                self.hung = false;
                self.answered_once = true;
            } else if !self.hung {
                let missing = self.unanswered(&ids, &answers);
                let detail = format!(
                    "no command stamped {t:.3} s within the timeout for {}",
                    missing.join(", ")
                );
                if self.answered_once {
                    // The commands that did come first, then every vehicle of the bridge under
                    // the fallback (a command would end a vehicle's fallback).
                    self.apply(sim, answers);
                    self.hung = true;
                    self.hung_stamp = ns(now);
                    // Only replies received from now on are signs of life.
                    self.newest_reply = i64::MIN;
                    self.event(t, step, "hung", detail);
                    sim.set_fallback(self.ros2.agent, self.agents.fallback);
                    flow = lost_agent(self.agents.fallback, "ros2", "hung", flow);
                    return Ok(flow);
                }
            }
            if self.hung && self.newest_reply >= self.hung_stamp {
                // Answering again (a reply to a tick since it hung): waited for from the next
                // tick on; its vehicles leave the fallback with their next command.
                self.hung = false;
                self.event(t, step, "reattached", "answering again".into());
            }
            self.apply(sim, answers);
        } else {
            let answers = self.drain_newest();
            if !answers.is_empty() && !self.answered_once {
                self.answered_once = true;
                self.event(t, step, "attached", String::new());
            }
            self.apply(sim, answers);
            if self.ros2.rtf > 0.0 {
                loop {
                    let ahead = t / self.ros2.rtf - wall0.elapsed().as_secs_f64();
                    if ahead <= 0.0 {
                        break;
                    }
                    if self.stopping() {
                        return Ok(Flow::Interrupted);
                    }
                    std::thread::sleep(Duration::from_secs_f64(ahead.min(0.01)));
                }
            }
        }
        Ok(flow)
    }

    /// Publishes a tick's observations (see the module doc); returns each vehicle's sensor
    /// messages, to publish again while a lock-step wait goes on.
    fn publish_tick(&mut self, obs: &[Observation], now: Time) -> Result<Vec<Sensors>, Ros2Error> {
        let mut tf = TfMessage {
            transforms: Vec::new(),
        };
        let mut sensors = Vec::with_capacity(obs.len());
        for o in obs {
            let Some(&k) = self.index.get(&o.id) else {
                continue;
            };
            let v = &self.vehicles[k];
            let frame = format!("{}/base_link", v.name);
            let mut s = Sensors {
                vehicle: k,
                imu: convert::imu(o, &frame),
                pressure: convert::pressure(o, self.density, self.gravity, &frame),
                odom: None,
            };
            if let (Some(p), Some(_)) = (o.position, &v.odom) {
                let (od, ts) = convert::odometry(o, p, &frame);
                s.odom = Some(od);
                tf.transforms.push(ts);
            }
            s.publish(v)?;
            sensors.push(s);
            for f in &o.frames {
                publish(&v.rx, convert::received(f, &v.name, &self.names))?;
            }
            for e in &o.outcomes {
                publish(&v.outcome, convert::outcome(e, &self.names))?;
            }
        }
        if let Some(p) = &self.world.tf {
            publish(p, tf)?;
        }
        publish(&self.world.clock, Clock { clock: now })?;
        Ok(sensors)
    }

    /// Waits for every vehicle in `ids` to answer the tick `now` (see the module doc); `None`
    /// when a stop is asked for. Sensor data is best effort and DDS discovery takes a while:
    /// while a vehicle has not answered, its `sensors` and `/clock` are published again every
    /// [`REPUBLISH`], so a node that matched after the first publication still sees the tick
    /// (a node tells ticks apart by their stamps). When `attaching`, a wait that goes on past
    /// [`ATTACH_NOTICE_AFTER`] is announced ([`Ros2Host::announce_waits`]).
    fn wait(
        &mut self,
        ids: &[u32],
        now: Time,
        timeout: Duration,
        attaching: bool,
        sensors: &[Sensors],
    ) -> Result<Option<HashMap<u32, Answer>>, Ros2Error> {
        let start = Instant::now();
        let mut announce = attaching && timeout > ATTACH_NOTICE_AFTER;
        let mut republished = Instant::now();
        let mut answers: HashMap<u32, Answer> = HashMap::new();
        let mut nap = Duration::from_micros(20);
        loop {
            for &id in ids {
                let Some(&k) = self.index.get(&id) else {
                    continue;
                };
                let v = &self.vehicles[k];
                let rej = &mut self.report.rejections;
                while let Some(f) = take(&v.tx, rej) {
                    self.tx[k].push(f);
                }
                for a in take_answers(v, rej) {
                    self.report.replies += 1;
                    self.newest_reply = self.newest_reply.max(a.stamp_ns());
                    if a.stamp_ns() == ns(now) {
                        answers.insert(id, a);
                    } else if a.stamp_ns() < ns(now) {
                        self.report.late_replies += 1;
                    }
                }
            }
            let ready = ids.iter().all(|id| {
                answers.get(id).is_some_and(|a| {
                    let k = self.index[id];
                    self.tx[k].iter().filter(|f| f.stamp == now).count() >= a.frames() as usize
                })
            });
            if ready || start.elapsed() >= timeout {
                // Frames stamped this tick go with their vehicle's command.
                for (id, a) in answers.iter_mut() {
                    let k = self.index[id];
                    let (mine, rest): (Vec<_>, Vec<_>) = std::mem::take(&mut self.tx[k])
                        .into_iter()
                        .partition(|f| f.stamp == now);
                    self.tx[k] = rest.into_iter().filter(|f| ns(f.stamp) > ns(now)).collect();
                    a.attach_frames(mine);
                }
                return Ok(Some(answers));
            }
            if self.stopping() {
                return Ok(None);
            }
            if announce && start.elapsed() >= ATTACH_NOTICE_AFTER {
                announce = false;
                let text = attach_wait_notice(&self.ros2, &self.unanswered(ids, &answers), timeout);
                if let Some(f) = self.notice.as_mut() {
                    f(&text);
                }
            }
            if republished.elapsed() >= REPUBLISH {
                for s in sensors {
                    let v = &self.vehicles[s.vehicle];
                    if !answers.contains_key(&v.id) {
                        s.publish(v)?;
                    }
                }
                publish(&self.world.clock, Clock { clock: now })?;
                republished = Instant::now();
            }
            std::thread::sleep(nap);
            nap = (nap * 2).min(Duration::from_micros(500));
        }
    }

    /// The ROS names of the vehicles in `ids` without an answer in `answers`.
    fn unanswered(&self, ids: &[u32], answers: &HashMap<u32, Answer>) -> Vec<&str> {
        ids.iter()
            .filter(|id| !answers.contains_key(id))
            .filter_map(|id| self.index.get(id).map(|&k| self.vehicles[k].name.as_str()))
            .collect()
    }

    /// Free-running: the newest command per vehicle that has arrived, with every frame.
    fn drain_newest(&mut self) -> HashMap<u32, Answer> {
        let mut answers = HashMap::new();
        for (k, v) in self.vehicles.iter().enumerate() {
            let rej = &mut self.report.rejections;
            while let Some(f) = take(&v.tx, rej) {
                self.tx[k].push(f);
            }
            let list = take_answers(v, rej);
            self.report.replies += list.len() as u64;
            if let Some(mut a) = list.into_iter().max_by_key(Answer::stamp_ns) {
                a.attach_frames(std::mem::take(&mut self.tx[k]));
                answers.insert(v.id, a);
            }
        }
        answers
    }

    fn apply(&mut self, sim: &mut Sim, answers: HashMap<u32, Answer>) {
        let mut ids: Vec<u32> = answers.keys().copied().collect();
        ids.sort_unstable();
        let mut answers = answers;
        for id in ids {
            let a = answers.remove(&id).expect("listed above");
            let rej = &mut self.report.rejections;
            if let Some(cmd) = a.into_command(id, &self.names, rej)
                && sim.command_vehicle(self.ros2.agent, &cmd, rej)
            {
                self.report.commands_applied += 1;
            }
        }
    }

    /// Round-trip statistics since the start or the last call, clearing them.
    pub fn take_round_trips(&mut self) -> RoundTrip {
        let r = RoundTrip::of(&mut self.rtt);
        self.rtt.clear();
        r
    }

    /// Ends the exchange and returns the bridge's report.
    pub fn finish(&mut self, _sim: &mut Sim) -> AgentReport {
        self.report.round_trip = RoundTrip::of(&mut self.rtt);
        self.report.attached_at_end = self.answered_once && !self.hung;
        let _ = &self.node;
        self.report.clone()
    }
}

/// A vehicle's sensor messages of one tick, kept to publish again while the world waits.
struct Sensors {
    /// Index in `Ros2Host::vehicles`.
    vehicle: usize,
    imu: Imu,
    pressure: FluidPressure,
    odom: Option<Odometry>,
}

impl Sensors {
    fn publish(&self, v: &VehicleTopics) -> Result<(), Ros2Error> {
        publish(&v.imu, self.imu.clone())?;
        publish(&v.pressure, self.pressure.clone())?;
        if let (Some(o), Some(p)) = (&self.odom, &v.odom) {
            publish(p, o.clone())?;
        }
        Ok(())
    }
}

fn publish<T: serde::Serialize + std::fmt::Debug>(
    p: &ros2_client::Publisher<T>,
    m: T,
) -> Result<(), Ros2Error> {
    p.publish(m)
        .map_err(|e| Ros2Error::Dds(format!("publish: {e:?}")))
}

/// The next sample of `s`; one that does not deserialise is counted as malformed and
/// skipped, never applied.
fn take<T: serde::de::DeserializeOwned + 'static>(
    s: &ros2_client::Subscription<T>,
    rej: &mut Rejections,
) -> Option<T> {
    // A bounded number of malformed samples in a row, so a flood cannot hold the world.
    for _ in 0..64 {
        match s.take() {
            Ok(m) => return m.map(|(m, _)| m),
            Err(_) => rej.malformed += 1,
        }
    }
    None
}

/// Every setpoint and actuator command that has arrived for vehicle `v`.
fn take_answers(v: &VehicleTopics, rej: &mut Rejections) -> Vec<Answer> {
    let mut out = Vec::new();
    while let Some(s) = take(&v.setpoint, rej) {
        out.push(Answer::Setpoint(s, Vec::new()));
    }
    while let Some(a) = take(&v.actuators, rej) {
        out.push(Answer::Actuators(a, Vec::new()));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_attach_wait_says_what_it_waits_for_how_long_and_how_to_stop() {
        let ros2 = Ros2Desc {
            domain_id: 7,
            namespace: "pool".into(),
            rtf: 1.0,
            localhost_only: true,
            agent: 0,
        };
        let two = attach_wait_notice(&ros2, &["a1", "b2"], Duration::from_secs(60));
        for part in [
            "up to 60 s",
            "domain 7",
            "/pool/{a1,b2}/setpoint",
            "/pool/{a1,b2}/actuators",
            "/clock",
            "Ctrl-C to stop",
            "--wait-agents SECONDS",
        ] {
            assert!(two.contains(part), "`{part}` missing in: {two}");
        }
        let one = attach_wait_notice(&ros2, &["a1"], Duration::from_secs_f64(2.5));
        assert!(
            one.contains("up to 2 s") || one.contains("up to 3 s"),
            "{one}"
        );
        assert!(one.contains("/pool/a1/setpoint"), "{one}");
    }
}
