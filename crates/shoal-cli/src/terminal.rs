//! What `shoal run` shows while a world runs: its lines on standard error and a progress bar
//! (indicatif), or nothing with `--quiet`; and the hold before an output file that the signal
//! tests ask for ([`crate::signals::output_hold`]).

use crate::signals::Hold;
use indicatif::{ProgressBar, ProgressStyle};
use shoal_output::words::factor;
use shoal_record::run::{Progress, Watch};
use std::path::Path;

/// A run's [`Watch`] on the terminal.
pub struct Terminal {
    quiet: bool,
    bar: ProgressBar,
    hold: Option<Box<Hold>>,
}

impl Terminal {
    /// Lines and a bar, or (`quiet`) nothing; `hold` is called before each output file.
    pub fn new(quiet: bool, hold: Option<Box<Hold>>) -> Self {
        let bar = if quiet {
            ProgressBar::hidden()
        } else {
            ProgressBar::new(0)
        };
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}% {msg}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        Self { quiet, bar, hold }
    }
}

impl Watch for Terminal {
    fn say(&mut self, line: &str) {
        if !self.quiet {
            self.bar.suspend(|| eprintln!("shoal: {line}"));
        }
    }

    fn started(&mut self, steps: u64) {
        self.bar.set_length(steps);
    }

    fn progress(&mut self, p: &Progress) {
        self.bar.set_position(p.step);
        self.bar.set_message(format!(
            "t = {:.1} s  ({}× real time)",
            p.sim_time_s,
            factor(p.sim_time_s / p.wall_s.max(1e-9))
        ));
    }

    fn stepped(&mut self) {
        self.bar.finish_and_clear();
    }

    fn before_file(&self, path: &Path) {
        if let Some(h) = &self.hold {
            h(path);
        }
    }
}
