//! The shared optical medium: frames take airtime, modems are half-duplex, overlapping frames
//! collide unless one is `capture_ratio` times stronger, transmit queues are bounded, access is
//! unslotted ALOHA or carrier sense, the LED→photodiode ray can be blocked by walls, obstacles
//! and other hulls, and every reception is decided by the link budget of
//! [`shoal_model::optics`] with a draw from the *receiver's* random stream.
//!
//! One step runs three systems in order (all in [`crate::systems::StepSet::Comm`]):
//! 1. [`comm_snapshot_system`]: modem poses and a spatial grid of the vehicles, pruning of old
//!    transmissions;
//! 2. [`comm_transmit_system`]: frames handed to modems (from behaviours or agents) enter the
//!    bounded queues; idle modems start transmitting in time order within the step, so carrier
//!    sense sees exactly the transmissions that started before it;
//! 3. [`comm_deliver_system`]: every frame whose transmission ended in this step is evaluated
//!    at each candidate receiver — in parallel over receivers, each using only its own state
//!    and random stream — so delivery never depends on system order or thread count.

use crate::components::{Kind, Physics, StaticGeometry, VehicleId};
use crate::parallel::Parallel;
use bevy_ecs::prelude::*;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;
use shoal_model::math::{Quat, Vec3};
use shoal_model::optics::{
    Access, Ambient, LinkGeometry, ModemParams, ModemPose, channel_gain, noise_variance, reception,
};
use shoal_model::vehicle::VehicleModel;
use shoal_world::geometry::segment_hits_hull;
use std::collections::{BTreeMap, BinaryHeap, HashMap, VecDeque};
use std::sync::Arc;

/// A frame handed to a vehicle's modem(s) by a behaviour or an agent.
#[derive(Clone, Debug, PartialEq)]
pub struct OutFrame {
    /// Modem index, or `None` for a copy on every modem (sent in sync).
    pub modem: Option<usize>,
    /// Payload bytes (the link-layer header is added on the air).
    pub payload: Vec<u8>,
    /// Time at which the frame is handed over [s].
    pub ready: f64,
}

/// Frames waiting to be handed to the modems.
#[derive(Component, Clone, Debug, Default)]
pub struct Outbox(pub Vec<OutFrame>);

/// A frame delivered to a vehicle.
#[derive(Clone, Debug, PartialEq)]
pub struct Received {
    /// End of the reception [s].
    pub t: f64,
    /// Sending vehicle (from the link-layer header).
    pub from: u32,
    /// Sender's frame sequence number.
    pub seq: u32,
    /// Which of this vehicle's modems received it.
    pub modem: usize,
    /// Received optical power at that modem [W].
    pub power: f64,
    /// Electrical SNR of the reception.
    pub snr: f64,
    /// Time the sender handed the frame over [s].
    pub sent: f64,
    /// Payload.
    pub payload: Arc<[u8]>,
}

/// Frames received since the vehicle's behaviour last looked.
#[derive(Component, Clone, Debug, Default)]
pub struct Inbox(pub Vec<Received>);

#[derive(Clone, Debug)]
struct Queued {
    payload: Arc<[u8]>,
    ready: f64,
    seq: u32,
}

/// One modem's transmit side.
#[derive(Clone, Debug, Default)]
pub struct ModemPort {
    queue: VecDeque<Queued>,
    busy_until: f64,
    /// Own transmissions (start, end) [s] still relevant for half-duplex checks.
    tx_log: VecDeque<(f64, f64)>,
}

impl ModemPort {
    /// Frames waiting.
    pub fn queued(&self) -> usize {
        self.queue.len()
    }

    fn transmitting_during(&self, start: f64, end: f64) -> bool {
        self.tx_log.iter().any(|&(s, e)| s < end && e > start)
    }
}

/// The modems of one vehicle (same order as its model's `modems`).
#[derive(Component, Clone, Debug, Default)]
pub struct Modems {
    /// One port per modem.
    pub ports: Vec<ModemPort>,
    next_seq: u32,
}

impl Modems {
    /// Ports for `n` modems.
    pub fn new(n: usize) -> Self {
        Self {
            ports: vec![ModemPort::default(); n],
            next_seq: 0,
        }
    }
}

/// The vehicle's own random stream for the medium (back-offs, reception draws).
#[derive(Component, Clone, Debug)]
pub struct CommRng(pub ChaCha8Rng);

/// How receptions of one sender's frames at one receiver ended.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct LinkStats {
    /// Frames whose sender was within the cut-off range.
    pub attempts: u64,
    /// Frames delivered.
    pub delivered: u64,
    /// Lost to range, angle (outside the LED's beam or the receiver's field of view) or bit
    /// errors.
    pub lost_range: u64,
    /// Lost because walls, obstacles, another hull or the water surface blocked the ray.
    pub lost_occlusion: u64,
    /// Lost to an overlapping frame that was not weak enough to capture over.
    pub lost_collision: u64,
    /// Lost because the receiving modem was transmitting.
    pub lost_half_duplex: u64,
    /// Sum of hand-over-to-delivery latencies of delivered frames [s].
    pub latency_sum_s: f64,
    /// Time of the last delivery [s] (−∞ if none).
    #[serde(skip)]
    pub last_delivery: f64,
}

impl LinkStats {
    /// Adds another set of counters to this one.
    pub fn add(&mut self, o: &LinkStats) {
        self.attempts += o.attempts;
        self.delivered += o.delivered;
        self.lost_range += o.lost_range;
        self.lost_occlusion += o.lost_occlusion;
        self.lost_collision += o.lost_collision;
        self.lost_half_duplex += o.lost_half_duplex;
        self.latency_sum_s += o.latency_sum_s;
    }

    fn record(&mut self, outcome: Outcome, latency: f64, t: f64) {
        self.attempts += 1;
        match outcome {
            Outcome::Delivered => {
                self.delivered += 1;
                self.latency_sum_s += latency;
                self.last_delivery = t;
            }
            Outcome::Range => self.lost_range += 1,
            Outcome::Occluded => self.lost_occlusion += 1,
            Outcome::Collision => self.lost_collision += 1,
            Outcome::HalfDuplex => self.lost_half_duplex += 1,
        }
    }
}

/// Width of a distance bin of the delivery histogram [m].
pub const DIST_BIN: f64 = 0.1;
/// Number of distance bins.
pub const DIST_BINS: usize = 80;
/// Latency histogram: bin `k` holds latencies in [10^(k/10 − 3), 10^((k+1)/10 − 3)) s.
pub const LAT_BINS: usize = 60;

/// Communication counters of one vehicle.
#[derive(Component, Clone, Debug)]
pub struct CommStats {
    /// Frames put on the air (copies on several modems count once).
    pub sent: u64,
    /// Frames dropped because a transmit queue was full.
    pub queue_overflow: u64,
    /// Frames dropped because the payload was longer than the modem allows.
    pub oversize: u64,
    /// Carrier-sense deferrals.
    pub cs_deferrals: u64,
    /// Receptions, all senders together.
    pub rx: LinkStats,
    /// Receptions by sender.
    pub links: BTreeMap<u32, LinkStats>,
    /// Attempts and deliveries by sender distance ([`DIST_BIN`] bins).
    pub by_distance: Vec<(u64, u64)>,
    /// Latency histogram of deliveries (see [`LAT_BINS`]).
    pub latency_hist: Vec<u64>,
}

impl Default for CommStats {
    fn default() -> Self {
        Self {
            sent: 0,
            queue_overflow: 0,
            oversize: 0,
            cs_deferrals: 0,
            rx: LinkStats::default(),
            links: BTreeMap::new(),
            by_distance: vec![(0, 0); DIST_BINS],
            latency_hist: vec![0; LAT_BINS],
        }
    }
}

/// Latency histogram bin of a latency [s].
pub fn latency_bin(l: f64) -> usize {
    ((l.max(1e-3).log10() + 3.0) * 10.0)
        .floor()
        .clamp(0.0, (LAT_BINS - 1) as f64) as usize
}

/// Lower edge of a latency bin [s].
pub fn latency_bin_start(k: usize) -> f64 {
    10f64.powf(k as f64 / 10.0 - 3.0)
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Outcome {
    // Ordered by how close the frame came to arriving (the best one is reported when a
    // vehicle has several modems).
    Range,
    Occluded,
    HalfDuplex,
    Collision,
    Delivered,
}

/// A frame on the air.
#[derive(Clone, Debug)]
pub struct Transmission {
    /// Unique id in the run.
    pub id: u64,
    /// Sending vehicle.
    pub tx: u32,
    /// Sending modem.
    pub modem: usize,
    /// Start and end of the transmission [s].
    pub start: f64,
    /// End [s].
    pub end: f64,
    /// Sender's sequence number (copies on several modems share it).
    pub seq: u32,
    /// Time the frame was handed over [s].
    pub sent: f64,
    /// Payload.
    pub payload: Arc<[u8]>,
    /// Bits on the line.
    pub bits: u64,
    /// Where the sending modem was.
    pub pose: ModemPose,
}

/// A uniform grid of points for neighbour queries (cell = the query radius).
#[derive(Clone, Debug, Default)]
pub struct Grid {
    cell: f64,
    cells: HashMap<(i32, i32, i32), Vec<u32>>,
}

impl Grid {
    fn key(&self, p: &Vec3) -> (i32, i32, i32) {
        (
            (p.x / self.cell).floor() as i32,
            (p.y / self.cell).floor() as i32,
            (p.z / self.cell).floor() as i32,
        )
    }

    /// Rebuilds the grid over `points` (index = id) with cells of `cell` [m].
    pub fn rebuild(&mut self, cell: f64, points: impl Iterator<Item = (u32, Vec3)>) {
        self.cell = cell.max(1e-3);
        self.cells.values_mut().for_each(Vec::clear);
        for (id, p) in points {
            let k = self.key(&p);
            self.cells.entry(k).or_default().push(id);
        }
    }

    /// Ids in the 27 cells around `p` (a superset of those within one cell size).
    pub fn near(&self, p: &Vec3) -> impl Iterator<Item = u32> + '_ {
        let (x, y, z) = self.key(p);
        (-1..=1).flat_map(move |dx| {
            (-1..=1).flat_map(move |dy| {
                (-1..=1).flat_map(move |dz| {
                    self.cells
                        .get(&(x + dx, y + dy, z + dz))
                        .into_iter()
                        .flat_map(|v| v.iter().copied())
                })
            })
        })
    }
}

/// The optical medium of a world.
#[derive(Resource)]
pub struct Medium {
    /// Beam attenuation of the water [1/m].
    pub attenuation: f64,
    /// Ambient light.
    pub ambient: Ambient,
    /// Beyond this distance no frame can be decoded and no interference matters [m].
    pub r_cut: f64,
    /// Model of every vehicle, by id.
    pub kinds: Vec<Arc<VehicleModel>>,
    /// Body position and attitude of every vehicle this step, by id.
    pub poses: Vec<(Vec3, Quat)>,
    /// Transmissions still relevant (active, or ended recently enough to overlap a frame that
    /// is still to end), in start order.
    pub txs: Vec<Transmission>,
    /// Vehicles by position (cell = `r_cut`).
    pub grid: Grid,
    next_id: u64,
    max_airtime: f64,
    /// Deliveries so far (whole world), for progress and tests.
    pub delivered: u64,
}

/// Distance at which the best LED on axis gives the most sensitive receiver an SNR of 0.25
/// (thermal and dark noise only): beyond it no frame is decodable and interference is below a
/// quarter of the noise.
pub fn cutoff_range(modems: &[&ModemParams], attenuation: f64) -> f64 {
    let mut r: f64 = 0.0;
    for tx in modems {
        for rx in modems {
            let snr = |d: f64| {
                let p = tx.led.power
                    * channel_gain(&tx.led, &rx.rx, &LinkGeometry::on_axis(d), attenuation);
                let i = rx.rx.responsivity * p;
                i * i / noise_variance(&rx.rx, 0.0, 0.0, 0.0)
            };
            let (mut lo, mut hi): (f64, f64) = (1e-3, 1e4);
            for _ in 0..100 {
                let mid = (lo * hi).sqrt();
                if snr(mid) > 0.25 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            r = r.max(hi);
        }
    }
    r
}

impl Medium {
    /// The medium of a world whose vehicles (by id) have these models.
    pub fn new(kinds: Vec<Arc<VehicleModel>>, attenuation: f64, ambient: Ambient) -> Self {
        // Distinct modem designs (vehicles of a kind share their model).
        let mut modems: Vec<&ModemParams> = Vec::new();
        for m in kinds.iter().flat_map(|k| k.params.modems.iter()) {
            if !modems.iter().any(|x| x.led == m.led && x.rx == m.rx) {
                modems.push(m);
            }
        }
        let r_cut = if modems.is_empty() {
            0.0
        } else {
            cutoff_range(&modems, attenuation)
        };
        let max_airtime = modems
            .iter()
            .map(|m| m.airtime(m.max_payload))
            .fold(0.0, f64::max);
        let n = kinds.len();
        Self {
            attenuation,
            ambient,
            r_cut,
            kinds,
            poses: vec![(Vec3::zeros(), Quat::identity()); n],
            txs: Vec::new(),
            grid: Grid::default(),
            next_id: 0,
            max_airtime,
            delivered: 0,
        }
    }

    /// Whether any vehicle has a modem.
    pub fn active(&self) -> bool {
        self.r_cut > 0.0
    }

    /// Whether the straight ray between two points is free of other vehicles' hulls
    /// (`skip` are the two vehicles at its ends).
    fn hulls_clear(&self, a: &Vec3, b: &Vec3, skip: (u32, u32)) -> bool {
        let mid = (a + b) * 0.5;
        for id in self.grid.near(&mid) {
            if id == skip.0 || id == skip.1 {
                continue;
            }
            let (p, q) = &self.poses[id as usize];
            if segment_hits_hull(a, b, &self.kinds[id as usize].params.body.hull_size, p, q) {
                return false;
            }
        }
        true
    }
}

/// RNG stream of a vehicle's medium draws (see [`crate::sim::vehicle_rng`]).
pub fn comm_rng(seed: u64, id: u32) -> CommRng {
    let mut r = ChaCha8Rng::seed_from_u64(seed);
    r.set_stream(u64::from(id) * 16 + crate::sim::stream::COMM);
    CommRng(r)
}

/// Step phase 1: snapshot poses, rebuild the grid, prune old transmissions.
pub fn comm_snapshot_system(
    clock: Res<crate::components::Clock>,
    mut medium: ResMut<Medium>,
    mut q: Query<(&VehicleId, &Physics, &mut Modems, &Outbox)>,
) {
    if !medium.active() {
        return;
    }
    // Nothing on the air and nothing waiting to go: the medium has no work this step.
    let idle = medium.txs.is_empty()
        && q.iter().all(|(_, _, modems, out)| {
            out.0.is_empty() && modems.ports.iter().all(|p| p.queue.is_empty())
        });
    if idle {
        return;
    }
    let m = &mut *medium;
    for (id, p, _, _) in &q {
        m.poses[id.0 as usize] = (p.state.rigid.position, p.state.rigid.attitude);
    }
    // `near` covers ±1 cell, so a cell of r_cut finds everything within r_cut; the occlusion
    // query at a segment's midpoint needs r_cut/2 + a hull, also covered.
    m.grid.rebuild(
        m.r_cut,
        m.poses.iter().enumerate().map(|(i, (p, _))| (i as u32, *p)),
    );
    // A frame ending in the coming steps started at most `max_airtime` before its end; what
    // ended before that can no longer overlap it.
    let horizon = clock.t() - m.max_airtime - clock.dt;
    m.txs.retain(|t| t.end > horizon);
    for (_, _, mut modems, _) in &mut q {
        for port in &mut modems.ports {
            while port.tx_log.front().is_some_and(|&(_, e)| e <= horizon) {
                port.tx_log.pop_front();
            }
        }
    }
}

/// Received optical power at a modem from every transmission active at time `t` except
/// those of vehicle `me` [W] (for carrier sense).
fn sensed_power(
    medium: &Medium,
    geo: &shoal_world::geometry::Geometry,
    me: u32,
    rx: &ModemParams,
    pose: &ModemPose,
    t: f64,
) -> f64 {
    medium
        .txs
        .iter()
        .filter(|x| x.tx != me && x.start <= t && x.end > t)
        .map(|x| {
            let g = LinkGeometry::between(&x.pose, pose);
            if g.distance > medium.r_cut {
                return 0.0;
            }
            let led = &medium.kinds[x.tx as usize].params.modems[x.modem].led;
            let gain = channel_gain(led, &rx.rx, &g, medium.attenuation);
            if gain > 0.0
                && geo.line_of_sight(&x.pose.position, &pose.position)
                && medium.hulls_clear(&x.pose.position, &pose.position, (x.tx, me))
            {
                led.power * gain
            } else {
                0.0
            }
        })
        .sum()
}

#[derive(PartialEq)]
struct StartEvent {
    t: f64,
    vehicle: u32,
    modem: usize,
}

impl Eq for StartEvent {}
impl PartialOrd for StartEvent {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for StartEvent {
    // Earliest first in a max-heap; ties by vehicle, then modem.
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        o.t.total_cmp(&self.t)
            .then(o.vehicle.cmp(&self.vehicle))
            .then(o.modem.cmp(&self.modem))
    }
}

/// Step phase 2: queue handed-over frames and start transmissions in time order.
pub fn comm_transmit_system(
    clock: Res<crate::components::Clock>,
    geo: Res<StaticGeometry>,
    mut medium: ResMut<Medium>,
    mut q: Query<(
        &VehicleId,
        &Kind,
        &mut Outbox,
        &mut Modems,
        &mut CommRng,
        &mut CommStats,
    )>,
) {
    if !medium.active() {
        return;
    }
    let pending = |out: &Outbox, modems: &Modems| {
        !out.0.is_empty() || modems.ports.iter().any(|p| !p.queue.is_empty())
    };
    if !q
        .iter()
        .any(|(_, _, out, modems, _, _)| pending(out, modems))
    {
        return;
    }
    let t_end = clock.t() + clock.dt;
    let mut items: Vec<_> = q.iter_mut().filter(|it| pending(&it.2, &it.3)).collect();
    items.sort_by_key(|it| it.0.0);
    let mut heap = BinaryHeap::new();
    for (id, kind, outbox, modems, _, stats) in &mut items {
        let params = &kind.0.params.modems;
        let modems = &mut **modems;
        for f in outbox.0.drain(..) {
            let targets: Vec<usize> = match f.modem {
                Some(k) if k < params.len() => vec![k],
                Some(_) => continue,
                None => (0..params.len()).collect(),
            };
            if targets
                .iter()
                .any(|&k| f.payload.len() > params[k].max_payload)
            {
                stats.oversize += 1;
                continue;
            }
            let seq = modems.next_seq;
            modems.next_seq = modems.next_seq.wrapping_add(1);
            let payload: Arc<[u8]> = f.payload.into();
            let mut queued_any = false;
            for k in targets {
                let port = &mut modems.ports[k];
                if port.queue.len() >= params[k].queue_frames {
                    stats.queue_overflow += 1;
                } else {
                    port.queue.push_back(Queued {
                        payload: payload.clone(),
                        ready: f.ready,
                        seq,
                    });
                    queued_any = true;
                }
            }
            if queued_any {
                stats.sent += 1;
            }
        }
        for (k, port) in modems.ports.iter().enumerate() {
            if let Some(front) = port.queue.front() {
                let start = front.ready.max(port.busy_until).max(clock.t());
                if start < t_end {
                    heap.push(StartEvent {
                        t: start,
                        vehicle: id.0,
                        modem: k,
                    });
                }
            }
        }
    }
    let index: HashMap<u32, usize> = items
        .iter()
        .enumerate()
        .map(|(i, it)| (it.0.0, i))
        .collect();
    let m = &mut *medium;
    let mut backoffs: HashMap<(u32, u64), f64> = HashMap::new();
    while let Some(ev) = heap.pop() {
        let (_, kind, _, modems, rng, stats) = &mut items[index[&ev.vehicle]];
        let params = &kind.0.params.modems[ev.modem];
        let (pos, att) = m.poses[ev.vehicle as usize];
        let pose = ModemPose::of(params, &pos, &att);
        // Carrier sense listens with all of the vehicle's photodiodes, and all modems of a
        // vehicle that defer at the same moment share one back-off, so that copies of a frame
        // on several modems stay in sync.
        if let Access::CarrierSense {
            threshold,
            backoff_max,
        } = params.access
            && kind.0.params.modems.iter().any(|rxm| {
                sensed_power(
                    m,
                    &geo.0,
                    ev.vehicle,
                    rxm,
                    &ModemPose::of(rxm, &pos, &att),
                    ev.t,
                ) > threshold
            })
        {
            let retry = *backoffs
                .entry((ev.vehicle, ev.t.to_bits()))
                .or_insert_with(|| {
                    stats.cs_deferrals += 1;
                    ev.t + rng.0.random::<f64>() * backoff_max
                });
            modems.ports[ev.modem].busy_until = retry;
            if retry < t_end {
                heap.push(StartEvent { t: retry, ..ev });
            }
            continue;
        }
        let port = &mut modems.ports[ev.modem];
        let Some(frame) = port.queue.pop_front() else {
            continue;
        };
        let end = ev.t + params.airtime(frame.payload.len());
        port.busy_until = end;
        port.tx_log.push_back((ev.t, end));
        m.txs.push(Transmission {
            id: m.next_id,
            tx: ev.vehicle,
            modem: ev.modem,
            start: ev.t,
            end,
            seq: frame.seq,
            sent: frame.ready,
            bits: params.frame_bits(frame.payload.len()),
            payload: frame.payload,
            pose,
        });
        m.next_id += 1;
        if let Some(next) = port.queue.front() {
            let start = next.ready.max(end);
            if start < t_end {
                heap.push(StartEvent {
                    t: start,
                    vehicle: ev.vehicle,
                    modem: ev.modem,
                });
            }
        }
    }
}

/// A frame as the receivers see it: all copies of one sender's frame that started together.
struct Logical<'a> {
    copies: Vec<&'a Transmission>,
}

impl Logical<'_> {
    fn first(&self) -> &Transmission {
        self.copies[0]
    }
}

/// Step phase 3: decide every reception of frames that ended in this step.
pub fn comm_deliver_system(
    clock: Res<crate::components::Clock>,
    par: Res<Parallel>,
    geo: Res<StaticGeometry>,
    mut medium: ResMut<Medium>,
    mut q: Query<(
        &VehicleId,
        &Kind,
        &Modems,
        &mut Inbox,
        &mut CommRng,
        &mut CommStats,
    )>,
) {
    if !medium.active() {
        return;
    }
    let (t0, t_end) = (clock.t(), clock.t() + clock.dt);
    let m = &*medium;
    // Frames ending in (t0, t_end], grouped into logical frames, in (end, id) order.
    let mut ended: Vec<&Transmission> = m
        .txs
        .iter()
        .filter(|x| x.end > t0 && x.end <= t_end)
        .collect();
    ended.sort_by(|a, b| a.end.total_cmp(&b.end).then(a.id.cmp(&b.id)));
    let mut logical: Vec<Logical<'_>> = Vec::new();
    let mut by_key: HashMap<(u32, u32, u64), usize> = HashMap::new();
    for t in ended {
        let key = (t.tx, t.seq, t.start.to_bits());
        match by_key.get(&key) {
            Some(&i) => logical[i].copies.push(t),
            None => {
                by_key.insert(key, logical.len());
                logical.push(Logical { copies: vec![t] });
            }
        }
    }
    if logical.is_empty() {
        return;
    }
    // Candidate receivers of each logical frame.
    let mut per_rx: HashMap<u32, Vec<usize>> = HashMap::new();
    for (i, l) in logical.iter().enumerate() {
        let f = l.first();
        let p = &m.poses[f.tx as usize].0;
        for id in m.grid.near(p) {
            if id != f.tx && (m.poses[id as usize].0 - p).norm() <= m.r_cut + 0.5 {
                per_rx.entry(id).or_default().push(i);
            }
        }
    }
    let mut items: Vec<_> = q
        .iter_mut()
        .filter(|it| per_rx.contains_key(&it.0.0))
        .collect();
    let geo = &geo.0;
    let delivered = std::sync::atomic::AtomicU64::new(0);
    par.for_each(&mut items, |(id, kind, modems, inbox, rng, stats)| {
        let frames = &per_rx[&id.0];
        for &i in frames {
            let l = &logical[i];
            if receive(m, geo, id.0, &kind.0, modems, l, &mut rng.0, stats, inbox) {
                delivered.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            }
        }
    });
    medium.delivered += delivered.into_inner();
}

/// Decides one logical frame at one receiver; returns whether it was delivered.
#[allow(clippy::too_many_arguments)]
fn receive(
    m: &Medium,
    geo: &shoal_world::geometry::Geometry,
    me: u32,
    kind: &VehicleModel,
    modems: &Modems,
    l: &Logical<'_>,
    rng: &mut ChaCha8Rng,
    stats: &mut CommStats,
    inbox: &mut Inbox,
) -> bool {
    let f = l.first();
    let (pos, att) = m.poses[me as usize];
    let sender = &m.kinds[f.tx as usize];
    let mut best = Outcome::Range;
    let mut got: Option<(usize, f64, f64)> = None;
    for (k, rxm) in kind.params.modems.iter().enumerate() {
        let pose = ModemPose::of(rxm, &pos, &att);
        // Signal: the sum of the copies this modem can see.
        let mut p_sig = 0.0;
        let mut outcome = Outcome::Range;
        for c in &l.copies {
            let led = &sender.params.modems[c.modem].led;
            let g = LinkGeometry::between(&c.pose, &pose);
            let gain = channel_gain(led, &rxm.rx, &g, m.attenuation);
            if gain <= 0.0 {
                continue;
            }
            let clear = c.pose.position.z > 0.0
                && pose.position.z > 0.0
                && geo.line_of_sight(&c.pose.position, &pose.position)
                && m.hulls_clear(&c.pose.position, &pose.position, (c.tx, me));
            if clear {
                p_sig += led.power * gain;
            } else {
                outcome = outcome.max(Outcome::Occluded);
            }
        }
        if p_sig <= 0.0 {
            best = best.max(outcome);
            continue;
        }
        if modems
            .ports
            .get(k)
            .is_some_and(|p| p.transmitting_during(f.start, f.end))
        {
            best = best.max(Outcome::HalfDuplex);
            continue;
        }
        // Interference: other transmissions overlapping this frame in time.
        let (mut p_int, mut p_max) = (0.0f64, 0.0f64);
        for x in &m.txs {
            if x.start >= f.end
                || x.end <= f.start
                || x.tx == me
                || (x.tx == f.tx && x.seq == f.seq)
            {
                continue;
            }
            let g = LinkGeometry::between(&x.pose, &pose);
            if g.distance > m.r_cut {
                continue;
            }
            let led = &m.kinds[x.tx as usize].params.modems[x.modem].led;
            let gain = channel_gain(led, &rxm.rx, &g, m.attenuation);
            if gain <= 0.0
                || !geo.line_of_sight(&x.pose.position, &pose.position)
                || !m.hulls_clear(&x.pose.position, &pose.position, (x.tx, me))
            {
                continue;
            }
            let p = led.power * gain;
            p_int += p;
            p_max = p_max.max(p);
        }
        if p_max * rxm.capture_ratio > p_sig {
            best = best.max(Outcome::Collision);
            continue;
        }
        let b = reception(&rxm.rx, p_sig, &m.ambient, pose.position.z, p_int, f.bits);
        if rng.random::<f64>() < b.fer {
            best = best.max(Outcome::Range);
            continue;
        }
        best = Outcome::Delivered;
        if got.is_none_or(|g| p_sig > g.1) {
            got = Some((k, p_sig, b.snr));
        }
    }
    let distance = (m.poses[f.tx as usize].0 - pos).norm();
    let latency = f.end - f.sent;
    stats.rx.record(best, latency, f.end);
    stats
        .links
        .entry(f.tx)
        .or_insert_with(|| LinkStats {
            last_delivery: f64::NEG_INFINITY,
            ..Default::default()
        })
        .record(best, latency, f.end);
    let bin = ((distance / DIST_BIN) as usize).min(DIST_BINS - 1);
    stats.by_distance[bin].0 += 1;
    if let Some((modem, power, snr)) = got {
        stats.by_distance[bin].1 += 1;
        stats.latency_hist[latency_bin(latency)] += 1;
        inbox.0.push(Received {
            t: f.end,
            from: f.tx,
            seq: f.seq,
            modem,
            power,
            snr,
            sent: f.sent,
            payload: f.payload.clone(),
        });
        true
    } else {
        false
    }
}
