//! Shared helpers of the hidden-effect tests: hide effects in a simulated μAUV² run, hand only
//! the run to the search, and report what it found.

#![allow(dead_code)]

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use shoal_model::effects::{EffectInstance, Effects, by_name};
use shoal_model::presets;
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::VehicleModel;
use shoal_sysid::evaluate::dataset::{DataOptions, Dataset};
use shoal_sysid::evaluate::open_loop::ReplayOptions;
use shoal_sysid::log::run::MeasuredRun;
use shoal_sysid::search::{Outcome, SearchOptions, search};
use shoal_testkit::design;
use shoal_testkit::synth::synthesize;

/// Which designed experiment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Exp {
    /// Diving mode, 1-DOF heave.
    Heave,
    /// Turning mode, 1-DOF yaw, tracked position.
    Yaw,
    /// Diving mode with roll and pitch logged as well.
    Trim,
}

/// A μAUV² run of `exp` (120 s, 50 Hz) with `hidden` effects, simulated at 5 ms with sensor
/// noise and quantisation from `seed`, written to CSV text and parsed back — the tool sees
/// only the file contents.
pub fn measured(exp: Exp, hidden: &[(&str, Vec<f64>)], seed: u64) -> MeasuredRun {
    let effects = Effects::new(
        hidden
            .iter()
            .map(|(n, p)| EffectInstance {
                effect: catalogue_effect(n),
                params: p.clone(),
            })
            .collect(),
    );
    let truth = VehicleModel::with_effects(presets::uauv2(), effects, 1000.0);
    let e = match exp {
        Exp::Heave => design::uauv2_heave(seed, 120.0),
        Exp::Yaw => design::uauv2_yaw(seed, 120.0),
        Exp::Trim => design::uauv2_trim(seed, 120.0),
    };
    let run = synthesize(&truth, &Environment::default(), &e, 0.005, seed ^ 0x5eed);
    let csv = run.to_csv();
    MeasuredRun::parse(&csv, std::path::Path::new(&format!("{}.csv", e.name)))
        .expect("synthetic CSV parses")
}

/// The catalogue effect `family` in its default form, or `family/form`.
pub fn catalogue_effect(name: &str) -> std::sync::Arc<dyn shoal_model::effects::Effect> {
    let effect = match name.split_once('/') {
        Some((family, form)) => shoal_model::effects::by_name_form(family, Some(form)),
        None => by_name(name),
    };
    effect.unwrap_or_else(|| panic!("no catalogue effect {name}"))
}

/// One run as the search sees it with the μAUV² preset as baseline (60/40 split, 20 ms
/// replay).
pub fn dataset(run: MeasuredRun) -> Dataset {
    Dataset::new(
        &presets::uauv2(),
        Environment::default(),
        vec![run],
        vec![],
        &DataOptions {
            replay: ReplayOptions {
                dt: 0.02,
                ..Default::default()
            },
            ..Default::default()
        },
    )
    .expect("dataset")
}

/// The search on one run with the μAUV² preset as baseline (60/40 split, 20 ms replay).
pub fn find(run: MeasuredRun) -> (Dataset, Outcome) {
    let base = presets::uauv2();
    let ds = dataset(run);
    // One search thread (results do not depend on it): the test runner runs the tests side
    // by side, one process each under cargo-nextest.
    let opts = SearchOptions {
        threads: 1,
        ..Default::default()
    };
    let out = search(&ds, &base, &opts, &|_| {});
    (ds, out)
}

/// [`find`] among the catalogue families `families` only (every form of each).
pub fn find_among(run: MeasuredRun, families: &[&str]) -> (Dataset, Outcome) {
    let base = presets::uauv2();
    let ds = dataset(run);
    let opts = SearchOptions {
        threads: 1,
        effects: shoal_model::effects::catalogue()
            .into_iter()
            .filter(|e| families.contains(&e.name()))
            .collect(),
        ..Default::default()
    };
    let out = search(&ds, &base, &opts, &|_| {});
    (ds, out)
}

/// Random realistic parameters of an effect for `seed` (ranges in each effect's unit; the
/// effect is always clearly present, in either direction where both make sense).
pub fn realistic(effect: &str, exp: Exp, seed: u64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_mul(7919) ^ effect.len() as u64);
    let mut u = |a: f64, b: f64| rng.random_range(a..b);
    let sign = |x: f64| if x < 0.5 { -1.0 } else { 1.0 };
    match effect {
        "thruster_lag" => vec![u(0.2, 0.6)],
        "thrust_gain" => {
            let s = u(0.0, 1.0);
            vec![if s < 0.5 { u(0.72, 0.85) } else { u(1.15, 1.3) }]
        }
        "thrust_asymmetry" => vec![u(0.65, 0.85)],
        "thruster_deadband" => vec![u(6.0, 15.0)],
        "battery_sag" => vec![u(0.001, 0.003)],
        "inflow_thrust_loss" => vec![u(0.5, 1.2)],
        "buoyancy_offset" => {
            let s = sign(u(0.0, 1.0));
            vec![s * u(0.001, 0.003)]
        }
        "ballast_mass" => vec![u(0.1, 0.2)],
        "damping_error" => {
            let a = if u(0.0, 1.0) < 0.5 {
                u(0.6, 0.8)
            } else {
                u(1.3, 1.6)
            };
            let b = if u(0.0, 1.0) < 0.5 {
                u(0.6, 0.8)
            } else {
                u(1.3, 1.6)
            };
            vec![a, b]
        }
        "added_mass_error" => {
            let s = u(0.0, 1.0);
            vec![if s < 0.5 { u(0.6, 0.75) } else { u(1.3, 1.7) }]
        }
        "water_current" => {
            let a = u(0.0, std::f64::consts::TAU);
            let m = u(0.02, 0.06);
            vec![m * a.cos(), m * a.sin()]
        }
        "depth_sensor_bias" => {
            let s = sign(u(0.0, 1.0));
            vec![u(-0.05, 0.05), s * u(0.0005, 0.0015)]
        }
        "sensor_delay" => vec![u(0.1, 0.4)],
        "thrust_coupling" => {
            let s = sign(u(0.0, 1.0));
            let kz = if exp == Exp::Heave {
                s * u(0.01, 0.03)
            } else {
                0.0
            };
            vec![kz, 0.0]
        }
        "thrust_saturation" => vec![u(0.5, 0.8)],
        // A tilt of 4–9° in pitch and 2–6° in roll for the μAUV²'s 15 mm metacentric height.
        "restoring_moment" => {
            let (sx, sy) = (sign(u(0.0, 1.0)), sign(u(0.0, 1.0)));
            vec![sx * u(0.001, 0.0025), sy * u(0.0005, 0.0015)]
        }
        _ => panic!("no realistic range for {effect}"),
    }
}

/// Per-channel relative validation-RMSE reductions of the chosen model [fraction].
pub fn channel_gains(out: &Outcome) -> Vec<(String, f64)> {
    out.baseline
        .eval
        .metrics
        .iter()
        .map(|(k, mb)| {
            let mf = &out.chosen.eval.metrics[k];
            (format!("y.{}", k.name()), 1.0 - mf.rmse / mb.rmse)
        })
        .collect()
}

pub mod pinned;
pub mod pinned_fits;
pub mod replays;
