//! Communication statistics: reception outcomes per receiver and sender ([`LinkStats`],
//! [`CommStats`], its senders in a [`LinkMap`]) and the bins of the world-wide delivery-by-distance
//! and latency histograms, tallied per chunk of receivers (`Tally`).

use super::ledger::LinkEvent;
pub use super::link_map::LinkMap;
use bevy_ecs::prelude::*;
use serde::Serialize;

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

    pub(super) fn record(&mut self, outcome: Outcome, latency: f64, t: f64) {
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
    /// Receptions, all senders together (complete once the ledger was folded:
    /// [`crate::sim::Sim::fold_comm`]; snapshots are).
    pub rx: LinkStats,
    links: LinkMap,
}

/// One reception attempt at a vehicle, as the replay reads them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Heard {
    /// End of the frame \[s\].
    pub t: f64,
    /// Sending vehicle.
    pub from: u32,
    /// Receiving vehicle.
    pub to: u32,
    /// What happened.
    pub outcome: Outcome,
}

impl CommStats {
    /// Counts one reception attempt (from the [`super::Ledger`]).
    pub fn apply(&mut self, e: &LinkEvent) {
        self.rx.record(e.outcome, e.latency, e.t);
        self.links.record(e);
    }

    /// Counts this receiver's attempts `events`, given in the order they happened (and
    /// left sorted by sender): the same counts and sums as [`CommStats::apply`] one by one.
    pub(super) fn apply_all(&mut self, events: &mut [LinkEvent]) {
        for e in events.iter() {
            self.rx.record(e.outcome, e.latency, e.t);
        }
        // Stable: each sender's attempts stay in time order.
        events.sort_by_key(|e| e.from);
        self.links.record_sorted(events.iter());
    }

    /// Receptions by sender (complete once the ledger was folded:
    /// [`crate::sim::Sim::fold_comm`]; snapshots are).
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

/// What became of a frame at one receiver. Ordered by how close the frame came to arriving
/// (the best one is reported when a vehicle has several modems).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Outcome {
    /// Out of the link budget: range, angle or bit errors.
    Range,
    /// The line of sight was blocked (wall, obstacle, hull).
    Occluded,
    /// The receiver was transmitting.
    HalfDuplex,
    /// Lost to interference from overlapping frames.
    Collision,
    /// Received.
    Delivered,
}

impl Outcome {
    /// Every outcome, in order.
    pub const ALL: [Outcome; 5] = [
        Outcome::Range,
        Outcome::Occluded,
        Outcome::HalfDuplex,
        Outcome::Collision,
        Outcome::Delivered,
    ];

    /// Position in [`Outcome::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }
}

/// World-wide counts of one chunk of receptions (summed over the chunks after the delivery
/// loop, so that no counter is shared between threads).
pub(super) struct Tally {
    /// Attempts and deliveries by distance ([`DIST_BIN`] bins).
    pub(super) by_distance: [(u64, u64); DIST_BINS],
    /// Deliveries by latency ([`latency_bin`]).
    pub(super) latency: [u64; LAT_BINS],
    /// Outcomes of frames ending in this second and the next, by [`Outcome::index`].
    pub(super) outcomes: [[u64; 5]; 2],
}

impl Tally {
    pub(super) fn new() -> Self {
        Self {
            by_distance: [(0, 0); DIST_BINS],
            latency: [0; LAT_BINS],
            outcomes: [[0; 5]; 2],
        }
    }

    pub(super) fn add(&mut self, o: &Tally) {
        for ((a, d), (oa, od)) in self.by_distance.iter_mut().zip(&o.by_distance) {
            *a += oa;
            *d += od;
        }
        for (a, b) in self.latency.iter_mut().zip(&o.latency) {
            *a += b;
        }
        for (a, b) in self
            .outcomes
            .iter_mut()
            .flatten()
            .zip(o.outcomes.iter().flatten())
        {
            *a += b;
        }
    }
}
