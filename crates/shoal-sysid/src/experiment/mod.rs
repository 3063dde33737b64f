//! The next experiment: for the questions a log leaves open — each "A or B", each effect left
//! possible (with it or without it) — the manoeuvre from the library ([`library`]) that the
//! rival models predict most differently, relative to what they leave unexplained on the log
//! (per channel the larger held-out RMSE of the two: a model-discrimination design after
//! Box & Hill, fly where the candidates disagree most, measured in the noise they must stand
//! out of).
//!
//! Every manoeuvre of the library is flown along the log's own command direction
//! ([`library::Axis`]) for the log's length (60–300 s), replayed open loop through both models
//! of every question ([`predict`]); the manoeuvre whose *smallest* separation over the
//! questions is largest is chosen, so that one flight answers all of them as well as one can.
//! The report gives each question's separation on the log (held-out part, where the two
//! models were fitted to agree) and predicted for the flight; `next_experiment.toml` is the
//! flight as a world file (raw commands, the vehicle as given) that `shoal run` flies, and a
//! log of it validated together with the first settles the question.

pub mod library;
pub mod predict;
mod world;

use crate::evaluate::dataset::Dataset;
use crate::log::run::ChannelKind;
use crate::search::{Outcome, SearchOptions};
use library::{Axis, LIBRARY, Manoeuvre, Schedule};
use predict::{Separation, flight_dataset, flight_run, separation};
use shoal_model::vehicle::VehicleParams;
use std::collections::BTreeMap;
pub use world::{describe, world_toml};

/// Shortest and longest flight \[s\].
const DURATION_S: (f64, f64) = (60.0, 300.0);

/// One open question and how well the log and the flight answer it.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Question {
    /// The first explanation (an effect family).
    pub a: String,
    /// The second (another family, or `no <family>`).
    pub b: String,
    /// How far apart the two models' predictions are on the log's held-out part.
    pub on_log: Option<Separation>,
    /// How far apart they are predicted to be on the flight.
    pub on_flight: Option<Separation>,
}

/// The suggested experiment.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct NextExperiment {
    /// The manoeuvre's name in the library.
    pub manoeuvre: String,
    /// What it shows.
    pub what: String,
    /// The questions it answers.
    pub questions: Vec<Question>,
    /// Its commands.
    #[serde(skip)]
    pub schedule: Schedule,
    /// Logging period of the flight (the log's) \[s\].
    pub period_s: f64,
    /// Where the flight starts: the channels' readings (channel unit).
    #[serde(skip)]
    pub start: Vec<(ChannelKind, f64)>,
    /// Every manoeuvre tried with its smallest separation ratio over the questions \[-\].
    pub tried: Vec<(String, f64)>,
}

impl NextExperiment {
    /// Where the flight starts for the vehicle `params`: the body origin's position \[m\]
    /// (the log's depth reading is the pressure port's; level, at its depth) and the heading
    /// \[rad\].
    pub fn start_pose(&self, params: &VehicleParams) -> (f64, f64) {
        let at = |k: ChannelKind| self.start.iter().find(|(c, _)| *c == k).map(|(_, v)| *v);
        let reading = at(ChannelKind::Depth).unwrap_or(1.0);
        let z = (reading - params.pressure.position.z).max(0.0);
        (z, at(ChannelKind::Yaw).unwrap_or(0.0))
    }
}

/// The median of `v` (0 when empty).
fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Where a flight starts: for each channel the log compares (not the commands), the depth at
/// the log's median, attitude, heading and position at the first run's first reading, rates
/// and velocities at rest.
fn start(ds: &Dataset) -> Vec<(ChannelKind, f64)> {
    let Some(first) = ds.runs.first() else {
        return Vec::new();
    };
    ds.kinds
        .iter()
        .filter(|k| !k.is_command())
        .map(|&k| {
            let v = match k {
                ChannelKind::Depth => median(
                    ds.runs
                        .iter()
                        .filter_map(|r| r.run.channel(k))
                        .flat_map(|c| c.values.iter().copied())
                        .collect(),
                ),
                ChannelKind::Roll
                | ChannelKind::Pitch
                | ChannelKind::Yaw
                | ChannelKind::X
                | ChannelKind::Y => first.run.channel(k).map_or(0.0, |c| c.values[0]),
                _ => 0.0,
            };
            (k, v)
        })
        .collect()
}

/// The log's sample period: the median step of its first run's times \[s\].
fn period(ds: &Dataset) -> f64 {
    let t = ds.runs.first().map_or(&[][..], |r| &r.run.t[..]);
    median(t.windows(2).map(|w| w[1] - w[0]).collect()).max(1e-3)
}

/// The experiment that best answers the questions of `outcome` (its rival models), or `None`
/// when it leaves none open, or no manoeuvre of the library can be flown or replayed.
pub fn next_experiment(
    ds: &Dataset,
    base: &VehicleParams,
    opts: &SearchOptions,
    outcome: &Outcome,
) -> Option<NextExperiment> {
    if outcome.rivals.is_empty() {
        return None;
    }
    let runs: Vec<_> = ds.runs.iter().map(|r| &r.run).collect();
    let axis = Axis::of(base, &runs)?;
    let duration = ds
        .runs
        .iter()
        .map(|r| r.run.duration())
        .fold(0.0, f64::max)
        .clamp(DURATION_S.0, DURATION_S.1);
    let density = ds.env.density;
    // Each question's yardstick: per channel, the larger held-out RMSE of its two models.
    let residuals: Vec<BTreeMap<ChannelKind, f64>> = outcome
        .rivals
        .iter()
        .map(|r| {
            (r.fit_a.eval.metrics.iter())
                .filter_map(|(k, m)| Some((*k, m.rmse.max(r.fit_b.eval.metrics.get(k)?.rmse))))
                .collect()
        })
        .collect();
    let models: Vec<_> = outcome
        .rivals
        .iter()
        .map(|r| {
            (
                r.fit_a.model(base, &opts.base_effects, density),
                r.fit_b.model(base, &opts.base_effects, density),
            )
        })
        .collect();
    let (period, start) = (period(ds), start(ds));
    let flights: Vec<(&Manoeuvre, Vec<Option<Separation>>)> = LIBRARY
        .iter()
        .filter(|m| m.applies(&axis))
        .filter_map(|m| {
            let schedule = m.schedule(base, &axis, duration);
            let run = flight_run(m.name, &schedule, period, &start);
            let fds = flight_dataset(base, ds, run).ok()?;
            let seps = models
                .iter()
                .zip(&residuals)
                .map(|((a, b), res)| separation(&fds.evaluate(a), &fds.evaluate(b), res, false))
                .collect();
            Some((m, seps))
        })
        .collect();
    let worst = |seps: &[Option<Separation>]| {
        seps.iter()
            .map(|s| s.map_or(0.0, |s| s.ratio))
            .fold(f64::INFINITY, f64::min)
    };
    let tried: Vec<(String, f64)> = flights
        .iter()
        .map(|(m, s)| (m.name.to_string(), worst(s)))
        .collect();
    let (best, seps) = flights
        .into_iter()
        .max_by(|x, y| worst(&x.1).total_cmp(&worst(&y.1)))?;
    let questions = outcome
        .rivals
        .iter()
        .zip(seps)
        .zip(&residuals)
        .map(|((r, on_flight), res)| Question {
            a: r.a.clone(),
            b: r.b.clone(),
            on_log: separation(&r.fit_a.eval, &r.fit_b.eval, res, true),
            on_flight,
        })
        .collect();
    Some(NextExperiment {
        manoeuvre: best.name.to_string(),
        what: best.what.to_string(),
        questions,
        schedule: best.schedule(base, &axis, duration),
        period_s: period,
        start,
        tried,
    })
}
