//! In-process swarm behaviours. A behaviour runs on its vehicle's control tick and sees what
//! the vehicle could know: its sensor readings, the frames its modems received since the last
//! tick, its own modems' mounting. It answers with setpoints for the built-in controller and
//! frames to send. Nothing else of the world is visible.
//!
//! Built in: [`Beacon`] (periodic broadcast, a traffic source), [`Gossip`] (flooding of a value
//! across the swarm) and [`Flock`] (alignment, cohesion and separation from received headings
//! and signal strengths: a flock that keeps optical contact).

mod formation;
mod reliable_gossip;

pub use formation::{Follower, Leader};
pub use reliable_gossip::ReliableGossip;

use crate::comm::{FrameEvent, OutFrame, Received};
use crate::rng::VehicleRng;
use bevy_ecs::prelude::*;
use rand::RngExt;
use shoal_model::control::{SensorReadings, Setpoints};
use shoal_model::math::{euler_rpy, wrap_pi};
use shoal_model::optics::ModemParams;
use shoal_world::spec::BehaviourSpec;
use std::collections::BTreeMap;

/// What a behaviour sees and does on one tick.
pub struct BehaviourIo<'a> {
    /// Time \[s\].
    pub t: f64,
    /// This vehicle's id (as written in the link-layer header of its frames).
    pub id: u32,
    /// Time to the next tick \[s\] (the control period, or the physics step).
    pub period: f64,
    /// Sensor readings.
    pub sensors: &'a SensorReadings,
    /// Frames received since the last tick, in order of arrival.
    pub inbox: &'a [Received],
    /// What became of this vehicle's acknowledged unicast frames since the last tick.
    pub outcomes: &'a [FrameEvent],
    /// Setpoints of the built-in controller (mode, depth, heading, forces).
    pub setpoints: &'a mut Setpoints,
    /// This vehicle's modems (mounting and limits).
    pub modems: &'a [ModemParams],
    /// The behaviour's own random stream.
    pub rng: &'a mut VehicleRng,
    /// Frames to send.
    pub outbox: &'a mut Vec<OutFrame>,
}

impl BehaviourIo<'_> {
    /// Hands `payload` to one modem (`Some(index)`) or to all of them in sync (`None`),
    /// `delay` \[s\] after now.
    pub fn send(&mut self, modem: Option<usize>, payload: &[u8], delay: f64) {
        self.outbox.push(OutFrame::broadcast(
            modem,
            payload.to_vec(),
            self.t + delay.max(0.0),
        ));
    }

    /// Hands `payload` for vehicle `to` alone to one modem or all of them, `delay` \[s\]
    /// after now; with `ack`, the destination acknowledges it and the modem retransmits until
    /// it does or its retries are used up ([`BehaviourIo::outcomes`] says which).
    pub fn send_to(
        &mut self,
        to: u32,
        modem: Option<usize>,
        payload: &[u8],
        delay: f64,
        ack: bool,
    ) {
        self.outbox.push(OutFrame {
            modem,
            payload: payload.to_vec(),
            ready: self.t + delay.max(0.0),
            to: Some(to),
            ack,
            tag: 0,
        });
    }

    /// Heading from the IMU \[rad\].
    pub fn heading(&self) -> f64 {
        euler_rpy(&self.sensors.attitude).2
    }
}

/// A swarm behaviour.
pub trait Behaviour: Send + Sync + 'static {
    /// Called on every control tick (every physics step if [`Behaviour::every_step`]).
    fn tick(&mut self, io: &mut BehaviourIo<'_>);
    /// Run on every physics step instead of every control tick: for link-layer logic that
    /// must react to a received frame at once (a relay), as a modem's receive interrupt would.
    fn every_step(&self) -> bool {
        false
    }
    /// Per-vehicle results for the run summary (name, value).
    fn report(&self) -> Vec<(&'static str, f64)> {
        Vec::new()
    }
}

/// The behaviour of a vehicle, with its random stream and its tick period.
#[derive(Component)]
pub struct Behave {
    /// The behaviour.
    pub behaviour: Box<dyn Behaviour>,
    /// Its random stream.
    pub rng: VehicleRng,
    /// Its tick period in physics steps: 1 for a behaviour that runs every step, else the
    /// vehicle's control period (kept here, so that finding the behaviours due at a step
    /// reads no other state of the vehicle).
    pub every: u64,
}

impl Behave {
    /// `behaviour` with its random stream, on a vehicle whose controller runs every
    /// `control_every` physics steps.
    pub fn new(behaviour: Box<dyn Behaviour>, rng: VehicleRng, control_every: u64) -> Self {
        let every = if behaviour.every_step() {
            1
        } else {
            control_every.max(1)
        };
        Self {
            behaviour,
            rng,
            every,
        }
    }
}

/// Builds a built-in behaviour from its file description; `id_of` gives the id of a vehicle
/// by name (destinations were checked on load: an unknown one sends broadcasts).
pub fn build(spec: &BehaviourSpec, id_of: &dyn Fn(&str) -> Option<u32>) -> Box<dyn Behaviour> {
    match *spec {
        BehaviourSpec::Beacon {
            period,
            payload_bytes,
            jitter,
        } => Box::new(Beacon {
            period,
            payload_bytes,
            jitter,
            next: None,
            sent: 0,
        }),
        BehaviourSpec::Poisson {
            rate,
            payload_bytes,
            ref to,
            ack,
        } => Box::new(Poisson {
            rate,
            payload_bytes,
            to: to.as_deref().and_then(id_of),
            ack,
            next: None,
            sent: 0,
        }),
        BehaviourSpec::Leader {
            ref followers,
            period,
        } => Box::new(Leader::new(
            followers.iter().filter_map(|n| id_of(n)).collect(),
            period,
        )),
        BehaviourSpec::Follower {} => Box::new(Follower::default()),
        BehaviourSpec::ReliableGossip {
            origin,
            start,
            hello,
        } => Box::new(ReliableGossip::new(origin, start, hello)),
        BehaviourSpec::Gossip {
            origin,
            start,
            repeats,
            interval,
            jitter,
        } => Box::new(Gossip {
            origin,
            start,
            repeats,
            interval,
            jitter,
            known: None,
            left: 0,
            next: 0.0,
        }),
        BehaviourSpec::Flock {
            surge,
            period,
            too_close,
            too_far,
            cohesion,
        } => Box::new(Flock {
            surge,
            period,
            too_close,
            too_far,
            cohesion,
            next: None,
            neighbours: BTreeMap::new(),
            last_bearing: None,
        }),
    }
}

/// Broadcasts a frame every `period` seconds, each offset by a random delay in [0, jitter].
pub struct Beacon {
    period: f64,
    payload_bytes: usize,
    jitter: f64,
    next: Option<f64>,
    sent: u64,
}

impl Behaviour for Beacon {
    fn tick(&mut self, io: &mut BehaviourIo<'_>) {
        let next = *self
            .next
            .get_or_insert_with(|| io.rng.random::<f64>() * self.period);
        if io.t + 1e-12 >= next {
            let mut payload = vec![0u8; self.payload_bytes];
            let n = self.sent.to_le_bytes();
            let k = payload.len().min(8);
            payload[..k].copy_from_slice(&n[..k]);
            let delay = io.rng.random::<f64>() * self.jitter;
            io.send(None, &payload, delay);
            self.sent += 1;
            self.next = Some(next + self.period);
        }
    }

    fn report(&self) -> Vec<(&'static str, f64)> {
        vec![("beacons", self.sent as f64)]
    }
}

/// Frames at the arrivals of a Poisson process: exponential gaps of mean 1 / `rate`, each
/// frame handed over at its arrival time (within the tick it falls in, as a delay).
pub struct Poisson {
    rate: f64,
    payload_bytes: usize,
    /// Destination (none: broadcast).
    to: Option<u32>,
    /// With acknowledgement.
    ack: bool,
    /// The next arrival \[s\].
    next: Option<f64>,
    sent: u64,
}

impl Poisson {
    /// An exponential gap of mean 1 / rate \[s\] (inverse transform of a draw in (0, 1]).
    fn gap(&self, rng: &mut VehicleRng) -> f64 {
        let u = 1.0 - rng.random::<f64>();
        -u.ln() / self.rate
    }
}

impl Behaviour for Poisson {
    fn tick(&mut self, io: &mut BehaviourIo<'_>) {
        let mut next = match self.next {
            Some(t) => t,
            None => io.t + self.gap(io.rng),
        };
        let payload = vec![0u8; self.payload_bytes];
        while next < io.t + io.period {
            match self.to {
                Some(to) => io.send_to(to, None, &payload, next - io.t, self.ack),
                None => io.send(None, &payload, next - io.t),
            }
            self.sent += 1;
            next += self.gap(io.rng);
        }
        self.next = Some(next);
    }

    fn report(&self) -> Vec<(&'static str, f64)> {
        vec![("frames", self.sent as f64)]
    }
}

/// Gossip frame tag.
const GOSSIP: u8 = b'G';

/// Flooding of one value: whoever learns it rebroadcasts it `repeats` times.
pub struct Gossip {
    origin: bool,
    start: f64,
    repeats: u32,
    interval: f64,
    jitter: f64,
    /// (value, hops, time learned).
    known: Option<(u32, u8, f64)>,
    left: u32,
    next: f64,
}

impl Gossip {
    fn learn(&mut self, value: u32, hops: u8, t: f64, rng: &mut VehicleRng) {
        self.known = Some((value, hops, t));
        self.left = self.repeats;
        self.next = t + rng.random::<f64>() * self.jitter;
    }
}

impl Behaviour for Gossip {
    fn every_step(&self) -> bool {
        true
    }

    fn tick(&mut self, io: &mut BehaviourIo<'_>) {
        if self.known.is_none() {
            if self.origin && io.t + 1e-12 >= self.start {
                self.learn(0xC0FFEE, 0, self.start, io.rng);
            } else if let Some(r) = io
                .inbox
                .iter()
                .find(|r| r.payload.len() >= 8 && r.payload[0] == GOSSIP)
            {
                let value =
                    u32::from_le_bytes([r.payload[1], r.payload[2], r.payload[3], r.payload[4]]);
                self.learn(value, r.payload[5].saturating_add(1), r.t, io.rng);
            }
        }
        if let Some((value, hops, _)) = self.known {
            while self.left > 0 && self.next <= io.t + io.period {
                let v = value.to_le_bytes();
                let id = (io.id as u16).to_le_bytes();
                let payload = [GOSSIP, v[0], v[1], v[2], v[3], hops, id[0], id[1]];
                let delay = self.next - io.t;
                io.send(None, &payload, delay);
                self.left -= 1;
                self.next += self.interval + io.rng.random::<f64>() * self.jitter;
            }
        }
    }

    fn report(&self) -> Vec<(&'static str, f64)> {
        match self.known {
            Some((_, hops, t)) => vec![
                ("learned_at", t),
                ("hops", f64::from(hops)),
                ("origin_start", self.start),
            ],
            None => vec![
                ("learned_at", f64::NAN),
                ("hops", f64::NAN),
                ("origin_start", self.start),
            ],
        }
    }
}

/// Flock frame tag.
const FLOCK: u8 = b'F';

#[derive(Clone, Copy, Debug)]
struct Neighbour {
    heading: f64,
    power: f64,
    /// Bearing of the receiving modem in the body frame [rad].
    bearing: f64,
    heard: f64,
}

/// Flocking from what the modems hear: headings for alignment, signal strength and the
/// direction of the receiving modem for cohesion and separation.
pub struct Flock {
    surge: f64,
    period: f64,
    too_close: f64,
    too_far: f64,
    cohesion: f64,
    next: Option<f64>,
    neighbours: BTreeMap<u32, Neighbour>,
    /// World bearing [rad] towards the neighbours when they were last heard, and when.
    last_bearing: Option<(f64, f64)>,
}

impl Behaviour for Flock {
    fn tick(&mut self, io: &mut BehaviourIo<'_>) {
        let heading = io.heading();
        for r in io
            .inbox
            .iter()
            .filter(|r| r.payload.len() >= 5 && r.payload[0] == FLOCK)
        {
            let h =
                f32::from_le_bytes([r.payload[1], r.payload[2], r.payload[3], r.payload[4]]) as f64;
            let d = io.modems[r.modem].direction;
            self.neighbours.insert(
                r.from,
                Neighbour {
                    heading: h,
                    power: r.power,
                    bearing: d.y.atan2(d.x),
                    heard: r.t,
                },
            );
        }
        let t = io.t;
        let memory = 3.0 * self.period;
        self.neighbours.retain(|_, n| t - n.heard < memory);
        // Beacon own heading.
        let next = *self
            .next
            .get_or_insert_with(|| io.rng.random::<f64>() * self.period);
        if t + 1e-12 >= next {
            let h = (heading as f32).to_le_bytes();
            let delay = io.rng.random::<f64>() * io.period;
            io.send(None, &[FLOCK, h[0], h[1], h[2], h[3]], delay);
            self.next = Some(next + self.period * (0.9 + 0.2 * io.rng.random::<f64>()));
        }
        if self.neighbours.is_empty() {
            match self.last_bearing {
                // Lost contact: go after the others where they were last heard ...
                Some((bearing, when)) if t - when < 20.0 => {
                    io.setpoints.yaw = bearing;
                    io.setpoints.surge = self.surge;
                }
                // ... or, after a while, stop and turn on the spot to find anyone.
                _ => {
                    io.setpoints.surge = 0.0;
                    io.setpoints.yaw = wrap_pi(heading + 0.6);
                }
            }
            return;
        }
        // Where the others are: the mean direction of the modems that hear them.
        let (bx, by) = self.neighbours.values().fold((0.0, 0.0), |(x, y), n| {
            (
                x + (heading + n.bearing).cos(),
                y + (heading + n.bearing).sin(),
            )
        });
        if bx * bx + by * by > 1e-12 {
            self.last_bearing = Some((by.atan2(bx), t));
        }
        // Alignment: mean of own and neighbours' headings (as unit vectors).
        let (mut x, mut y) = (heading.cos(), heading.sin());
        for n in self.neighbours.values() {
            x += n.heading.cos();
            y += n.heading.sin();
        }
        let norm = (x * x + y * y).sqrt().max(1e-9);
        let (mut ax, mut ay) = (x / norm, y / norm);
        // Cohesion and separation towards / away from the modem that hears each neighbour.
        let (mut cx, mut cy) = (0.0, 0.0);
        for n in self.neighbours.values() {
            let w = if n.power < self.too_far {
                1.0
            } else if n.power > self.too_close {
                -1.0
            } else {
                0.0
            };
            let b = heading + n.bearing;
            cx += w * b.cos();
            cy += w * b.sin();
        }
        ax += self.cohesion * cx;
        ay += self.cohesion * cy;
        io.setpoints.yaw = ay.atan2(ax);
        // Slow down when the flock is behind (someone is weak at the rear modem).
        let behind = self
            .neighbours
            .values()
            .any(|n| n.power < self.too_far && n.bearing.cos() < -0.5);
        io.setpoints.surge = if behind { 0.3 * self.surge } else { self.surge };
    }

    fn report(&self) -> Vec<(&'static str, f64)> {
        vec![("neighbours", self.neighbours.len() as f64)]
    }
}
