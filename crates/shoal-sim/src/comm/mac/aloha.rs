//! Unslotted (pure) ALOHA: a modem transmits as soon as a frame is ready and it is idle.

use super::{Ctx, Decision, MediumAccess};
use shoal_world::access::Aloha;

impl MediumAccess for Aloha {
    fn decide(&self, _: &mut Ctx<'_>) -> Decision {
        Decision::Send
    }
}
