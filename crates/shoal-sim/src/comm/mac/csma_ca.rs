//! CSMA/CA with binary exponential back-off (the distributed coordination function of IEEE
//! 802.11, basic access): before a frame the modem draws a back-off of 0 … CW − 1 slots; it
//! counts a slot down for every slot the channel stays idle, freezes while it is busy, and
//! waits a DIFS of idle channel after every busy period before it counts again; it sends when
//! the count is zero. CW starts at `cw_min` and doubles (up to `cw_max`) each time a unicast
//! frame's acknowledgement does not come, back to `cw_min` when one does — the protocol whose
//! saturation throughput Bianchi's model predicts.

use super::{AccessState, Ctx, Decision, MediumAccess, count_idle};
use rand::RngExt;
use shoal_world::access::CsmaCa;

/// The contention window of `p` at back-off stage `stage` \[slots\].
fn window(p: &CsmaCa, stage: u32) -> u32 {
    p.cw_min
        .saturating_mul(1u32.checked_shl(stage).unwrap_or(u32::MAX))
        .min(p.cw_max)
}

impl MediumAccess for CsmaCa {
    fn decide(&self, ctx: &mut Ctx<'_>) -> Decision {
        let count = match ctx.state.counter {
            Some(c) => c,
            None => {
                let w = window(self, ctx.state.stage);
                let c = ctx.rng.random_range(0..w);
                ctx.state.counter = Some(c);
                c
            }
        };
        let since = match (ctx.idle_since)(self.threshold) {
            Ok(since) => since,
            // Busy: frozen; look again when it may have fallen idle.
            Err(until) => return Decision::At(until),
        };
        // The idle slots start a DIFS after the channel fell idle, for every station that
        // heard it fall idle: a station that comes back later (after waiting for an
        // acknowledgement) joins the same slots.
        // The medium forgets frames a DIFS after they ended: the anchor remembers the last
        // one heard (none at all: slots from the start of the run).
        let first = if since.is_finite() {
            since + self.difs
        } else {
            ctx.state.anchor.unwrap_or(self.difs)
        };
        count_idle(ctx, first, self.backoff_slot, count)
    }

    fn listens(&self) -> bool {
        true
    }

    fn memory(&self) -> f64 {
        self.difs
    }

    fn feedback(&self, state: &mut AccessState, acknowledged: bool) {
        if acknowledged {
            state.stage = 0;
        } else if window(self, state.stage) < self.cw_max {
            state.stage += 1;
        }
    }
}
