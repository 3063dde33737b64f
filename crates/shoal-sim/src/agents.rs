//! External agents, independent of how they are reached: what an agent sees of its vehicles
//! on a control tick ([`Observation`]), what it may answer ([`Command`]), how every answer is
//! checked before it touches the world ([`Sim::command_vehicle`]), and how many of an agent's
//! vehicles are under the fallback ([`Sim::fallback_count`]). The fallback itself, which takes
//! over while an agent is absent ([`Sim::set_fallback`]), belongs to the world: a world starts
//! its agent-driven vehicles under it, before any agent is there.
//!
//! The transport (shared memory, in `shoal-bridge`) calls, before each physics step whose
//! control tick is due ([`Sim::agent_tick_due`]): [`Sim::observe_agents`], then
//! [`Sim::command_vehicle`] for each command received. Commands therefore act in the same
//! control tick as a built-in behaviour's setpoints would, and a lock-step run is as
//! reproducible as one without agents.

use crate::comm::{FrameEvent, Inbox, Outbox, Received};
use crate::components::*;
use crate::fleet::Fleet;
use crate::orders::{FrameOrder, Peers, check_frame, force_limit};
use crate::sim::Sim;
use bevy_ecs::prelude::Mut;
use shoal_model::math::wrap_pi;
use shoal_model::prelude::*;
use shoal_world::spec::FallbackSpec;

pub use crate::components::External;

/// What an agent sees of one vehicle on a control tick: only what the vehicle could sense.
#[derive(Clone, Debug)]
pub struct Observation {
    /// Vehicle id (index in the world).
    pub id: u32,
    /// Physics step of this tick.
    pub step: u64,
    /// Simulated time \[s\].
    pub t: f64,
    /// Sensor readings (quantised depth, IMU attitude and rates, tilt angles, tank switch).
    pub sensors: SensorReadings,
    /// True position of the body origin, world frame \[m\] — only if the world grants it.
    pub position: Option<Vec3>,
    /// Frames received since the last tick, in order of arrival.
    pub frames: Vec<Received>,
    /// What became of the vehicle's acknowledged unicasts since the last tick (acknowledged,
    /// or given up after its retries), in order.
    pub outcomes: Vec<FrameEvent>,
    /// Whether the fallback is driving the vehicle.
    pub fallback: bool,
}

/// What an agent asks of one vehicle.
#[derive(Clone, Debug, PartialEq)]
pub enum Order {
    /// Keep the setpoints in force (e.g. only send frames).
    Keep,
    /// A controller mode with its setpoints.
    Mode {
        /// The mode (not [`Mode::Raw`]).
        mode: Mode,
        /// Depth [m, positive down].
        depth: f64,
        /// Heading \[rad\].
        yaw: f64,
        /// Surge force \[N\].
        surge: f64,
        /// Sway force \[N\].
        sway: f64,
    },
    /// Raw actuator commands.
    Raw {
        /// Per thruster [%]; missing ones are 0.
        thrusters: Vec<f64>,
        /// Per tilt drive \[rad\]; missing ones are 0.
        tilts: Vec<f64>,
        /// Pump.
        pump: Pump,
    },
}

/// One agent command for one vehicle.
#[derive(Clone, Debug, PartialEq)]
pub struct Command {
    /// Vehicle id.
    pub id: u32,
    /// Setpoints.
    pub order: Order,
    /// Frames to send.
    pub frames: Vec<FrameOrder>,
}

/// Counts of what was wrong in agents' commands. A rejected command changes nothing; a
/// clamped value is applied at the nearest allowed value.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Rejections {
    /// Commands rejected for a NaN or infinite number.
    pub non_finite: u64,
    /// Values outside their range, clamped.
    pub clamped: u64,
    /// Commands for a vehicle that does not exist or is not this agent's.
    pub unknown_vehicle: u64,
    /// Commands with an unknown mode or pump value.
    pub invalid: u64,
    /// Frames rejected: longer than the modem's payload, unknown modem, no modem.
    pub bad_frames: u64,
    /// Messages of another protocol version, or malformed at the transport.
    pub malformed: u64,
}

impl Rejections {
    /// Sum of every count.
    pub fn total(&self) -> u64 {
        self.non_finite
            + self.clamped
            + self.unknown_vehicle
            + self.invalid
            + self.bad_frames
            + self.malformed
    }

    /// Adds `o` to these counts.
    pub fn add(&mut self, o: &Rejections) {
        self.non_finite += o.non_finite;
        self.clamped += o.clamped;
        self.unknown_vehicle += o.unknown_vehicle;
        self.invalid += o.invalid;
        self.bad_frames += o.bad_frames;
        self.malformed += o.malformed;
    }
}

/// Something that happened to an agent.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct AgentEvent {
    /// Simulated time \[s\].
    pub t: f64,
    /// Physics step.
    pub step: u64,
    /// `attached`, `left`, `hung`, `gone` (process died), `reattached`.
    pub what: &'static str,
    /// Details for people.
    pub detail: String,
}

/// Round-trip statistics \[µs\].
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct RoundTrip {
    /// Exchanges measured.
    pub count: usize,
    /// Median \[µs\].
    pub median_us: f64,
    /// 99th percentile \[µs\].
    pub p99_us: f64,
    /// Largest \[µs\].
    pub max_us: f64,
}

impl RoundTrip {
    /// Statistics of round trips `v` \[µs\] (sorts them in place).
    pub fn of(v: &mut [f64]) -> RoundTrip {
        if v.is_empty() {
            return RoundTrip::default();
        }
        v.sort_by(f64::total_cmp);
        let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
        RoundTrip {
            count: v.len(),
            median_us: at(0.5),
            p99_us: at(0.99),
            max_us: v[v.len() - 1],
        }
    }
}

/// What a run does when agent `name` is lost (`how`: hung, died, left): ends with a reason
/// under the fallback `stop` (unless it already ends), else goes on as `flow` says.
pub fn lost_agent(fallback: FallbackSpec, name: &str, how: &str, flow: Flow) -> Flow {
    if fallback == FallbackSpec::Stop && flow == Flow::Continue {
        Flow::Stop(format!("agent `{name}` {how} and the fallback is `stop`"))
    } else {
        flow
    }
}

/// What the run should do after an exchange with agents.
#[derive(Clone, Debug, PartialEq)]
pub enum Flow {
    /// Go on.
    Continue,
    /// End the run (fallback `stop`), with the reason.
    Stop(String),
    /// A stop was asked for while waiting for an agent: end the run without this step.
    Interrupted,
}

/// The agents of a run as the run driver sees them, whatever carries their messages (the
/// binary joins shared-memory agents and ROS 2 nodes behind it): one exchange before each
/// physics step, and a report per agent at the end.
pub trait AgentHost {
    /// Once the world is built, before its first step: e.g. wait for the agents to attach.
    fn start(&mut self) -> Result<(), Box<dyn std::error::Error + Send + Sync>> {
        Ok(())
    }
    /// The exchange before a physics step (on a control tick of agent-driven vehicles:
    /// observations out, commands in and applied through [`Sim::command_vehicle`]); what the
    /// run does next. An error is a transport failure, not an agent's bad command.
    fn before_step(
        &mut self,
        sim: &mut Sim,
    ) -> Result<Flow, Box<dyn std::error::Error + Send + Sync>>;
    /// Ends the exchange, giving agents `grace` to see the end; the reports, one per agent.
    fn finish(&mut self, sim: &mut Sim, grace: std::time::Duration) -> Vec<AgentReport>;
}

/// Everything about one agent for the run summary.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct AgentReport {
    /// Agent name.
    pub name: String,
    /// Vehicles it drives.
    pub vehicles: usize,
    /// Attached when the run ended.
    pub attached_at_end: bool,
    /// Events in order (the first 1,000).
    pub events: Vec<AgentEvent>,
    /// Events after the first 1,000, only counted.
    pub events_omitted: u64,
    /// Reply slices received.
    pub replies: u64,
    /// Replies to an older step (ignored in lock-step).
    pub late_replies: u64,
    /// Commands applied.
    pub commands_applied: u64,
    /// Problems found in its commands.
    pub rejections: Rejections,
    /// Vehicle control ticks spent under the fallback.
    pub fallback_ticks: u64,
    /// Lock-step: publish → matching reply, wall time.
    pub round_trip: RoundTrip,
}

/// Events kept per agent report; later ones are only counted (an agent that hangs on every
/// tick).
pub const MAX_EVENTS: usize = 1000;

impl AgentReport {
    /// The report of agent `name` driving `vehicles` vehicles, before anything happened.
    pub fn new(name: &str, vehicles: usize) -> AgentReport {
        AgentReport {
            name: name.to_string(),
            vehicles,
            attached_at_end: false,
            events: Vec::new(),
            events_omitted: 0,
            replies: 0,
            late_replies: 0,
            commands_applied: 0,
            rejections: Rejections::default(),
            fallback_ticks: 0,
            round_trip: RoundTrip::default(),
        }
    }

    /// Records an event at simulated time `t` \[s\], physics step `step` (the first
    /// [`MAX_EVENTS`]; later ones are counted in `events_omitted`).
    pub fn event(&mut self, t: f64, step: u64, what: &'static str, detail: String) {
        if self.events.len() >= MAX_EVENTS {
            self.events_omitted += 1;
            return;
        }
        self.events.push(AgentEvent {
            t,
            step,
            what,
            detail,
        });
    }
}

/// The agents part of a run summary.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct AgentsSummary {
    /// Service-name prefix of the world.
    pub prefix: String,
    /// `lockstep` or `free`.
    pub timing: &'static str,
    /// What vehicles did without their agent.
    pub fallback: String,
    /// Why the run was ended early by the fallback `stop`, if it was.
    pub stopped: Option<String>,
    /// Per agent.
    pub agents: Vec<AgentReport>,
}

impl Sim {
    /// Whether any agent-driven vehicle has its control tick at the coming step.
    pub fn agent_tick_due(&mut self) -> bool {
        let step = self.step_count();
        let mut q = self.world_mut().query::<(&VehicleId, &External)>();
        let fleet = self.fleet();
        q.iter(self.world())
            .any(|(id, _)| step.is_multiple_of(fleet.get(*id).control.every))
    }

    /// Observations of every agent-driven vehicle whose control tick is at the coming step,
    /// grouped by agent index (`n_agents` groups, each sorted by vehicle id). Takes the frames
    /// each vehicle received since its last tick.
    pub fn observe_agents(
        &mut self,
        n_agents: usize,
        grant_position: bool,
    ) -> Vec<Vec<Observation>> {
        self.observe(n_agents, grant_position, None)
    }

    /// Observations of agent `agent`'s vehicles whose control tick is at the coming step, as
    /// [`Sim::observe_agents`] gives them; other agents' vehicles keep their frames (a second
    /// transport, the ROS 2 bridge, serves one agent index beside the iceoryx2 ones).
    pub fn observe_agent(&mut self, agent: usize, grant_position: bool) -> Vec<Observation> {
        self.observe(agent + 1, grant_position, Some(agent))
            .swap_remove(agent)
    }

    fn observe(
        &mut self,
        n_agents: usize,
        grant_position: bool,
        only: Option<usize>,
    ) -> Vec<Vec<Observation>> {
        let step = self.step_count();
        let t = self.time();
        let mut out = vec![Vec::new(); n_agents];
        self.world_mut().resource_scope(|world, fleet: Mut<Fleet>| {
            let mut q = world.query::<(&VehicleId, &External, &mut Inbox)>();
            for (id, ext, mut inbox) in q.iter_mut(world) {
                let v = fleet.get(*id);
                if !step.is_multiple_of(v.control.every)
                    || ext.agent >= n_agents
                    || only.is_some_and(|a| a != ext.agent)
                {
                    continue;
                }
                out[ext.agent].push(Observation {
                    id: id.0,
                    step,
                    t,
                    sensors: v.sensors.clone(),
                    position: grant_position.then_some(v.physics.state.rigid.position),
                    frames: std::mem::take(&mut inbox.frames),
                    outcomes: std::mem::take(&mut inbox.outcomes),
                    fallback: ext.fallback,
                });
            }
        });
        for o in &mut out {
            o.sort_by_key(|o| o.id);
        }
        out
    }

    /// Index of the agent that drives vehicle `id`, if any.
    pub fn agent_of(&self, id: u32) -> Option<usize> {
        let e = *self.entities().get(id as usize)?;
        self.world().get::<External>(e).map(|x| x.agent)
    }

    /// Applies an agent's command to its vehicle after checking every value: a non-finite
    /// number or an unknown mode rejects the command, values out of range are clamped, bad
    /// frames are dropped; each case is counted in `rej`. Returns whether the command was
    /// applied. `agent` must drive the vehicle. The command ends the vehicle's fallback.
    pub fn command_vehicle(&mut self, agent: usize, cmd: &Command, rej: &mut Rejections) -> bool {
        if self.agent_of(cmd.id) != Some(agent) {
            rej.unknown_vehicle += 1;
            return false;
        }
        let e = self.entities()[cmd.id as usize];
        let t = self.time();
        let pool_depth = self.pool_size().z;
        let peers = Peers {
            me: cmd.id,
            count: self.len(),
        };
        let model = self.fleet().get(VehicleId(cmd.id)).model.clone();
        let mut ent = self.world_mut().entity_mut(e);
        let p = &model.params;
        let finite = |xs: &[f64]| xs.iter().all(|x| x.is_finite());
        // Check everything before changing anything.
        let clamped = std::cell::Cell::new(0u64);
        let clamp = |x: f64, lo: f64, hi: f64| {
            if x < lo || x > hi {
                clamped.set(clamped.get() + 1);
            }
            x.clamp(lo, hi)
        };
        let new_setpoints = match &cmd.order {
            Order::Keep => None,
            Order::Mode {
                mode,
                depth,
                yaw,
                surge,
                sway,
            } => {
                if !finite(&[*depth, *yaw, *surge, *sway]) {
                    rej.non_finite += 1;
                    return false;
                }
                if *mode == Mode::Raw {
                    rej.invalid += 1;
                    return false;
                }
                let f = force_limit(&model);
                Some((
                    *mode,
                    clamp(*depth, 0.0, pool_depth),
                    wrap_pi(*yaw),
                    clamp(*surge, -f, f),
                    clamp(*sway, -f, f),
                    None,
                ))
            }
            Order::Raw {
                thrusters,
                tilts,
                pump,
            } => {
                if !finite(thrusters) || !finite(tilts) {
                    rej.non_finite += 1;
                    return false;
                }
                let mut raw = model.zero_commands();
                for (i, x) in thrusters.iter().enumerate() {
                    match p.thrusters.get(i) {
                        Some(th) => raw.thrusters[i] = clamp(*x, -th.max_command, th.max_command),
                        None if *x != 0.0 => clamped.set(clamped.get() + 1),
                        None => {}
                    }
                }
                for (i, x) in tilts.iter().enumerate() {
                    match p.tilts.get(i) {
                        Some(tl) => raw.tilts[i] = clamp(*x, tl.min, tl.max),
                        None if *x != 0.0 => clamped.set(clamped.get() + 1),
                        None => {}
                    }
                }
                raw.pump = if p.ballast.is_some() {
                    *pump
                } else {
                    Pump::Off
                };
                Some((Mode::Raw, 0.0, 0.0, 0.0, 0.0, Some(raw)))
            }
        };
        let mut frames = Vec::new();
        for f in &cmd.frames {
            if check_frame(&p.modems, f, peers).is_err() {
                rej.bad_frames += 1;
                continue;
            }
            frames.push(f.out_frame(t));
        }
        rej.clamped += clamped.get();
        ent.get_mut::<Outbox>().expect("vehicle").0.extend(frames);
        ent.get_mut::<External>().expect("vehicle").fallback = false;
        if let Some((mode, depth, yaw, surge, sway, raw)) = new_setpoints {
            let mut fleet = self.fleet_mut();
            let sp = &mut fleet.get_mut(VehicleId(cmd.id)).control.setpoints;
            sp.mode = mode;
            if let Some(raw) = raw {
                sp.raw = raw;
            } else {
                sp.depth = depth;
                sp.yaw = yaw;
                sp.surge = surge;
                sp.sway = sway;
            }
        }
        true
    }

    /// Number of vehicles driven by `agent` that are in fallback, and in all.
    pub fn fallback_count(&mut self, agent: usize) -> (usize, usize) {
        let mut q = self.world_mut().query::<&External>();
        let mine: Vec<bool> = q
            .iter(self.world())
            .filter(|x| x.agent == agent)
            .map(|x| x.fallback)
            .collect();
        (mine.iter().filter(|f| **f).count(), mine.len())
    }
}
