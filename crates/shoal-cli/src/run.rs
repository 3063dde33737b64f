//! `shoal run` and `shoal check`.

use crate::Failure;
use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use shoal_sim::prelude::*;
use shoal_world::desc::WorldDesc;
use shoal_world::load::{default_world, load_file};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Arguments of `shoal run`.
#[derive(clap::Args, Debug)]
pub struct RunArgs {
    /// World file (TOML); without it the embedded default world runs.
    pub world: Option<PathBuf>,
    /// Output folder [default: out/<world name>].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Working threads for per-vehicle loops.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..=256))]
    pub threads: u16,
    /// Override the world's seed.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Override the world's duration [s].
    #[arg(long)]
    pub duration: Option<f64>,
    /// Skip plots.
    #[arg(long)]
    pub no_plots: bool,
    /// Print only the summary (no progress bar).
    #[arg(long, short)]
    pub quiet: bool,
}

fn load(world: Option<&Path>) -> Result<WorldDesc, Failure> {
    match world {
        Some(p) => load_file(p),
        None => default_world(),
    }
    .map_err(|e| Failure::Input(e.to_string()))
}

fn slug(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect();
    let s = s
        .split('-')
        .filter(|p| !p.is_empty())
        .collect::<Vec<_>>()
        .join("-");
    if s.is_empty() { "world".into() } else { s }
}

/// `shoal run`.
pub fn run(args: &RunArgs) -> Result<ExitCode, Failure> {
    let mut desc = load(args.world.as_deref())?;
    if let Some(s) = args.seed {
        desc.seed = s;
    }
    if let Some(d) = args.duration {
        if !(d.is_finite() && d > 0.0 && d <= 1e7) {
            return Err(Failure::Input(format!(
                "--duration {d}: allowed 0 < duration ≤ 10000000 s"
            )));
        }
        desc.duration = d;
    }
    if args.no_plots {
        desc.output.plots = false;
    }
    let out_dir = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(slug(&desc.name)));

    let interrupted = Arc::new(AtomicBool::new(false));
    {
        let flag = interrupted.clone();
        // A second Ctrl-C while outputs are being written is ignored; the first one only
        // asks the loop to stop after the current chunk.
        ctrlc::set_handler(move || flag.store(true, Ordering::SeqCst))
            .context("cannot install the Ctrl-C handler")?;
    }

    let steps = desc.steps();
    let mut sim = Sim::new(
        &desc,
        SimOptions {
            threads: usize::from(args.threads),
            record: true,
        },
    );
    let mut out = RunOutput::create(&out_dir, &desc)
        .with_context(|| format!("cannot create outputs in {}", out_dir.display()))?;
    let pb = if args.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(steps)
    };
    pb.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}% {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    if !args.quiet {
        eprintln!(
            "shoal: running `{}` — {} vehicles, {:.1} s at dt = {} s, {} thread(s) → {}",
            desc.name,
            desc.vehicles.len(),
            desc.duration,
            desc.dt,
            args.threads,
            out_dir.display()
        );
    }
    let chunk = (steps / 500).clamp(1, 500);
    let start = Instant::now();
    while sim.step_count() < steps && !interrupted.load(Ordering::SeqCst) {
        let n = chunk.min(steps - sim.step_count());
        sim.run(n);
        out.write(&sim.drain())
            .context("cannot write trajectories")?;
        let wall = start.elapsed().as_secs_f64();
        pb.set_position(sim.step_count());
        pb.set_message(format!(
            "t = {:.1} s  ({:.1}× real time)",
            sim.time(),
            sim.time() / wall.max(1e-9)
        ));
    }
    let was_interrupted = interrupted.load(Ordering::SeqCst);
    pb.finish_and_clear();
    let wall = start.elapsed().as_secs_f64();
    let summary = out
        .finish(&desc, &sim, wall, was_interrupted)
        .context("cannot write the run outputs")?;
    println!("{}", summary.to_text());
    Ok(if was_interrupted {
        ExitCode::from(130)
    } else {
        ExitCode::SUCCESS
    })
}

/// `shoal preset`.
pub fn preset(name: &str) -> Result<ExitCode, Failure> {
    let Some(p) = shoal_model::presets::by_name(name) else {
        return Err(Failure::Input(format!(
            "unknown preset `{name}` (available: {})",
            shoal_model::presets::NAMES.join(", ")
        )));
    };
    let spec = shoal_world::spec::VehicleSpec::from_params(&p);
    let text = shoal_world::load::vehicle_world_toml(&spec, [5.0, 5.0, 1.0])
        .context("cannot write the preset")?;
    println!(
        "# The `{name}` preset as a world file (shoal preset {name}). Numbers are marked paper /"
    );
    println!(
        "# derived / assumed in crates/shoal-model/src/presets.rs. Units: SI; angles in `_deg` fields."
    );
    print!("{text}");
    Ok(ExitCode::SUCCESS)
}

/// `shoal check`.
pub fn check(world: &Path) -> Result<ExitCode, Failure> {
    let desc = load(Some(world))?;
    println!(
        "{}: ok — `{}`, {} vehicles in {} group(s), {} obstacle(s), pool {} × {} × {} m, {:.1} s at dt = {} s ({} steps), seed {}",
        world.display(),
        desc.name,
        desc.vehicles.len(),
        desc.groups.len(),
        desc.geometry.obstacles.len(),
        desc.geometry.pool.x,
        desc.geometry.pool.y,
        desc.geometry.pool.z,
        desc.duration,
        desc.dt,
        desc.steps(),
        desc.seed
    );
    Ok(ExitCode::SUCCESS)
}
