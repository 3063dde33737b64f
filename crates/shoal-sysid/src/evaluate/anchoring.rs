//! Which replay a dataset uses: open loop from each run's first samples, or re-anchored to
//! the measurements every so many seconds ([`Horizon`]; the mechanism is
//! [`crate::evaluate::open_loop::anchors`]). A horizon is given, or chosen from the data:
//! how long the baseline's replay stays within a few times the sensors' noise of the
//! measurements ([`Horizon::Auto`]).

use crate::evaluate::current::Current;
use crate::evaluate::evaluation::{Evaluation, noise_floor};
use crate::log::run::ChannelKind;
use std::collections::BTreeMap;

/// How a dataset's runs are replayed.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum Horizon {
    /// Chosen from the log: as [`Horizon::Auto`] for a run of [`LONG_RUN_S`] or longer (a
    /// mission), open loop for shorter ones (a designed experiment) — and the report says why,
    /// and what the log's commands were (evidence only in a [`Horizon::Closed`] replay).
    #[default]
    Choose,
    /// Open loop, each run from its first samples (short designed runs).
    Open,
    /// Re-anchored every this many seconds \[s\].
    Every(f64),
    /// Re-anchored at a horizon chosen from the data: the median over the runs of how long
    /// the baseline's replay stays within [`AUTO_NOISE_MULTIPLE`] times the noise floor
    /// (1-s moving RMS of its residual, on every anchored channel), at least
    /// [`AUTO_MIN_HORIZON`]; open loop when it stays there throughout.
    Auto,
    /// As [`Horizon::Auto`], and beside each replay its closed-loop twin: the vehicle's
    /// controller follows the references the log carries, and the logged thruster commands
    /// are compared with the twin's as channels ([`crate::evaluate::controlled`]); where
    /// that is not possible, as [`Horizon::Auto`] alone.
    Closed,
}

impl Horizon {
    /// Shortest horizon that may be given \[s\].
    pub const MIN_S: f64 = 0.5;
    /// Longest horizon that may be given \[s\] (an hour).
    pub const MAX_S: f64 = 3600.0;
}

impl std::str::FromStr for Horizon {
    type Err = String;

    /// `choose`, `open`, `auto`, `closed` or a number of seconds (checked against its range
    /// where it is used).
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim() {
            "choose" => Ok(Horizon::Choose),
            "open" => Ok(Horizon::Open),
            "auto" => Ok(Horizon::Auto),
            "closed" => Ok(Horizon::Closed),
            t => t.parse::<f64>().map(Horizon::Every).map_err(|_| {
                format!("`{s}`: allowed choose, open, auto, closed or a number of seconds")
            }),
        }
    }
}

/// Shortest horizon [`Horizon::Auto`] chooses \[s\]: shorter ones leave too little of each horizon for an effect's
/// dynamics to show.
pub const AUTO_MIN_HORIZON: f64 = 2.0;

/// How far above its noise floor the baseline's replay may stray before [`Horizon::Auto`]
/// re-anchors it (multiple of the floor).
pub const AUTO_NOISE_MULTIPLE: f64 = 10.0;

/// Length from which [`Horizon::Choose`] replays a log without references re-anchored as
/// [`Horizon::Auto`] does rather than open loop \[s\]: a mission of minutes, not a designed
/// experiment (those run 1–3 minutes).
pub const LONG_RUN_S: f64 = 300.0;

/// The replay a dataset uses, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Anchoring {
    /// The horizon \[s\], or `None` for open-loop replays.
    pub horizon: Option<f64>,
    /// Whether each run's replay has its closed-loop twin, the vehicle's controller in the
    /// loop (the logged commands compared with the twin's as channels).
    pub closed_loop: bool,
    /// Per transported channel, the water's wandering current estimated from the baseline's
    /// re-anchored replay ([`crate::evaluate::current`]); empty for open-loop replays and
    /// where the water is still.
    pub currents: BTreeMap<ChannelKind, Current>,
    /// Why, in one sentence.
    pub why: String,
}

impl Default for Anchoring {
    fn default() -> Self {
        Self {
            horizon: None,
            closed_loop: false,
            currents: BTreeMap::new(),
            why: OPEN_DEFAULT.to_string(),
        }
    }
}

/// Why a dataset's replays are open loop when nothing else was asked.
const OPEN_DEFAULT: &str = "open-loop replay from each run's first samples (the default)";

/// What [`Horizon::Choose`] says of the commands of a log without references.
const UNREFERENCED: &str = "its commands drive the replay and are no evidence: the log carries \
     no references (r.mode, r.depth, r.yaw, …) for a closed-loop replay";

/// What [`Horizon::Choose`] says of the commands of a log with references.
const REFERENCED: &str = "its commands drive the replay: `--horizon closed` adds a closed-loop \
     twin, the vehicle's controller following its references, and compares the commands too \
     (not the default: on the kit's gusty five-minute missions it named 7 of 18 hidden effects \
     exactly, the re-anchored replay alone 9; docs/validation.md)";

/// The replay `horizon` asks for: for [`Horizon::Auto`], chosen from the evaluation of the
/// baseline's open-loop replay, which `baseline` makes (only then).
pub fn choose(
    horizon: Horizon,
    longest_s: f64,
    referenced: bool,
    baseline: impl FnOnce() -> Evaluation,
) -> Anchoring {
    let evidence = if referenced { REFERENCED } else { UNREFERENCED };
    let (horizon, why) = match horizon {
        Horizon::Open => (
            None,
            "open-loop replay from each run's first samples (asked for)".to_string(),
        ),
        Horizon::Choose if longest_s >= LONG_RUN_S => {
            let (h, why) = auto(&baseline());
            let long = format!(
                "{why}; the log runs {longest_s:.0} s (≥ {LONG_RUN_S} s, where an open-loop \
                 replay accumulates every disturbance no model has) and {evidence}"
            );
            (h, long)
        }
        Horizon::Choose => (
            None,
            format!("open-loop replay from each run's first samples; {evidence}"),
        ),
        Horizon::Every(h) => (Some(h), format!("re-anchored every {h} s (given)")),
        Horizon::Auto | Horizon::Closed => auto(&baseline()),
    };
    Anchoring {
        horizon,
        closed_loop: false,
        currents: BTreeMap::new(),
        why,
    }
}

/// [`Horizon::Auto`]'s choice from the baseline's evaluation.
fn auto(eval: &Evaluation) -> (Option<f64>, String) {
    let floors: Vec<(ChannelKind, f64)> = eval
        .metrics
        .keys()
        .filter(|k| k.is_anchored())
        .map(|&k| (k, noise_floor(eval, k)))
        .filter(|(_, f)| *f > 0.0)
        .collect();
    let mut stays: Vec<f64> = Vec::new();
    let mut open = 0;
    for r in &eval.runs {
        let first = r
            .channels
            .iter()
            .filter_map(|c| {
                let floor = floors.iter().find(|(k, _)| *k == c.kind)?.1;
                strays_at(&c.times, &c.resid, AUTO_NOISE_MULTIPLE * floor)
            })
            .fold(f64::INFINITY, f64::min);
        if first.is_finite() {
            stays.push(first);
        } else {
            open += 1;
        }
    }
    if stays.is_empty() {
        return (
            None,
            format!(
                "open-loop replay: the baseline stays within {AUTO_NOISE_MULTIPLE} × the noise \
                 floor on every run"
            ),
        );
    }
    stays.sort_by(f64::total_cmp);
    let median = stays[stays.len() / 2];
    let h = ((median * 10.0).round() / 10.0).max(AUTO_MIN_HORIZON);
    (
        Some(h),
        format!(
            "re-anchored every {h} s: the baseline's replay leaves {AUTO_NOISE_MULTIPLE} × the \
             noise floor after a median {median:.1} s ({} of {} runs; {open} stay within it)",
            stays.len(),
            stays.len() + open
        ),
    )
}

/// The first time \[s since the first sample\] at which the 1-s moving RMS of `resid` exceeds
/// `bound`, or `None`.
fn strays_at(times: &[f64], resid: &[f64], bound: f64) -> Option<f64> {
    let t0 = *times.first()?;
    let (mut from, mut ss) = (0usize, 0.0);
    for (i, (&t, &r)) in times.iter().zip(resid).enumerate() {
        ss += r * r;
        while times[from] < t - 1.0 {
            ss -= resid[from] * resid[from];
            from += 1;
        }
        let n = (i + 1 - from) as f64;
        if t - t0 >= 1.0 && (ss.max(0.0) / n).sqrt() > bound {
            return Some(t - t0);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_residual_strays_when_its_moving_rms_passes_the_bound() {
        let times: Vec<f64> = (0..1000).map(|i| i as f64 * 0.01).collect();
        // Zero for 4 s, then a ramp 0.1 per second: x s into the ramp, the mean square over
        // the last second is ∫₀ˣ (0.1 s)² ds = 0.01 x³/3, which reaches 0.05² at
        // x = (0.75)^(1/3) = 0.9086 s.
        let resid: Vec<f64> = times.iter().map(|t| 0.1 * (t - 4.0).max(0.0)).collect();
        let at = strays_at(&times, &resid, 0.05).unwrap();
        assert!((at - 4.9086).abs() < 0.015, "{at}");
        assert_eq!(strays_at(&times, &resid, 1.0), None);
    }
}
