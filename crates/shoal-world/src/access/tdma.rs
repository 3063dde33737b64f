//! Time-division multiple access: the settings of `access = "tdma"`.

use super::{Frames, Number, Protocol, SLOT};
use crate::range::{End, FieldRange, r};
use serde::{Deserialize, Serialize};

/// Time-division: frames start only at the beginning of the vehicle's own slot in a cycle
/// of `slots` slots of length `slot`, one frame per slot.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tdma {
    /// Slot length \[s\]; at least the longest frame's airtime.
    #[serde(default = "super::slotted_aloha::slot")]
    pub slot: f64,
    /// Slots per cycle.
    #[serde(default = "slots")]
    pub slots: u32,
    /// The vehicle's slot in the cycle, 0 … `slots` − 1; `None`: its id modulo `slots`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub own_slot: Option<u32>,
}

fn slots() -> u32 {
    1
}

impl Default for Tdma {
    fn default() -> Self {
        Self {
            slot: super::slotted_aloha::slot(),
            slots: slots(),
            own_slot: None,
        }
    }
}

/// Allowed ranges of its settings.
pub(super) const RANGES: &[FieldRange] = &[
    SLOT,
    r(
        "vehicles[].model.modems[].access.slots",
        End::Closed(1.0),
        End::Closed(1e6),
        "slots",
        "tdma: slots per cycle",
    ),
    r(
        "vehicles[].model.modems[].access.own_slot",
        End::Closed(0.0),
        End::OpenField("slots"),
        "",
        "tdma: the vehicles' slot; default: vehicle id modulo slots",
    ),
];

impl Protocol for Tdma {
    fn numbers(&self, frames: &Frames) -> Vec<Number> {
        let mut n = vec![
            Number {
                lo: Some(frames.longest),
                ..Number::new("slot", self.slot)
            },
            Number::new("slots", f64::from(self.slots)),
        ];
        if let Some(own) = self.own_slot {
            n.push(Number {
                hi: Some(f64::from(self.slots)),
                ..Number::new("own_slot", f64::from(own))
            });
        }
        n
    }

    fn slot(&self) -> Option<f64> {
        Some(self.slot)
    }
}
