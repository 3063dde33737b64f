//! CSMA/CA with binary exponential back-off (the distributed coordination function of IEEE
//! 802.11, basic access): before a frame the modem draws a back-off of 0 … CW − 1 slots; it
//! counts a slot down for every slot the channel stays idle, freezes while it is busy, and
//! waits a DIFS of idle channel after every busy period before it counts again; it sends when
//! the count is zero. CW starts at `cw_min` and doubles (up to `cw_max`) each time a unicast
//! frame's acknowledgement does not come, back to `cw_min` when one does — the protocol whose
//! saturation throughput Bianchi's model predicts.

use super::{AccessState, Ctx, Decision, MediumAccess, next_boundary};
use rand::RngExt;

/// CSMA/CA with binary exponential back-off.
#[derive(Debug)]
pub(super) struct CsmaCa {
    /// Busy threshold on received optical power \[W\].
    pub(super) threshold: f64,
    /// Back-off slot \[s\].
    pub(super) slot: f64,
    /// Idle time after a busy channel before the count resumes \[s\].
    pub(super) difs: f64,
    /// Smallest contention window \[slots\].
    pub(super) cw_min: u32,
    /// Largest contention window \[slots\].
    pub(super) cw_max: u32,
}

impl CsmaCa {
    /// The contention window at back-off stage `stage` \[slots\].
    fn window(&self, stage: u32) -> u32 {
        self.cw_min
            .saturating_mul(1u32.checked_shl(stage).unwrap_or(u32::MAX))
            .min(self.cw_max)
    }
}

impl MediumAccess for CsmaCa {
    fn decide(&self, ctx: &mut Ctx<'_>) -> Decision {
        let t = ctx.t;
        let count = match ctx.state.counter {
            Some(c) => c,
            None => {
                let w = self.window(ctx.state.stage);
                let c = ctx.rng.random_range(0..w);
                ctx.state.counter = Some(c);
                c
            }
        };
        let Some(since) = (ctx.idle_since)(self.threshold) else {
            // Busy: frozen; look again a slot later.
            return Decision::At(t + self.slot);
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
        ctx.state.anchor = Some(first);
        if t < first - 1e-9 * self.slot {
            return Decision::At(first);
        }
        let (b, on) = next_boundary(t, self.slot, first);
        if !on {
            return Decision::At(b);
        }
        if count == 0 {
            ctx.state.counter = None;
            Decision::Send
        } else {
            ctx.state.counter = Some(count - 1);
            Decision::At(t + self.slot)
        }
    }

    fn memory(&self) -> f64 {
        self.difs
    }

    fn feedback(&self, state: &mut AccessState, acknowledged: bool) {
        if acknowledged {
            state.stage = 0;
        } else if self.window(state.stage) < self.cw_max {
            state.stage += 1;
        }
    }
}
