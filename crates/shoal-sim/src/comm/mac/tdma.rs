//! Time-division multiple access: a cycle of `slots` slots of length `slot`; a vehicle starts
//! frames only at the beginning of its own slot, one per slot. With distinct slots and a slot
//! that holds the longest frame (checked on load), no two frames of the schedule overlap.

use super::{Ctx, Decision, MediumAccess, next_boundary};

/// TDMA from a fixed schedule.
#[derive(Debug)]
pub(super) struct Tdma {
    /// Slot length \[s\].
    pub(super) slot: f64,
    /// Slots per cycle.
    pub(super) slots: u32,
    /// The vehicle's slot; `None`: its id modulo `slots`.
    pub(super) own: Option<u32>,
}

impl MediumAccess for Tdma {
    fn decide(&self, ctx: &mut Ctx<'_>) -> Decision {
        let own = self.own.unwrap_or(ctx.vehicle % self.slots);
        let cycle = self.slot * f64::from(self.slots);
        let (b, now) = next_boundary(ctx.t, cycle, self.slot * f64::from(own));
        if now { Decision::Send } else { Decision::At(b) }
    }

    fn acks_wait(&self) -> bool {
        true
    }
}
