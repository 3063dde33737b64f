//! Slotted p-persistent CSMA: the settings of `access = "p_persistent"`.

use super::{BACKOFF_SLOT, Frames, Number, Protocol, THRESHOLD};
use crate::range::{End, FieldRange, r};
use serde::{Deserialize, Serialize};

/// Slotted p-persistent CSMA: a ready frame waits for the channel to be idle; from then on,
/// at every slot boundary (slots of `backoff_slot`, the first one a slot after the channel
/// fell idle) it is sent with probability `p`, else it waits for the next boundary; a busy
/// channel starts the wait over.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PPersistent {
    /// Busy threshold on received optical power \[W\].
    #[serde(default = "threshold")]
    pub threshold: f64,
    /// Contention slot \[s\].
    #[serde(default = "backoff_slot")]
    pub backoff_slot: f64,
    /// Probability of sending at an idle slot boundary \[1\].
    #[serde(default = "p")]
    pub p: f64,
}

fn threshold() -> f64 {
    1e-9
}
fn backoff_slot() -> f64 {
    0.001
}
fn p() -> f64 {
    0.1
}

impl Default for PPersistent {
    fn default() -> Self {
        Self {
            threshold: threshold(),
            backoff_slot: backoff_slot(),
            p: p(),
        }
    }
}

/// Allowed ranges of its settings.
pub(super) const RANGES: &[FieldRange] = &[
    THRESHOLD,
    BACKOFF_SLOT,
    r(
        "vehicles[].model.modems[].access.p",
        End::Open(0.0),
        End::Closed(1.0),
        "",
        "p_persistent: probability of sending at an idle slot boundary",
    ),
];

impl Protocol for PPersistent {
    fn numbers(&self, _: &Frames) -> Vec<Number> {
        vec![
            Number::new("threshold", self.threshold),
            Number::new("backoff_slot", self.backoff_slot),
            Number::new("p", self.p),
        ]
    }
}
