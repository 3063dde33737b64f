//! Time-division multiple access: a cycle of `slots` slots of length `slot`; a vehicle starts
//! frames only at the beginning of its own slot, one per slot. With distinct slots and a slot
//! that holds the longest frame (checked on load), no two frames of the schedule overlap.

use super::{Ctx, Decision, MediumAccess, next_boundary};
use shoal_world::access::Tdma;

impl MediumAccess for Tdma {
    fn decide(&self, ctx: &mut Ctx<'_>) -> Decision {
        let own = self.own_slot.unwrap_or(ctx.vehicle % self.slots);
        let cycle = self.slot * f64::from(self.slots);
        let (b, now) = next_boundary(ctx.t, cycle, self.slot * f64::from(own));
        if now { Decision::Send } else { Decision::At(b) }
    }

    fn acks_wait(&self) -> bool {
        true
    }
}
