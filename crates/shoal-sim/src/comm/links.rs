//! Links between a sender and a receiver: what became of one attempt ([`Outcome`],
//! [`LinkEvent`]), a link's counters ([`LinkStats`]) and one receiver's links by sender
//! ([`LinkMap`]: a vector sorted by sender, so that folding a batch of attempts sorted by
//! sender walks it front to back instead of probing a hash table at random).

use serde::{Deserialize, Serialize};

/// What became of a frame at one receiver: the one list of link outcomes, with the codes the
/// replay's `links` array, `run.mcap`'s `/links` and the colour key of the plots use
/// ([`Outcome::code`]). How close each came to arriving is [`Outcome::rank`] (a vehicle with
/// several modems reports the best, [`Outcome::better`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[repr(u32)]
pub enum Outcome {
    /// Received.
    Delivered = 0,
    /// Lost to interference from overlapping frames not weak enough to capture over.
    Collided = 1,
    /// The line of sight was blocked (wall, obstacle, hull).
    Occluded = 2,
    /// Out of the link budget: range, angle or bit errors.
    OutOfBudget = 3,
    /// The receiver was transmitting (half-duplex).
    HalfDuplex = 4,
}

impl Outcome {
    /// Every outcome, in code order.
    pub const ALL: [Outcome; 5] = [
        Outcome::Delivered,
        Outcome::Collided,
        Outcome::Occluded,
        Outcome::OutOfBudget,
        Outcome::HalfDuplex,
    ];

    /// Position in [`Outcome::ALL`] (its code).
    pub fn index(self) -> usize {
        self as usize
    }

    /// Its code in the replay's `links` array and `run.mcap`'s `/links`.
    pub fn code(self) -> u32 {
        self as u32
    }

    /// The outcome of the code `code`, if there is one.
    pub fn from_code(code: u32) -> Option<Outcome> {
        Self::ALL.get(usize::try_from(code).ok()?).copied()
    }

    /// How close the frame came to arriving: out of budget (0) < occluded < half-duplex <
    /// collided < delivered (4).
    pub fn rank(self) -> u8 {
        match self {
            Outcome::OutOfBudget => 0,
            Outcome::Occluded => 1,
            Outcome::HalfDuplex => 2,
            Outcome::Collided => 3,
            Outcome::Delivered => 4,
        }
    }

    /// The one of `self` and `other` that came closer to arriving ([`Outcome::rank`]).
    pub fn better(self, other: Outcome) -> Outcome {
        if other.rank() > self.rank() {
            other
        } else {
            self
        }
    }
}

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
            Outcome::OutOfBudget => self.lost_range += 1,
            Outcome::Occluded => self.lost_occlusion += 1,
            Outcome::Collided => self.lost_collision += 1,
            Outcome::HalfDuplex => self.lost_half_duplex += 1,
        }
    }
}

/// One reception attempt.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinkEvent {
    /// Receiving vehicle.
    pub rx: u32,
    /// Sending vehicle.
    pub from: u32,
    /// What happened.
    pub outcome: Outcome,
    /// Hand-over-to-end latency of the frame \[s\].
    pub latency: f64,
    /// End of the frame \[s\].
    pub t: f64,
}

/// Per-sender statistics of one receiver, in ascending sender order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LinkMap {
    entries: Vec<(u32, LinkStats)>,
}

impl LinkMap {
    /// Senders heard at least once (attempted).
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether no frame was ever attempted.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The statistics of sender `from`.
    pub fn get(&self, from: u32) -> Option<&LinkStats> {
        self.find(from).ok().map(|k| &self.entries[k].1)
    }

    /// `(sender, statistics)` in ascending sender order.
    pub fn iter(&self) -> impl Iterator<Item = (&u32, &LinkStats)> {
        self.entries.iter().map(|(k, v)| (k, v))
    }

    fn find(&self, from: u32) -> Result<usize, usize> {
        self.entries.binary_search_by_key(&from, |e| e.0)
    }

    fn fresh() -> LinkStats {
        LinkStats {
            last_delivery: f64::NEG_INFINITY,
            ..Default::default()
        }
    }

    /// Counts one attempt.
    pub(super) fn record(&mut self, e: &LinkEvent) {
        let k = match self.find(e.from) {
            Ok(k) => k,
            Err(k) => {
                self.entries.insert(k, (e.from, Self::fresh()));
                k
            }
        };
        self.entries[k].1.record(e.outcome, e.latency, e.t);
    }

    /// Counts a batch of attempts sorted by sender (each sender's in the order they
    /// happened): one walk over the entries, new senders merged in at the end.
    pub(super) fn record_sorted<'e>(&mut self, events: impl Iterator<Item = &'e LinkEvent>) {
        let before = self.entries.len();
        let mut j = 0;
        for e in events {
            while j < before && self.entries[j].0 < e.from {
                j += 1;
            }
            if j < before && self.entries[j].0 == e.from {
                self.entries[j].1.record(e.outcome, e.latency, e.t);
                continue;
            }
            // A sender not heard before this batch: its entry is among the new ones at the
            // end (the batch is sorted, so it is the last one if it exists).
            let grown = self.entries.len() > before;
            match self.entries.last_mut() {
                Some(last) if grown && last.0 == e.from => {
                    last.1.record(e.outcome, e.latency, e.t);
                }
                _ => {
                    let mut s = Self::fresh();
                    s.record(e.outcome, e.latency, e.t);
                    self.entries.push((e.from, s));
                }
            }
        }
        if self.entries.len() > before {
            // Both parts are sorted and their keys distinct.
            self.entries.sort_by_key(|e| e.0);
        }
    }
}

impl std::ops::Index<&u32> for LinkMap {
    type Output = LinkStats;

    fn index(&self, from: &u32) -> &LinkStats {
        self.get(*from).expect("no statistics for this sender")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::comm::Outcome;

    fn ev(from: u32, outcome: Outcome, t: f64) -> LinkEvent {
        LinkEvent {
            rx: 0,
            from,
            outcome,
            latency: 0.01 * t,
            t,
        }
    }

    #[test]
    fn a_sorted_batch_counts_as_one_attempt_at_a_time() {
        let first = [
            ev(7, Outcome::Delivered, 1.0),
            ev(3, Outcome::OutOfBudget, 1.1),
            ev(7, Outcome::Collided, 1.2),
        ];
        let second = [
            ev(1, Outcome::Delivered, 2.0),
            ev(3, Outcome::Delivered, 2.1),
            ev(9, Outcome::HalfDuplex, 2.2),
            ev(3, Outcome::Delivered, 2.3),
            ev(7, Outcome::Occluded, 2.4),
        ];
        let mut one = LinkMap::default();
        for e in first.iter().chain(&second) {
            one.record(e);
        }
        let mut batch = LinkMap::default();
        for part in [&first[..], &second[..]] {
            let mut sorted = part.to_vec();
            sorted.sort_by_key(|e| e.from);
            batch.record_sorted(sorted.iter());
        }
        assert_eq!(batch, one);
        let senders: Vec<u32> = batch.iter().map(|(k, _)| *k).collect();
        assert_eq!(senders, [1, 3, 7, 9]);
        assert_eq!(batch[&3].delivered, 2);
        assert_eq!(batch[&3].last_delivery, 2.3);
        assert_eq!(batch[&7].attempts, 3);
        assert!(batch.get(4).is_none());
    }
}
