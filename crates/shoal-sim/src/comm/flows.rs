//! Per-flow measures of addressed traffic: for every sender → destination pair that
//! exchanged unicast frames, what was offered, what the destination took, what was
//! acknowledged or given up, how often frames were retransmitted, how long an acknowledgement
//! took, and the LED time the flow cost — its frames at the sender and their acknowledgements
//! at the destination ([`Flows`], kept by the medium). Broadcasts have no flow: their
//! receptions are counted per link (`links`).
//!
//! The transmit phase (one thread) updates the flows directly; the delivery phase, which
//! runs on many threads, collects [`FlowEvent`]s per thread and folds them in afterwards, so
//! that the result does not depend on the number of threads.

use super::stats::{latency_bin, latency_percentile};
use std::collections::BTreeMap;

/// What one flow (sender → destination) measured.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FlowStats {
    /// Unicast frames handed over for the destination (each once, however often sent).
    pub offered: u64,
    /// Their payload \[bytes\].
    pub offered_bytes: u64,
    /// Frames the destination took (a retransmission of one it already had is not counted
    /// again).
    pub delivered: u64,
    /// Their payload \[bytes\].
    pub delivered_bytes: u64,
    /// Frames sent with acknowledgement that were acknowledged.
    pub acknowledged: u64,
    /// Frames sent with acknowledgement that were given up (after their retries, or refused
    /// by a full queue).
    pub gave_up: u64,
    /// Retransmissions.
    pub retransmissions: u64,
    /// Time LEDs were on for the flow: its frames' copies at the sender and their
    /// acknowledgements' at the destination \[s\].
    pub led_on_s: f64,
    /// Optical energy of those transmissions \[J\].
    pub led_energy_j: f64,
    /// Hand-over → acknowledgement latencies: (latency bin, count), by bin.
    latency: Vec<(u8, u32)>,
}

impl FlowStats {
    /// The `q` quantile (0 … 1) of the hand-over → acknowledgement latency \[s\] (the centre
    /// of its histogram bin: ±6 %), if any frame was acknowledged.
    pub fn latency_quantile(&self, q: f64) -> Option<f64> {
        latency_percentile(
            self.latency
                .iter()
                .map(|&(k, n)| (k as usize, u64::from(n))),
            q,
        )
    }

    /// acknowledged / (acknowledged + gave up), if any frame asked for acknowledgement.
    pub fn delivery_after_retries(&self) -> Option<f64> {
        let ended = self.acknowledged + self.gave_up;
        (ended > 0).then(|| self.acknowledged as f64 / ended as f64)
    }

    fn add_latency(&mut self, latency: f64) {
        let k = latency_bin(latency) as u8;
        match self.latency.binary_search_by_key(&k, |b| b.0) {
            Ok(i) => self.latency[i].1 += 1,
            Err(i) => self.latency.insert(i, (k, 1)),
        }
    }
}

/// Something the delivery phase learnt about a flow.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum FlowEvent {
    /// The destination took a frame of `bytes` payload bytes.
    Delivered {
        /// Sender.
        from: u32,
        /// Destination.
        to: u32,
        /// Payload \[bytes\].
        bytes: u64,
    },
    /// The sender decoded the acknowledgement of a frame handed over `latency` \[s\] before.
    Acknowledged {
        /// Sender.
        from: u32,
        /// Destination.
        to: u32,
        /// Hand-over → acknowledgement \[s\].
        latency: f64,
    },
}

/// Every flow of the world, by (sender, destination).
#[derive(Clone, Debug, Default)]
pub struct Flows(BTreeMap<(u32, u32), FlowStats>);

impl Flows {
    /// The flows, by (sender, destination) ascending.
    pub fn iter(&self) -> impl Iterator<Item = (&(u32, u32), &FlowStats)> {
        self.0.iter()
    }

    /// Number of flows.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// Whether no unicast frame was handed over.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The flow from `from` to `to`, created on first use.
    pub(super) fn get(&mut self, from: u32, to: u32) -> &mut FlowStats {
        self.0.entry((from, to)).or_default()
    }

    /// Adds `other`, the flows the link layer counted for a part of the transmit phase's
    /// vehicles: what it counts (frames handed over, their bytes, given up, retransmissions),
    /// flow by flow, each flow it touched created here too.
    pub(super) fn absorb(&mut self, other: Flows) {
        for ((from, to), d) in other.0 {
            debug_assert!(
                d.delivered == 0
                    && d.acknowledged == 0
                    && d.led_on_s == 0.0
                    && d.led_energy_j == 0.0
                    && d.latency.is_empty(),
                "only the link layer's counts are absorbed"
            );
            let f = self.get(from, to);
            f.offered += d.offered;
            f.offered_bytes += d.offered_bytes;
            f.gave_up += d.gave_up;
            f.retransmissions += d.retransmissions;
        }
    }

    /// Folds in an event of the delivery phase.
    pub(super) fn apply(&mut self, e: &FlowEvent) {
        match *e {
            FlowEvent::Delivered { from, to, bytes } => {
                let f = self.get(from, to);
                f.delivered += 1;
                f.delivered_bytes += bytes;
            }
            FlowEvent::Acknowledged { from, to, latency } => {
                let f = self.get(from, to);
                f.acknowledged += 1;
                f.add_latency(latency);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Events fold into their flow; latencies land in their bins and give quantiles within
    /// a bin's ±6 %.
    #[test]
    fn events_fold_into_their_flow() {
        let mut f = Flows::default();
        for latency in [0.01, 0.01, 0.02, 0.1] {
            f.apply(&FlowEvent::Acknowledged {
                from: 1,
                to: 2,
                latency,
            });
        }
        f.apply(&FlowEvent::Delivered {
            from: 1,
            to: 2,
            bytes: 20,
        });
        f.get(1, 2).gave_up += 1;
        assert_eq!(f.len(), 1);
        let s = &f.0[&(1, 2)];
        assert_eq!((s.acknowledged, s.delivered, s.delivered_bytes), (4, 1, 20));
        assert_eq!(s.delivery_after_retries(), Some(0.8));
        let median = s.latency_quantile(0.5).unwrap();
        assert!((median / 0.01 - 1.0).abs() < 0.06, "{median}");
        let top = s.latency_quantile(1.0).unwrap();
        assert!((top / 0.1 - 1.0).abs() < 0.06, "{top}");
        assert_eq!(Flows::default().0.get(&(2, 1)), None);
    }

    /// A part's link-layer counts add to the flows, flow by flow; a flow the part only
    /// touched exists afterwards, as it would had the part counted into the flows directly.
    #[test]
    fn a_parts_link_counts_add_up() {
        let mut all = Flows::default();
        all.get(1, 2).offered = 3;
        all.get(1, 2).acknowledged = 2;
        let mut part = Flows::default();
        let f = part.get(1, 2);
        (f.offered, f.offered_bytes, f.gave_up, f.retransmissions) = (2, 40, 1, 5);
        part.get(7, 8);
        all.absorb(part);
        let s = &all.0[&(1, 2)];
        assert_eq!(
            (
                s.offered,
                s.offered_bytes,
                s.gave_up,
                s.retransmissions,
                s.acknowledged
            ),
            (5, 40, 1, 5, 2)
        );
        assert_eq!(all.len(), 2);
    }
}
