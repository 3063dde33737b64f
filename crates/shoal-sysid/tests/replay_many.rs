//! Replaying several models together ([`Dataset::replayed_many`], [`simulate_many`]: one lane
//! of the RK4 kernel each, with its own constants of motion) gives each model's own replay
//! bit for bit — for models that differ in every kind of constant the kernel reads (thrust
//! lag, damping, added mass, the pump's flow and with it the mass properties, the water
//! current) and in what is read from the replay (a sensor delay, a depth-sensor bias), on a
//! diving log whose pump fills and empties the tank, for whole and estimation replays, with a
//! hold-out run, and for replays that end at different steps.

mod common;

use common::replays::{model, offgrid_options as options, pumping_heave_run as heave_run};
use shoal_model::effects::by_name;
use shoal_model::presets;
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::VehicleModel;
use shoal_sysid::evaluate::dataset::{Dataset, Part};
use shoal_sysid::evaluate::masses::MassTable;
use shoal_sysid::evaluate::open_loop::{ReplayOptions, Trace, simulate_many, simulate_with};
use shoal_sysid::log::run::MeasuredRun;
use shoal_testkit::design;
use shoal_testkit::synth::synthesize;
use std::path::Path;

/// A 30 s yaw run (tilted thrusters).
fn yaw_run(seed: u64) -> MeasuredRun {
    let truth = model(&[]);
    let exp = design::uauv2_yaw(seed, 30.0);
    let run = synthesize(&truth, &Environment::default(), &exp, 0.005, seed);
    MeasuredRun::parse(&run.to_csv(), Path::new(&format!("yaw{seed}.csv"))).unwrap()
}

/// The effect `name` at its typical values, each parameter scaled by `k` about its null.
fn typical(name: &str, k: f64) -> (&str, Vec<f64>) {
    let params = by_name(name).unwrap().params(&presets::uauv2());
    (
        name,
        params
            .iter()
            .map(|p| (p.null + k * (p.typical - p.null)).clamp(p.lo, p.hi))
            .collect(),
    )
}

/// Nine models (two groups of four lanes and one alone): the baseline and models that differ
/// in every kind of constant of motion and of reading.
fn models() -> Vec<VehicleModel> {
    vec![
        model(&[]),
        model(&[typical("thruster_lag", 1.0)]),
        model(&[typical("damping_error", 1.5)]),
        model(&[typical("added_mass_error", 1.2)]),
        model(&[typical("ballast_mass", 2.0)]),
        model(&[typical("water_current", 1.0), ("sensor_delay", vec![0.13])]),
        model(&[
            typical("ballast_mass", 0.5),
            typical("added_mass_error", 0.7),
            typical("damping_error", 0.8),
        ]),
        model(&[
            typical("depth_sensor_bias", 1.0),
            typical("thruster_lag", 0.4),
        ]),
        model(&[
            typical("buoyancy_offset", 1.0),
            ("sensor_delay", vec![0.05]),
        ]),
    ]
}

fn bits(t: &Trace) -> Vec<u64> {
    t.values.iter().map(|x| x.to_bits()).collect()
}

/// `replayed_many` equals `replayed` of each model, for both parts; returns how many of the
/// models' replays differ from the first one's (so that the models are seen to differ).
fn same_as_one_by_one(ds: &Dataset, models: &[VehicleModel]) -> usize {
    let mut differ = 0;
    for part in [Part::All, Part::Estimation] {
        let many = ds.replayed_many(models, part);
        assert_eq!(many.len(), models.len());
        let one: Vec<_> = models.iter().map(|m| ds.replayed(m, part)).collect();
        for (i, (a, b)) in many.iter().zip(&one).enumerate() {
            // Bit for bit: the weighted residuals and every series of the evaluation.
            let (ea, eb) = (ds.evaluation(a), ds.evaluation(b));
            let f = eb.ml_factors();
            let wa: Vec<u64> = ea.weighted(&f).iter().map(|x| x.to_bits()).collect();
            let wb: Vec<u64> = eb.weighted(&f).iter().map(|x| x.to_bits()).collect();
            assert_eq!(wa, wb, "model {i}, {part:?}: weighted residuals");
            for (ra, rb) in ea.runs.iter().zip(&eb.runs) {
                for (ca, cb) in ra.channels.iter().zip(&rb.channels) {
                    let pa: Vec<u64> = ca.predicted.iter().map(|x| x.to_bits()).collect();
                    let pb: Vec<u64> = cb.predicted.iter().map(|x| x.to_bits()).collect();
                    assert_eq!(pa, pb, "model {i}, {part:?}: {} {:?}", ra.name, ca.kind);
                }
            }
            assert_eq!(a, b, "model {i}, {part:?}");
            if i > 0 && one[0] != *b {
                differ += 1;
            }
        }
    }
    differ
}

#[test]
fn models_replayed_together_equal_each_replayed_alone() {
    let ds = Dataset::new(
        &presets::uauv2(),
        Environment::default(),
        vec![heave_run(1), yaw_run(2)],
        vec![],
        &options(),
    )
    .unwrap();
    let models = models();
    // Every model changes the replay (in both parts).
    assert_eq!(same_as_one_by_one(&ds, &models), 2 * (models.len() - 1));
    // Groups of two and three lanes (the rest of the lanes unused).
    assert!(same_as_one_by_one(&ds, &models[..2]) > 0);
    assert!(same_as_one_by_one(&ds, &models[4..7]) > 0);
}

/// Re-anchored replays with their filters (each model two lanes: its replay and the filter
/// that gives it its horizontal velocities at each anchor) equal each model re-anchored alone,
/// on a closed-loop mission where the hull moves in every direction.
#[test]
fn re_anchored_replays_with_their_filters_too() {
    let case = shoal_testkit::closed_loop::cases(90.0)
        .into_iter()
        .find(|c| c.name == "m_null_1")
        .unwrap();
    let csv = case.csv(&shoal_testkit::mission::Disturbance::default());
    let mission = MeasuredRun::parse(&csv, Path::new("m.csv")).unwrap();
    let mut ds = Dataset::new(
        &presets::uauv2(),
        Environment::default(),
        vec![mission, yaw_run(2)],
        vec![],
        &options(),
    )
    .unwrap();
    let models = models();
    ds.anchor(
        shoal_sysid::evaluate::anchoring::Horizon::Every(3.0),
        &models[0],
    );
    assert!(!ds.runs[0].init.filter.is_empty() && !ds.runs[0].init.anchors.is_empty());
    // Most models change the replay (a mission's first minute does not show every effect).
    assert!(same_as_one_by_one(&ds, &models) >= models.len());
    assert!(same_as_one_by_one(&ds, &models[..3]) > 0);
}

#[test]
fn with_a_hold_out_run_too() {
    let ds = Dataset::new(
        &presets::uauv2(),
        Environment::default(),
        vec![heave_run(1)],
        vec![heave_run(3)],
        &options(),
    )
    .unwrap();
    let models = models();
    assert_eq!(same_as_one_by_one(&ds, &models), 2 * (models.len() - 1));
}

/// Replays of one group that end at different steps: each is the replay alone with its own
/// bound (the lanes whose replay has ended no longer count, the others go on).
#[test]
fn replays_that_end_at_different_steps() {
    let run = heave_run(4);
    let models = models();
    let params = &models[0].params;
    let mut run_mapped = run.clone();
    let map = shoal_sysid::evaluate::open_loop::InputMap::new(params, &mut run_mapped).unwrap();
    let init = shoal_sysid::evaluate::open_loop::InitialState::from_run(params, &run_mapped, 0.5);
    let kinds = [
        shoal_sysid::log::run::ChannelKind::Depth,
        shoal_sysid::log::run::ChannelKind::Pitch,
        shoal_sysid::log::run::ChannelKind::Yaw,
        shoal_sysid::log::run::ChannelKind::W,
    ];
    let opts = ReplayOptions {
        dt: 0.007,
        ..Default::default()
    };
    let env = Environment::default();
    let masses = MassTable::default();
    let refs: Vec<&VehicleModel> = models.iter().collect();
    let bounds = [4000, 17, usize::MAX, 0, 2500, 4001, 3999, usize::MAX, 100];
    let many = simulate_many(
        &refs,
        &bounds,
        &env,
        &run_mapped,
        &map,
        &init,
        &kinds,
        &opts,
        &masses,
    );
    for (i, (m, &n)) in models.iter().zip(&bounds).enumerate() {
        let one = simulate_with(
            m,
            &env,
            &run_mapped,
            &map,
            &init,
            &kinds,
            &opts,
            &MassTable::default(),
            n,
        );
        assert_eq!(one.len(), many[i].len(), "model {i}");
        assert_eq!(bits(&one), bits(&many[i]), "model {i} (bound {n})");
    }
    // The whole run is 30 s: 4286 steps.
    assert_eq!(many[2].len(), 4287);
    assert_eq!(many[3].len(), 1);
}

/// Replays with a closed-loop twin (each model three lanes: its re-anchored replay, its
/// filter and its twin with the controller in the loop, whose commands the replay records)
/// equal each model's replay stepped alone (`simulate_with`, one hull after another), for
/// replays that end at different steps too; the twins' commands differ between the models.
#[test]
fn replays_with_a_closed_loop_twin_too() {
    let case = shoal_testkit::closed_loop::cases(60.0)
        .into_iter()
        .find(|c| c.name == "m_null_1")
        .unwrap();
    let csv = case.csv(&shoal_testkit::mission::Disturbance::default());
    let mission = MeasuredRun::parse(&csv, Path::new("m.csv")).unwrap();
    let models = models();
    let mut ds = Dataset::new(
        &presets::uauv2(),
        Environment::default(),
        vec![mission],
        vec![],
        &options(),
    )
    .unwrap();
    ds.anchor(
        shoal_sysid::evaluate::anchoring::Horizon::Closed,
        &models[0],
    );
    assert!(ds.anchoring.closed_loop, "{}", ds.anchoring.why);
    let rd = &ds.runs[0];
    assert!(!rd.init.anchors.is_empty() && rd.init.control.is_some());
    let mut kinds: Vec<_> = rd
        .channels
        .iter()
        .map(|&i| rd.run.channels[i].kind)
        .collect();
    kinds.sort();
    let port = kinds
        .iter()
        .position(|k| *k == shoal_sysid::log::run::ChannelKind::command("port"))
        .expect("the port command compared");
    let refs: Vec<&VehicleModel> = models.iter().collect();
    let bounds = [4000, 17, usize::MAX, 0, 2500, 4001, 3999, usize::MAX, 100];
    let masses = MassTable::default();
    let env = Environment::default();
    let opts = options().replay;
    let many = simulate_many(
        &refs, &bounds, &env, &rd.run, &rd.map, &rd.init, &kinds, &opts, &masses,
    );
    let mut commands = Vec::new();
    for (i, (m, &n)) in models.iter().zip(&bounds).enumerate() {
        let one = simulate_with(
            m, &env, &rd.run, &rd.map, &rd.init, &kinds, &opts, &masses, n,
        );
        assert_eq!(bits(&one), bits(&many[i]), "model {i} (bound {n})");
        if n == usize::MAX {
            commands.push(
                one.values[port..]
                    .iter()
                    .step_by(kinds.len())
                    .copied()
                    .collect::<Vec<f64>>(),
            );
        }
    }
    assert!(commands[0].iter().any(|c| *c != 0.0));
    assert_ne!(commands[0], commands[1]);
}
