//! The optical medium itself: frames on the air ([`Transmission`]), the cut-off range of the
//! link budget ([`cutoff_range`]; the budget itself, with its precomputed constants, is
//! [`shoal_model::optics::received_power`]) and the
//! [`Medium`] resource with its power bounds and hull-occlusion tests.

use super::copy_lanes::{CopyChunk, bound_geometry};
use super::frames::Kind;
use super::grid::Grid;
use super::lanes::W;
use super::mac::{self, ModemLink};
use super::stats::{DIST_BINS, LAT_BINS};
use bevy_ecs::prelude::*;
use shoal_model::math::{Quat, Vec3};
use shoal_model::optics::{
    Ambient, LinkGeometry, ModemParams, ModemPose, channel_gain, noise_variance, reception,
};
pub use shoal_model::optics::{ModemConsts, received_power};
use shoal_model::vehicle::VehicleModel;
use shoal_world::access::LinkParams;
use shoal_world::geometry::segment_hits_hull;
use std::collections::HashMap;
use std::sync::Arc;

/// How far a vehicle may move before the medium's spatial grid is rebuilt \[m\] (see
/// [`Medium::update_grid`]): at a swarm's speeds of a few dm/s, a rebuild every few dozen
/// steps instead of every step, for query boxes a quarter metre wider.
pub const GRID_SKIN: f64 = 0.25;

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
    /// What it is to the link layer (broadcast, unicast, acknowledgement).
    pub kind: Kind,
}

#[cfg(test)]
impl Medium {
    /// A medium of vehicles of `kinds` (ALOHA on every modem, 3 retries, 50 ms for an
    /// acknowledgement) in dark water of attenuation 0.15 /m, seed 1 (for tests).
    pub(super) fn in_the_dark(kinds: Vec<Arc<VehicleModel>>) -> Self {
        let links: Vec<Arc<[LinkParams]>> = kinds
            .iter()
            .map(|k| {
                let link = LinkParams {
                    access: Default::default(),
                    retries: 3,
                    ack_timeout: 0.05,
                };
                vec![link; k.params.modems.len()].into()
            })
            .collect();
        let dark = Ambient {
            surface_irradiance: 0.0,
            diffuse_attenuation: 0.0,
        };
        Self::new(kinds, &links, 1, 0.15, dark)
    }
}

#[cfg(test)]
impl Transmission {
    /// An empty 256-bit frame of vehicle 0 on the air in [0, 10 ms], sent by its modem `modem`
    /// from `pose` (for tests of the geometry).
    pub(super) fn sent_from(id: u64, modem: usize, pose: ModemPose) -> Self {
        Self {
            id,
            tx: 0,
            modem,
            start: 0.0,
            end: 0.01,
            seq: 0,
            sent: 0.0,
            payload: Arc::from(&[][..]),
            bits: 256,
            pose,
            kind: Kind::Broadcast,
        }
    }
}

/// A frame as the receivers see it: all copies of one sender's frame that started together.
pub(super) struct Logical<'a> {
    /// The copies, in (end, id) order.
    pub(super) copies: &'a [&'a Transmission],
    /// The copies in lanes, in the same order.
    pub(super) lanes: &'a [CopyChunk],
    /// Other transmissions overlapping this frame in time (possible interferers), in id order.
    pub(super) overlap: &'a [&'a Transmission],
    /// Received power below which this frame fails with probability > 1 − 10⁻¹² at every
    /// receiver design in the world (no ambient light, no interference) [W].
    pub(super) p_dead: f64,
}

impl Logical<'_> {
    /// The first copy (sender, sequence number, start and payload are those of every copy).
    pub(super) fn first(&self) -> &Transmission {
        self.copies[0]
    }
}

/// The link layers of a vehicle's modems, in the model's order.
pub(super) type Protocols = Arc<[ModemLink]>;

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
    /// Link layer (medium access, retries) of every vehicle's modems, by id (shared by the
    /// vehicles of a group).
    pub(super) access: Vec<Protocols>,
    /// How long ended frames stay in [`Medium::txs`] for the medium-access protocols that look
    /// back ([`super::mac::MediumAccess::memory`]) \[s\].
    pub(super) memory: f64,
    /// How fast every vehicle's clock runs against true time, by id \[1\] (empty: every
    /// clock is exact; see [`Medium::clock_rate`]).
    clock_rates: Vec<f64>,
    /// Body position and attitude of every vehicle this step, by id (written by the vehicle
    /// pass, [`crate::systems::vehicle_system`], as it finishes each vehicle).
    pub poses: Vec<(Vec3, Quat)>,
    /// Transmissions still relevant (on the air, or ended after the earliest start of those on
    /// the air, so that they may overlap a frame still to end), in start order.
    pub txs: Vec<Transmission>,
    /// Vehicles by position, as they were at the grid's last rebuild (see
    /// [`Medium::update_grid`]).
    pub grid: Grid,
    /// Vehicle positions when the grid was last rebuilt, by id \[m\].
    grid_points: Vec<Vec3>,
    /// Largest distance any vehicle has moved since the grid was last rebuilt \[m\] (at most
    /// [`GRID_SKIN`]); every query box is widened by it.
    grid_slack: f64,
    /// Link-budget constants of every vehicle's modems, by id.
    pub consts: Vec<Arc<[ModemConsts]>>,
    /// Squared bounding-sphere radius of every vehicle's hull, by id [m²].
    hull_r2: Vec<f64>,
    /// Vehicles with frames queued at a modem after the last transmit phase, ascending, each
    /// with when its first frame is due at the earliest \[s\] ([`super::transmit::earliest`]).
    pub(super) waiting: Vec<(u32, f64)>,
    /// Vehicles whose link layer has work (an outstanding frame, frames behind it,
    /// acknowledgements to send or their feedback), as the last transmit or delivery phase
    /// left them; the transmit phase runs the link layer of these and of those that handed
    /// frames over only.
    pub(super) linked: Vec<u32>,
    pub(super) next_id: u64,
    /// Deliveries so far (whole world), for progress and tests.
    pub delivered: u64,
    /// Outcomes of acknowledged unicasts so far (acknowledged or given up, whole world).
    pub ended: u64,
    /// Per-flow measures of unicast traffic.
    pub(super) flows: super::flows::Flows,
    /// Ask the protocols that count back-off slots at every slot boundary, instead of once
    /// for a run of idle ones (`countdown.rs`): the same frames at the same instants, only
    /// slower — the reference the countdown is checked against. Off by default.
    pub slot_by_slot: bool,
    /// Transmissions started so far, and their total line bits (for the mean frame length).
    pub started: (u64, u64),
    /// Largest hull bounding-sphere radius [m].
    pub(super) max_hull_radius: f64,
    /// Largest distance of a modem from its hull's origin, any vehicle \[m\].
    pub(super) max_modem_offset: f64,
    /// Attempts and deliveries by distance between sender and receiver
    /// ([`DIST_BIN`](super::DIST_BIN) bins).
    pub(super) by_distance: Vec<(u64, u64)>,
    /// Latency histogram of deliveries (see [`LAT_BINS`]).
    pub(super) latency_hist: Vec<u64>,
    /// Latency histogram of acknowledged unicasts, hand-over to acknowledgement (see
    /// [`LAT_BINS`]).
    pub(super) ack_latency_hist: Vec<u64>,
    /// Reception attempts by second of the run (entry `k`: frames that ended in
    /// `[k, k + 1)` s) and outcome (index [`super::Outcome::index`]).
    pub per_second: Vec<[u64; 5]>,
    /// Whether every reception attempt is also logged for the replay, which drains them
    /// ([`super::Ledger::drain_heard`]).
    pub log_links: bool,
    /// Distinct receivers in the world (for [`Medium::dead_power`]).
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

/// Every vehicle's clock rate (1 + its error), by id: the error of a vehicle whose modems
/// allow a clock drift (the largest of its modems') times a number drawn once, uniformly in
/// [−1, 1), from its own stream; empty when no modem allows one.
fn clock_rates(access: &[Arc<[LinkParams]>], seed: u64) -> Vec<f64> {
    use rand::RngExt;
    let drift = |a: &[LinkParams]| a.iter().map(|x| x.access.clock_drift()).fold(0.0, f64::max);
    if access.iter().all(|a| drift(a) == 0.0) {
        return Vec::new();
    }
    access
        .iter()
        .enumerate()
        .map(|(id, a)| {
            let d = drift(a);
            if d == 0.0 {
                return 1.0;
            }
            let mut rng = crate::rng::vehicle_rng(seed, id as u32, crate::rng::stream::CLOCK);
            1.0 + d * (2.0 * rng.random::<f64>() - 1.0)
        })
        .collect()
}

impl Medium {
    /// The medium of a world whose vehicles (by id) have these models and these medium
    /// link layers of their modems; `seed`: the world's (for the vehicles' clock errors).
    pub fn new(
        kinds: Vec<Arc<VehicleModel>>,
        link: &[Arc<[LinkParams]>],
        seed: u64,
        attenuation: f64,
        ambient: Ambient,
    ) -> Self {
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
        let max_modem_offset = kinds
            .iter()
            .flat_map(|k| k.params.modems.iter())
            .map(|m| m.position.norm())
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
        let mut protocols: HashMap<*const [LinkParams], Protocols> = HashMap::new();
        let access_by_id = link
            .iter()
            .map(|a| {
                protocols
                    .entry(Arc::as_ptr(a))
                    .or_insert_with(|| a.iter().map(mac::build).collect())
                    .clone()
            })
            .collect();
        Self {
            attenuation,
            ambient,
            r_cut,
            kinds,
            memory: protocols
                .values()
                .flat_map(|p| p.iter())
                .map(|l| l.access.memory())
                .fold(0.0, f64::max),
            access: access_by_id,
            clock_rates: clock_rates(link, seed),
            poses: vec![(Vec3::zeros(), Quat::identity()); n],
            txs: Vec::new(),
            grid: Grid::default(),
            grid_points: Vec::new(),
            grid_slack: 0.0,
            consts,
            hull_r2,
            waiting: Vec::new(),
            linked: Vec::new(),
            next_id: 0,
            delivered: 0,
            ended: 0,
            flows: Default::default(),
            slot_by_slot: false,
            started: (0, 0),
            max_hull_radius,
            max_modem_offset,
            by_distance: vec![(0, 0); DIST_BINS],
            latency_hist: vec![0; LAT_BINS],
            ack_latency_hist: vec![0; LAT_BINS],
            per_second: Vec::new(),
            log_links: false,
            receivers,
            dead_cache: std::sync::Mutex::new(HashMap::new()),
        }
    }

    /// How fast vehicle `v`'s clock runs against true time \[1\].
    pub(super) fn clock_rate(&self, v: u32) -> f64 {
        self.clock_rates.get(v as usize).copied().unwrap_or(1.0)
    }

    /// Optical power [W] that transmission `x` delivers to a receiving modem at `rx` with
    /// constants `rc` (no occlusion test); cheap rejections come before any root or exponential.
    #[inline]
    pub(super) fn power_between(&self, x: &Transmission, rx: &ModemPose, rc: &ModemConsts) -> f64 {
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
    pub(super) fn dead_power(&self, bits: u64) -> f64 {
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

    /// Whether frame `l` may be decodable at vehicle `me` (photodiodes of at most `rx_area`
    /// \[m²\]): whether an upper bound of the power it can deliver to any modem of `me` — every
    /// copy's LED gain taken at the most favourable direction within the receiver's hull, the
    /// photodiode on axis, the shortest possible distance, summed over the copies in order —
    /// reaches [`Logical::p_dead`]. The terms are never negative, so the partial sums only
    /// grow: the sum stops at the first that reaches `p_dead`, with the full sum's decision.
    pub(super) fn may_decode(&self, l: &Logical<'_>, me: u32, rx_area: f64) -> bool {
        let (pos, _) = self.poses[me as usize];
        let r = self.hull_r2[me as usize].sqrt();
        // As `Iterator::sum` of f64.
        let mut sum = -0.0;
        for (copies, chunk) in l.copies.chunks(W).zip(l.lanes) {
            // The geometry of up to W copies at once; the terms in copy order.
            let g = bound_geometry(chunk, &pos, r);
            for (k, c) in copies.iter().enumerate() {
                sum += self.bound_term(c, g.dist[k], g.cos_best[k], r, rx_area);
                if sum >= l.p_dead {
                    return true;
                }
            }
        }
        // Not below p_dead, as the full sum's test was: a NaN bound never rejected a frame.
        sum.is_nan()
    }

    /// The term of copy `c` in [`Medium::may_decode`] for a receiver whose centre is `dist`
    /// \[m\] from the LED, with a hull of bounding radius `r` \[m\] seen from the LED at best
    /// `cos_best` \[1\] off its axis (see [`bound_geometry`]), and photodiodes of at most
    /// `rx_area` \[m²\] \[W\].
    fn bound_term(&self, c: &Transmission, dist: f64, cos_best: f64, r: f64, rx_area: f64) -> f64 {
        if dist <= r {
            return f64::INFINITY;
        }
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
    }

    /// Attempts and deliveries by distance ([`DIST_BIN`](super::DIST_BIN) bins), whole world.
    pub fn delivery_by_distance(&self) -> Vec<(u64, u64)> {
        self.by_distance.clone()
    }

    /// Latency histogram of deliveries (see [`LAT_BINS`]), whole world.
    pub fn latency_histogram(&self) -> Vec<u64> {
        self.latency_hist.clone()
    }

    /// Latency histogram of acknowledged unicasts, hand-over to acknowledgement (see
    /// [`LAT_BINS`]), whole world: its total is the number of frames acknowledged.
    pub fn ack_latency_histogram(&self) -> &[u64] {
        &self.ack_latency_hist
    }

    /// Per-flow measures of unicast traffic (sender → destination).
    pub fn flows(&self) -> &super::flows::Flows {
        &self.flows
    }

    /// Brings the spatial grid up to date with [`Medium::poses`], incrementally: the grid is
    /// rebuilt only when some vehicle has moved more than [`GRID_SKIN`] since the last
    /// rebuild; until then queries widen their boxes by the largest such move, so they still
    /// find every vehicle (a superset, which the callers' exact distance tests trim). Which
    /// grid is used never changes a result, only the work of finding candidates.
    pub fn update_grid(&mut self) {
        let moved2 = if self.grid_points.len() == self.poses.len() {
            self.poses
                .iter()
                .zip(&self.grid_points)
                .map(|((p, _), q)| (p - q).norm_squared())
                .fold(0.0, f64::max)
        } else {
            f64::INFINITY
        };
        if moved2 <= GRID_SKIN * GRID_SKIN {
            self.grid_slack = moved2.sqrt();
            return;
        }
        self.grid_points.clear();
        self.grid_points.extend(self.poses.iter().map(|(p, _)| *p));
        // `near` covers ±1 cell, so a cell of r_cut finds everything within r_cut; the
        // occlusion query at a segment's midpoint needs r_cut/2 + a hull, also covered.
        // Cells of about a metre: small enough that an occlusion query along a link touches a
        // few dozen vehicles, large enough that a range query stays a few hundred cells.
        let cell = (2.0 * self.max_hull_radius).max(self.r_cut / 4.0);
        self.grid.rebuild(cell, &self.grid_points);
        self.grid_slack = 0.0;
    }

    /// Calls `f` with every vehicle within the box `lo … hi` \[m\] (and possibly others
    /// nearby); stops early when `f` returns `false`. Returns whether it ran to the end.
    pub fn each_near(&self, lo: &Vec3, hi: &Vec3, f: impl FnMut(u32) -> bool) -> bool {
        let s = Vec3::repeat(self.grid_slack);
        self.grid.each_in_box(&(lo - s), &(hi + s), f)
    }

    /// Reception attempts decided so far (whole world): every frame ended at every candidate
    /// receiver, whatever the outcome.
    pub fn attempts(&self) -> u64 {
        self.per_second.iter().flatten().sum()
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
        self.each_near(
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
    pub(super) fn vehicles_clear(&self, from: u32, to: u32) -> bool {
        self.hulls_clear(
            &self.poses[from as usize].0,
            &self.poses[to as usize].0,
            (from, to),
        )
    }
}
