//! The ledger of reception outcomes ([`Ledger`]): the delivery phase appends every attempt
//! to a buffer of its chunk of receivers instead of writing each receiver's statistics, and
//! the ledger is folded into the vehicles' [`CommStats`] in bulk — at every connectivity
//! sample (each second), when it grows past a bound, and when statistics are read
//! ([`crate::sim::Sim::fold_comm`]). A receiver's statistics are then touched once per fold
//! rather than once per frame, which at thousands of receivers per step is most of what
//! recording cost (a cache miss each). The fold applies each receiver's events in the order
//! they happened, so every counter and sum is the one the per-frame updates gave.

use super::ending::ByVehicle;
use super::stats::{CommStats, Heard, Outcome};
use bevy_ecs::prelude::*;
use std::ops::DerefMut;

/// One reception attempt, as the delivery phase records it.
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

/// Events per vehicle the ledger holds at most before it is folded (≈ 32 B each): it is
/// folded at every connectivity sample anyway, so the bound only matters for heavy traffic.
const EVENTS_PER_VEHICLE: usize = 16;

/// Reception attempts not yet folded into the vehicles' [`CommStats`], in the order the
/// delivery phase decided them (step by step; within a step, receiver by receiver).
#[derive(Resource, Default)]
pub struct Ledger {
    events: Vec<LinkEvent>,
    /// Every attempt since the replay last drained them, when the medium logs them
    /// ([`crate::comm::Medium::log_links`]).
    heard: Vec<Heard>,
    /// The events in receiver order while they are folded (kept to reuse its buffers).
    grouped: Option<ByVehicle<LinkEvent>>,
}

impl Ledger {
    /// Appends one chunk's events; with `log`, also to the log the replay drains.
    pub(super) fn append(&mut self, events: &[LinkEvent], log: bool) {
        self.events.extend_from_slice(events);
        if log {
            self.heard.extend(events.iter().map(|e| Heard {
                t: e.t,
                from: e.from,
                to: e.rx,
                outcome: e.outcome,
            }));
        }
    }

    /// Events not yet folded.
    pub fn len(&self) -> usize {
        self.events.len()
    }

    /// Whether every event has been folded.
    pub fn is_empty(&self) -> bool {
        self.events.is_empty()
    }

    /// Whether the ledger holds more than its bound for a world of `vehicles`.
    pub fn full(&self, vehicles: usize) -> bool {
        self.events.len() >= EVENTS_PER_VEHICLE * vehicles.max(1)
    }

    /// The events of receiver `id` not yet folded, in order.
    pub fn pending(&self, id: u32) -> impl Iterator<Item = &LinkEvent> {
        self.events.iter().filter(move |e| e.rx == id)
    }

    /// Takes the attempts logged since the last call (see [`crate::comm::Medium::log_links`]).
    pub fn drain_heard(&mut self) -> std::vec::Drain<'_, Heard> {
        self.heard.drain(..)
    }

    /// Takes the events grouped by receiver (see [`Grouped`]); hand them back with
    /// [`Ledger::done`] once applied.
    pub fn grouped(&mut self, vehicles: usize) -> Grouped {
        // Copied into receiver order, so that each receiver's fold reads its events from one
        // place rather than gathering them from the whole ledger.
        let pairs = self.events.iter().map(|e| (e.rx, *e));
        let by = match self.grouped.take() {
            Some(mut by) => {
                by.regroup(vehicles, pairs);
                by
            }
            None => ByVehicle::new(vehicles, pairs),
        };
        self.events.clear();
        Grouped(by)
    }

    /// Takes back the buffers of events that were applied.
    pub fn done(&mut self, g: Grouped) {
        self.grouped = Some(g.0);
    }

    /// Folds every event into the statistics of its receiver, on the calling thread: `items`
    /// pairs each vehicle id (below `vehicles`) with its statistics, in any order.
    pub fn fold_into<S>(&mut self, vehicles: usize, items: impl Iterator<Item = (u32, S)>)
    where
        S: DerefMut<Target = CommStats>,
    {
        if self.events.is_empty() {
            return;
        }
        let g = self.grouped(vehicles);
        let mut scratch = Vec::new();
        for (id, mut stats) in items {
            g.apply(id, &mut stats, &mut scratch);
        }
        self.done(g);
    }
}

/// The ledger's events grouped by receiver, each receiver's in the order they happened (a
/// stable grouping), so receivers can be folded independently, e.g. in parallel.
pub struct Grouped(ByVehicle<LinkEvent>);

impl Grouped {
    /// Applies the events of receiver `id` to its statistics `stats` (`scratch`: a buffer,
    /// reused from receiver to receiver).
    pub fn apply(&self, id: u32, stats: &mut CommStats, scratch: &mut Vec<u32>) {
        stats.apply_all(self.0.of(id), scratch);
    }
}
