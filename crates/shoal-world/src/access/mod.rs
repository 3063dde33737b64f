//! A modem's link layer as a world states it: how it gets the medium (the world file's
//! `access` with its fields, resolved: [`Access`]) and how it retries unicast frames sent with
//! acknowledgement ([`LinkParams`]). The protocols that act on them are the simulation's
//! (`shoal_sim::comm::mac`, one file each); this is what a world says about them, checked on
//! load.

/// The link layer of one modem.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinkParams {
    /// Medium access.
    pub access: Access,
    /// Retransmissions of an unacknowledged unicast frame before the sender gives up.
    pub retries: u32,
    /// How long a sender waits for an acknowledgement after its frame ended \[s\].
    pub ack_timeout: f64,
}

/// A modem's medium access, in SI units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Access {
    /// Unslotted ALOHA: transmit as soon as a frame is ready and the modem is idle.
    Aloha,
    /// Listen before talk: transmit only if the optical power the vehicle's photodiodes
    /// receive is below `threshold`; otherwise wait a random time up to `backoff_max` and
    /// listen again.
    CarrierSense {
        /// Busy threshold on received optical power \[W\].
        threshold: f64,
        /// Longest random back-off \[s\].
        backoff_max: f64,
    },
    /// Slotted ALOHA: a ready frame waits for the next slot boundary of the vehicle's own
    /// clock, which runs `1 + clock_drift` times as fast as true time.
    SlottedAloha {
        /// Slot length on the vehicle's clock \[s\].
        slot: f64,
        /// Largest relative rate error of a vehicle's clock \[1\] (each vehicle's is drawn
        /// once, uniformly in ±this, from the world seed).
        clock_drift: f64,
    },
    /// Time-division: frames start only at the beginning of the vehicle's own slot in a
    /// cycle of `slots` slots of length `slot`, one frame per slot.
    Tdma {
        /// Slot length \[s\].
        slot: f64,
        /// Slots per cycle.
        slots: u32,
        /// The vehicle's slot in the cycle; `None`: its id modulo `slots`.
        own: Option<u32>,
    },
    /// CSMA/CA with binary exponential back-off: a random back-off of 0 … CW − 1 slots,
    /// counted down while the channel stays idle (after a DIFS of idle channel), CW doubling
    /// from `cw_min` to `cw_max` each time an acknowledgement does not come.
    CsmaCa {
        /// Busy threshold on received optical power \[W\].
        threshold: f64,
        /// Back-off slot \[s\].
        slot: f64,
        /// Idle channel before the count resumes \[s\].
        difs: f64,
        /// Smallest contention window \[slots\].
        cw_min: u32,
        /// Largest contention window \[slots\].
        cw_max: u32,
    },
}

impl Access {
    /// The slot length of slotted protocols \[s\] (`None` for unslotted ones).
    pub fn slot(&self) -> Option<f64> {
        match *self {
            Access::SlottedAloha { slot, .. } | Access::Tdma { slot, .. } => Some(slot),
            Access::Aloha | Access::CarrierSense { .. } | Access::CsmaCa { .. } => None,
        }
    }
}
