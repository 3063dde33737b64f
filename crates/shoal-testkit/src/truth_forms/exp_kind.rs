//! Which designed μAUV² experiment a truth form shows in.

use crate::design;
use crate::synth::Experiment;

/// Which designed μAUV² experiment ([`crate::design`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ExpKind {
    /// Diving mode, 1-DOF heave ([`design::uauv2_heave`]): logs depth, heading and yaw rate.
    Heave,
    /// Turning mode, 1-DOF yaw ([`design::uauv2_yaw`]): logs heading, yaw rate, depth and
    /// the tracked position.
    Yaw,
    /// Diving mode with the attitude logged ([`design::uauv2_trim`]): logs depth, roll,
    /// pitch, heading and yaw rate.
    Trim,
}

impl ExpKind {
    /// Every experiment.
    pub const ALL: [ExpKind; 3] = [ExpKind::Heave, ExpKind::Yaw, ExpKind::Trim];

    /// The experiment for `seed`, `duration` \[s\] long.
    pub fn experiment(self, seed: u64, duration: f64) -> Experiment {
        match self {
            ExpKind::Heave => design::uauv2_heave(seed, duration),
            ExpKind::Yaw => design::uauv2_yaw(seed, duration),
            ExpKind::Trim => design::uauv2_trim(seed, duration),
        }
    }

    /// Short tag used in case names: `h`, `y` or `t`.
    pub fn tag(self) -> &'static str {
        match self {
            ExpKind::Heave => "h",
            ExpKind::Yaw => "y",
            ExpKind::Trim => "t",
        }
    }

    /// Lower-case name: `heave`, `yaw` or `trim`.
    pub fn name(self) -> &'static str {
        match self {
            ExpKind::Heave => "heave",
            ExpKind::Yaw => "yaw",
            ExpKind::Trim => "trim",
        }
    }
}
