//! Slotted ALOHA: a ready frame waits for the next slot boundary of the vehicle's own clock.
//! With perfect clocks every vehicle's slots coincide and two frames either overlap wholly or
//! not at all (throughput G·e^(−G) instead of pure ALOHA's G·e^(−2G)); a clock that runs fast
//! or slow (`clock_drift_ppm`) lets the slots of different vehicles slide against each other.

use super::{Ctx, Decision, MediumAccess, next_boundary};
use shoal_world::access::SlottedAloha;

impl MediumAccess for SlottedAloha {
    fn decide(&self, ctx: &mut Ctx<'_>) -> Decision {
        // On the vehicle's clock, τ = rate · t; its boundaries k · slot are at true times
        // k · slot / rate.
        let (b, now) = next_boundary(ctx.t, self.slot / ctx.clock_rate, 0.0);
        if now { Decision::Send } else { Decision::At(b) }
    }

    fn acks_wait(&self) -> bool {
        true
    }
}
