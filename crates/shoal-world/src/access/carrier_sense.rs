//! Carrier sense (listen before talk): the settings of `access = "carrier_sense"`.

use super::{Frames, Number, Protocol, THRESHOLD};
use crate::range::{End, FieldRange, r};
use serde::{Deserialize, Serialize};

/// Listen before talk: transmit only if the optical power the vehicle's photodiodes receive
/// is below `threshold`; otherwise wait a random time up to `backoff_max` and listen again.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CarrierSense {
    /// Busy threshold on received optical power \[W\].
    #[serde(default = "threshold")]
    pub threshold: f64,
    /// Longest random back-off \[s\].
    #[serde(default = "backoff_max")]
    pub backoff_max: f64,
}

fn threshold() -> f64 {
    1e-9
}
fn backoff_max() -> f64 {
    0.05
}

impl Default for CarrierSense {
    fn default() -> Self {
        Self {
            threshold: threshold(),
            backoff_max: backoff_max(),
        }
    }
}

/// Allowed ranges of its settings.
pub(super) const RANGES: &[FieldRange] = &[
    THRESHOLD,
    r(
        "vehicles[].model.modems[].access.backoff_max",
        End::Closed(1e-6),
        End::Closed(100.0),
        "s",
        "carrier_sense: longest random back-off",
    ),
];

impl Protocol for CarrierSense {
    fn numbers(&self, _: &Frames) -> Vec<Number> {
        vec![
            Number::new("threshold", self.threshold),
            Number::new("backoff_max", self.backoff_max),
        ]
    }
}
