//! Writes two measured-run CSVs of a μAUV² diving experiment with a model effect hidden in
//! them, to try `shoal validate` on: by default a 0.4 s thruster lag; any catalogue effect
//! with parameters can be given instead.
//!
//! ```sh
//! cargo run --release --example hidden_effect                          # thruster_lag 0.4
//! cargo run --release --example hidden_effect -- buoyancy_offset 0.002
//! cargo run --release -- validate out/hidden/dive_a.csv --holdout out/hidden/dive_b.csv \
//!     --out out/hidden/report
//! ```
//!
//! Each run is 120 s at 50 Hz (random thrust steps, the pump cycling), simulated at 5 ms with
//! the pressure sensor's noise and 1.8 mm quantisation; seeds 1 and 2.

use shoal::model::effects::{EffectInstance, Effects, by_name, names};
use shoal::model::presets;
use shoal::model::rigid_body::Environment;
use shoal::model::vehicle::VehicleModel;
use shoal_testkit::design;
use shoal_testkit::synth::synthesize;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args.first().map_or("thruster_lag", String::as_str);
    let Some(effect) = by_name(name) else {
        eprintln!("unknown effect `{name}` (allowed: {})", names().join(", "));
        return ExitCode::from(2);
    };
    let info = effect.params(&presets::uauv2());
    let params: Vec<f64> = if args.len() > 1 {
        match args[1..].iter().map(|a| a.parse::<f64>()).collect() {
            Ok(p) => p,
            Err(e) => {
                eprintln!("parameters must be numbers: {e}");
                return ExitCode::from(2);
            }
        }
    } else if name == "thruster_lag" {
        vec![0.4]
    } else {
        info.iter().map(|p| p.typical).collect()
    };
    if params.len() != info.len() {
        let want: Vec<&str> = info.iter().map(|p| p.name).collect();
        eprintln!(
            "`{name}` takes {} parameter(s): {}",
            info.len(),
            want.join(", ")
        );
        return ExitCode::from(2);
    }
    for (p, v) in info.iter().zip(&params) {
        if !(p.lo..=p.hi).contains(v) {
            eprintln!(
                "{}.{} = {v} is out of range {} … {} {}",
                name, p.name, p.lo, p.hi, p.unit
            );
            return ExitCode::from(2);
        }
    }
    let truth = VehicleModel::with_effects(
        presets::uauv2(),
        Effects::new(vec![EffectInstance {
            effect,
            params: params.clone(),
        }]),
        1000.0,
    );
    let dir = std::path::Path::new("out/hidden");
    if let Err(e) = std::fs::create_dir_all(dir) {
        eprintln!("cannot create {}: {e}", dir.display());
        return ExitCode::FAILURE;
    }
    for (file, seed) in [("dive_a.csv", 1), ("dive_b.csv", 2)] {
        let exp = design::uauv2_heave(seed, 120.0);
        let run = synthesize(&truth, &Environment::default(), &exp, 0.005, seed ^ 0x5eed);
        let path = dir.join(file);
        if let Err(e) = std::fs::write(&path, run.to_csv()) {
            eprintln!("cannot write {}: {e}", path.display());
            return ExitCode::FAILURE;
        }
        println!("wrote {} ({} rows)", path.display(), run.t.len());
    }
    let shown: Vec<String> = info
        .iter()
        .zip(&params)
        .map(|(p, v)| format!("{} = {v} {}", p.name, p.unit))
        .collect();
    println!("hidden: {name} ({})", shown.join(", "));
    ExitCode::SUCCESS
}
