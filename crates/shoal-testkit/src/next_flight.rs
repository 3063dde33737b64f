//! The next experiment's loop in simulation: a log that cannot tell a sensor delay from a
//! thruster lag ([`slow_heave`]: a heave run whose commands follow one slow sine, where a
//! short delay and a short lag shift the response by about the same phase), and the flight a
//! world file describes ([`flight_of`]: its first vehicle's raw-mode mission), both flown on
//! the hidden truth ([`delayed_uauv2`]) as a logger writes them ([`fly`]).

use crate::design;
use crate::synth::{Experiment, synthesize};
use shoal_model::effects::{EffectInstance, Effects, by_name};
use shoal_model::math::Vec3;
use shoal_model::presets;
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::VehicleModel;
use shoal_sysid::experiment::NextExperiment;
use shoal_sysid::experiment::library::Schedule;
use shoal_sysid::log::run::MeasuredRun;
use shoal_world::desc::WorldDesc;
use std::f64::consts::{FRAC_PI_2, TAU};

/// The hidden truth: the μAUV² whose sensors read `delay` \[s\] late.
pub fn delayed_uauv2(delay: f64) -> VehicleModel {
    let effect = EffectInstance {
        effect: by_name("sensor_delay").expect("a catalogue family"),
        params: vec![delay],
    };
    VehicleModel::with_effects(presets::uauv2(), Effects::new(vec![effect]), 1000.0)
}

/// A diving-mode heave run whose commands follow one slow sine (0.03 Hz, ±40 %): 120 s logged
/// at 50 Hz (depth, heading, yaw rate), the pressure port 1 m deep at the start.
pub fn slow_heave() -> Experiment {
    let mut inputs = vec![
        (0.0, "alpha".to_string(), 0.0),
        (0.0, "beta".to_string(), -FRAC_PI_2),
        (0.0, "top".to_string(), 0.0),
    ];
    for i in 0..6000 {
        let t = i as f64 * 0.02;
        let n = 40.0 * (TAU * 0.03 * t).sin();
        inputs.push((t, "port".into(), n));
        inputs.push((t, "stbd".into(), n));
    }
    // The designed heave experiment's logging, start and channels, other commands.
    Experiment {
        name: "slow_heave".into(),
        inputs,
        ..design::uauv2_heave(0, 120.0)
    }
}

/// The flight of the world file `world` (its first vehicle's raw-mode mission: thruster, tilt
/// and pump commands), named `name`, logged every `period` \[s\] with the channels of
/// [`slow_heave`], started where it starts.
pub fn flight_of(world: &WorldDesc, name: &str, period: f64) -> Experiment {
    let v = &world.vehicles[0];
    let p = &v.model.params;
    let mut inputs = Vec::new();
    for s in &v.mission.steps {
        for (i, n) in &s.thrusters {
            inputs.push((s.t, p.thrusters[*i].name.clone(), *n));
        }
        for (i, a) in &s.tilts {
            inputs.push((s.t, p.tilts[*i].name.clone(), *a));
        }
        if let Some(pump) = s.pump {
            inputs.push((s.t, "pump".to_string(), pump.sign()));
        }
    }
    Experiment {
        name: name.into(),
        duration: world.duration,
        sample_period: period,
        inputs,
        ..slow_heave()
    }
}

/// A schedule's commands as an experiment's inputs: (time \[s\], input, value) at every
/// change.
pub fn schedule_inputs(schedule: &Schedule) -> Vec<(f64, String, f64)> {
    let mut inputs = Vec::new();
    for (t, values) in &schedule.steps {
        for (input, v) in schedule.inputs.iter().zip(values) {
            inputs.push((*t, input.clone(), *v));
        }
    }
    inputs
}

/// The flight `x` suggests as an experiment: its commands from its start (depth and heading;
/// the horizontal position, the logging period and the channels of `like`), named `name`.
pub fn experiment_of(x: &NextExperiment, name: &str, like: &Experiment) -> Experiment {
    let (z, yaw) = x.start_pose(&presets::uauv2());
    Experiment {
        name: name.into(),
        duration: x.schedule.duration,
        sample_period: x.period_s,
        inputs: schedule_inputs(&x.schedule),
        channels: like.channels.clone(),
        position: Vec3::new(like.position.x, like.position.y, z),
        yaw,
        tracking_noise: like.tracking_noise,
    }
}

/// `exp` flown on `truth` (5 ms steps, the sensors' noise from `seed`) and read back from the
/// CSV text a logger writes.
pub fn fly(truth: &VehicleModel, exp: &Experiment, seed: u64) -> MeasuredRun {
    let run = synthesize(truth, &Environment::default(), exp, 0.005, seed);
    MeasuredRun::parse(
        &run.to_csv(),
        std::path::Path::new(&format!("{}.csv", exp.name)),
    )
    .expect("synthetic CSV parses")
}
