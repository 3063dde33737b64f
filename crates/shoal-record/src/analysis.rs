//! Step-response metrics of recorded trajectories: split a signal where its setpoint changes
//! and measure each segment (overshoot, time to enter a band, 10–90 % rate, final error).
//! Used by the paper-reproduction tests and the comparison in `docs/paper-comparison.md`.

use shoal_model::math::wrap_pi;
use shoal_sim::recorder::{self, col};
use shoal_sim::sim::{Sim, SimOptions};
use shoal_world::desc::WorldDesc;

/// Every recorded row of a whole run, split per vehicle: `rows[vehicle][sample][column]`
/// (columns as in [`recorder::FIXED`], then the vehicle's actuators).
pub fn record_run(desc: &WorldDesc) -> Vec<Vec<Vec<f64>>> {
    let mut sim = Sim::new(
        desc,
        SimOptions {
            threads: 1,
            record: true,
        },
    );
    sim.run(desc.steps());
    sim.drain()
        .rows
        .iter()
        .zip(&desc.vehicles)
        .map(|(flat, v)| {
            flat.chunks(recorder::stride(&v.model))
                .map(<[f64]>::to_vec)
                .collect()
        })
        .collect()
}

/// True (noise-free) depth \[m\] of a point at body-frame height `port_z` \[m\] on the vehicle's
/// vertical axis (e.g. the pressure port), from a recorded row.
pub fn point_depth(row: &[f64], port_z: f64) -> f64 {
    row[col::Z] + port_z * row[col::ROLL].cos() * row[col::PITCH].cos()
}

/// One setpoint segment of a step response.
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    /// Start and end time of the segment \[s\].
    pub t0: f64,
    /// End time \[s\].
    pub t1: f64,
    /// Signal value at the start.
    pub from: f64,
    /// The setpoint.
    pub target: f64,
    /// Largest excursion beyond the target in the direction of the move (≥ 0).
    pub overshoot: f64,
    /// Time from `t0` until the signal first enters `target ± band` \[s\].
    pub time_to_band: Option<f64>,
    /// Target minus the value at the end of the segment.
    pub final_error: f64,
    /// Mean rate between 10 % and 90 % of the move [unit/s].
    pub rate_10_90: Option<f64>,
    /// Largest rate towards the target between consecutive samples [unit/s].
    pub peak_rate: f64,
}

/// Splits `(t, value, setpoint)` samples at setpoint changes and measures each segment.
/// With `angular` (radians), the signal is unwrapped and, in each segment, the setpoint is
/// taken on the branch (±2πk) nearest to where the signal ends — the way the vehicle went.
pub fn segments(samples: &[(f64, f64, f64)], band: f64, angular: bool) -> Vec<Segment> {
    let unwrapped: Vec<(f64, f64, f64)> = if angular {
        let mut prev: Option<f64> = None;
        samples
            .iter()
            .map(|&(t, v, sp)| {
                let u = prev.map_or(v, |p| p + wrap_pi(v - p));
                prev = Some(u);
                (t, u, sp)
            })
            .collect()
    } else {
        samples.to_vec()
    };
    let samples = &unwrapped[..];
    let err = |v: f64, sp: f64| sp - v;
    let mut out = Vec::new();
    let mut start = 0;
    while start < samples.len() {
        let raw_sp = samples[start].2;
        let mut end = start;
        while end + 1 < samples.len() && samples[end + 1].2 == raw_sp {
            end += 1;
        }
        let seg = &samples[start..=end];
        let sp = if angular {
            let last = seg[seg.len() - 1].1;
            last + wrap_pi(raw_sp - last)
        } else {
            raw_sp
        };
        let e0 = err(seg[0].1, sp);
        let dir = e0.signum();
        let (t0, t1) = (seg[0].0, seg[seg.len() - 1].0);
        let mut overshoot: f64 = 0.0;
        let mut time_to_band = None;
        let (mut t10, mut t90) = (None, None);
        let peak_rate = seg
            .windows(2)
            .map(|w| (w[1].1 - w[0].1) / (w[1].0 - w[0].0) * dir)
            .filter(|r| r.is_finite())
            .fold(0.0, f64::max);
        for &(t, v, _) in seg {
            let e = err(v, sp);
            // Past the target means the error changed sign relative to the start.
            if dir != 0.0 && e * dir < 0.0 {
                overshoot = overshoot.max(-e * dir);
            }
            if time_to_band.is_none() && e.abs() <= band {
                time_to_band = Some(t - t0);
            }
            let progress = if e0 != 0.0 { 1.0 - e / e0 } else { 1.0 };
            if t10.is_none() && progress >= 0.1 {
                t10 = Some(t);
            }
            if t90.is_none() && progress >= 0.9 {
                t90 = Some(t);
            }
        }
        let rate_10_90 = match (t10, t90) {
            (Some(a), Some(b)) if b > a => Some(0.8 * e0.abs() / (b - a)),
            _ => None,
        };
        out.push(Segment {
            t0,
            t1,
            from: seg[0].1,
            target: raw_sp,
            overshoot,
            time_to_band,
            final_error: err(seg[seg.len() - 1].1, sp),
            rate_10_90,
            peak_rate,
        });
        start = end + 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_order_step() {
        // x(t) = 1 − e^(−t) from 0 towards 1: 10–90 % takes ln 9 s.
        let s: Vec<(f64, f64, f64)> = (0..2000)
            .map(|k| {
                let t = k as f64 * 0.01;
                (t, 1.0 - (-t).exp(), 1.0)
            })
            .collect();
        let seg = &segments(&s, 0.05, false)[0];
        assert_eq!(seg.overshoot, 0.0);
        assert!((seg.time_to_band.unwrap() - 20f64.ln()).abs() < 0.011);
        assert!((seg.rate_10_90.unwrap() - 0.8 / 9f64.ln()).abs() < 1e-2);
    }

    #[test]
    fn overshoot_and_wrapping() {
        let s = vec![(0.0, 3.0, 3.1), (1.0, -3.1, 3.1), (2.0, 3.1, 3.1)];
        let seg = &segments(&s, 0.01, true)[0];
        // −3.1 rad is 0.083 rad past +3.1 going up (through ±π).
        assert!((seg.overshoot - (2.0 * std::f64::consts::PI - 6.2)).abs() < 1e-9);
        // A large command taken the positive way from slightly below zero.
        let s = vec![(0.0, -0.01, 3.0), (1.0, 1.5, 3.0), (2.0, 3.0, 3.0)];
        let seg = &segments(&s, 0.01, true)[0];
        assert_eq!(seg.overshoot, 0.0);
        assert!(seg.final_error.abs() < 1e-9);
    }
}
