//! Carrier sense (listen before talk): a modem transmits only if the optical power all of the
//! vehicle's photodiodes receive is below a threshold; otherwise it waits a random back-off
//! and listens again.

use super::{Ctx, Decision, MediumAccess};
use shoal_world::access::CarrierSense;

impl MediumAccess for CarrierSense {
    fn decide(&self, ctx: &mut Ctx<'_>) -> Decision {
        if (ctx.busy)(self.threshold) {
            Decision::Backoff(self.backoff_max)
        } else {
            Decision::Send
        }
    }

    fn listens(&self) -> bool {
        true
    }
}
