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
use crate::sim::VehicleRng;
use bevy_ecs::prelude::*;
use rand::RngExt;
use serde::Serialize;
use shoal_model::math::{Quat, Vec3};
use shoal_model::optics::{
    Access, Ambient, LinkGeometry, ModemParams, ModemPose, background_current, ber_ook,
    channel_gain, frame_error_rate, lambertian_order, noise_variance, reception,
};
use shoal_model::vehicle::VehicleModel;
use shoal_world::geometry::segment_hits_hull;
use std::collections::{BinaryHeap, HashMap, VecDeque};
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::atomic::AtomicU64;
use std::sync::atomic::Ordering::Relaxed;

/// A fixed multiplicative hash for vehicle ids: fast, and the same in every run.
#[derive(Clone, Copy, Debug, Default)]
pub struct IdHasher(u64);

impl Hasher for IdHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 = (self.0.rotate_left(8) ^ u64::from(*b)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        }
    }
    fn write_u32(&mut self, i: u32) {
        self.0 = (u64::from(i) ^ self.0).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
}

/// Per-sender statistics of one receiver (iterate in sorted order for output).
pub type LinkMap = HashMap<u32, LinkStats, BuildHasherDefault<IdHasher>>;
use std::sync::Arc;

/// A frame handed to a vehicle's modem(s) by a behaviour or an agent.
#[derive(Clone, Debug, PartialEq)]
pub struct OutFrame {
    /// Modem index, or `None` for a copy on every modem (sent in sync).
    pub modem: Option<usize>,
    /// Payload bytes (the link-layer header is added on the air).
    pub payload: Vec<u8>,
    /// Time at which the frame is handed over \[s\].
    pub ready: f64,
}

/// Frames waiting to be handed to the modems.
#[derive(Component, Clone, Debug, Default)]
pub struct Outbox(pub Vec<OutFrame>);

/// A frame delivered to a vehicle.
#[derive(Clone, Debug, PartialEq)]
pub struct Received {
    /// End of the reception \[s\].
    pub t: f64,
    /// Sending vehicle (from the link-layer header).
    pub from: u32,
    /// Sender's frame sequence number.
    pub seq: u32,
    /// Which of this vehicle's modems received it.
    pub modem: usize,
    /// Received optical power at that modem \[W\].
    pub power: f64,
    /// Electrical SNR of the reception.
    pub snr: f64,
    /// Time the sender handed the frame over \[s\].
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
pub struct CommRng(pub VehicleRng);

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
    /// Sum of hand-over-to-delivery latencies of delivered frames \[s\].
    pub latency_sum_s: f64,
    /// Time of the last delivery \[s\] (−∞ if none).
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

/// Width of a distance bin of the delivery histogram \[m\].
pub const DIST_BIN: f64 = 0.1;
/// Number of distance bins.
pub const DIST_BINS: usize = 80;
/// Latency histogram: 20 bins per decade from 0.1 ms to 100 s; bin `k` holds latencies in
/// [10^(k/20 − 4), 10^((k+1)/20 − 4)) s.
pub const LAT_BINS: usize = 120;

/// Communication counters of one vehicle.
#[derive(Component, Clone, Debug, Default)]
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
    links: LinkMap,
    /// Reception outcomes not yet folded into `links` (appending is cheap; the map is updated
    /// in batches, while it is in cache).
    pending: Vec<LinkEvent>,
}

#[derive(Clone, Copy, Debug)]
struct LinkEvent {
    from: u32,
    outcome: Outcome,
    latency: f64,
    t: f64,
}

/// Events gathered before they are folded into the per-sender map.
const FOLD_BATCH: usize = 32;

impl CommStats {
    fn record(&mut self, from: u32, outcome: Outcome, latency: f64, t: f64) {
        self.rx.record(outcome, latency, t);
        self.pending.push(LinkEvent {
            from,
            outcome,
            latency,
            t,
        });
        if self.pending.len() >= FOLD_BATCH {
            self.fold();
        }
    }

    /// Folds buffered outcomes into the per-sender statistics.
    pub fn fold(&mut self) {
        for e in self.pending.drain(..) {
            self.links
                .entry(e.from)
                .or_insert_with(|| LinkStats {
                    last_delivery: f64::NEG_INFINITY,
                    ..Default::default()
                })
                .record(e.outcome, e.latency, e.t);
        }
    }

    /// Receptions by sender (complete after [`CommStats::fold`]; snapshots are folded).
    pub fn links(&self) -> &LinkMap {
        &self.links
    }
}

/// Latency histogram bin of a latency \[s\].
pub fn latency_bin(l: f64) -> usize {
    ((l.max(1e-4).log10() + 4.0) * 20.0)
        .floor()
        .clamp(0.0, (LAT_BINS - 1) as f64) as usize
}

/// Geometric centre of a latency bin \[s\] (within ±6 % of any latency in it).
pub fn latency_bin_centre(k: usize) -> f64 {
    10f64.powf((k as f64 + 0.5) / 20.0 - 4.0)
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
    /// Start and end of the transmission \[s\].
    pub start: f64,
    /// End \[s\].
    pub end: f64,
    /// Sender's sequence number (copies on several modems share it).
    pub seq: u32,
    /// Time the frame was handed over \[s\].
    pub sent: f64,
    /// Payload.
    pub payload: Arc<[u8]>,
    /// Bits on the line.
    pub bits: u64,
    /// Where the sending modem was.
    pub pose: ModemPose,
}

/// A dense uniform grid of points (compressed rows: ids sorted by cell), rebuilt every step by
/// a counting sort; box queries index it directly.
#[derive(Clone, Debug, Default)]
pub struct Grid {
    origin: Vec3,
    cell: f64,
    dims: [usize; 3],
    start: Vec<u32>,
    ids: Vec<u32>,
}

impl Grid {
    fn coord(&self, p: &Vec3) -> [usize; 3] {
        let c =
            |v: f64, o: f64, n: usize| (((v - o) / self.cell).floor().max(0.0) as usize).min(n - 1);
        [
            c(p.x, self.origin.x, self.dims[0]),
            c(p.y, self.origin.y, self.dims[1]),
            c(p.z, self.origin.z, self.dims[2]),
        ]
    }

    fn flat(&self, c: [usize; 3]) -> usize {
        (c[0] * self.dims[1] + c[1]) * self.dims[2] + c[2]
    }

    /// Rebuilds the grid over `points` (index = id) with cells of about `cell` \[m\] (larger if
    /// the points spread so far that the grid would exceed a few cells per point).
    pub fn rebuild(&mut self, cell: f64, points: &[Vec3]) {
        let (mut lo, mut hi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
        for p in points {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        if points.is_empty() {
            lo = Vec3::zeros();
            hi = Vec3::zeros();
        }
        let mut cell = cell.max(1e-3);
        let budget = 4 * points.len() + 4096;
        let dims = |cell: f64| {
            let n = |a: f64, b: f64| ((b - a) / cell).floor() as usize + 1;
            [n(lo.x, hi.x), n(lo.y, hi.y), n(lo.z, hi.z)]
        };
        while dims(cell).iter().product::<usize>() > budget {
            cell *= 1.5;
        }
        self.origin = lo;
        self.cell = cell;
        self.dims = dims(cell);
        let cells = self.dims.iter().product::<usize>();
        self.start.clear();
        self.start.resize(cells + 1, 0);
        for p in points {
            let k = self.flat(self.coord(p));
            self.start[k + 1] += 1;
        }
        for k in 0..cells {
            self.start[k + 1] += self.start[k];
        }
        self.ids.clear();
        self.ids.resize(points.len(), 0);
        let mut fill = self.start.clone();
        for (i, p) in points.iter().enumerate() {
            let k = self.flat(self.coord(p));
            self.ids[fill[k] as usize] = i as u32;
            fill[k] += 1;
        }
    }

    /// Calls `f` with every id whose cell overlaps the box `lo … hi` \[m\] (a superset of the
    /// points inside it); stops early when `f` returns `false`. Returns whether it ran to the end.
    pub fn each_in_box(&self, lo: &Vec3, hi: &Vec3, mut f: impl FnMut(u32) -> bool) -> bool {
        if self.dims[0] == 0 {
            return true;
        }
        let (a, b) = (self.coord(lo), self.coord(hi));
        for x in a[0]..=b[0] {
            for y in a[1]..=b[1] {
                let row = self.flat([x, y, 0]);
                let (s, e) = (
                    self.start[row + a[2]] as usize,
                    self.start[row + b[2] + 1] as usize,
                );
                for &id in &self.ids[s..e] {
                    if !f(id) {
                        return false;
                    }
                }
            }
        }
        true
    }
}

/// Per-modem constants of the link budget, precomputed once per design.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModemConsts {
    /// P_t (m+1)/(2π) of the LED \[W\].
    pub coef: f64,
    /// Lambertian order m.
    pub order: f64,
    /// cos of the receiver's field of view.
    pub cos_fov: f64,
    /// Photodiode area \[m²\].
    pub area: f64,
}

impl ModemConsts {
    /// The constants of a modem.
    pub fn of(m: &ModemParams) -> Self {
        let order = lambertian_order(m.led.half_angle);
        Self {
            coef: m.led.power * (order + 1.0) / (2.0 * std::f64::consts::PI),
            order,
            cos_fov: m.rx.fov.cos(),
            area: m.rx.area,
        }
    }
}

/// Received optical power \[W\]: `P_t · H` of [`shoal_model::optics::channel_gain`] with the
/// constants precomputed.
#[inline]
pub fn received_power(
    tx: &ModemConsts,
    rx: &ModemConsts,
    g: &LinkGeometry,
    attenuation: f64,
) -> f64 {
    if g.cos_tx <= 0.0 || g.cos_rx < rx.cos_fov || g.distance <= 0.0 {
        return 0.0;
    }
    let ct = if (tx.order - 1.0).abs() < 1e-9 {
        g.cos_tx
    } else {
        g.cos_tx.powf(tx.order)
    };
    tx.coef / (g.distance * g.distance)
        * ct
        * rx.area
        * g.cos_rx
        * (-attenuation * g.distance).exp()
}

/// The optical medium of a world.
#[derive(Resource)]
pub struct Medium {
    /// Beam attenuation of the water [1/m].
    pub attenuation: f64,
    /// Ambient light.
    pub ambient: Ambient,
    /// Beyond this distance no frame can be decoded and no interference matters \[m\].
    pub r_cut: f64,
    /// Model of every vehicle, by id.
    pub kinds: Vec<Arc<VehicleModel>>,
    /// Body position and attitude of every vehicle this step, by id.
    pub poses: Vec<(Vec3, Quat)>,
    /// Transmissions still relevant (active, or ended recently enough to overlap a frame that
    /// is still to end), in start order.
    pub txs: Vec<Transmission>,
    /// Vehicles by position.
    pub grid: Grid,
    /// Link-budget constants of every vehicle's modems, by id.
    pub consts: Vec<Arc<[ModemConsts]>>,
    /// Squared bounding-sphere radius of every vehicle's hull, by id [m²].
    hull_r2: Vec<f64>,
    next_id: u64,
    max_airtime: f64,
    /// Deliveries so far (whole world), for progress and tests.
    pub delivered: u64,
    /// Transmissions started so far, and their total line bits (for the mean frame length).
    pub started: (u64, u64),
    /// Largest hull bounding-sphere radius [m].
    max_hull_radius: f64,
    /// Attempts and deliveries by distance between sender and receiver ([`DIST_BIN`] bins).
    by_distance: Vec<(AtomicU64, AtomicU64)>,
    /// Latency histogram of deliveries (see [`LAT_BINS`]).
    latency_hist: Vec<AtomicU64>,
    /// Distinct receivers in the world (for [`Medium::dead_distance`]).
    receivers: Vec<shoal_model::optics::Receiver>,
    dead_cache: std::sync::Mutex<HashMap<u64, f64>>,
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
        let mut receivers: Vec<shoal_model::optics::Receiver> = Vec::new();
        for m in &modems {
            if !receivers.contains(&m.rx) {
                receivers.push(m.rx.clone());
            }
        }
        let max_hull_radius = kinds
            .iter()
            .map(|k| 0.5 * k.params.body.hull_size.norm())
            .fold(0.0, f64::max);
        let hull_r2 = kinds
            .iter()
            .map(|k| 0.25 * k.params.body.hull_size.norm_squared())
            .collect();
        let mut by_kind: HashMap<*const VehicleModel, Arc<[ModemConsts]>> = HashMap::new();
        let consts = kinds
            .iter()
            .map(|k| {
                by_kind
                    .entry(Arc::as_ptr(k))
                    .or_insert_with(|| k.params.modems.iter().map(ModemConsts::of).collect())
                    .clone()
            })
            .collect();
        Self {
            attenuation,
            ambient,
            r_cut,
            kinds,
            poses: vec![(Vec3::zeros(), Quat::identity()); n],
            txs: Vec::new(),
            grid: Grid::default(),
            consts,
            hull_r2,
            next_id: 0,
            max_airtime,
            delivered: 0,
            started: (0, 0),
            max_hull_radius,
            by_distance: (0..DIST_BINS)
                .map(|_| (AtomicU64::new(0), AtomicU64::new(0)))
                .collect(),
            latency_hist: (0..LAT_BINS).map(|_| AtomicU64::new(0)).collect(),
            receivers,
            dead_cache: std::sync::Mutex::new(HashMap::new()),
        }
    }

    /// Optical power [W] that transmission `x` delivers to a receiving modem at `rx` with
    /// constants `rc` (no occlusion test); cheap rejections come before any root or exponential.
    #[inline]
    fn power_between(&self, x: &Transmission, rx: &ModemPose, rc: &ModemConsts) -> f64 {
        let d = rx.position - x.pose.position;
        let along = x.pose.axis.dot(&d);
        if along <= 0.0 {
            return 0.0; // behind the LED
        }
        let d2 = d.norm_squared();
        if d2 > self.r_cut * self.r_cut || d2 <= 0.0 {
            return 0.0;
        }
        let dist = d2.sqrt();
        let cos_rx = -rx.axis.dot(&d) / dist;
        if cos_rx < rc.cos_fov {
            return 0.0; // outside the receiver's field of view
        }
        let g = LinkGeometry {
            distance: dist,
            cos_tx: along / dist,
            cos_rx,
        };
        received_power(
            &self.consts[x.tx as usize][x.modem],
            rc,
            &g,
            self.attenuation,
        )
    }

    /// Received optical power [W] below which a frame of `bits` line bits fails with
    /// probability > 1 − 10⁻¹² at every receiver design in the world, without ambient light or
    /// interference (noise only grows from there).
    fn dead_power(&self, bits: u64) -> f64 {
        if let Some(p) = self
            .dead_cache
            .lock()
            .ok()
            .and_then(|c| c.get(&bits).copied())
        {
            return p;
        }
        let dark = Ambient {
            surface_irradiance: 0.0,
            diffuse_attenuation: 0.0,
        };
        let p = self
            .receivers
            .iter()
            .map(|rx| {
                // Bisection on log power: FER falls monotonically with power.
                let (mut lo, mut hi): (f64, f64) = (1e-30, 1.0);
                for _ in 0..200 {
                    let mid = (lo * hi).sqrt();
                    if reception(rx, mid, &dark, 1.0, 0.0, bits).fer > 1.0 - 1e-12 {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                lo
            })
            .fold(f64::INFINITY, f64::min);
        if let Ok(mut c) = self.dead_cache.lock() {
            c.insert(bits, p);
        }
        p
    }

    /// An upper bound of the power that frame `l` can deliver to any modem of vehicle `me`:
    /// every copy's LED gain taken at the most favourable direction within the receiver's
    /// hull, the photodiode on axis, the shortest possible distance.
    fn power_bound(&self, l: &Logical<'_>, me: u32, rx_area: f64) -> f64 {
        let (pos, _) = self.poses[me as usize];
        let r = self.hull_r2[me as usize].sqrt();
        l.copies
            .iter()
            .map(|c| {
                let d = pos - c.pose.position;
                let dist = d.norm();
                if dist <= r {
                    return f64::INFINITY;
                }
                let cos_phi = (c.pose.axis.dot(&d) / dist).clamp(-1.0, 1.0);
                let sin_delta = r / dist;
                let cos_delta = (1.0 - sin_delta * sin_delta).sqrt();
                // cos(φ − δ), or 1 when the cone of directions contains the LED axis.
                let sin_phi = (1.0 - cos_phi * cos_phi).sqrt();
                let cos_best = if cos_phi >= cos_delta {
                    1.0
                } else {
                    cos_phi * cos_delta + sin_phi * sin_delta
                };
                if cos_best <= 0.0 {
                    return 0.0;
                }
                let k = &self.consts[c.tx as usize][c.modem];
                let ct = if (k.order - 1.0).abs() < 1e-9 {
                    cos_best
                } else {
                    cos_best.powf(k.order)
                };
                let near = dist - r;
                k.coef * ct * rx_area * (-self.attenuation * near).exp() / (near * near)
            })
            .sum()
    }

    /// Attempts and deliveries by distance ([`DIST_BIN`] bins), whole world.
    pub fn delivery_by_distance(&self) -> Vec<(u64, u64)> {
        self.by_distance
            .iter()
            .map(|(a, d)| (a.load(Relaxed), d.load(Relaxed)))
            .collect()
    }

    /// Latency histogram of deliveries (see [`LAT_BINS`]), whole world.
    pub fn latency_histogram(&self) -> Vec<u64> {
        self.latency_hist.iter().map(|h| h.load(Relaxed)).collect()
    }

    /// Whether any vehicle has a modem.
    pub fn active(&self) -> bool {
        self.r_cut > 0.0
    }

    /// Whether the straight segment between two points passes through no hull other than
    /// those of `skip` (the vehicles at its ends).
    fn hulls_clear(&self, a: &Vec3, b: &Vec3, skip: (u32, u32)) -> bool {
        let r = self.max_hull_radius;
        let d = b - a;
        let len2 = d.norm_squared();
        self.grid.each_in_box(
            &(a.inf(b) - Vec3::repeat(r)),
            &(a.sup(b) + Vec3::repeat(r)),
            |id| {
                if id == skip.0 || id == skip.1 {
                    return true;
                }
                let (p, q) = &self.poses[id as usize];
                // Bounding sphere first (squared distances, no roots).
                let s = if len2 > 0.0 {
                    ((p - a).dot(&d) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                if (a + d * s - p).norm_squared() > self.hull_r2[id as usize] {
                    return true;
                }
                !segment_hits_hull(a, b, &self.kinds[id as usize].params.body.hull_size, p, q)
            },
        )
    }

    /// Hull occlusion between two vehicles, judged on the line between their centres: the
    /// modems sit on the hulls, within a hull radius of those centres, and the hulls of the two
    /// vehicles themselves are not counted.
    fn vehicles_clear(&self, from: u32, to: u32) -> bool {
        self.hulls_clear(
            &self.poses[from as usize].0,
            &self.poses[to as usize].0,
            (from, to),
        )
    }
}

/// RNG stream of a vehicle's medium draws (see [`crate::sim::vehicle_rng`]).
pub fn comm_rng(seed: u64, id: u32) -> CommRng {
    CommRng(crate::sim::vehicle_rng(seed, id, crate::sim::stream::COMM))
}

/// Step phase 1: snapshot poses, rebuild the grid, prune old transmissions.
pub fn comm_snapshot_system(
    clock: Res<crate::components::Clock>,
    mut medium: ResMut<Medium>,
    q: Query<(&VehicleId, &Physics, &Modems, &Outbox)>,
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
    // Cells of about a metre: small enough that an occlusion query along a link touches a few
    // dozen vehicles, large enough that a range query stays a few hundred cells.
    let cell = (2.0 * m.max_hull_radius).max(m.r_cut / 4.0);
    let points: Vec<Vec3> = m.poses.iter().map(|(p, _)| *p).collect();
    m.grid.rebuild(cell, &points);
    // A frame ending in the coming steps started at most `max_airtime` before its end; what
    // ended before that can no longer overlap it.
    let horizon = clock.t() - m.max_airtime - clock.dt;
    m.txs.retain(|t| t.end > horizon);
}

/// Received optical power at a modem from every transmission active at time `t` except
/// those of vehicle `me` [W] (for carrier sense).
fn sensed_power(
    medium: &Medium,
    geo: &shoal_world::geometry::Geometry,
    me: u32,
    k: usize,
    pose: &ModemPose,
    t: f64,
) -> f64 {
    let rx = &medium.consts[me as usize][k];
    medium
        .txs
        .iter()
        .filter(|x| x.tx != me && x.start <= t && x.end > t)
        .map(|x| {
            let g = LinkGeometry::between(&x.pose, pose);
            if g.distance > medium.r_cut {
                return 0.0;
            }
            let p = received_power(
                &medium.consts[x.tx as usize][x.modem],
                rx,
                &g,
                medium.attenuation,
            );
            if p > 0.0
                && geo.line_of_sight(&x.pose.position, &pose.position)
                && medium.vehicles_clear(x.tx, me)
            {
                p
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
            && kind.0.params.modems.iter().enumerate().any(|(k, rxm)| {
                sensed_power(
                    m,
                    &geo.0,
                    ev.vehicle,
                    k,
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
        // Own transmissions that ended before any frame still on the air began are no longer
        // needed for half-duplex checks.
        let horizon = ev.t - m.max_airtime - clock.dt;
        while port.tx_log.front().is_some_and(|&(_, e)| e <= horizon) {
            port.tx_log.pop_front();
        }
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
        m.started.0 += 1;
        m.started.1 += m.txs.last().map_or(0, |t| t.bits);
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
    /// Other transmissions overlapping this frame in time (possible interferers).
    overlap: Vec<&'a Transmission>,
    /// Received power below which this frame fails with probability > 1 − 10⁻¹² at every
    /// receiver design in the world (no ambient light, no interference) [W].
    p_dead: f64,
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
                logical.push(Logical {
                    copies: vec![t],
                    overlap: Vec::new(),
                    p_dead: 0.0,
                });
            }
        }
    }
    if logical.is_empty() {
        return;
    }
    for l in &mut logical {
        l.p_dead = m.dead_power(l.first().bits);
    }
    // Possible interferers of each frame: overlapping in time, and close enough to the sender
    // to reach a receiver that could hear the sender (within 2 r_cut). Transmissions are
    // indexed by position for this.
    let near = 2.0 * (m.r_cut + m.max_hull_radius);
    let tx_points: Vec<Vec3> = m.txs.iter().map(|x| x.pose.position).collect();
    let mut tx_grid = Grid::default();
    tx_grid.rebuild(near / 2.0, &tx_points);
    for l in &mut logical {
        let f = l.copies[0];
        let p = m.poses[f.tx as usize].0;
        let mut overlap = Vec::new();
        tx_grid.each_in_box(&(p - Vec3::repeat(near)), &(p + Vec3::repeat(near)), |k| {
            let x = &m.txs[k as usize];
            if x.start < f.end
                && x.end > f.start
                && !(x.tx == f.tx && x.seq == f.seq)
                && (x.pose.position - p).norm_squared() <= near * near
            {
                overlap.push(x);
            }
            true
        });
        // Grid order is spatial; keep the medium's order so results do not depend on it.
        overlap.sort_unstable_by_key(|x| x.id);
        l.overlap = overlap;
    }
    // Candidate receivers of each logical frame (vehicles within the cut-off range), as
    // (receiver, frame) pairs counting-sorted by receiver.
    let n = m.poses.len();
    let reach = m.r_cut + m.max_hull_radius;
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for (i, l) in logical.iter().enumerate() {
        let f = l.first();
        let p = m.poses[f.tx as usize].0;
        m.grid.each_in_box(
            &(p - Vec3::repeat(reach)),
            &(p + Vec3::repeat(reach)),
            |id| {
                if id != f.tx && (m.poses[id as usize].0 - p).norm_squared() <= reach * reach {
                    pairs.push((id, i as u32));
                }
                true
            },
        );
    }
    let mut start = vec![0u32; n + 1];
    for &(r, _) in &pairs {
        start[r as usize + 1] += 1;
    }
    for k in 0..n {
        start[k + 1] += start[k];
    }
    let mut frames_of = vec![0u32; pairs.len()];
    let mut fill = start.clone();
    // `pairs` is in frame order, so each receiver's frames stay in (end, id) order.
    for &(r, i) in &pairs {
        frames_of[fill[r as usize] as usize] = i;
        fill[r as usize] += 1;
    }
    let mut items: Vec<_> = q
        .iter_mut()
        .filter(|it| start[it.0.0 as usize + 1] > start[it.0.0 as usize])
        .collect();
    let geo = &geo.0;
    let delivered = AtomicU64::new(0);
    par.for_each(&mut items, |(id, kind, modems, inbox, rng, stats)| {
        let frames = &frames_of[start[id.0 as usize] as usize..start[id.0 as usize + 1] as usize];
        let mut scratch = Scratch::default();
        for &i in frames {
            let l = &logical[i as usize];
            if receive(
                m,
                geo,
                id.0,
                &kind.0,
                modems,
                l,
                &mut rng.0,
                stats,
                inbox,
                &mut scratch,
            ) {
                delivered.fetch_add(1, Relaxed);
            }
        }
    });
    medium.delivered += delivered.into_inner();
}

/// Buffers reused across the receptions of one receiver.
#[derive(Default)]
struct Scratch<'a> {
    interferers: Vec<&'a Transmission>,
    hulls: Vec<(u32, bool)>,
}

/// Decides one logical frame at one receiver; returns whether it was delivered.
#[allow(clippy::too_many_arguments)]
fn receive<'a>(
    m: &Medium,
    geo: &shoal_world::geometry::Geometry,
    me: u32,
    kind: &VehicleModel,
    modems: &Modems,
    l: &Logical<'a>,
    rng: &mut VehicleRng,
    stats: &mut CommStats,
    inbox: &mut Inbox,
    scratch: &mut Scratch<'a>,
) -> bool {
    let f = l.first();
    let (pos, att) = m.poses[me as usize];
    let latency = f.end - f.sent;
    let distance = (m.poses[f.tx as usize].0 - pos).norm();
    let area = m.consts[me as usize]
        .iter()
        .map(|c| c.area)
        .fold(0.0, f64::max);
    if m.power_bound(l, me, area) < l.p_dead {
        // Undecodable even in the best case (P(delivery) < 1e-12): lost to range.
        stats.record(f.tx, Outcome::Range, latency, f.end);
        let bin = ((distance / DIST_BIN) as usize).min(DIST_BINS - 1);
        m.by_distance[bin].0.fetch_add(1, Relaxed);
        return false;
    }
    let my = &m.consts[me as usize];
    let mut best = Outcome::Range;
    let mut got: Option<(usize, f64, f64)> = None;
    // Hull occlusion per other vehicle, computed once for this reception.
    let hulls = &mut scratch.hulls;
    hulls.clear();
    let mut clear_of_hulls = |other: u32| -> bool {
        if let Some(&(_, c)) = hulls.iter().find(|h| h.0 == other) {
            return c;
        }
        let c = m.vehicles_clear(other, me);
        hulls.push((other, c));
        c
    };
    let path_clear = |a: &ModemPose, b: &ModemPose| {
        a.position.z > 0.0 && b.position.z > 0.0 && geo.line_of_sight(&a.position, &b.position)
    };
    // Interferers within range of this receiver.
    let reach = m.r_cut + m.max_hull_radius;
    let interferers = &mut scratch.interferers;
    interferers.clear();
    interferers.extend(
        l.overlap
            .iter()
            .copied()
            .filter(|x| x.tx != me && (x.pose.position - pos).norm_squared() <= reach * reach),
    );
    for (k, rxm) in kind.params.modems.iter().enumerate() {
        let pose = ModemPose::of(rxm, &pos, &att);
        // Signal: the sum of the copies this modem can see.
        let mut p_sig = 0.0;
        let mut outcome = Outcome::Range;
        for c in &l.copies {
            let p = m.power_between(c, &pose, &my[k]);
            if p <= 0.0 {
                continue;
            }
            if path_clear(&c.pose, &pose) && clear_of_hulls(c.tx) {
                p_sig += p;
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
        for x in interferers.iter() {
            let p = m.power_between(x, &pose, &my[k]);
            if p <= 0.0 || !path_clear(&x.pose, &pose) || !clear_of_hulls(x.tx) {
                continue;
            }
            p_int += p;
            p_max = p_max.max(p);
        }
        if p_max * rxm.capture_ratio > p_sig {
            best = best.max(Outcome::Collision);
            continue;
        }
        // Delivered when a uniform draw is at least the frame error rate. The Chernoff bound
        // FER ≤ n·BER ≤ n·½·e^(−SNR/2) settles most draws without the error function; the
        // decision is exactly the one the full rate gives.
        let i_s = rxm.rx.responsivity * p_sig;
        let i_bg = background_current(&rxm.rx, &m.ambient, pose.position.z);
        let snr = i_s * i_s / noise_variance(&rxm.rx, i_s, i_bg, p_int);
        let u = rng.random::<f64>();
        let bound = f.bits as f64 * 0.5 * (-0.5 * snr).exp();
        if u < bound && u < frame_error_rate(ber_ook(snr), f.bits) {
            best = best.max(Outcome::Range);
            continue;
        }
        best = Outcome::Delivered;
        if got.is_none_or(|g| p_sig > g.1) {
            got = Some((k, p_sig, snr));
        }
    }
    stats.record(f.tx, best, latency, f.end);
    let bin = ((distance / DIST_BIN) as usize).min(DIST_BINS - 1);
    m.by_distance[bin].0.fetch_add(1, Relaxed);
    if let Some((modem, power, snr)) = got {
        m.by_distance[bin].1.fetch_add(1, Relaxed);
        m.latency_hist[latency_bin(latency)].fetch_add(1, Relaxed);
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

#[cfg(test)]
mod tests {
    use super::*;
    use shoal_model::optics::Led;
    use shoal_model::presets::uauv2_modem;

    #[test]
    fn precomputed_power_equals_the_link_budget() {
        let mut narrow = uauv2_modem();
        narrow.led = Led {
            power: 0.2,
            half_angle: 25f64.to_radians(),
        };
        for tx in [uauv2_modem(), narrow] {
            let rx = uauv2_modem();
            for (d, ct, cr) in [
                (1.0, 1.0, 1.0),
                (2.3, 0.8, 0.6),
                (3.1, 0.2, 0.51),
                (0.5, 0.95, 0.49),
                (1.0, -0.1, 1.0),
            ] {
                let g = LinkGeometry {
                    distance: d,
                    cos_tx: ct,
                    cos_rx: cr,
                };
                let want = tx.led.power * channel_gain(&tx.led, &rx.rx, &g, 0.1);
                let got = received_power(&ModemConsts::of(&tx), &ModemConsts::of(&rx), &g, 0.1);
                assert!(
                    (got - want).abs() <= 1e-12 * want.abs().max(1e-30),
                    "{got} vs {want}"
                );
            }
        }
    }

    /// A box query yields each point of the cells the box overlaps, once: every point inside
    /// the box, the points of those cells outside it (within one cell of the box), and no
    /// other point — checked against brute force for boxes inside, across and beyond the
    /// points, on a grid whose cell was enlarged to fit the budget and one that was not.
    #[test]
    fn dense_grid_box_query_finds_exactly_the_points_inside() {
        use std::collections::BTreeSet;
        let pts: Vec<Vec3> = (0..500)
            .map(|i| {
                let f = i as f64;
                Vec3::new((f * 0.37) % 9.0, (f * 0.61) % 7.0, (f * 0.13) % 2.0)
            })
            .collect();
        let boxes = [
            (Vec3::new(2.0, 1.5, 0.3), Vec3::new(5.5, 4.0, 1.2)),
            (Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.9, 0.9, 0.9)),
            // Beyond the points on every side: clamped to the outer cells.
            (Vec3::new(-3.0, 5.9, -1.0), Vec3::new(1.1, 9.0, 0.5)),
            (Vec3::new(8.2, -2.0, 1.7), Vec3::new(12.0, 0.4, 5.0)),
            // Thinner than a cell.
            (Vec3::new(4.0, 3.0, 1.0), Vec3::new(4.05, 3.05, 1.05)),
        ];
        for cell in [0.8, 0.05] {
            let mut g = Grid::default();
            g.rebuild(cell, &pts);
            assert!(g.cell >= cell);
            for (lo, hi) in &boxes {
                let mut found = Vec::new();
                assert!(g.each_in_box(lo, hi, |id| {
                    found.push(id);
                    true
                }));
                let set: BTreeSet<u32> = found.iter().copied().collect();
                assert_eq!(set.len(), found.len(), "no duplicates");
                // Brute force: the points whose cell lies in the box's range of cells.
                let (a, b) = (g.coord(lo), g.coord(hi));
                let in_cells: BTreeSet<u32> = (0..pts.len() as u32)
                    .filter(|&i| {
                        let c = g.coord(&pts[i as usize]);
                        (0..3).all(|k| a[k] <= c[k] && c[k] <= b[k])
                    })
                    .collect();
                assert_eq!(set, in_cells, "box {lo:?} … {hi:?}, cell {}", g.cell);
                // Independently of the cells: every point inside is found, and nothing more
                // than one cell outside the box on any axis.
                let within = |p: &Vec3, margin: f64| {
                    (0..3).all(|k| p[k] >= lo[k] - margin && p[k] <= hi[k] + margin)
                };
                let inside: BTreeSet<u32> = (0..pts.len() as u32)
                    .filter(|&i| within(&pts[i as usize], 0.0))
                    .collect();
                assert!(
                    inside.is_subset(&set),
                    "missed {:?}",
                    inside.difference(&set)
                );
                let far: Vec<u32> = set
                    .iter()
                    .copied()
                    .filter(|&i| !within(&pts[i as usize], g.cell))
                    .collect();
                assert!(far.is_empty(), "found points far outside the box: {far:?}");
                assert!(
                    set.len() < pts.len(),
                    "box {lo:?} … {hi:?} yields every point"
                );
            }
        }
        // The first box holds points, and points lie outside it.
        let (lo, hi) = boxes[0];
        let n_in = pts
            .iter()
            .filter(|p| (0..3).all(|k| p[k] >= lo[k] && p[k] <= hi[k]))
            .count();
        assert!(n_in > 10 && n_in < 250, "{n_in} points inside");
    }
}
