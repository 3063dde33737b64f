//! Communication statistics: each vehicle's counters ([`CommStats`], its receptions by sender
//! in a [`LinkMap`]) and the bins of the world-wide delivery-by-distance
//! and latency histograms, tallied per chunk of receivers (`Tally`).

use super::links::{LinkEvent, LinkMap, LinkStats, Outcome};
use bevy_ecs::prelude::*;

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
    /// Acknowledgements sent.
    pub acks_sent: u64,
    /// Retransmissions of unacknowledged unicast frames.
    pub retransmissions: u64,
    /// Unicast frames given up after their last retransmission.
    pub gave_up: u64,
    /// Time its LEDs were on, summed over its modems \[s\].
    pub led_on_s: f64,
    /// Optical energy its LEDs sent \[J\].
    pub led_energy_j: f64,
    /// Receptions, all senders together (complete once the ledger was folded:
    /// [`crate::sim::Sim::fold_comm`]; snapshots are).
    pub rx: LinkStats,
    links: LinkMap,
}

/// One reception attempt at a vehicle, as the replay and the run driver read them.
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
    /// The frame's payload (the link-layer header added on the air not counted) \[bytes\].
    pub bytes: u32,
    /// Whether the frame was an acknowledgement ([`super::Kind::Ack`]: the link layer's
    /// answer to a unicast frame it received), not a frame a behaviour or agent sent.
    pub ack: bool,
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
    // Clamped first, then truncated: the floor of the value in range.
    ((l.max(1e-4).log10() + 4.0) * 20.0).clamp(0.0, (LAT_BINS - 1) as f64) as usize
}

/// Geometric centre of a latency bin \[s\] (within ±6 % of any latency in it).
pub fn latency_bin_centre(k: usize) -> f64 {
    10f64.powf((k as f64 + 0.5) / 20.0 - 4.0)
}

/// The `q` quantile (0 … 1) of a latency histogram given as (bin, count) pairs in bin order
/// \[s\]: the centre of the bin that holds it (±6 %); `None` for an empty histogram.
pub fn latency_percentile<I>(bins: I, q: f64) -> Option<f64>
where
    I: IntoIterator<Item = (usize, u64)>,
    I::IntoIter: Clone,
{
    let bins = bins.into_iter();
    let total: u64 = bins.clone().map(|b| b.1).sum();
    if total == 0 {
        return None;
    }
    let target = (q * total as f64).ceil().max(1.0) as u64;
    let mut acc = 0;
    for (k, n) in bins {
        acc += n;
        if acc >= target {
            return Some(latency_bin_centre(k));
        }
    }
    None
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
    /// Acknowledged unicasts by latency, hand-over to acknowledgement ([`latency_bin`]).
    pub(super) acknowledged: [u64; LAT_BINS],
}

impl Tally {
    pub(super) fn new() -> Self {
        Self {
            by_distance: [(0, 0); DIST_BINS],
            latency: [0; LAT_BINS],
            outcomes: [[0; 5]; 2],
            acknowledged: [0; LAT_BINS],
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
        for (a, b) in self.acknowledged.iter_mut().zip(&o.acknowledged) {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Each latency falls into the bin whose range holds it: the bin's centre is within 6 %
    /// of the latency, and the bins are the floor of 20 · (log₁₀ l + 4), clamped — checked at
    /// and just around every bin edge, below 0.1 ms and beyond the last bin.
    #[test]
    fn latency_bins_are_the_floor_of_twenty_per_decade() {
        for k in 0..LAT_BINS {
            let edge = 10f64.powf(k as f64 / 20.0 - 4.0);
            for l in [edge * (1.0 - 1e-9), edge, edge * (1.0 + 1e-9), edge * 1.05] {
                let want = ((l.max(1e-4).log10() + 4.0) * 20.0)
                    .floor()
                    .clamp(0.0, (LAT_BINS - 1) as f64) as usize;
                let got = latency_bin(l);
                assert_eq!(got, want, "latency {l}");
                let c = latency_bin_centre(got);
                if l >= 1e-4 && got < LAT_BINS - 1 {
                    assert!((c / l - 1.0).abs() < 0.06, "latency {l}: centre {c}");
                }
            }
        }
        assert_eq!(latency_bin(1e-7), 0);
        assert_eq!(latency_bin(0.0), 0);
        assert_eq!(latency_bin(1e6), LAT_BINS - 1);
    }
}
