//! Shared helpers of the replay tests: μAUV² models with effects, a diving log whose pump
//! runs within its estimation part, and a replay step the samples do not fall on.

use shoal_model::effects::{EffectInstance, Effects, by_name};
use shoal_model::presets;
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::VehicleModel;
use shoal_sysid::evaluate::dataset::DataOptions;
use shoal_sysid::evaluate::open_loop::ReplayOptions;
use shoal_sysid::log::run::MeasuredRun;
use shoal_testkit::design;
use shoal_testkit::synth::synthesize;
use std::path::Path;

/// The μAUV² preset with `effects` (name, parameters) in water of 1000 kg/m³.
pub fn model(effects: &[(&str, Vec<f64>)]) -> VehicleModel {
    let list = effects
        .iter()
        .map(|(n, p)| EffectInstance {
            effect: by_name(n).unwrap(),
            params: p.clone(),
        })
        .collect();
    VehicleModel::with_effects(presets::uauv2(), Effects::new(list), 1000.0)
}

/// A 30 s diving run with a 0.3 s thruster lag hidden in it, whose pump fills, stops,
/// empties, stops, … from one thrust segment to the next (the experiment's own pump segments
/// come later than 30 s): the tank fills and empties within the first half of the run, which
/// is estimation data at the default split.
pub fn pumping_heave_run(seed: u64) -> MeasuredRun {
    let truth = model(&[("thruster_lag", vec![0.3])]);
    let mut exp = design::uauv2_heave(seed, 30.0);
    let mut segment = 0;
    for (_, name, value) in &mut exp.inputs {
        if name == "pump" {
            *value = [1.0, 0.0, -1.0, 0.0][segment % 4];
            segment += 1;
        }
    }
    let run = synthesize(&truth, &Environment::default(), &exp, 0.005, seed);
    let run = MeasuredRun::parse(&run.to_csv(), Path::new(&format!("heave{seed}.csv"))).unwrap();
    let pump = &run.input("pump").unwrap().values;
    let early = &pump[..pump.len() / 2];
    assert!(early.contains(&1.0) && early.contains(&-1.0));
    run
}

/// Data options with a 7 ms replay step: the 20 ms samples fall between grid points, so a
/// sample is interpolated towards the grid point after it.
pub fn offgrid_options() -> DataOptions {
    DataOptions {
        replay: ReplayOptions {
            dt: 0.007,
            ..Default::default()
        },
        ..Default::default()
    }
}
