//! [`Run`]: a world built, run and recorded — the one run path of `shoal run`, `shoal sweep`'s
//! runs and Python's `shoal.run`.

use super::ending::{Ending, Ran};
use super::watch::{Progress, Watch};
use crate::output::{OutputError, RunOutput, Summary};
use shoal_output::words::count;
use shoal_sim::agents::{AgentHost, AgentsSummary, Flow};
use shoal_sim::sim::{Sim, SimOptions};
use shoal_world::cancel::Cancel;
use shoal_world::desc::WorldDesc;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Most vehicle-steps between two writes of trajectory rows (≈ 0.1 s of work).
const CHUNK_WORK: u64 = 200_000;

/// How long agents are given to see the end of a run.
const AGENTS_GRACE: Duration = Duration::from_secs(1);

/// Why a run could not go on: its outputs could not be written, or the agents' transport
/// failed. (A vehicle's non-finite state or a stop request is an [`Ending`], not an error.)
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// An output file could not be written (the message names it and the reason); the files
    /// before it stay.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The agents' transport failed.
    #[error("external agents: {0}")]
    Agents(Box<dyn std::error::Error + Send + Sync>),
}

/// One run of a world into an output folder.
///
/// ```no_run
/// use shoal_record::run::{Changes, Quiet, Ran, Run, load_world};
/// use shoal_world::cancel::Cancel;
/// let cancel = Cancel::new();
/// let changes = Changes { duration: Some(5.0), ..Changes::default() };
/// let desc = load_world(None, &changes, &cancel)?;
/// if let Ran::Finished { summary, .. } = Run::new(&desc, "out/default").execute(&mut Quiet, &cancel)? {
///     println!("{}", summary.to_text());
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Run<'a> {
    desc: &'a WorldDesc,
    out: PathBuf,
    threads: usize,
    agents: Option<&'a mut dyn AgentHost>,
}

impl<'a> Run<'a> {
    /// A run of `desc` writing into the folder `out` (made if missing), on one thread, without
    /// external agents.
    pub fn new(desc: &'a WorldDesc, out: impl Into<PathBuf>) -> Self {
        Self {
            desc,
            out: out.into(),
            threads: 1,
            agents: None,
        }
    }

    /// Working threads for the per-vehicle loops (the results are the same for any number).
    pub fn threads(mut self, threads: usize) -> Self {
        self.threads = threads.max(1);
        self
    }

    /// The run's external agents, already open (the world names them; see
    /// [`AgentHost`]).
    pub fn agents(mut self, host: &'a mut dyn AgentHost) -> Self {
        self.agents = Some(host);
        self
    }

    /// The output folder.
    pub fn out(&self) -> &Path {
        &self.out
    }

    /// Builds the world, runs it to its duration (or a stop request through `cancel`, an
    /// agents' fallback `stop`, a non-finite state) and writes its outputs, telling `watch`
    /// how it goes. A stop request while the world is built ends it before anything is
    /// written ([`Ran::StoppedBeforeStart`]).
    pub fn execute(self, watch: &mut dyn Watch, cancel: &Cancel) -> Result<Ran, RunError> {
        let Run {
            desc,
            out,
            threads,
            mut agents,
        } = self;
        for w in &desc.warnings {
            watch.say(&format!("warning: {w}"));
        }
        watch.say(&format!(
            "building `{}` — {}",
            desc.name,
            count(desc.vehicles.len(), "vehicle")
        ));
        let built = Sim::new_until(
            desc,
            SimOptions {
                threads,
                record: true,
            },
            cancel,
        );
        let Ok(mut sim) = built else {
            return Ok(stopped_before_start(cancel));
        };
        if desc.output.replay {
            sim.enable_replay(desc);
        }
        // The summary says where the time went (a few clock reads per step).
        sim.time_phases();
        let mut output = RunOutput::create(&out, desc)?;
        watch.say(&format!(
            "running `{}` — {}, {:.1} s at dt = {} s, {} → {}",
            desc.name,
            count(desc.vehicles.len(), "vehicle"),
            desc.duration,
            desc.dt,
            count(threads, "thread"),
            out.display()
        ));
        if let Some(h) = agents.as_deref_mut() {
            h.start().map_err(RunError::Agents)?;
        }
        let steps = desc.steps();
        watch.started(steps);
        let start = Instant::now();
        let stopped = step_to_end(&mut sim, &mut output, &mut agents, watch, cancel, start)?;
        watch.stepped();
        let wall = start.elapsed().as_secs_f64();
        if let Some(h) = agents {
            output.agents = Some(AgentsSummary {
                prefix: desc.agents.prefix.clone(),
                timing: if desc.agents.lockstep {
                    "lockstep"
                } else {
                    "free"
                },
                fallback: format!("{:?}", desc.agents.fallback).to_lowercase(),
                stopped: stopped.clone(),
                agents: h.finish(&mut sim, AGENTS_GRACE),
            });
        }
        output.replay = sim.take_replay();
        let w: &dyn Watch = watch;
        let begin = |p: &Path| w.before_file(p);
        output.before_file = Some(&begin);
        // The error names the file that could not be written and why; the files before it stay.
        let summary = output.finish(&mut sim, wall, cancel)?;
        let ending = ending(&sim, cancel, &summary);
        Ok(Ran::Finished {
            summary: Box::new(summary),
            ending,
        })
    }
}

/// Steps the world to its end or an early stop, writing the recorded rows chunk by chunk;
/// the reason when the agents' fallback `stop` ended it.
fn step_to_end(
    sim: &mut Sim,
    output: &mut RunOutput<'_>,
    agents: &mut Option<&mut dyn AgentHost>,
    watch: &mut dyn Watch,
    cancel: &Cancel,
    start: Instant,
) -> Result<Option<String>, RunError> {
    let desc_steps = output.steps();
    let vehicles = output.vehicles().max(1) as u64;
    // Steps between progress updates and trajectory writes: at most 500 updates and at most
    // CHUNK_WORK vehicle-steps, so a stop request (seen at every step) is followed by little
    // writing — the rows recorded in the chunk so far are written before the outputs end.
    let chunk = (desc_steps / 500)
        .clamp(1, 500)
        .min((CHUNK_WORK / vehicles).max(1));
    let mut stopped = None;
    while sim.step_count() < desc_steps
        && !cancel.is_requested()
        && stopped.is_none()
        && sim.fault().is_none()
    {
        let n = chunk.min(desc_steps - sim.step_count());
        match agents.as_deref_mut() {
            // A stop request ends the chunk at a step boundary; the loop condition sees it.
            None => {
                let _ = sim.run_until(n, cancel);
            }
            Some(h) => {
                for _ in 0..n {
                    if cancel.is_requested() || sim.fault().is_some() {
                        break;
                    }
                    match h.before_step(sim).map_err(RunError::Agents)? {
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
        output.write(&sim.drain())?;
        output.writing_s += writing.elapsed().as_secs_f64();
        watch.progress(&Progress {
            step: sim.step_count(),
            steps: desc_steps,
            sim_time_s: sim.time(),
            wall_s: start.elapsed().as_secs_f64(),
        });
    }
    Ok(stopped)
}

/// The ending of a run stopped before it started.
fn stopped_before_start(cancel: &Cancel) -> Ran {
    // Only a stop request interrupts building a world, and it has a cause.
    Ran::StoppedBeforeStart(cancel.cause().unwrap_or(shoal_world::cancel::Cause {
        name: "a stop request",
        code: 0,
    }))
}

/// How a run that started ended.
fn ending(sim: &Sim, cancel: &Cancel, summary: &Summary) -> Ending {
    if let Some(f) = sim.fault() {
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
    }
}
