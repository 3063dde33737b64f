//! The next experiment: a log that cannot tell a sensor delay from a thruster lag (a heave
//! run whose commands follow one slow sine, where a short delay and a short lag both shift
//! the response by about the same phase) is reported as "A or B"; the flight that
//! `next_experiment.toml` describes, flown in simulation on the hidden truth and validated
//! together with the first log, names the truth alone — and a flight of the same length
//! through the manoeuvre the ranking put last does not.

use shoal_model::presets;
use shoal_sysid::experiment::library::{Axis, LIBRARY, Schedule};
use shoal_sysid::log::run::MeasuredRun;
use shoal_sysid::validate::{Config, Horizon, RunInput, Validation};
use shoal_testkit::next_flight::{delayed_uauv2, flight_of, fly, schedule_inputs, slow_heave};
use shoal_testkit::synth::Experiment;
use shoal_world::load::load_str;
use std::path::PathBuf;

/// The hidden sensor delay \[s\].
const DELAY_S: f64 = 0.08;

/// `shoal validate` among the delay and the lag on `runs` (CSV text, each split 60/40).
fn validate(runs: &[&MeasuredRun]) -> Validation {
    let config = Config {
        effects: vec!["sensor_delay".into(), "thruster_lag".into()],
        threads: Some(1),
        dt: 0.02,
        horizon: Horizon::Open,
        ..Default::default()
    };
    let inputs: Vec<RunInput> = runs
        .iter()
        .map(|r| RunInput::Text {
            name: format!("{}.csv", r.name),
            csv: r.to_csv(),
        })
        .collect();
    shoal_sysid::validate::validate(&config, &inputs, &[], &|_| {}).expect("validated")
}

/// The flight of `schedule` on the truth, started as the first log was.
fn fly_schedule(name: &str, schedule: &Schedule, period: f64, seed: u64) -> MeasuredRun {
    let exp = Experiment {
        name: name.into(),
        duration: schedule.duration,
        sample_period: period,
        inputs: schedule_inputs(schedule),
        ..slow_heave()
    };
    fly(&delayed_uauv2(DELAY_S), &exp, seed)
}

/// The pair the log cannot separate, in either order.
fn pair(v: &Validation) -> Vec<[String; 2]> {
    v.outcome
        .verdict
        .ambiguous
        .iter()
        .map(|a| {
            let mut p = a.effects.clone();
            p.sort();
            p
        })
        .collect()
}

#[test]
fn the_suggested_experiment_settles_a_delay_against_a_lag() {
    let truth = delayed_uauv2(DELAY_S);
    let first = fly(&truth, &slow_heave(), 11);
    let v = validate(&[&first]);
    let delay_or_lag = [String::from("sensor_delay"), String::from("thruster_lag")];
    assert!(
        v.outcome.verdict.effects.is_empty(),
        "{:?}",
        v.outcome.verdict
    );
    assert_eq!(pair(&v), std::slice::from_ref(&delay_or_lag));
    let x = v.next_experiment.as_ref().expect("a next experiment");
    // The report's world file is the flight: it loads, and flown on the truth it settles it.
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("next_experiment");
    let _ = std::fs::remove_dir_all(&dir);
    let written = v.write(&dir, false).expect("report written");
    let path = written
        .next_experiment
        .expect("next_experiment.toml written");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("sensor_delay or thruster_lag"), "{text}");
    let world = load_str(&text, &path).expect("next_experiment.toml loads");
    assert_eq!(
        world.vehicles[0].mission.steps.len(),
        x.schedule.steps.len()
    );
    let second = fly(&truth, &flight_of(&world, "next", x.period_s), 12);
    let both = validate(&[&first, &second]);
    assert_eq!(
        both.outcome.verdict.effects,
        ["sensor_delay"],
        "{} flown: {:?}",
        x.manoeuvre,
        both.outcome.verdict
    );
    // The flight the ranking put last, as long, leaves the question open: the choice matters.
    let (worst, _) = x.tried.iter().min_by(|a, b| a.1.total_cmp(&b.1)).unwrap();
    assert_ne!(worst, &x.manoeuvre);
    let base = presets::uauv2();
    let axis = Axis::of(&base, &[&first]).unwrap();
    let m = LIBRARY.iter().find(|m| m.name == worst).unwrap();
    let schedule = m.schedule(&base, &axis, x.schedule.duration);
    let other = fly_schedule("other", &schedule, x.period_s, 12);
    let control = validate(&[&first, &other]);
    assert!(
        control.outcome.verdict.effects.is_empty() && pair(&control) == [delay_or_lag],
        "{worst} flown: {:?}",
        control.outcome.verdict
    );
}
