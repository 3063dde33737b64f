//! The next experiment's loop in simulation, for docs/validation.md's worked example: writes
//! a log that cannot tell an 80-ms sensor delay from a thruster lag (`slow_heave.csv`), and,
//! given the `next_experiment.toml` that `shoal validate` wrote for it, flies that flight on
//! the same hidden truth (`next.csv`), to be validated together with the first.
//!
//! ```sh
//! cargo run --release -p shoal-testkit --example next_experiment -- --out out/next
//! cargo run --release -- validate out/next/slow_heave.csv --effects sensor_delay,thruster_lag \
//!     --out out/next/first
//! cargo run --release -p shoal-testkit --example next_experiment -- --out out/next \
//!     --fly out/next/first/next_experiment.toml
//! cargo run --release -- validate out/next/slow_heave.csv out/next/next.csv \
//!     --effects sensor_delay,thruster_lag --out out/next/both
//! ```

use shoal_testkit::next_flight::{delayed_uauv2, flight_of, fly, slow_heave};
use std::path::PathBuf;
use std::process::ExitCode;

/// The hidden sensor delay \[s\].
const DELAY_S: f64 = 0.08;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1))
    };
    let Some(out) = value("--out").map(PathBuf::from) else {
        eprintln!("usage: next_experiment --out DIR [--fly next_experiment.toml]");
        return ExitCode::from(2);
    };
    if let Err(e) = std::fs::create_dir_all(&out) {
        eprintln!("cannot create {}: {e}", out.display());
        return ExitCode::FAILURE;
    }
    let truth = delayed_uauv2(DELAY_S);
    let (run, file) = match value("--fly") {
        None => (fly(&truth, &slow_heave(), 11), out.join("slow_heave.csv")),
        Some(world) => {
            let world = match shoal_world::load::load_file(std::path::Path::new(world)) {
                Ok(w) => w,
                Err(e) => {
                    eprintln!("{e}");
                    return ExitCode::FAILURE;
                }
            };
            let period = 1.0 / world.output.record_hz;
            let exp = flight_of(&world, "next", period);
            (fly(&truth, &exp, 12), out.join("next.csv"))
        }
    };
    if let Err(e) = std::fs::write(&file, run.to_csv()) {
        eprintln!("cannot write {}: {e}", file.display());
        return ExitCode::FAILURE;
    }
    println!("wrote {} ({} rows)", file.display(), run.t.len());
    ExitCode::SUCCESS
}
