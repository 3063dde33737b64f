//! What a vehicle's modems hold: frames handed over for sending ([`OutFrame`], [`Outbox`]),
//! frames received ([`Received`], [`Inbox`]), the per-modem transmit queues ([`ModemPort`],
//! [`Modems`]) and the vehicle's random stream for the medium ([`CommRng`], [`comm_rng`]).

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
pub(super) struct Queued {
    pub(super) payload: Arc<[u8]>,
    pub(super) ready: f64,
    pub(super) seq: u32,
}

/// One modem's transmit side.
#[derive(Clone, Debug, Default)]
pub struct ModemPort {
    pub(super) queue: VecDeque<Queued>,
    pub(super) busy_until: f64,
}

impl ModemPort {
    /// Frames waiting.
    pub fn queued(&self) -> usize {
        self.queue.len()
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
}

impl Modems {
    /// Ports for `n` modems.
    pub fn new(n: usize) -> Self {
        Self {
            ports: vec![ModemPort::default(); n],
            next_seq: 0,
            queued: 0,
        }
    }

    /// Frames waiting in all ports' queues.
    pub fn queued(&self) -> usize {
        self.queued as usize
    }
}

/// The vehicle's own random stream for the medium (back-offs, reception draws).
#[derive(Component, Clone, Debug)]
pub struct CommRng(pub VehicleRng);

/// RNG stream of a vehicle's medium draws (see [`crate::rng::vehicle_rng`]).
pub fn comm_rng(seed: u64, id: u32) -> CommRng {
    CommRng(crate::rng::vehicle_rng(seed, id, crate::rng::stream::COMM))
}
