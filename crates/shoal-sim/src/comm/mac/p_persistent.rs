//! Slotted p-persistent CSMA: a ready frame waits for the channel to be idle; from then on,
//! at every slot boundary (slots of `backoff_slot` counted from the moment the channel fell
//! idle, the first a slot later) it is sent with probability p, else it waits for the next
//! boundary; a busy channel starts the wait over. Stations that decide at the same boundary
//! do not hear each other start (sensing takes time) and collide — in saturation each idle
//! slot carries a success with probability n·p·(1 − p)^(n−1) among n stations.

use super::{Ctx, Decision, MediumAccess, next_boundary};
use rand::RngExt;
use shoal_world::access::PPersistent;

impl MediumAccess for PPersistent {
    fn decide(&self, ctx: &mut Ctx<'_>) -> Decision {
        let (t, slot) = (ctx.t, self.backoff_slot);
        let since = match (ctx.idle_since)(self.threshold) {
            Ok(since) => since,
            // Busy: look again when it may have fallen idle.
            Err(until) => return Decision::At(until),
        };
        // Slots from a slot after the channel fell idle. The medium forgets frames two slots
        // after they ended (`memory`), by when every station has looked at least once: the
        // anchor remembers where the slots begin (nothing heard yet: from t = 0), so that
        // all stations keep the same boundaries.
        let first = if since.is_finite() {
            since + slot
        } else {
            ctx.state.anchor.unwrap_or(0.0)
        };
        ctx.state.anchor = Some(first);
        if t < first - 1e-9 * slot {
            return Decision::At(first);
        }
        let (b, on) = next_boundary(t, slot, first);
        if !on {
            Decision::At(b)
        } else if ctx.rng.random::<f64>() < self.p {
            Decision::Send
        } else {
            Decision::At(t + slot)
        }
    }

    fn memory(&self) -> f64 {
        2.0 * self.backoff_slot
    }
}
