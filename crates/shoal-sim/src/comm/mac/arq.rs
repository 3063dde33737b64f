//! Stop-and-wait ARQ above any medium access: a unicast frame sent with acknowledgement
//! (`OutFrame { to: Some(v), ack: true, .. }`) stays the vehicle's one outstanding frame until
//! the destination's acknowledgement arrives or its retries are used up; the frames handed
//! over meanwhile wait behind it. The destination acknowledges every copy it decodes — an
//! acknowledgement is a header-only frame with its own airtime and collisions, sent on all of
//! its modems at the front of their queues — and hands a frame to its
//! behaviour once: a retransmission of a frame it already has (its acknowledgement was lost)
//! is acknowledged again and dropped (duplicate suppression by the sender's sequence number).
//!
//! What became of each such frame — acknowledged, or given up after its retries — is a
//! [`FrameEvent`] in the sender's inbox, for its behaviour or agent.

use super::super::frames::{FrameEvent, FrameOutcome, OutFrame};
use bevy_ecs::prelude::Component;
use std::collections::VecDeque;
use std::sync::Arc;

/// A vehicle's link-layer state: empty (no allocation) until it sends or receives a frame
/// with acknowledgement.
#[derive(Component, Clone, Debug, Default)]
pub struct Link(Option<Box<LinkState>>);

/// The outstanding frame of a vehicle.
#[derive(Clone, Debug)]
pub(in crate::comm) struct Pending {
    /// Its sequence number.
    pub(in crate::comm) seq: u32,
    /// Its destination.
    pub(in crate::comm) to: u32,
    /// The sender's tag for it.
    pub(in crate::comm) tag: u32,
    /// Its modem (`None`: a copy on every modem).
    pub(in crate::comm) modem: Option<usize>,
    /// Its payload, shared by its copies.
    pub(in crate::comm) payload: Arc<[u8]>,
    /// When it was handed over \[s\].
    pub(in crate::comm) sent: f64,
    /// Times it went into the queues (1 + retransmissions).
    pub(in crate::comm) transmissions: u32,
    /// When the wait for its acknowledgement ends (+∞ until it went on the air) \[s\].
    pub(in crate::comm) deadline: f64,
}

/// An acknowledgement a vehicle owes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(in crate::comm) struct AckDue {
    /// The vehicle to acknowledge.
    pub(in crate::comm) to: u32,
    /// Its frame's sequence number.
    pub(in crate::comm) seq: u32,
    /// When the frame ended \[s\].
    pub(in crate::comm) ready: f64,
}

/// The link-layer state behind [`Link`].
#[derive(Clone, Debug, Default)]
pub(in crate::comm) struct LinkState {
    /// The outstanding frame.
    pub(in crate::comm) pending: Option<Pending>,
    /// Acknowledged-unicast frames handed over while another was outstanding, in order.
    pub(in crate::comm) waiting: VecDeque<OutFrame>,
    /// Acknowledgements to send.
    pub(in crate::comm) acks: Vec<AckDue>,
    /// The last sequence number delivered from each sender that asked for acknowledgements
    /// (sorted by sender).
    seen: Vec<(u32, u32)>,
    /// For the medium access of the outstanding frames' modems (`None`: all): whether each
    /// was acknowledged or timed out, since the transmit phase last looked.
    pub(in crate::comm) feedback: Vec<(Option<usize>, bool)>,
}

impl Link {
    /// The state, created on first use.
    pub(in crate::comm) fn state(&mut self) -> &mut LinkState {
        self.0.get_or_insert_with(Default::default)
    }

    /// Whether the transmit phase has work for this vehicle: an outstanding frame to time
    /// out, frames waiting behind it, or acknowledgements to send.
    pub(in crate::comm) fn busy(&self) -> bool {
        self.0.as_ref().is_some_and(|s| {
            s.pending.is_some()
                || !s.waiting.is_empty()
                || !s.acks.is_empty()
                || !s.feedback.is_empty()
        })
    }
}

impl LinkState {
    /// Frame `seq` of `from` decoded here: whether it is new (not a retransmission of the
    /// last frame delivered from `from`); remembers it.
    pub(in crate::comm) fn first_delivery(&mut self, from: u32, seq: u32) -> bool {
        match self.seen.binary_search_by_key(&from, |s| s.0) {
            Ok(i) if self.seen[i].1 == seq => false,
            Ok(i) => {
                self.seen[i].1 = seq;
                true
            }
            Err(i) => {
                self.seen.insert(i, (from, seq));
                true
            }
        }
    }

    /// The acknowledgement of frame `seq` from `from` decoded at `t` \[s\]: ends the
    /// outstanding frame if it is that one, with its outcome.
    pub(in crate::comm) fn acknowledged(
        &mut self,
        from: u32,
        seq: u32,
        t: f64,
    ) -> Option<FrameEvent> {
        let p = self.pending.as_ref()?;
        if p.seq != seq || p.to != from {
            return None;
        }
        let p = self.pending.take()?;
        self.feedback.push((p.modem, true));
        Some(p.event(t, FrameOutcome::Acknowledged))
    }
}

impl Pending {
    /// Its outcome event at `t` \[s\].
    pub(in crate::comm) fn event(&self, t: f64, outcome: FrameOutcome) -> FrameEvent {
        FrameEvent {
            t,
            to: self.to,
            seq: self.seq,
            tag: self.tag,
            payload: self.payload.clone(),
            sent: self.sent,
            transmissions: self.transmissions,
            outcome,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A retransmission of the last delivered frame is a duplicate; the next sequence number,
    /// or the same number from another sender, is not.
    #[test]
    fn duplicates_are_the_same_sender_and_sequence_number_again() {
        let mut s = LinkState::default();
        assert!(s.first_delivery(4, 10));
        assert!(!s.first_delivery(4, 10));
        assert!(s.first_delivery(2, 10));
        assert!(s.first_delivery(4, 11));
        assert!(!s.first_delivery(4, 11));
        assert!(!s.first_delivery(2, 10));
        assert_eq!(s.seen, vec![(2, 10), (4, 11)]);
    }

    /// An acknowledgement ends the outstanding frame only if it names that frame and comes
    /// from its destination.
    #[test]
    fn an_acknowledgement_ends_only_its_own_frame() {
        let mut s = LinkState {
            pending: Some(Pending {
                seq: 3,
                to: 7,
                tag: 11,
                modem: None,
                payload: Arc::from(&[1u8, 2][..]),
                sent: 0.5,
                transmissions: 2,
                deadline: 1.0,
            }),
            ..Default::default()
        };
        assert!(
            s.acknowledged(7, 4, 0.9).is_none(),
            "another sequence number"
        );
        assert!(s.acknowledged(6, 3, 0.9).is_none(), "another vehicle");
        assert!(s.pending.is_some());
        let e = s.acknowledged(7, 3, 0.9).expect("its acknowledgement");
        assert!(s.pending.is_none());
        assert_eq!(
            (e.to, e.seq, e.tag, e.transmissions, e.outcome, e.sent, e.t),
            (7, 3, 11, 2, FrameOutcome::Acknowledged, 0.5, 0.9)
        );
        assert_eq!(s.feedback, vec![(None, true)]);
        assert!(s.acknowledged(7, 3, 1.0).is_none(), "already ended");
    }
}
