//! CSMA/CA with binary exponential back-off: the settings of `access = "csma_ca"`.

use super::{BACKOFF_SLOT, Frames, Number, Protocol, THRESHOLD};
use crate::range::{End, FieldRange, r};
use serde::{Deserialize, Serialize};

/// CSMA/CA with binary exponential back-off: a random back-off of 0 … CW − 1 slots,
/// counted down while the channel stays idle (after a DIFS of idle channel), CW doubling
/// from `cw_min` to `cw_max` each time an acknowledgement does not come.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CsmaCa {
    /// Busy threshold on received optical power \[W\].
    #[serde(default = "threshold")]
    pub threshold: f64,
    /// Back-off slot \[s\].
    #[serde(default = "backoff_slot")]
    pub backoff_slot: f64,
    /// Idle channel before the count resumes \[s\].
    #[serde(default = "difs")]
    pub difs: f64,
    /// Smallest contention window \[slots\].
    #[serde(default = "cw_min")]
    pub cw_min: u32,
    /// Largest contention window \[slots\].
    #[serde(default = "cw_max")]
    pub cw_max: u32,
}

fn threshold() -> f64 {
    1e-9
}
fn backoff_slot() -> f64 {
    0.001
}
fn difs() -> f64 {
    0.003
}
fn cw_min() -> u32 {
    16
}
fn cw_max() -> u32 {
    1024
}

impl Default for CsmaCa {
    fn default() -> Self {
        Self {
            threshold: threshold(),
            backoff_slot: backoff_slot(),
            difs: difs(),
            cw_min: cw_min(),
            cw_max: cw_max(),
        }
    }
}

/// Allowed ranges of its settings.
pub(super) const RANGES: &[FieldRange] = &[
    THRESHOLD,
    BACKOFF_SLOT,
    r(
        "vehicles[].model.modems[].access.difs",
        End::Closed(0.0),
        End::Closed(1.0),
        "s",
        "csma_ca: idle channel before the back-off count resumes",
    ),
    r(
        "vehicles[].model.modems[].access.cw_min",
        End::Closed(1.0),
        End::Closed(1e6),
        "slots",
        "csma_ca: smallest contention window",
    ),
    r(
        "vehicles[].model.modems[].access.cw_max",
        End::Field("cw_min"),
        End::Closed(1e6),
        "slots",
        "csma_ca: largest contention window",
    ),
];

impl Protocol for CsmaCa {
    fn numbers(&self, _: &Frames) -> Vec<Number> {
        vec![
            Number::new("threshold", self.threshold),
            Number::new("backoff_slot", self.backoff_slot),
            Number::new("difs", self.difs),
            Number::new("cw_min", f64::from(self.cw_min)),
            Number {
                lo: Some(f64::from(self.cw_min)),
                ..Number::new("cw_max", f64::from(self.cw_max))
            },
        ]
    }
}
