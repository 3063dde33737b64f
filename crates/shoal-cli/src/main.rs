//! `shoal`: run worlds of minuscule AUVs, check world files, validate the model against
//! measured runs, benchmark scaling.
//!
//! Exit codes (docs/exit-codes.md):
//! - 0: success;
//! - 1: failure, e.g. an output file could not be written (the message names it and gives the
//!   operating system's reason; files finished before it stay);
//! - 2: invalid input (world file, measured run, vehicle file, option value);
//! - 3: `shoal run` ended early by the world's agent fallback `stop` (outputs complete);
//! - 4: `shoal run` stopped because a vehicle's state became non-finite (the message names
//!   the vehicle, the time and the last finite state; outputs up to that step are written and
//!   summary.json says `failed`);
//! - 129, 130, 143: `shoal run` stopped by SIGHUP, SIGINT (Ctrl-C) or SIGTERM (128 + the
//!   signal number); outputs up to that step are written, or nothing when the signal came
//!   while the world was being loaded or built.
//!
//! `shoal sweep` exits 1 also when some of its runs failed or are missing (results.csv lists
//! them), and 128 + n when a signal stopped it (the table holds the runs that finished).

mod agents;
mod alloc;
mod bench;
mod bench_access;
mod bench_agent;
mod bench_measure;
mod bench_ros2;
mod bench_rows;
mod effects;
mod exit;
mod render;
mod run;
mod signals;
mod sweep;
mod terminal;
mod validate;

use clap::{Parser, Subcommand};
use exit::Failure;
use std::path::PathBuf;
use std::process::ExitCode;

#[global_allocator]
static ALLOC: alloc::Counting = alloc::Counting;

/// Swarm simulator for minuscule AUVs (DFKI μAUV²) with optical modems.
#[derive(Parser, Debug)]
#[command(name = "shoal", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run a world (the embedded default swarm when no file is given) and write trajectories,
    /// a summary and plots.
    Run(run::RunArgs),
    /// Validate a world file and print what it contains.
    Check {
        /// The world file.
        world: PathBuf,
    },
    /// Draw an animated GIF of a finished run from its replay.html (no browser needed).
    Render(render::RenderArgs),
    /// Print a scaling table: vehicles × threads → vehicle-steps/s, real-time factor, memory.
    Bench(bench::BenchArgs),
    /// Compare measured runs with the vehicle model: what it gets wrong, which catalogue
    /// effects explain it, the fitted extension (vehicle.toml) and its validation gain.
    Validate(validate::ValidateArgs),
    /// Print the effect catalogue of `validate`: every effect and form with its parameters'
    /// units, bounds (for the given vehicle) and null values.
    Effects {
        /// Vehicle model in the world-file format (bounds depend on it) [default: the μAUV²
        /// preset].
        #[arg(long, value_name = "FILE")]
        vehicle: Option<PathBuf>,
        /// Print the Markdown table of docs/validation.md instead of plain text.
        #[arg(long)]
        markdown: bool,
    },
    /// Run a sweep: many runs of a world with parameters varied, one table (locally, as a
    /// Slurm job array, or as a Kubernetes Indexed Job); see docs/sweeps.md.
    Sweep(sweep::SweepCmd),
    /// Print a built-in vehicle model as a runnable world file (every number, to copy and edit).
    Preset {
        /// Preset name.
        #[arg(default_value = "uauv2")]
        name: String,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run(a) => run::run(&a),
        Command::Render(a) => render::render(&a),
        Command::Check { world } => run::check(&world),
        Command::Preset { name } => run::preset(&name),
        Command::Sweep(a) => sweep::main(&a),
        Command::Validate(a) => validate::validate(&a),
        Command::Effects { vehicle, markdown } => effects::print(vehicle.as_deref(), markdown),
        Command::Bench(a) => bench::bench(&a)
            .map(|()| ExitCode::SUCCESS)
            .map_err(Failure::Other),
    };
    match result {
        Ok(code) => code,
        Err(Failure::Input(msg)) => {
            eprintln!("error: {msg}");
            ExitCode::from(2)
        }
        Err(Failure::Other(e)) => {
            eprintln!("error: {e:#}");
            ExitCode::from(1)
        }
    }
}
