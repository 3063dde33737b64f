//! Identification experiments for the μAUV², designed so that every catalogue effect leaves a
//! mark in the log: command steps up and down (lags, added mass), forward and reverse thrust
//! (asymmetry), small and full commands (dead band, saturation), coasting (damping, buoyancy),
//! pump phases (ballast), a long run (battery sag, drift). Each pattern is repeated so that both
//! the estimation and the validation part of a split run contain every feature. The seed
//! varies levels (±15 %) and hold times (±20 %, in whole tenths of a second).
//!
//! * [`uauv2_heave`] — diving mode (both side thrusters tilted down, β = −π/2, equal
//!   commands): the 1-DOF heave law; logs depth, heading and yaw rate.
//! * [`uauv2_trim`] — the heave experiment with the IMU's attitude logged as well (depth,
//!   roll, pitch, heading and yaw rate): what a trim error shows in.
//! * [`uauv2_yaw`] — turning mode (β = 0, commands balanced for zero surge force as the
//!   validation spec prescribes): the 1-DOF yaw law; logs heading, yaw rate, depth and the
//!   tracked position.

use crate::synth::Experiment;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use shoal_model::math::Vec3;
use shoal_model::presets::{UAUV2_CT_NEG, UAUV2_CT_POS};
use shoal_sysid::log::run::ChannelKind;
use std::f64::consts::FRAC_PI_2;

/// One segment of a pattern: hold time [s], command [%], pump (−1, 0, +1).
type Segment = (f64, f64, f64);

const HEAVE: [Segment; 16] = [
    (3.0, 0.0, 0.0),
    (4.0, 60.0, 0.0),
    (3.0, 0.0, 0.0),
    (4.0, -70.0, 0.0),
    (3.0, 0.0, 0.0),
    (5.0, 25.0, 0.0),
    (5.0, -25.0, 0.0),
    (2.5, 100.0, 0.0),
    (2.5, -100.0, 0.0),
    (3.0, 0.0, 0.0),
    (5.0, 10.0, 0.0),
    (5.0, -10.0, 0.0),
    (3.0, 40.0, 0.0),
    (2.0, 0.0, 0.0),
    (6.0, 0.0, 1.0),
    (6.0, 0.0, -1.0),
];

const YAW: [Segment; 16] = [
    (2.0, 0.0, 0.0),
    (4.0, 50.0, 0.0),
    (3.0, 0.0, 0.0),
    (4.0, -50.0, 0.0),
    (3.0, 0.0, 0.0),
    (3.0, 75.0, 0.0),
    (3.0, -75.0, 0.0),
    (3.0, 0.0, 0.0),
    (5.0, 20.0, 0.0),
    (5.0, -20.0, 0.0),
    (3.0, 0.0, 0.0),
    (5.0, 10.0, 0.0),
    (5.0, -10.0, 0.0),
    (3.0, 0.0, 0.0),
    (4.0, 35.0, 0.0),
    (4.0, -35.0, 0.0),
];

fn expand(pattern: &[Segment], duration: f64, seed: u64) -> Vec<(f64, f64, f64)> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Vec::new();
    let mut t = 0.0;
    'outer: loop {
        for &(hold, n, pump) in pattern {
            if t >= duration {
                break 'outer;
            }
            // Whole tenths of a second: commands change on logger samples.
            let hold = (hold * rng.random_range(0.8..1.2) * 10.0).round() / 10.0;
            let n = (n * rng.random_range(0.85..1.15)).clamp(-100.0, 100.0);
            out.push((t, n, pump));
            t += hold;
        }
    }
    out
}

/// The diving-mode heave experiment: `duration` \[s\], logged at 50 Hz, starting at rest with
/// the pressure port 1 m deep.
pub fn uauv2_heave(seed: u64, duration: f64) -> Experiment {
    let mut inputs = vec![
        (0.0, "alpha".to_string(), 0.0),
        (0.0, "beta".to_string(), -FRAC_PI_2),
        (0.0, "top".to_string(), 0.0),
    ];
    for (t, n, pump) in expand(&HEAVE, duration, seed) {
        inputs.push((t, "port".into(), n));
        inputs.push((t, "stbd".into(), n));
        inputs.push((t, "pump".into(), pump));
    }
    Experiment {
        name: format!("uauv2_heave_{seed}"),
        duration,
        sample_period: 0.02,
        inputs,
        channels: vec![ChannelKind::Depth, ChannelKind::Yaw, ChannelKind::R],
        position: Vec3::new(5.0, 5.0, 1.091),
        yaw: 0.3,
        tracking_noise: 0.0,
    }
}

/// The diving-mode heave experiment of [`uauv2_heave`] with roll and pitch logged as well: a
/// resting hull's tilt and the thrust's pitching and rolling show in them.
pub fn uauv2_trim(seed: u64, duration: f64) -> Experiment {
    let heave = uauv2_heave(seed, duration);
    Experiment {
        name: format!("uauv2_trim_{seed}"),
        channels: vec![
            ChannelKind::Depth,
            ChannelKind::Roll,
            ChannelKind::Pitch,
            ChannelKind::Yaw,
            ChannelKind::R,
        ],
        ..heave
    }
}

/// Starboard command that cancels the surge force of the port command `port` [%] for the
/// preset's C_t⁺/C_t⁻ (the paper's balanced yaw experiment).
pub fn balanced_stbd(port: f64) -> f64 {
    if port >= 0.0 {
        -port * (UAUV2_CT_POS / UAUV2_CT_NEG).sqrt()
    } else {
        -port * (UAUV2_CT_NEG / UAUV2_CT_POS).sqrt()
    }
}

/// The turning-mode yaw experiment: `duration` \[s\], logged at 50 Hz, with a tracked position
/// (1 cm noise), starting at rest 1 m deep.
pub fn uauv2_yaw(seed: u64, duration: f64) -> Experiment {
    let mut inputs = vec![
        (0.0, "alpha".to_string(), 0.0),
        (0.0, "beta".to_string(), 0.0),
        (0.0, "top".to_string(), 0.0),
    ];
    for (t, n, _) in expand(&YAW, duration, seed) {
        // Keep the starboard command within ±100 %.
        let port = n.clamp(-79.0, 79.0);
        inputs.push((t, "port".into(), port));
        inputs.push((t, "stbd".into(), balanced_stbd(port)));
    }
    Experiment {
        name: format!("uauv2_yaw_{seed}"),
        duration,
        sample_period: 0.02,
        inputs,
        channels: vec![
            ChannelKind::Yaw,
            ChannelKind::R,
            ChannelKind::Depth,
            ChannelKind::X,
            ChannelKind::Y,
        ],
        position: Vec3::new(5.0, 5.0, 1.091),
        yaw: -0.5,
        tracking_noise: 0.01,
    }
}
