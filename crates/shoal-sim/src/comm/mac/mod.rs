//! The link layer: medium access — when a modem may start the frame at the head of its queue,
//! one protocol per file, each a [`MediumAccess`] — and, above any of them, stop-and-wait ARQ
//! for unicast frames sent with acknowledgement (`arq.rs`: [`Link`], [`FrameEvent`]).
//! [`build`] turns a world's [`LinkParams`] into a modem's [`ModemLink`].
//!
//! The transmit phase ([`super::comm_transmit_system`]) walks the modems' start events in time
//! order within the step and asks the modem's protocol at each one:
//!
//! | protocol | file | decides |
//! |---|---|---|
//! | unslotted ALOHA | `aloha.rs` | always [`Decision::Send`] |
//! | carrier sense | `carrier_sense.rs` | send if the vehicle's photodiodes receive less than the threshold, else a random [`Decision::Backoff`] |
//! | slotted ALOHA | `slotted_aloha.rs` | send on a slot boundary of the vehicle's own (drifting) clock, else wait for the next one ([`Decision::At`]) |
//! | TDMA | `tdma.rs` | send at the start of the vehicle's own slot of the cycle, else wait for it |
//! | CSMA/CA | `csma_ca.rs` | count a random back-off down over idle slots after a DIFS of idle channel ([`Decision::Count`]), then send; the window doubles when an acknowledgement does not come ([`MediumAccess::feedback`]) |
//! | p-persistent CSMA | `p_persistent.rs` | at each slot boundary of an idle channel, send with probability p, else wait for the next (the number of boundaries it lets pass drawn at once, and counted down) |
//!
//! Acknowledgements bypass the protocol (sent as soon as the modem is free, like 802.11's
//! after SIFS) unless it says they wait ([`MediumAccess::acks_wait`]: the slotted ones).
//!
//! Adding a protocol is a file here (its [`MediumAccess`], a line in [`build`]'s `access`), its
//! world-file settings (a file of `shoal_world::access`: their type, defaults and allowed
//! ranges, a line in its list of protocols) and its row in `docs/mac.md` — as
//! `p_persistent.rs` was added.

mod aloha;
mod arq;
mod carrier_sense;
mod csma_ca;
mod p_persistent;
mod slotted_aloha;
mod tdma;

use super::frames::AccessState;
use crate::rng::VehicleRng;
pub use arq::Link;
pub(super) use arq::{AckDue, LinkState, Pending};
use shoal_world::access::{Access, LinkParams};
use std::sync::Arc;

/// What a modem does with the frame at the head of its queue.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Decision {
    /// Start it now.
    Send,
    /// Ask again at this time \[s\] (a slot boundary; later than now).
    At(f64),
    /// The channel is idle now; from the slot boundary `from` (now, or the next one) on,
    /// `left` boundaries of `slot` \[s\] are to pass idle (`from` included): ask again at the
    /// boundary after them, with `AccessState::counter` 0 — or, if a frame starts nearby
    /// first, at the first boundary after its start, with the count still to go there
    /// (`countdown.rs`). Slot by slot, the same as `At(from)` with the counter at `left` (or,
    /// if `from` is now, `At(now + slot)` with the counter at `left − 1`), asked again at each.
    Count {
        /// The first boundary counted \[s\].
        from: f64,
        /// Slot \[s\].
        slot: f64,
        /// Boundaries to pass idle, `from` included.
        left: u32,
    },
    /// The channel is busy: ask again after a random delay, uniform up to this long \[s\],
    /// drawn from the vehicle's stream — one draw for all of the vehicle's modems that defer
    /// at the same moment, so that the copies of a frame stay in sync.
    Backoff(f64),
}

/// What a protocol may look at when it decides.
pub(super) struct Ctx<'a> {
    /// Now \[s\].
    pub(super) t: f64,
    /// The deciding vehicle's id.
    pub(super) vehicle: u32,
    /// How fast the vehicle's clock runs against true time \[1\] (1 + its drift).
    pub(super) clock_rate: f64,
    /// Whether the optical power the vehicle's photodiodes receive now exceeds this \[W\]
    /// (from the frames of other vehicles on the air).
    pub(super) busy: &'a mut dyn FnMut(f64) -> bool,
    /// With this busy threshold \[W\]: `Ok(since)` if the channel is idle now, since when \[s\]
    /// (the end of the last frame heard above it, the vehicle's own included; −∞ if none);
    /// `Err(until)` if it is busy, until when at least \[s\] (the first end of a frame heard
    /// now: it cannot fall idle earlier).
    pub(super) idle_since: &'a mut dyn FnMut(f64) -> Result<f64, f64>,
    /// The modem's state.
    pub(super) state: &'a mut AccessState,
    /// The vehicle's random stream for the medium.
    pub(super) rng: &'a mut VehicleRng,
}

/// A medium-access protocol of a modem (shared by the modems of a group: its per-modem state
/// is an [`AccessState`] in the decision's context, not in it).
pub(super) trait MediumAccess: Send + Sync + std::fmt::Debug {
    /// What to do with the frame at the head of the queue at `ctx.t`.
    fn decide(&self, ctx: &mut Ctx<'_>) -> Decision;

    /// A unicast frame sent with acknowledgement was acknowledged (`true`) or its wait ran
    /// out (`false`).
    fn feedback(&self, _state: &mut AccessState, _acknowledged: bool) {}

    /// Whether acknowledgements wait for the protocol like any frame (slotted protocols)
    /// instead of leaving as soon as the modem is free.
    fn acks_wait(&self) -> bool {
        false
    }

    /// How far back the protocol looks at frames that ended (`Ctx::idle_since`) \[s\]: the
    /// medium keeps them that long.
    fn memory(&self) -> f64 {
        0.0
    }

    /// Whether it listens to the channel before it sends (`Ctx::busy`, `Ctx::idle_since`): its
    /// decisions then compute link budgets around the vehicle, and the transmit walk is worth
    /// splitting over threads when many of them are due (`comm/parts.rs`).
    fn listens(&self) -> bool {
        false
    }
}

/// The link layer of one modem: its medium access and its retries.
#[derive(Clone, Debug)]
pub(super) struct ModemLink {
    /// Medium access.
    pub(super) access: Arc<dyn MediumAccess>,
    /// Retransmissions of an unacknowledged unicast frame.
    pub(super) retries: u32,
    /// Wait for an acknowledgement after a frame ended \[s\].
    pub(super) ack_timeout: f64,
}

/// The link layer a world asks for.
pub(super) fn build(l: &LinkParams) -> ModemLink {
    ModemLink {
        access: access(&l.access),
        retries: l.retries,
        ack_timeout: l.ack_timeout,
    }
}

/// The medium-access protocol a world asks for: its settings are the protocol (each file
/// here implements [`MediumAccess`] for the settings' type of `shoal_world::access`).
fn access(a: &Access) -> Arc<dyn MediumAccess> {
    match *a {
        Access::Aloha(p) => Arc::new(p),
        Access::CarrierSense(p) => Arc::new(p),
        Access::SlottedAloha(p) => Arc::new(p),
        Access::Tdma(p) => Arc::new(p),
        Access::CsmaCa(p) => Arc::new(p),
        Access::PPersistent(p) => Arc::new(p),
    }
}

/// The decision at `ctx.t` of a protocol that counts idle slot boundaries (CSMA/CA,
/// p-persistent CSMA) on a channel found idle: its boundaries are `first + k · slot` \[s\]
/// (k ≥ 0; `first` kept as the state's anchor), and `left` of them are to pass idle before the
/// one to send at. On a boundary with nothing left: send (the count is done); else count from
/// this boundary, or from the next one ([`Decision::Count`]).
pub(super) fn count_idle(ctx: &mut Ctx<'_>, first: f64, slot: f64, left: u32) -> Decision {
    let t = ctx.t;
    ctx.state.anchor = Some(first);
    let (b, on) = if t < first - 1e-9 * slot {
        (first, false)
    } else {
        next_boundary(t, slot, first)
    };
    match (on, left) {
        (true, 0) => {
            ctx.state.counter = None;
            Decision::Send
        }
        (true, _) => Decision::Count {
            from: t,
            slot,
            left,
        },
        (false, _) => Decision::Count {
            from: b,
            slot,
            left,
        },
    }
}

/// The first boundary of the lattice `phase + k · period` (k an integer) at or after `t`
/// \[s\], with a tolerance of 10⁻⁹ periods so that a time computed as a boundary counts as
/// one; and whether `t` is (within that tolerance) that boundary.
pub(super) fn next_boundary(t: f64, period: f64, phase: f64) -> (f64, bool) {
    let eps = 1e-9 * period;
    let k = ((t - eps - phase) / period).ceil();
    let b = phase + k * period;
    (b, b - t <= eps)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Boundaries: a time on the lattice is its own boundary (also when computed with
    /// rounding), a time just after one waits for the next, a phase shifts them.
    #[test]
    fn next_boundary_finds_the_lattice_point_at_or_after_a_time() {
        assert_eq!(next_boundary(0.0, 0.035, 0.0), (0.0, true));
        let (b, on) = next_boundary(3.0 * 0.035, 0.035, 0.0);
        assert!(on && (b - 0.105).abs() < 1e-15, "{b}");
        let (b, on) = next_boundary(0.1051, 0.035, 0.0);
        assert!(!on && (b - 0.14).abs() < 1e-15, "{b}");
        // Phase 0.02 in a cycle of 0.1: 0.02, 0.12, …
        let (b, on) = next_boundary(0.05, 0.1, 0.02);
        assert!(!on && (b - 0.12).abs() < 1e-15, "{b}");
        let (b, on) = next_boundary(0.0, 0.1, 0.02);
        assert!(!on && (b - 0.02).abs() < 1e-15, "{b}");
        // Every boundary computed as phase + k · period is found as one.
        for k in 0..10_000 {
            let t = 0.013 + f64::from(k) * 0.037;
            assert_eq!(next_boundary(t, 0.037, 0.013), (t, true), "k = {k}");
        }
    }
}
