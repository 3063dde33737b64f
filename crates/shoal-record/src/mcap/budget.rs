//! How much of a run `run.mcap` holds, decided before the run from the world (vehicles,
//! duration, `record_hz`) so that the file stays bounded for any swarm and duration:
//!
//! * **Vehicles**: at most [`MAX_VEHICLES`] have topics (and a frame in `/tf`): every
//!   `⌈n / 1000⌉`-th vehicle by id, the way the plots pick theirs. An MCAP file holds at most
//!   65,535 channels, and seven per vehicle leave room for about 9,300.
//! * **Samples**: the per-vehicle topics and `/tf` take every `k`-th recorded sample, the
//!   smallest `k` whose messages — estimated at [`BYTES_PER_VEHICLE_SAMPLE`] plus
//!   [`BYTES_PER_ACTUATOR`] per thruster and tilt drive, uncompressed — fit in
//!   [`SAMPLE_BUDGET_BYTES`].
//! * **Optical frames**: `/optical/frames` and `/links` keep at most [`FRAME_BUDGET`] reception
//!   attempts in all, spread over the run: each recorded interval earns its share of the
//!   budget (`FRAME_BUDGET · interval / duration`), unspent shares carry over for up to
//!   [`FRAME_CREDIT_S`] simulated seconds, and an interval with more attempts than its credit
//!   keeps an evenly spaced subset ([`FrameQuota::keep`]).
//!
//! What was left out is counted in [`super::McapSummary`] (`summary.json`, the end-of-run
//! report).

/// Most vehicles with topics in `run.mcap`.
pub const MAX_VEHICLES: usize = 1000;
/// Uncompressed bytes the per-vehicle messages of one sample may take in all (state, pressure,
/// IMU, thrusters, tilts, tilt angles, pump and the vehicle's `/tf` entry, with their MCAP records).
pub const SAMPLE_BUDGET_BYTES: u64 = 512 << 20;
/// Estimated uncompressed bytes of one vehicle's messages in one sample, without its actuators
/// (measured: ≈ 1.2 kB for a μAUV² with a short name; a test keeps it above the real size and within 1.5× of it).
pub const BYTES_PER_VEHICLE_SAMPLE: u64 = 1400;
/// Estimated bytes per thruster or tilt drive and sample (its value in the state's arrays
/// and its name in their labels).
pub const BYTES_PER_ACTUATOR: u64 = 24;
/// Most reception attempts written (each one a `/optical/frames` message and a line in
/// `/links`, ≈ 0.9 kB uncompressed together; an acknowledgement's dashed line up to 0.6 kB
/// more).
pub const FRAME_BUDGET: u64 = 200_000;
/// How long unspent frame budget is kept for a later burst \[s, simulated\].
pub const FRAME_CREDIT_S: f64 = 10.0;

/// What the budget leaves in.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// The vehicles with topics, by id, ascending.
    pub vehicles: Vec<usize>,
    /// Every how many recorded samples one is written (≥ 1).
    pub sample_every: u64,
}

impl Plan {
    /// The plan for `actuators[i]` (thrusters plus tilt drives) of each vehicle `i`, over
    /// `duration_s` seconds recorded at `record_hz` \[Hz\].
    pub fn new(actuators: &[usize], duration_s: f64, record_hz: f64) -> Self {
        let n = actuators.len();
        let stride = n.div_ceil(MAX_VEHICLES).max(1);
        let vehicles: Vec<usize> = (0..n).step_by(stride).collect();
        // Samples at t = 0, 1/record_hz, … up to the duration (truncation intended).
        let samples_planned = (duration_s * record_hz).max(0.0).floor() as u64 + 1;
        let per_sample: u64 = vehicles
            .iter()
            .map(|&i| BYTES_PER_VEHICLE_SAMPLE + BYTES_PER_ACTUATOR * actuators[i] as u64)
            .sum();
        let all = samples_planned.saturating_mul(per_sample.max(1));
        Self {
            vehicles,
            sample_every: all.div_ceil(SAMPLE_BUDGET_BYTES).max(1),
        }
    }
}

/// The share of [`FRAME_BUDGET`] a run may still spend.
#[derive(Clone, Debug)]
pub struct FrameQuota {
    /// Attempts earned per simulated second.
    per_s: f64,
    /// Attempts that may be kept now.
    credit: f64,
    /// Most credit kept.
    cap: f64,
}

impl FrameQuota {
    /// The quota of a run planned for `duration_s` seconds.
    pub fn new(duration_s: f64) -> Self {
        let per_s = FRAME_BUDGET as f64 / duration_s.max(1e-9);
        Self {
            per_s,
            credit: 0.0,
            cap: (per_s * FRAME_CREDIT_S).max(1.0),
        }
    }

    /// Of `n` attempts in an interval of `dt_s` seconds, which to keep: `keep(i)` for the
    /// i-th, evenly spaced, as many as the credit allows.
    pub fn keep(&mut self, n: usize, dt_s: f64) -> impl Fn(usize) -> bool + use<> {
        self.credit = (self.credit + self.per_s * dt_s.max(0.0)).min(self.cap);
        // Truncation intended: whole attempts.
        let kept = (self.credit.floor() as usize).min(n);
        self.credit -= kept as f64;
        move |i| (i * kept) / n.max(1) < ((i + 1) * kept) / n.max(1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_runs_keep_everything() {
        let p = Plan::new(&[5; 12], 100.0, 10.0);
        assert_eq!(p.vehicles, (0..12).collect::<Vec<_>>());
        assert_eq!(p.sample_every, 1);
        // 12 vehicles × 1520 B: 1000 s fit (182 MB), 10,000 s need every 4th sample
        // (1.82 GB of 537 MB).
        assert_eq!(Plan::new(&[5; 12], 1000.0, 10.0).sample_every, 1);
        assert_eq!(Plan::new(&[5; 12], 10_000.0, 10.0).sample_every, 4);
    }

    #[test]
    fn big_swarms_are_thinned_in_vehicles_and_time() {
        let p = Plan::new(&[5; 10_000], 100.0, 10.0);
        assert_eq!(p.vehicles.len(), 1000);
        assert_eq!(p.vehicles[..3], [0, 10, 20]);
        // 1001 samples × 1000 vehicles × 1520 B = 1.52 GB: every 3rd sample.
        assert_eq!(p.sample_every, 3);
        let per_sample = 1000 * (BYTES_PER_VEHICLE_SAMPLE + 5 * BYTES_PER_ACTUATOR);
        assert!(1001u64.div_ceil(p.sample_every) * per_sample <= SAMPLE_BUDGET_BYTES);
    }

    #[test]
    fn frames_are_kept_evenly_up_to_the_budget() {
        // 100 s: 2000 attempts per second earned.
        let mut q = FrameQuota::new(100.0);
        let keep = q.keep(10_000, 1.0);
        let kept: Vec<usize> = (0..10_000).filter(|&i| keep(i)).collect();
        assert_eq!(kept.len(), 2000);
        assert!(kept.windows(2).all(|w| w[1] - w[0] == 5), "evenly spaced");
        // A quiet second saves its share for the next.
        assert!((0..10).all(q.keep(10, 1.0)));
        let keep = q.keep(10_000, 1.0);
        assert_eq!((0..10_000).filter(|&i| keep(i)).count(), 2000 + 1990);
        // Never more than the budget over the whole run.
        let mut q = FrameQuota::new(100.0);
        let total: usize = (0..1000)
            .map(|_| {
                let keep = q.keep(5000, 0.1);
                (0..5000).filter(|&i| keep(i)).count()
            })
            .sum();
        assert!(
            total as u64 <= FRAME_BUDGET && total as u64 > FRAME_BUDGET - 10,
            "{total}"
        );
    }
}
