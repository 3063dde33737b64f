//! Reliable gossip: flooding one value with acknowledged unicasts instead of blind rebroadcasts.
//! Every vehicle says hello (a short broadcast) every `hello` seconds, so that each knows its
//! neighbours; a vehicle that knows the value hands it to each neighbour it has heard and does
//! not know to have it, one unicast each, acknowledged and retried by the link layer
//! (stop-and-wait ARQ, `comm::mac::arq`). A neighbour counts as served when its
//! acknowledgement arrives or when it is heard passing the value on; one whose retries ran out
//! is tried again after its next hello.

use super::{Behaviour, BehaviourIo};
use crate::comm::FrameOutcome;
use rand::RngExt;
use std::collections::BTreeMap;

/// Frame tags.
const HELLO: u8 = b'H';
const VALUE: u8 = b'R';

/// What a vehicle knows of a neighbour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Neighbour {
    /// Heard; the value not handed to it yet.
    Heard,
    /// A unicast with the value is on its way.
    Sending,
    /// It has the value (acknowledged, or heard passing it on).
    Served,
    /// Its retries ran out; tried again after its next hello.
    Failed,
}

/// Reliable gossip (see the module doc).
pub struct ReliableGossip {
    origin: bool,
    start: f64,
    hello: f64,
    /// (value, hops, time learned).
    known: Option<(u32, u8, f64)>,
    next_hello: Option<f64>,
    neighbours: BTreeMap<u32, Neighbour>,
    /// Unicasts handed over, acknowledged, given up.
    counts: (u64, u64, u64),
}

impl ReliableGossip {
    /// A member of the flood; `origin` learns the value at `start` \[s\]; hellos every
    /// `hello` \[s\].
    pub fn new(origin: bool, start: f64, hello: f64) -> Self {
        Self {
            origin,
            start,
            hello,
            known: None,
            next_hello: None,
            neighbours: BTreeMap::new(),
            counts: (0, 0, 0),
        }
    }
}

impl Behaviour for ReliableGossip {
    fn tick(&mut self, io: &mut BehaviourIo<'_>) {
        // Hellos, from a random phase on.
        let next = *self
            .next_hello
            .get_or_insert_with(|| io.t + io.rng.random::<f64>() * self.hello);
        if next <= io.t + io.period {
            io.send(None, &[HELLO], next - io.t);
            self.next_hello = Some(next + self.hello);
        }
        for r in io.inbox {
            match r.payload.first() {
                Some(&HELLO) => {
                    let n = self.neighbours.entry(r.from).or_insert(Neighbour::Heard);
                    if *n == Neighbour::Failed {
                        *n = Neighbour::Heard;
                    }
                }
                Some(&VALUE) if r.payload.len() >= 6 => {
                    self.neighbours.insert(r.from, Neighbour::Served);
                    if self.known.is_none() {
                        let v = [r.payload[1], r.payload[2], r.payload[3], r.payload[4]];
                        let hops = r.payload[5].saturating_add(1);
                        self.known = Some((u32::from_le_bytes(v), hops, r.t));
                    }
                }
                _ => {}
            }
        }
        for e in io.outcomes {
            let ok = e.outcome == FrameOutcome::Acknowledged;
            self.counts.1 += u64::from(ok);
            self.counts.2 += u64::from(!ok);
            self.neighbours.insert(
                e.to,
                if ok {
                    Neighbour::Served
                } else {
                    Neighbour::Failed
                },
            );
        }
        if self.known.is_none() && self.origin && io.t + 1e-12 >= self.start {
            self.known = Some((0xC0FFEE, 0, self.start));
        }
        let Some((value, hops, _)) = self.known else {
            return;
        };
        let v = value.to_le_bytes();
        let payload = [VALUE, v[0], v[1], v[2], v[3], hops];
        for (&id, n) in self.neighbours.iter_mut() {
            if *n == Neighbour::Heard {
                io.send_to(id, None, &payload, 0.0, true);
                *n = Neighbour::Sending;
                self.counts.0 += 1;
            }
        }
    }

    fn report(&self) -> Vec<(&'static str, f64)> {
        let (t, hops) = self
            .known
            .map_or((f64::NAN, f64::NAN), |(_, h, t)| (t, f64::from(h)));
        vec![
            ("learned_at", t),
            ("hops", hops),
            ("origin_start", self.start),
            ("unicasts", self.counts.0 as f64),
            ("acknowledged", self.counts.1 as f64),
            ("gave_up", self.counts.2 as f64),
        ]
    }
}
