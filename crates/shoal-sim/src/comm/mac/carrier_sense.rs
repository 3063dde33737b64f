//! Carrier sense (listen before talk): a modem transmits only if the optical power all of the
//! vehicle's photodiodes receive is below a threshold; otherwise it waits a random back-off
//! and listens again.

use super::{Ctx, Decision, MediumAccess};

/// Carrier sense with a uniform random back-off.
#[derive(Debug)]
pub(super) struct CarrierSense {
    /// Busy threshold on received optical power \[W\].
    pub(super) threshold: f64,
    /// Longest back-off \[s\].
    pub(super) backoff_max: f64,
}

impl MediumAccess for CarrierSense {
    fn decide(&self, ctx: &mut Ctx<'_>) -> Decision {
        if (ctx.busy)(self.threshold) {
            Decision::Backoff(self.backoff_max)
        } else {
            Decision::Send
        }
    }
}
