//! The ledger of reception outcomes ([`Ledger`]): the delivery phase appends every attempt
//! to a buffer of its chunk of receivers instead of writing each receiver's statistics, and
//! the ledger is folded into the vehicles' [`CommStats`] in bulk — at every connectivity
//! sample (each second), when it grows past a bound, and when statistics are read
//! ([`crate::sim::Sim::fold_comm`]). A receiver's statistics are then touched once per fold
//! rather than once per frame, which at thousands of receivers per step is most of what
//! recording cost (a cache miss each). The fold applies each receiver's events in the order
//! they happened, so every counter and sum is the one the per-frame updates gave.

use super::ending::ByVehicle;
use super::frames::Kind;
use super::links::{LinkEvent, Outcome};
use super::medium::Transmission;
use super::stats::{CommStats, Heard};
use bevy_ecs::prelude::*;
use std::ops::DerefMut;

/// A frame of the ledger: what its attempts share.
#[derive(Clone, Copy, Debug)]
struct FrameInfo {
    /// Sending vehicle.
    from: u32,
    /// Hand-over time \[s\].
    sent: f64,
    /// End of the frame \[s\].
    end: f64,
    /// Payload \[bytes\].
    bytes: u32,
    /// Whether it is an acknowledgement ([`Kind::Ack`]).
    ack: bool,
}

/// One reception attempt as the ledger keeps it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Attempt {
    /// Receiving vehicle.
    rx: u32,
    /// The frame (index in the ledger's frame table).
    frame: u32,
    /// What happened.
    outcome: Outcome,
}

impl Attempt {
    /// The full event, with the frame's fields from `frames`.
    fn event(&self, frames: &[FrameInfo]) -> LinkEvent {
        let f = &frames[self.frame as usize];
        LinkEvent {
            rx: self.rx,
            from: f.from,
            outcome: self.outcome,
            latency: f.end - f.sent,
            t: f.end,
        }
    }
}

/// Events per vehicle the ledger holds at most before it is folded (12 B each): it is
/// folded at every connectivity sample (each second) anyway, so the bound only matters for
/// heavy traffic — a swarm beaconing once a second with ≈ 40 neighbours in range stays
/// below it, so that each receiver's statistics are visited once a second.
const EVENTS_PER_VEHICLE: usize = 48;

/// Reception attempts not yet folded into the vehicles' [`CommStats`], in the order the
/// delivery phase decided them (step by step; within a step, receiver by receiver).
#[derive(Resource, Default)]
pub struct Ledger {
    attempts: Vec<Attempt>,
    frames: Vec<FrameInfo>,
    /// Every attempt since the replay last drained them, when the medium logs them
    /// ([`crate::comm::Medium::log_links`]).
    heard: Vec<Heard>,
    /// Every attempt since the run driver last drained them with the trajectory rows
    /// ([`Ledger::log_for_drain`], [`Ledger::drain_logged`]); `None` when nobody asked.
    logged: Option<Vec<Heard>>,
    /// The attempts in receiver order while they are folded (kept to reuse its buffers).
    grouped: Option<ByVehicle<Attempt>>,
}

impl Ledger {
    /// Enters frames, each given by its first copy on the air; returns the number of the
    /// first (the others follow it) for [`Ledger::attempt`]. Each keeps its sender, times,
    /// payload length and whether it is an acknowledgement, for [`Heard`].
    pub(super) fn frames_of<'t>(&mut self, frames: impl Iterator<Item = &'t Transmission>) -> u32 {
        let first = self.frames.len() as u32;
        self.frames.extend(frames.map(|f| FrameInfo {
            from: f.tx,
            sent: f.sent,
            end: f.end,
            bytes: u32::try_from(f.payload.len()).unwrap_or(u32::MAX),
            ack: matches!(f.kind, Kind::Ack { .. }),
        }));
        first
    }

    /// An attempt at receiver `rx` of frame `frame` (from [`Ledger::frames_of`]).
    pub(super) fn attempt(rx: u32, frame: u32, outcome: Outcome) -> Attempt {
        Attempt { rx, frame, outcome }
    }

    /// Appends one chunk's attempts; with `log`, also to the log the replay drains, and to
    /// the run driver's log when it asked for one ([`Ledger::log_for_drain`]).
    pub(super) fn append(&mut self, attempts: &[Attempt], log: bool) {
        self.attempts.extend_from_slice(attempts);
        let frames = &self.frames;
        let heard = attempts.iter().map(|a| {
            let e = a.event(frames);
            let f = &frames[a.frame as usize];
            Heard {
                t: e.t,
                from: e.from,
                to: e.rx,
                outcome: e.outcome,
                bytes: f.bytes,
                ack: f.ack,
            }
        });
        if log {
            self.heard.extend(heard.clone());
        }
        if let Some(l) = &mut self.logged {
            l.extend(heard);
        }
    }

    /// Logs every attempt from now on for [`Ledger::drain_logged`] too (a second log beside
    /// the replay's, drained by the run driver with the trajectory rows; see
    /// [`crate::sim::Sim::drain`]).
    pub fn log_for_drain(&mut self) {
        self.logged.get_or_insert_with(Vec::new);
    }

    /// Takes the attempts logged for the run driver since the last call (empty unless
    /// [`Ledger::log_for_drain`] was called), in the order they were decided.
    pub fn drain_logged(&mut self) -> Vec<Heard> {
        self.logged.as_mut().map(std::mem::take).unwrap_or_default()
    }

    /// Attempts not yet folded.
    pub fn len(&self) -> usize {
        self.attempts.len()
    }

    /// Whether every attempt has been folded.
    pub fn is_empty(&self) -> bool {
        self.attempts.is_empty()
    }

    /// Whether the ledger holds more than its bound for a world of `vehicles`.
    pub fn full(&self, vehicles: usize) -> bool {
        self.attempts.len() >= EVENTS_PER_VEHICLE * vehicles.max(1)
    }

    /// The attempts not yet folded, in the order they were decided.
    pub fn events(&self) -> impl Iterator<Item = LinkEvent> + '_ {
        self.attempts.iter().map(|a| a.event(&self.frames))
    }

    /// The attempts at receiver `id` not yet folded, in order.
    pub fn pending(&self, id: u32) -> impl Iterator<Item = LinkEvent> + '_ {
        self.events().filter(move |e| e.rx == id)
    }

    /// Takes the attempts logged since the last call (see [`crate::comm::Medium::log_links`]).
    pub fn drain_heard(&mut self) -> std::vec::Drain<'_, Heard> {
        self.heard.drain(..)
    }

    /// Takes the attempts grouped by receiver (see [`Grouped`]); hand them back with
    /// [`Ledger::done`] once applied.
    pub fn grouped(&mut self, vehicles: usize) -> Grouped {
        // Copied into receiver order, so that each receiver's fold reads its attempts from
        // one place rather than gathering them from the whole ledger.
        let pairs = self.attempts.iter().map(|a| (a.rx, *a));
        let by = match self.grouped.take() {
            Some(mut by) => {
                by.regroup(vehicles, pairs);
                by
            }
            None => ByVehicle::new(vehicles, pairs),
        };
        self.attempts.clear();
        Grouped {
            by,
            frames: std::mem::take(&mut self.frames),
        }
    }

    /// Takes back the buffers of attempts that were applied.
    pub fn done(&mut self, g: Grouped) {
        // No frame enters between `grouped` and `done` (both run in the same system): the
        // table handed out comes back emptied, keeping its allocation.
        debug_assert!(self.frames.is_empty());
        self.grouped = Some(g.by);
        self.frames = g.frames;
        self.frames.clear();
    }

    /// Folds every attempt into the statistics of its receiver, on the calling thread:
    /// `items` pairs each vehicle id (below `vehicles`) with its statistics, in any order.
    pub fn fold_into<S>(&mut self, vehicles: usize, items: impl Iterator<Item = (u32, S)>)
    where
        S: DerefMut<Target = CommStats>,
    {
        if self.attempts.is_empty() {
            // Frames nobody was in range of: nothing refers to them.
            self.frames.clear();
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

/// The ledger's attempts grouped by receiver, each receiver's in the order they happened (a
/// stable grouping), so receivers can be folded independently, e.g. in parallel.
pub struct Grouped {
    by: ByVehicle<Attempt>,
    frames: Vec<FrameInfo>,
}

impl Grouped {
    /// Applies the attempts at receiver `id` to its statistics `stats` (`scratch`: a
    /// buffer, reused from receiver to receiver).
    pub fn apply(&self, id: u32, stats: &mut CommStats, scratch: &mut Vec<LinkEvent>) {
        scratch.clear();
        scratch.extend(self.by.of(id).iter().map(|a| a.event(&self.frames)));
        stats.apply_all(scratch);
    }
}
