//! `shoal run` and `shoal check`.
//!
//! A run stops early, cleanly, on SIGINT, SIGTERM or SIGHUP ([`crate::signals`]): while the
//! world is loaded or built it stops before the run starts and writes nothing; while it runs
//! it stops at the next step and writes the outputs up to that step (see
//! `shoal_sim::output`); agents are told and the shared memory is removed; the exit code is
//! 128 + the signal number.

use crate::agents::open_agents;
use crate::{Failure, signals};
use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use shoal_sim::agents::AgentsSummary;
use shoal_sim::agents::Flow;
use shoal_sim::prelude::*;
use shoal_world::cancel::{Cancel, Cause};
use shoal_world::desc::WorldDesc;
use shoal_world::load::{DEFAULT_WORLD, EMBEDDED_NAME, LoadError, load_file_until, load_str_until};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Most vehicle-steps between two writes of trajectory rows (≈ 0.1 s of work).
const CHUNK_WORK: u64 = 200_000;

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
    /// Override the world's seed.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Override the world's duration [s].
    #[arg(long)]
    pub duration: Option<f64>,
    /// Skip plots.
    #[arg(long)]
    pub no_plots: bool,
    /// Skip `replay.html`, the interactive 3D replay (also `[output] replay = false`).
    #[arg(long)]
    pub no_replay: bool,
    /// Also write `run.mcap`: the run for Foxglove (3D scene, plots) and ROS 2 tools (also
    /// `[output] mcap = true`; topics and size budget: docs/mcap.md).
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
    /// External agents: how long to wait for them to attach before starting [s].
    #[arg(long, value_name = "SECONDS")]
    pub wait_agents: Option<f64>,
}

/// Loads the world file (or the embedded default world) until `cancel` asks for a stop.
pub fn load(world: Option<&Path>, cancel: &Cancel) -> Result<WorldDesc, LoadError> {
    match world {
        Some(p) => load_file_until(p, cancel),
        None => load_str_until(DEFAULT_WORLD, Path::new(EMBEDDED_NAME), cancel),
    }
}

/// The end of a run stopped before it started: says so and gives the signal's exit code.
fn stopped_before_start(cancel: &Cancel, phase: &str) -> ExitCode {
    let Some(cause) = cancel.cause() else {
        // (Only a stop request interrupts loading and building.)
        return ExitCode::FAILURE;
    };
    eprintln!(
        "shoal: interrupted by {} while {phase}, before the run started; nothing was written",
        cause.name
    );
    signals::exit_code(cause)
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
    let cancel = signals::install().context("cannot catch signals")?;
    if !args.quiet {
        eprintln!(
            "shoal: loading {}",
            args.world
                .as_deref()
                .map_or_else(|| EMBEDDED_NAME.into(), |p| p.display().to_string())
        );
    }
    let mut desc = match load(args.world.as_deref(), &cancel) {
        Ok(d) => d,
        Err(LoadError::World(e)) => return Err(Failure::Input(e.to_string())),
        Err(LoadError::Interrupted(_)) => {
            return Ok(stopped_before_start(&cancel, "loading the world"));
        }
    };
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
    if args.mcap {
        desc.output.mcap = true;
    }
    if let Some(t) = &args.timing {
        desc.agents.lockstep = t == "lockstep";
    }
    if let Some(p) = &args.prefix {
        if !shoal_world::load::valid_service_word(p) {
            return Err(Failure::Input(format!(
                "--prefix `{p}`: use 1–64 letters, digits, `_`, `-` or `.`"
            )));
        }
        desc.agents.prefix = p.clone();
    }
    if let Some(w) = args.wait_agents {
        if !(w.is_finite() && (0.0..=86400.0).contains(&w)) {
            return Err(Failure::Input(format!(
                "--wait-agents {w}: allowed 0 … 86400 s"
            )));
        }
        desc.agents.attach_timeout = w;
    }
    let out_dir = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(slug(&desc.name)));
    let threads = args.threads.map_or_else(crate::all_cores, usize::from);
    let ran = execute(
        &desc,
        &out_dir,
        &Execute {
            threads,
            replay: !args.no_replay,
            quiet: args.quiet,
            cancel: &cancel,
        },
    )?;
    let (summary, ending) = match ran {
        Ran::StoppedBeforeStart(code) => return Ok(code),
        Ran::Finished { summary, ending } => (summary, ending),
    };
    println!("{}", summary.to_text());
    if let Ending::Fault { time, message } = &ending {
        eprintln!(
            "error: the run stopped at t = {time} s: {message}. The outputs up to that step \
             are written; summary.json says `failed`."
        );
    }
    Ok(ending.exit_code())
}

/// How a run that started ended (its outputs are written either way).
#[derive(Clone, Debug)]
pub enum Ending {
    /// Every planned step ran.
    Complete,
    /// The world's agent fallback `stop` ended it early (the outputs are complete).
    AgentsStopped,
    /// A vehicle's state became non-finite.
    Fault {
        /// Time of the last finite state \[s\].
        time: f64,
        /// Which vehicle, when, its last finite state.
        message: String,
    },
    /// A stop request (a signal) ended it at a step boundary.
    Interrupted(Cause),
}

impl Ending {
    /// The exit code of `shoal run` for this ending (docs/exit-codes.md).
    pub fn exit_code(&self) -> ExitCode {
        match self {
            Ending::Complete => ExitCode::SUCCESS,
            Ending::AgentsStopped => ExitCode::from(3),
            Ending::Fault { .. } => ExitCode::from(4),
            Ending::Interrupted(cause) => signals::exit_code(*cause),
        }
    }
}

/// What [`execute`] did.
pub enum Ran {
    /// A stop request came while the world was being built: nothing was written; the exit
    /// code of the signal.
    StoppedBeforeStart(ExitCode),
    /// The run started; its outputs are written.
    Finished {
        /// What `summary.json` says.
        summary: Box<Summary>,
        /// How it ended.
        ending: Ending,
    },
}

/// How [`execute`] runs a world.
pub struct Execute<'a> {
    /// Working threads for per-vehicle loops (results do not depend on it).
    pub threads: usize,
    /// Write `replay.html` when the world asks for it.
    pub replay: bool,
    /// No progress bar and no messages on standard error.
    pub quiet: bool,
    /// The stop request that ends the run early.
    pub cancel: &'a Arc<Cancel>,
}

/// Builds the world `desc`, runs it to its duration (or a stop, an agent fallback `stop`, a
/// non-finite state) and writes its outputs into `out_dir`: the one run path shared by
/// `shoal run` and each run of `shoal sweep`. Errors are failures to write outputs or to
/// open agent services.
pub fn execute(desc: &WorldDesc, out_dir: &Path, opts: &Execute<'_>) -> Result<Ran, Failure> {
    let Execute {
        threads,
        replay,
        quiet,
        cancel,
    } = *opts;
    let steps = desc.steps();
    if !quiet {
        for w in &desc.warnings {
            eprintln!("shoal: warning: {w}");
        }
        eprintln!(
            "shoal: building `{}` — {} vehicles",
            desc.name,
            desc.vehicles.len()
        );
    }
    let built = Sim::new_until(
        desc,
        SimOptions {
            threads,
            record: true,
        },
        cancel,
    );
    let Ok(mut sim) = built else {
        return Ok(Ran::StoppedBeforeStart(stopped_before_start(
            cancel,
            "building the world",
        )));
    };
    if replay && desc.output.replay {
        sim.enable_replay(desc);
    }
    // The summary says where the time went (a few clock reads per step).
    sim.time_phases();
    let mut out = RunOutput::create(out_dir, desc)
        .with_context(|| format!("cannot create outputs in {}", out_dir.display()))?;
    out.before_file = signals::output_hold(cancel);
    let pb = if quiet {
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
    if !quiet {
        eprintln!(
            "shoal: running `{}` — {} vehicles, {:.1} s at dt = {} s, {} thread(s) → {}",
            desc.name,
            desc.vehicles.len(),
            desc.duration,
            desc.dt,
            threads,
            out_dir.display()
        );
    }
    let mut host = open_agents(desc, quiet, cancel)?;
    let mut stopped: Option<String> = None;
    // Steps between progress updates and trajectory writes: at most 500 and at most
    // CHUNK_WORK vehicle-steps, so a stop request (seen at every step) is followed by little
    // writing — the rows recorded in the chunk so far are written before the outputs end.
    let chunk = (steps / 500)
        .clamp(1, 500)
        .min((CHUNK_WORK / desc.vehicles.len().max(1) as u64).max(1));
    let start = Instant::now();
    while sim.step_count() < steps
        && !cancel.is_requested()
        && stopped.is_none()
        && sim.fault().is_none()
    {
        let n = chunk.min(steps - sim.step_count());
        match host.as_mut() {
            // A stop request ends the chunk at a step boundary; the loop condition sees it.
            None => {
                let _ = sim.run_until(n, cancel);
            }
            Some(h) => {
                for _ in 0..n {
                    if cancel.is_requested() || sim.fault().is_some() {
                        break;
                    }
                    match h.before_step(&mut sim).context("external agents")? {
                        Flow::Continue => sim.step(),
                        Flow::Stop(why) => {
                            stopped = Some(why);
                            break;
                        }
                        Flow::Interrupted => break,
                    }
                }
            }
        }
        let writing = Instant::now();
        out.write(&sim.drain())
            .map_err(|e| Failure::Other(e.into()))?;
        out.writing_s += writing.elapsed().as_secs_f64();
        let wall = start.elapsed().as_secs_f64();
        pb.set_position(sim.step_count());
        pb.set_message(format!(
            "t = {:.1} s  ({:.1}× real time)",
            sim.time(),
            sim.time() / wall.max(1e-9)
        ));
    }
    pb.finish_and_clear();
    let wall = start.elapsed().as_secs_f64();
    if let Some(mut h) = host {
        let reports = h.finish(&mut sim, Duration::from_secs(1));
        out.agents = Some(AgentsSummary {
            prefix: desc.agents.prefix.clone(),
            timing: if desc.agents.lockstep {
                "lockstep"
            } else {
                "free"
            },
            fallback: format!("{:?}", desc.agents.fallback).to_lowercase(),
            stopped,
            agents: reports,
        });
        drop(h);
    }
    out.replay = sim.take_replay();
    // The error names the file that could not be written and why; the files before it stay.
    let summary = out
        .finish(desc, &mut sim, wall, cancel)
        .map_err(|e| Failure::Other(e.into()))?;
    let ending = if let Some(f) = sim.fault() {
        Ending::Fault {
            time: f.state.time,
            message: f.to_string(),
        }
    } else if let Some(cause) = cancel.cause() {
        Ending::Interrupted(cause)
    } else if summary.agents.as_ref().is_some_and(|a| a.stopped.is_some()) {
        Ending::AgentsStopped
    } else {
        Ending::Complete
    };
    Ok(Ran::Finished {
        summary: Box::new(summary),
        ending,
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
