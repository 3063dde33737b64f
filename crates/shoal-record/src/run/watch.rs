//! What the caller of a [`super::Run`] sees of it while it runs: lines for people and the
//! progress after each chunk of steps. The binary draws a progress bar; Python prints lines or
//! nothing; a sweep's run is [`Quiet`].

use std::path::Path;

/// The progress of a running world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress {
    /// Steps done.
    pub step: u64,
    /// Steps planned.
    pub steps: u64,
    /// Simulated time \[s\].
    pub sim_time_s: f64,
    /// Wall time since the run started \[s\].
    pub wall_s: f64,
}

/// Receives what a run says while it runs. Every method has an empty default.
pub trait Watch {
    /// A line for people: what is being built, where the outputs go, a warning of the world.
    fn say(&mut self, _line: &str) {}
    /// The run has started: `steps` planned.
    fn started(&mut self, _steps: u64) {}
    /// After each chunk of steps (at most 500 per run, about 0.1 s of work each).
    fn progress(&mut self, _p: &Progress) {}
    /// The world has stopped stepping; the outputs are written next.
    fn stepped(&mut self) {}
    /// Just before each output file is begun (its final name).
    fn before_file(&self, _path: &Path) {}
}

/// A [`Watch`] that says nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Quiet;

impl Watch for Quiet {}
