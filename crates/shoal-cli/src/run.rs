//! `shoal run` and `shoal check`.

use crate::Failure;
use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use shoal_bridge::host::{Flow, Host};
use shoal_sim::agents::AgentsSummary;
use shoal_sim::prelude::*;
use shoal_world::desc::WorldDesc;
use shoal_world::load::{default_world, load_file};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

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
    let mut host = open_agents(&desc, args.quiet, &interrupted)?;
    let mut stopped: Option<String> = None;
    let chunk = (steps / 500).clamp(1, 500);
    let start = Instant::now();
    while sim.step_count() < steps
        && !interrupted.load(Ordering::SeqCst)
        && stopped.is_none()
        && sim.fault().is_none()
    {
        let n = chunk.min(steps - sim.step_count());
        match host.as_mut() {
            None => sim.run(n),
            Some(h) => {
                for _ in 0..n {
                    if sim.fault().is_some() {
                        break;
                    }
                    match h.before_step(&mut sim).context("external agents")? {
                        Flow::Continue => sim.step(),
                        Flow::Stop(why) => {
                            stopped = Some(why);
                            break;
                        }
                    }
                }
            }
        }
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
    let summary = out
        .finish(&desc, &sim, wall, was_interrupted)
        .context("cannot write the run outputs")?;
    println!("{}", summary.to_text());
    if let Some(f) = sim.fault() {
        eprintln!(
            "error: the run stopped at t = {} s: {f}. The outputs up to that step are written; \
             summary.json says `failed`.",
            f.state.time
        );
        return Ok(ExitCode::from(4));
    }
    Ok(if was_interrupted {
        ExitCode::from(130)
    } else if summary.agents.as_ref().is_some_and(|a| a.stopped.is_some()) {
        // The world's agent fallback `stop` ended the run early (outputs are complete).
        ExitCode::from(3)
    } else {
        ExitCode::SUCCESS
    })
}

/// Opens the world's agent services (when a vehicle group names an agent) and waits for the
/// agents to attach, printing where they attach.
fn open_agents(
    desc: &WorldDesc,
    quiet: bool,
    interrupted: &AtomicBool,
) -> Result<Option<Host>, Failure> {
    if desc.agents.names.is_empty() {
        return Ok(None);
    }
    let counts: Vec<usize> = desc
        .agents
        .names
        .iter()
        .map(|n| {
            desc.vehicles
                .iter()
                .filter(|v| v.agent.as_deref() == Some(n))
                .count()
        })
        .collect();
    let mut host = Host::open(&desc.agents, &counts).map_err(|e| Failure::Input(e.to_string()))?;
    if !quiet {
        eprintln!(
            "shoal: agents ({}) attach with prefix `{}`: {}",
            if desc.agents.lockstep {
                "lock-step"
            } else {
                "free-running"
            },
            desc.agents.prefix,
            desc.agents
                .names
                .iter()
                .zip(&counts)
                .map(|(n, c)| format!("`{n}` ({c} vehicles)"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let wait = Duration::from_secs_f64(desc.agents.attach_timeout);
    let mut shown = false;
    let missing = host.wait_for_agents(wait, &mut |missing| {
        if !quiet && !shown {
            eprintln!(
                "shoal: waiting up to {:.0} s for {} (Ctrl-C to stop)",
                wait.as_secs_f64(),
                missing.join(", ")
            );
            shown = true;
        }
        !interrupted.load(Ordering::SeqCst)
    });
    if !missing.is_empty() && !quiet {
        eprintln!(
            "shoal: starting without {}: their vehicles hold depth and heading until they attach",
            missing.join(", ")
        );
    }
    Ok(Some(host))
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
