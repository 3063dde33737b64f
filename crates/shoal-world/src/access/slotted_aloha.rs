//! Slotted ALOHA: the settings of `access = "slotted_aloha"`.

use super::{Frames, Number, Protocol, SLOT};
use crate::range::{End, FieldRange, r};
use serde::{Deserialize, Serialize};

/// Slotted ALOHA: a ready frame waits for the next slot boundary of the vehicle's own
/// clock, which runs `1 + drift` times as fast as true time (each vehicle's drift drawn once,
/// uniformly in ±`clock_drift_ppm`, from the world seed).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SlottedAloha {
    /// Slot length on the vehicle's clock \[s\]; at least the longest frame's airtime.
    #[serde(default = "slot")]
    pub slot: f64,
    /// Largest clock rate error of a vehicle \[ppm\].
    #[serde(default)]
    pub clock_drift_ppm: f64,
}

/// The default slot \[s\]: the μAUV² modem's longest frame (64 bytes of 10 line bits at
/// 19.2 kbit/s: 33.3 ms) and a guard of 1.7 ms.
pub(super) fn slot() -> f64 {
    0.035
}

impl Default for SlottedAloha {
    fn default() -> Self {
        Self {
            slot: slot(),
            clock_drift_ppm: 0.0,
        }
    }
}

/// Allowed ranges of its settings.
pub(super) const RANGES: &[FieldRange] = &[
    SLOT,
    r(
        "vehicles[].model.modems[].access.clock_drift_ppm",
        End::Closed(0.0),
        End::Closed(1e5),
        "ppm",
        "slotted_aloha: largest clock rate error",
    ),
];

impl Protocol for SlottedAloha {
    fn numbers(&self, frames: &Frames) -> Vec<Number> {
        vec![
            Number {
                lo: Some(frames.longest),
                ..Number::new("slot", self.slot)
            },
            Number::new("clock_drift_ppm", self.clock_drift_ppm),
        ]
    }

    fn slot(&self) -> Option<f64> {
        Some(self.slot)
    }

    fn clock_drift(&self) -> f64 {
        self.clock_drift_ppm * 1e-6
    }
}
