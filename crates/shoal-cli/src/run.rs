//! `shoal run` and `shoal check`.
//!
//! A run stops early, cleanly, on SIGINT, SIGTERM or SIGHUP ([`crate::signals`]): while the
//! world is loaded or built it stops before the run starts and writes nothing; while it runs
//! it stops at the next step and writes the outputs up to that step (see
//! `shoal_record::output`); agents are told and the shared memory is removed; the exit code is
//! 128 + the signal number.

use crate::agents::open_agents;
use crate::exit::{Failure, run_exit_code};
use crate::signals;
use crate::terminal::Terminal;
use anyhow::Context;
use shoal_record::run::{Changes, LoadWorldError, Ran, Run, RunOption, default_out, load_world};
use shoal_world::cancel::{Cancel, Cause};
use shoal_world::desc::WorldDesc;
use shoal_world::load::{EMBEDDED_NAME, LoadError, load_file_until};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

/// Arguments of `shoal run`.
#[derive(clap::Args, Debug)]
pub struct RunArgs {
    /// World file (TOML); without it the embedded default world runs.
    pub world: Option<PathBuf>,
    /// Output folder [default: out/<world name>].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Working threads for per-vehicle loops [default: every core of this machine]. The
    /// results are the same for any number.
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=256))]
    pub threads: Option<u16>,
    /// Override the world's seed (`seed`).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Override the world's duration [s] (`duration`; the world file's range).
    #[arg(long)]
    pub duration: Option<f64>,
    /// Skip plots (`[output] plots = false`).
    #[arg(long)]
    pub no_plots: bool,
    /// Skip `replay.html`, the interactive 3D replay (`[output] replay = false`).
    #[arg(long)]
    pub no_replay: bool,
    /// Also write `run.mcap`: the run for Foxglove and ROS 2 tools (`[output] mcap = true`;
    /// topics and size budget: docs/mcap.md).
    #[arg(long)]
    pub mcap: bool,
    /// Print only the summary (no progress bar).
    #[arg(long, short)]
    pub quiet: bool,
    /// External agents: wait for them each control period (`lockstep`) or never (`free`)
    /// [default: the world's `[agents] timing`].
    #[arg(long, value_parser = ["lockstep", "free"])]
    pub timing: Option<String>,
    /// External agents: service-name prefix of this world [default: `[agents] prefix`, else
    /// the world's name].
    #[arg(long)]
    pub prefix: Option<String>,
    /// External agents: how long to wait for them to attach before starting [s]
    /// (`[agents] attach_timeout`).
    #[arg(long, value_name = "SECONDS")]
    pub wait_agents: Option<f64>,
}

impl RunArgs {
    /// The options that change the world, as world-file overrides.
    fn changes(&self) -> Changes {
        Changes {
            seed: self.seed,
            duration: self.duration,
            plots: self.no_plots.then_some(false),
            replay: self.no_replay.then_some(false),
            mcap: self.mcap.then_some(true),
            timing: self.timing.clone(),
            prefix: self.prefix.clone(),
            wait_agents: self.wait_agents,
        }
    }
}

/// The command-line option of a run option.
fn flag(option: RunOption) -> &'static str {
    match option {
        RunOption::Seed => "--seed",
        RunOption::Duration => "--duration",
        RunOption::Plots => "--no-plots",
        RunOption::Replay => "--no-replay",
        RunOption::Mcap => "--mcap",
        RunOption::Timing => "--timing",
        RunOption::Prefix => "--prefix",
        RunOption::WaitAgents => "--wait-agents",
    }
}

/// Loads the world file (or the embedded default world) until `cancel` asks for a stop.
pub fn load(world: Option<&Path>, cancel: &Cancel) -> Result<WorldDesc, LoadError> {
    match world {
        Some(p) => load_file_until(p, cancel),
        None => shoal_world::load::load_str_until(
            shoal_world::load::DEFAULT_WORLD,
            Path::new(EMBEDDED_NAME),
            cancel,
        ),
    }
}

/// The end of a run stopped before it started: says so and gives the signal's exit code.
fn stopped_before_start(cause: Cause, phase: &str) -> ExitCode {
    eprintln!(
        "shoal: interrupted by {} while {phase}, before the run started; nothing was written",
        cause.name
    );
    signals::exit_code(cause)
}

/// `shoal run`: flags → world overrides → [`Run`].
pub fn run(args: &RunArgs) -> Result<ExitCode, Failure> {
    let cancel = signals::install().context("cannot catch signals")?;
    if !args.quiet {
        eprintln!(
            "shoal: loading {}",
            args.world
                .as_deref()
                .map_or_else(|| EMBEDDED_NAME.into(), |p| p.display().to_string())
        );
    }
    let desc = match load_world(args.world.as_deref(), &args.changes(), &cancel) {
        Ok(d) => d,
        Err(LoadWorldError::Interrupted(_)) => match cancel.cause() {
            Some(cause) => return Ok(stopped_before_start(cause, "loading the world")),
            None => return Ok(ExitCode::FAILURE),
        },
        Err(LoadWorldError::Option { option, message }) => {
            return Err(Failure::Input(format!("{}: {message}", flag(option))));
        }
        Err(e) => return Err(Failure::Input(e.to_string())),
    };
    let out_dir = args.out.clone().unwrap_or_else(|| default_out(&desc.name));
    let threads = args
        .threads
        .map_or_else(shoal_sim::parallel::all_cores, usize::from);
    let ran = execute(&desc, &out_dir, threads, args.quiet, &cancel)?;
    let (summary, ending) = match ran {
        Ran::StoppedBeforeStart(cause) => {
            return Ok(stopped_before_start(cause, "building the world"));
        }
        Ran::Finished { summary, ending } => (summary, ending),
    };
    println!("{}", summary.to_text());
    if let shoal_record::run::Ending::Fault { time, message } = &ending {
        eprintln!(
            "error: the run stopped at t = {time} s: {message}. The outputs up to that step \
             are written; summary.json says `failed`."
        );
    }
    Ok(run_exit_code(&ending))
}

/// Runs `desc` into `out_dir` with the world's external agents (opened and waited for here)
/// and, unless `quiet`, the terminal's lines and progress bar: `shoal run`'s run, and each run
/// of `shoal sweep` (quiet).
pub fn execute(
    desc: &WorldDesc,
    out_dir: &Path,
    threads: usize,
    quiet: bool,
    cancel: &Arc<Cancel>,
) -> Result<Ran, Failure> {
    let mut agents = open_agents(desc, quiet, cancel)?;
    let mut watch = Terminal::new(quiet, signals::output_hold(cancel));
    let mut run = Run::new(desc, out_dir).threads(threads);
    if let Some(a) = agents.as_mut() {
        run = run.agents(a);
    }
    run.execute(&mut watch, cancel)
        .map_err(|e| Failure::Other(anyhow::Error::new(e)))
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
    let desc = load(Some(world), &Cancel::new()).map_err(|e| Failure::Input(e.to_string()))?;
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
    for w in &desc.warnings {
        println!("warning: {w}");
    }
    Ok(ExitCode::SUCCESS)
}
