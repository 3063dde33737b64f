//! The manoeuvres a next experiment is chosen from: open-loop command patterns, each aimed at
//! what some families do and others do not — short steps (a lag's shape, an added mass),
//! fast reversals (a delay against a lag), every command level in both directions (a dead
//! band, a saturation, a gain curve, an asymmetry), long holds at speed (an inflow loss, a
//! damping law), coasting (damping, buoyancy, trim), pump cycles (the ballast) and one step
//! repeated for the whole flight (a battery's sag against a constant gain).
//!
//! A pattern is written in *levels*: fractions of the manoeuvre's amplitude along the log's
//! own command direction ([`Axis`]): the combination of thrusters the log drove most (its
//! first principal direction), at the tilt setting it used most. So the same library serves
//! a heave log (both side thrusters together, tilted down), a yaw log (the two against each
//! other) or any vehicle a file describes. The pattern repeats until the flight's length.

use crate::log::run::MeasuredRun;
use nalgebra::{DMatrix, SymmetricEigen};
use shoal_model::vehicle::VehicleParams;
use std::collections::BTreeMap;

/// One segment of a pattern: hold time \[s\], command level (fraction of the amplitude, −1…1),
/// pump (−1 empty, 0 off, +1 fill).
pub type Segment = (f64, f64, f64);

/// A manoeuvre of the library.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Manoeuvre {
    /// Its name (in the report and the world file's header).
    pub name: &'static str,
    /// What it shows, in words.
    pub what: &'static str,
    /// Levels are fractions of the full command (`true`) or of the log's usual amplitude.
    pub full_scale: bool,
    /// The pattern, repeated.
    pub pattern: &'static [Segment],
}

const SHORT_STEPS: [Segment; 12] = [
    (1.0, 1.0, 0.0),
    (2.0, 0.0, 0.0),
    (0.5, 1.0, 0.0),
    (2.0, 0.0, 0.0),
    (1.0, -1.0, 0.0),
    (2.0, 0.0, 0.0),
    (0.5, -1.0, 0.0),
    (2.0, 0.0, 0.0),
    (2.0, 1.0, 0.0),
    (2.0, 0.0, 0.0),
    (2.0, -1.0, 0.0),
    (2.0, 0.0, 0.0),
];

const REVERSALS: [Segment; 18] = [
    (0.6, 1.0, 0.0),
    (0.6, -1.0, 0.0),
    (0.6, 1.0, 0.0),
    (0.6, -1.0, 0.0),
    (0.6, 1.0, 0.0),
    (0.6, -1.0, 0.0),
    (0.6, 1.0, 0.0),
    (0.6, -1.0, 0.0),
    (3.0, 0.0, 0.0),
    (0.3, 1.0, 0.0),
    (0.3, -1.0, 0.0),
    (0.3, 1.0, 0.0),
    (0.3, -1.0, 0.0),
    (0.3, 1.0, 0.0),
    (0.3, -1.0, 0.0),
    (0.3, 1.0, 0.0),
    (0.3, -1.0, 0.0),
    (3.0, 0.0, 0.0),
];

const LEVELS: [Segment; 36] = [
    (3.0, 0.05, 0.0),
    (2.0, 0.0, 0.0),
    (3.0, -0.05, 0.0),
    (2.0, 0.0, 0.0),
    (3.0, 0.1, 0.0),
    (2.0, 0.0, 0.0),
    (3.0, -0.1, 0.0),
    (2.0, 0.0, 0.0),
    (3.0, 0.15, 0.0),
    (2.0, 0.0, 0.0),
    (3.0, -0.15, 0.0),
    (2.0, 0.0, 0.0),
    (3.0, 0.25, 0.0),
    (2.0, 0.0, 0.0),
    (3.0, -0.25, 0.0),
    (2.0, 0.0, 0.0),
    (3.0, 0.4, 0.0),
    (2.0, 0.0, 0.0),
    (3.0, -0.4, 0.0),
    (2.0, 0.0, 0.0),
    (3.0, 0.6, 0.0),
    (2.0, 0.0, 0.0),
    (3.0, -0.6, 0.0),
    (2.0, 0.0, 0.0),
    (2.5, 0.8, 0.0),
    (2.0, 0.0, 0.0),
    (2.5, -0.8, 0.0),
    (2.0, 0.0, 0.0),
    (2.0, 1.0, 0.0),
    (2.0, 0.0, 0.0),
    (2.0, -1.0, 0.0),
    (2.0, 0.0, 0.0),
    (2.0, 0.9, 0.0),
    (2.0, 0.0, 0.0),
    (2.0, -0.9, 0.0),
    (2.0, 0.0, 0.0),
];

const HOLDS: [Segment; 12] = [
    (2.5, 0.25, 0.0),
    (2.5, 0.5, 0.0),
    (2.5, 0.75, 0.0),
    (10.0, 1.0, 0.0),
    (2.5, 0.5, 0.0),
    (8.0, 0.0, 0.0),
    (2.5, -0.25, 0.0),
    (2.5, -0.5, 0.0),
    (2.5, -0.75, 0.0),
    (10.0, -1.0, 0.0),
    (2.5, -0.5, 0.0),
    (8.0, 0.0, 0.0),
];

const COASTING: [Segment; 4] = [
    (3.0, 1.0, 0.0),
    (12.0, 0.0, 0.0),
    (3.0, -1.0, 0.0),
    (12.0, 0.0, 0.0),
];

const PUMP: [Segment; 4] = [
    (8.0, 0.0, 1.0),
    (6.0, 0.0, 0.0),
    (8.0, 0.0, -1.0),
    (6.0, 0.0, 0.0),
];

const REPEATED: [Segment; 4] = [
    (4.0, 1.0, 0.0),
    (4.0, 0.0, 0.0),
    (4.0, -1.0, 0.0),
    (4.0, 0.0, 0.0),
];

/// The library.
pub const LIBRARY: [Manoeuvre; 7] = [
    Manoeuvre {
        name: "short_steps",
        what: "short command steps (0.5–2 s) up and down: the shape of a response's start",
        full_scale: false,
        pattern: &SHORT_STEPS,
    },
    Manoeuvre {
        name: "reversals",
        what: "fast command reversals (0.3 and 0.6 s): what lags the command against what \
               lags the reading",
        full_scale: false,
        pattern: &REVERSALS,
    },
    Manoeuvre {
        name: "levels",
        what: "every command level from 5 % to full, both directions: the thrust's law over \
               the whole range",
        full_scale: true,
        pattern: &LEVELS,
    },
    Manoeuvre {
        name: "speed_holds",
        what: "ramps to a long hold at speed, both directions: what grows with speed",
        full_scale: false,
        pattern: &HOLDS,
    },
    Manoeuvre {
        name: "coasting",
        what: "a push, then 12 s of coasting, both directions: damping, buoyancy and trim \
               without thrust",
        full_scale: false,
        pattern: &COASTING,
    },
    Manoeuvre {
        name: "pump_cycles",
        what: "the pump filling and emptying with the thrusters off: the ballast's flow",
        full_scale: false,
        pattern: &PUMP,
    },
    Manoeuvre {
        name: "repeated_step",
        what: "the same command step repeated for the whole flight: what changes over time \
               against what does not",
        full_scale: false,
        pattern: &REPEATED,
    },
];

/// The log's own command direction: the combination of thrusters it drove most, at the tilt
/// setting it used most, and how hard it usually drove them.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// Per thruster of the vehicle, its share of the command (the largest is 1) \[-\].
    pub direction: Vec<f64>,
    /// The log's usual command along the direction: the 90th percentile of its absolute
    /// projection, within 20–80 % of the full command \[%\].
    pub amplitude: f64,
    /// Per tilt drive of the vehicle that the log sets, its angle \[rad\].
    pub tilts: BTreeMap<String, f64>,
    /// Whether the vehicle has a pump and the log drives it.
    pub pump: bool,
}

/// The rows' tilt settings rounded to 0.01 rad: the most frequent one.
fn usual_tilts(params: &VehicleParams, runs: &[&MeasuredRun]) -> BTreeMap<String, f64> {
    let mut counts: BTreeMap<Vec<i64>, (usize, Vec<f64>)> = BTreeMap::new();
    let names: Vec<&str> = params.tilts.iter().map(|t| t.name.as_str()).collect();
    for run in runs {
        let cols: Vec<Option<&Vec<f64>>> = names
            .iter()
            .map(|n| run.input(n).map(|c| &c.values))
            .collect();
        for row in 0..run.t.len() {
            let v: Vec<f64> = cols.iter().map(|c| c.map_or(0.0, |c| c[row])).collect();
            let key: Vec<i64> = v.iter().map(|x| (x * 100.0).round() as i64).collect();
            counts.entry(key).or_insert((0, v)).0 += 1;
        }
    }
    let best = counts.into_values().max_by_key(|(n, _)| *n);
    let Some((_, values)) = best else {
        return BTreeMap::new();
    };
    names
        .iter()
        .zip(values)
        .filter(|(n, _)| runs.iter().any(|r| r.input(n).is_some()))
        .map(|(n, v)| (n.to_string(), v))
        .collect()
}

impl Axis {
    /// The axis of `runs` for the vehicle `params`; `None` when the log drives no thruster
    /// and no pump.
    pub fn of(params: &VehicleParams, runs: &[&MeasuredRun]) -> Option<Axis> {
        let tilts = usual_tilts(params, runs);
        let n = params.thrusters.len();
        let pump = params.ballast.is_some() && runs.iter().any(|r| r.input("pump").is_some());
        // Second moments of the thruster commands on the rows at the usual tilt setting.
        let mut m = DMatrix::<f64>::zeros(n, n);
        let mut rows: Vec<Vec<f64>> = Vec::new();
        for run in runs {
            let cols: Vec<Option<&Vec<f64>>> = params
                .thrusters
                .iter()
                .map(|t| run.input(&t.name).map(|c| &c.values))
                .collect();
            let tilt_cols: Vec<(&Vec<f64>, f64)> = tilts
                .iter()
                .filter_map(|(name, v)| run.input(name).map(|c| (&c.values, *v)))
                .collect();
            for row in 0..run.t.len() {
                if tilt_cols.iter().any(|(c, v)| (c[row] - v).abs() > 0.005) {
                    continue;
                }
                let u: Vec<f64> = cols.iter().map(|c| c.map_or(0.0, |c| c[row])).collect();
                for i in 0..n {
                    for j in 0..n {
                        m[(i, j)] += u[i] * u[j];
                    }
                }
                rows.push(u);
            }
        }
        if m.iter().all(|x| *x == 0.0) {
            return pump.then(|| Axis {
                direction: vec![0.0; n],
                amplitude: 0.0,
                tilts,
                pump,
            });
        }
        let eig = SymmetricEigen::new(m);
        let k = eig.eigenvalues.imax();
        let v = eig.eigenvectors.column(k);
        let big = v
            .iter()
            .copied()
            .max_by(|a, b| a.abs().total_cmp(&b.abs()))?;
        let direction: Vec<f64> = v.iter().map(|x| x / big).collect();
        let mut proj: Vec<f64> = rows
            .iter()
            .map(|u| {
                let dot: f64 = u.iter().zip(&direction).map(|(a, b)| a * b).sum();
                let norm: f64 = direction.iter().map(|d| d * d).sum();
                (dot / norm).abs()
            })
            .collect();
        proj.sort_by(f64::total_cmp);
        let full = params
            .thrusters
            .iter()
            .map(|t| t.max_command)
            .fold(f64::INFINITY, f64::min);
        let p90 = proj[(0.9 * (proj.len() - 1) as f64) as usize];
        Some(Axis {
            direction,
            amplitude: p90.clamp(0.2 * full, 0.8 * full),
            tilts,
            pump,
        })
    }
}

/// A flight's commands: the inputs it sets and, at each change, their values.
#[derive(Clone, Debug, PartialEq)]
pub struct Schedule {
    /// Input names (thrusters, tilt drives, `pump`), as the log names them after `u.`.
    pub inputs: Vec<String>,
    /// (time \[s\], the value of each input from then on \[% / rad / −1, 0, +1\]).
    pub steps: Vec<(f64, Vec<f64>)>,
    /// Length \[s\].
    pub duration: f64,
}

impl Manoeuvre {
    /// Whether the manoeuvre can be flown along `axis` (the pump cycles need a pump, the
    /// others a thruster direction).
    pub fn applies(&self, axis: &Axis) -> bool {
        let pumps = self.pattern.iter().any(|s| s.2 != 0.0);
        if pumps {
            axis.pump
        } else {
            axis.amplitude > 0.0
        }
    }

    /// The manoeuvre along `axis` for `duration` \[s\], the pattern repeated; commands within
    /// each thruster's range.
    pub fn schedule(&self, params: &VehicleParams, axis: &Axis, duration: f64) -> Schedule {
        let mut inputs: Vec<String> = params.thrusters.iter().map(|t| t.name.clone()).collect();
        inputs.extend(axis.tilts.keys().cloned());
        if axis.pump {
            inputs.push("pump".into());
        }
        let full = params
            .thrusters
            .iter()
            .map(|t| t.max_command)
            .fold(f64::INFINITY, f64::min);
        let amp = if self.full_scale {
            full
        } else {
            axis.amplitude
        };
        let mut steps = Vec::new();
        let mut t = 0.0;
        'flight: loop {
            for &(hold, level, pump) in self.pattern {
                if t >= duration {
                    break 'flight;
                }
                let mut v: Vec<f64> = params
                    .thrusters
                    .iter()
                    .zip(&axis.direction)
                    .map(|(th, d)| (level * amp * d).clamp(-th.max_command, th.max_command))
                    .collect();
                v.extend(axis.tilts.values());
                if axis.pump {
                    v.push(pump);
                }
                steps.push((t, v));
                t += hold;
            }
        }
        Schedule {
            inputs,
            steps,
            duration,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shoal_model::presets;

    /// Every pattern is balanced (as much time at +level as at −level), so that a flight does
    /// not drift off in one direction: its time-weighted mean level is zero.
    #[test]
    fn patterns_push_as_much_one_way_as_the_other() {
        for m in LIBRARY {
            let mean: f64 = m.pattern.iter().map(|(h, l, _)| h * l).sum();
            let pump: f64 = m.pattern.iter().map(|(h, _, p)| h * p).sum();
            assert!(mean.abs() < 1e-9 && pump.abs() < 1e-9, "{}", m.name);
        }
    }

    /// A schedule repeats its pattern to the flight's length and keeps each command within
    /// its thruster's range; the levels manoeuvre reaches the full command.
    #[test]
    fn a_schedule_fills_the_flight_within_the_ranges() {
        let p = presets::uauv2();
        let axis = Axis {
            direction: vec![0.0, 1.0, 1.0],
            amplitude: 50.0,
            tilts: BTreeMap::from([("beta".to_string(), -std::f64::consts::FRAC_PI_2)]),
            pump: true,
        };
        let s = LIBRARY[2].schedule(&p, &axis, 120.0);
        assert_eq!(s.inputs, ["top", "port", "stbd", "beta", "pump"]);
        let last = s.steps.last().unwrap().0;
        assert!(last < 120.0 && last > 110.0, "{last}");
        let max = s.steps.iter().map(|(_, v)| v[1].abs()).fold(0.0, f64::max);
        assert_eq!(max, 100.0);
        let short = LIBRARY[0].schedule(&p, &axis, 60.0);
        let max = short
            .steps
            .iter()
            .map(|(_, v)| v[2].abs())
            .fold(0.0, f64::max);
        assert_eq!(max, 50.0);
        assert!(short.steps.iter().all(|(_, v)| v[0] == 0.0 && v[4] == 0.0));
    }
}
