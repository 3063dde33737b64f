//! Slotted p-persistent CSMA: a ready frame waits for the channel to be idle; from then on,
//! at every slot boundary (slots of `backoff_slot` counted from the moment the channel fell
//! idle, the first a slot later) it is sent with probability p, else it waits for the next
//! boundary; a busy channel starts the wait over. Stations that decide at the same boundary
//! do not hear each other start (sensing takes time) and collide — in saturation each idle
//! slot carries a success with probability n·p·(1 − p)^(n−1) among n stations.
//!
//! The draws are made at once: how many idle boundaries pass before the one it sends at is
//! geometric (failures before the first success at probability p), drawn when the frame first
//! finds the channel idle and then counted down like CSMA/CA's back-off ([`Decision::Count`]).
//! A busy channel freezes the count; since the draws are independent, what is left of it is
//! again geometric — the same law as drawing afresh at every boundary.

use super::{Ctx, Decision, MediumAccess, count_idle};
use rand::RngExt;
use shoal_world::access::PPersistent;

/// The number of failures before the first success of independent trials of probability `p`
/// in (0, 1], by inversion of the geometric law's distribution at `u` uniform in [0, 1).
fn failures(u: f64, p: f64) -> u32 {
    // P(k ≥ n) = (1 − p)^n: k = ⌊ln(1 − u) / ln(1 − p)⌋ (0 for p = 1; saturating).
    ((-u).ln_1p() / (-p).ln_1p()).floor() as u32
}

impl MediumAccess for PPersistent {
    fn decide(&self, ctx: &mut Ctx<'_>) -> Decision {
        let slot = self.backoff_slot;
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
        // How many idle boundaries let pass before the one to send at: drawn once the channel
        // is found idle.
        let left = *ctx
            .state
            .counter
            .get_or_insert_with(|| failures(ctx.rng.random::<f64>(), self.p));
        count_idle(ctx, first, slot, left)
    }

    fn listens(&self) -> bool {
        true
    }

    fn memory(&self) -> f64 {
        2.0 * self.backoff_slot
    }
}

#[cfg(test)]
mod tests {
    use super::failures;

    /// The failures drawn follow the geometric law: P(k = n) = (1 − p)^n · p, checked on a
    /// fine grid of u for p = 0.1 and 0.5; p = 1 never fails.
    #[test]
    fn failures_are_geometric() {
        for p in [0.1, 0.5] {
            let n = 1_000_000;
            let mut counts = [0u32; 8];
            for i in 0..n {
                let k = failures((f64::from(i) + 0.5) / f64::from(n), p) as usize;
                if k < counts.len() {
                    counts[k] += 1;
                }
            }
            for (k, &c) in counts.iter().enumerate() {
                let law = (1.0 - p).powi(k as i32) * p;
                let got = f64::from(c) / f64::from(n);
                assert!((got - law).abs() < 2e-6, "p = {p}, k = {k}: {got} vs {law}");
            }
        }
        assert_eq!(failures(0.999_999, 1.0), 0);
        assert_eq!(failures(0.0, 1.0), 0);
    }
}
