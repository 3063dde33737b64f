//! What a vehicle's modems hold: frames handed over for sending ([`OutFrame`], [`Outbox`]),
//! frames received and the outcomes of its acknowledged frames ([`Received`], [`FrameEvent`],
//! [`Inbox`]), the per-modem transmit queues ([`ModemPort`], [`Modems`]) with the medium
//! access's state ([`AccessState`]), and the vehicle's random stream for the medium
//! ([`CommRng`], [`comm_rng`]).

use crate::rng::VehicleRng;
use bevy_ecs::prelude::*;
use std::collections::VecDeque;
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
    /// Destination vehicle, or `None` for a broadcast.
    pub to: Option<u32>,
    /// With a destination: ask it to acknowledge, and retransmit until it does (stop-and-wait
    /// ARQ, see [`super::Link`]).
    pub ack: bool,
    /// A number of the sender's choosing, returned with the frame's outcome
    /// ([`FrameEvent::tag`]) so that it knows which of its frames the outcome is about.
    pub tag: u32,
}

impl OutFrame {
    /// A broadcast of `payload` on `modem` (`None`: all), handed over at `ready` \[s\].
    pub fn broadcast(modem: Option<usize>, payload: Vec<u8>, ready: f64) -> Self {
        Self {
            modem,
            payload,
            ready,
            to: None,
            ack: false,
            tag: 0,
        }
    }
}

/// What a frame on the air is to the link layer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Kind {
    /// For every vehicle that receives it.
    #[default]
    Broadcast,
    /// For vehicle `to` alone (others drop it); `ack`: to be acknowledged.
    Unicast {
        /// Destination vehicle.
        to: u32,
        /// Acknowledgement requested.
        ack: bool,
    },
    /// The acknowledgement of frame `seq` of vehicle `to`.
    Ack {
        /// The vehicle whose frame is acknowledged.
        to: u32,
        /// Its sequence number.
        seq: u32,
    },
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
    /// Whether it was sent to this vehicle alone (a unicast), not to everyone.
    pub unicast: bool,
}

/// What became of a unicast frame sent with acknowledgement.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameOutcome {
    /// The destination acknowledged it.
    Acknowledged,
    /// No acknowledgement came after the last retransmission (or the frame never went on the
    /// air: its queue was full; then `transmissions` is 0).
    GaveUp,
}

/// The end of one acknowledged-unicast frame at its sender.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameEvent {
    /// When it ended: the acknowledgement decoded, or the last wait timed out \[s\].
    pub t: f64,
    /// Destination vehicle.
    pub to: u32,
    /// The sender's sequence number of the frame.
    pub seq: u32,
    /// The tag the sender gave the frame ([`OutFrame::tag`]).
    pub tag: u32,
    /// Its payload.
    pub payload: Arc<[u8]>,
    /// When it was handed over \[s\].
    pub sent: f64,
    /// Times it went on the air (1 + retransmissions).
    pub transmissions: u32,
    /// Acknowledged or given up.
    pub outcome: FrameOutcome,
}

/// What reached the vehicle since its behaviour or agent last looked: frames received, and
/// what became of its own frames sent with acknowledgement.
#[derive(Component, Clone, Debug, Default)]
pub struct Inbox {
    /// Frames received, in order of arrival.
    pub frames: Vec<Received>,
    /// Outcomes of its acknowledged unicasts, in order.
    pub outcomes: Vec<FrameEvent>,
}

impl Inbox {
    /// Forgets everything (once the behaviour or agent has seen it).
    pub fn clear(&mut self) {
        self.frames.clear();
        self.outcomes.clear();
    }

    /// Whether nothing is waiting.
    pub fn is_empty(&self) -> bool {
        self.frames.is_empty() && self.outcomes.is_empty()
    }
}

/// A frame in a modem's transmit queue.
#[derive(Clone, Debug)]
pub(super) struct Queued {
    pub(super) payload: Arc<[u8]>,
    /// When it was handed over \[s\].
    pub(super) ready: f64,
    /// The sender's sequence number (shared by its copies and its retransmissions).
    pub(super) seq: u32,
    /// What it is to the link layer.
    pub(super) kind: Kind,
}

/// What the transmit phase reads of the frame at the head of a queue, kept beside the queue
/// (the walk through a step asks every port of a vehicle when it is due, and most are not:
/// this answers without reading the queue's storage).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Head {
    /// When it was handed over \[s\].
    pub(super) ready: f64,
    /// Its sequence number.
    pub(super) seq: u32,
    /// Whether it is an acknowledgement.
    pub(super) ack: bool,
}

impl Head {
    fn of(q: &Queued) -> Self {
        Self {
            ready: q.ready,
            seq: q.seq,
            ack: matches!(q.kind, Kind::Ack { .. }),
        }
    }
}

/// One modem's transmit side.
#[derive(Clone, Debug, Default)]
pub struct ModemPort {
    queue: VecDeque<Queued>,
    /// The head of `queue`, if any.
    head: Option<Head>,
    /// Until when the modem is taken (sending, or waiting as its medium access said) \[s\].
    pub(super) busy_until: f64,
}

impl ModemPort {
    /// Frames waiting.
    pub fn queued(&self) -> usize {
        self.queue.len()
    }

    /// The frame at the head of the queue, if any.
    pub(super) fn head(&self) -> Option<Head> {
        self.head
    }

    /// Queues `q` at the back, or at the front (a retransmission).
    pub(super) fn push(&mut self, q: Queued, front: bool) {
        if front {
            self.queue.push_front(q);
        } else {
            self.queue.push_back(q);
        }
        self.head = self.queue.front().map(Head::of);
    }

    /// Takes the frame at the head of the queue.
    pub(super) fn pop(&mut self) -> Option<Queued> {
        let q = self.queue.pop_front();
        self.head = self.queue.front().map(Head::of);
        q
    }
}

/// The modems of one vehicle (same order as its model's `modems`).
#[derive(Component, Clone, Debug, Default)]
pub struct Modems {
    /// One port per modem.
    pub ports: Vec<ModemPort>,
    pub(super) next_seq: u32,
    /// Frames waiting in all ports' queues (kept beside the ports, so that finding the
    /// vehicles with work for the medium reads no port).
    pub(super) queued: u32,
    /// What the medium-access protocol keeps between decisions: one per vehicle, whose
    /// modems contend as one station (the copies of a frame go out together).
    pub(super) access: AccessState,
}

impl Modems {
    /// Ports for `n` modems.
    pub fn new(n: usize) -> Self {
        Self {
            ports: vec![ModemPort::default(); n],
            next_seq: 0,
            queued: 0,
            access: Default::default(),
        }
    }

    /// Frames waiting in all ports' queues.
    pub fn queued(&self) -> usize {
        self.queued as usize
    }
}

/// What a medium-access protocol keeps per vehicle between its decisions.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AccessState {
    /// Back-off stage (CSMA/CA: the window is `cw_min · 2^stage`).
    pub(super) stage: u32,
    /// Back-off slots still to count down, once drawn.
    pub(super) counter: Option<u32>,
    /// Where the idle slots begin (CSMA/CA: a DIFS after the channel last fell idle), kept
    /// for when the frame that ended it is no longer on record \[s\].
    pub(super) anchor: Option<f64>,
}

/// The vehicle's own random stream for the medium (back-offs, reception draws).
#[derive(Component, Clone, Debug)]
pub struct CommRng(pub VehicleRng);

/// RNG stream of a vehicle's medium draws (see [`crate::rng::vehicle_rng`]).
pub fn comm_rng(seed: u64, id: u32) -> CommRng {
    CommRng(crate::rng::vehicle_rng(seed, id, crate::rng::stream::COMM))
}
