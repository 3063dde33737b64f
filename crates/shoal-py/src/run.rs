//! `shoal.run`'s compiled half: what `shoal run` does, as a function — the same world loader
//! and options ([`shoal_record::run::load_world`]), the same driver ([`Run`]) and so the same
//! files (`summary.json`, `trajectories.csv`, `vehicles.csv`, plots, `replay.html`,
//! `run.mcap`) in the same folder (`out/<world name>` unless named). The GIL is released
//! while the world runs; progress lines go to stderr unless `quiet`; Ctrl-C stops the run at
//! the next chunk of steps, the outputs up to it are written, then `KeyboardInterrupt` is
//! raised. Worlds with external agents are refused: they need the `shoal run` process that
//! the agents attach to.

use crate::errors::{SimulationError, WorldError};
use crate::source::{self, Source};
use pyo3::exceptions::{PyKeyboardInterrupt, PyOSError};
use pyo3::prelude::*;
use shoal_output::words::factor;
use shoal_record::run::{
    Changes, Ending, LoadWorldError, Progress, Ran, Run, Watch, default_out, load_world,
};
use shoal_world::cancel::{Cancel, Cause};
use std::path::PathBuf;

/// The cause of a stop asked for by Python (Ctrl-C's `KeyboardInterrupt`, or any exception a
/// signal handler raised).
const PYTHON_SIGNAL: Cause = Cause {
    name: "SIGINT",
    code: 2,
};

/// Progress as lines on stderr (about every tenth of the run), and Python's signals checked
/// after each chunk of steps.
struct Lines<'c> {
    quiet: bool,
    cancel: &'c Cancel,
    next_tenth: u64,
    steps: u64,
}

impl Watch for Lines<'_> {
    fn say(&mut self, line: &str) {
        if !self.quiet {
            eprintln!("shoal: {line}");
        }
    }

    fn started(&mut self, steps: u64) {
        self.steps = steps.max(1);
    }

    fn progress(&mut self, p: &Progress) {
        if Python::attach(|py| py.check_signals()).is_err() {
            self.cancel.request(PYTHON_SIGNAL);
        }
        if self.quiet || p.step * 10 < self.next_tenth * self.steps {
            return;
        }
        self.next_tenth = p.step * 10 / self.steps + 1;
        eprintln!(
            "shoal: {:>3} %  t = {:.1} s  ({}× real time)",
            p.step * 100 / self.steps,
            p.sim_time_s,
            factor(p.sim_time_s / p.wall_s.max(1e-9))
        );
    }
}

/// Runs a world as `shoal run` does; returns `(ending, out folder)`
/// with the ending `complete` or `agents-stopped`; raises `SimulationError` when a state
/// became non-finite and `KeyboardInterrupt` on Ctrl-C, both after the outputs are written.
#[pyfunction]
#[pyo3(signature = (world=None, out=None, *, seed=None, duration=None, threads=None, plots=None, replay=None, mcap=None, quiet=false))]
#[expect(clippy::too_many_arguments, reason = "a Python function's keywords")]
pub fn run(
    py: Python<'_>,
    world: Option<&Bound<'_, PyAny>>,
    out: Option<PathBuf>,
    seed: Option<u64>,
    duration: Option<f64>,
    threads: Option<usize>,
    plots: Option<bool>,
    replay: Option<bool>,
    mcap: Option<bool>,
    quiet: bool,
) -> PyResult<(&'static str, PathBuf)> {
    let source = Source::of(world)?;
    let threads = source::threads(threads)?;
    let changes = Changes {
        seed,
        duration,
        plots,
        replay,
        mcap,
        ..Changes::default()
    };
    let cancel = Cancel::new();
    let desc = py
        .detach(|| load_world(source.as_world(), &changes, &cancel))
        .map_err(|e| match e {
            LoadWorldError::Option { option, message } => {
                WorldError::new_err(format!("{}: {message}", option.name()))
            }
            e => WorldError::new_err(e.to_string()),
        })?;
    if !desc.agents.names.is_empty() {
        return Err(WorldError::new_err(format!(
            "{}: its vehicles are driven by external agents ({}), which attach to a `shoal run` \
             process: run it with `shoal run`, or drive the vehicles from Python with \
             shoal.World",
            desc.name,
            desc.agents.names.join(", ")
        )));
    }
    let out = out.unwrap_or_else(|| default_out(&desc.name));
    // Lines even when quiet: they also check Python's signals (Ctrl-C).
    let mut lines = Lines {
        quiet,
        cancel: &cancel,
        next_tenth: 0,
        steps: 1,
    };
    let ran = py.detach(|| {
        Run::new(&desc, &out)
            .threads(threads)
            .execute(&mut lines, &cancel)
    });
    let ran = ran.map_err(|e| PyOSError::new_err(e.to_string()))?;
    let ending = match ran {
        Ran::StoppedBeforeStart(_) => {
            return Err(PyKeyboardInterrupt::new_err(
                "interrupted while building the world, before the run started; nothing was written",
            ));
        }
        Ran::Finished { ending, .. } => ending,
    };
    match ending {
        Ending::Complete => Ok(("complete", out)),
        Ending::AgentsStopped => Ok(("agents-stopped", out)),
        Ending::Fault { time, message } => Err(SimulationError::new_err(format!(
            "the run stopped at t = {time} s: {message}; the outputs up to that step are in {}",
            out.display()
        ))),
        Ending::Interrupted(_) => Err(PyKeyboardInterrupt::new_err(format!(
            "interrupted; the outputs up to the last step are in {}",
            out.display()
        ))),
    }
}
