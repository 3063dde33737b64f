//! Leader–follower formation on unicast: the leader tells each follower, by an acknowledged
//! unicast every `period` seconds, the heading, depth and surge it is steering for; a
//! follower steers for what it was last told. Started in formation, the group turns and
//! travels together — open loop: a follower keeps its offset only as well as its own control
//! follows the same orders, and it drifts when orders stop arriving.

use super::{Behaviour, BehaviourIo};
use crate::comm::FrameOutcome;
use shoal_model::control::Mode;

/// Order frame tag.
const ORDER: u8 = b'F';

/// The leader: sends its setpoints to every follower.
pub struct Leader {
    /// Follower ids.
    followers: Vec<u32>,
    /// Time between orders \[s\].
    period: f64,
    next: f64,
    /// Orders handed over, acknowledged, given up.
    counts: (u64, u64, u64),
}

impl Leader {
    /// A leader of `followers` (ids), ordering every `period` \[s\].
    pub fn new(followers: Vec<u32>, period: f64) -> Self {
        Self {
            followers,
            period,
            next: 0.0,
            counts: (0, 0, 0),
        }
    }
}

impl Behaviour for Leader {
    fn tick(&mut self, io: &mut BehaviourIo<'_>) {
        for e in io.outcomes {
            let ok = e.outcome == FrameOutcome::Acknowledged;
            self.counts.1 += u64::from(ok);
            self.counts.2 += u64::from(!ok);
        }
        if io.t + 1e-12 < self.next {
            return;
        }
        self.next = io.t + self.period;
        let sp = &io.setpoints;
        let mut payload = vec![ORDER];
        for x in [sp.yaw, sp.depth, sp.surge] {
            payload.extend_from_slice(&(x as f32).to_le_bytes());
        }
        for &f in &self.followers {
            io.send_to(f, None, &payload, 0.0, true);
            self.counts.0 += 1;
        }
    }

    fn report(&self) -> Vec<(&'static str, f64)> {
        vec![
            ("orders", self.counts.0 as f64),
            ("acknowledged", self.counts.1 as f64),
            ("gave_up", self.counts.2 as f64),
        ]
    }
}

/// A follower: steers (auto mode) for the heading, depth and surge of the last order.
#[derive(Default)]
pub struct Follower {
    orders: u64,
    last: f64,
}

impl Behaviour for Follower {
    fn tick(&mut self, io: &mut BehaviourIo<'_>) {
        let is_order = |r: &&crate::comm::Received| {
            r.unicast && r.payload.len() >= 13 && r.payload[0] == ORDER
        };
        self.orders += io.inbox.iter().filter(is_order).count() as u64;
        let Some(r) = io.inbox.iter().rev().find(is_order) else {
            return;
        };
        let f = |k: usize| {
            let b = &r.payload[1 + 4 * k..5 + 4 * k];
            f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        };
        io.setpoints.mode = Mode::Auto;
        io.setpoints.yaw = f(0);
        io.setpoints.depth = f(1);
        io.setpoints.surge = f(2);
        self.last = r.t;
    }

    fn report(&self) -> Vec<(&'static str, f64)> {
        vec![("orders", self.orders as f64), ("last_order_at", self.last)]
    }
}
