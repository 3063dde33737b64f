//! How the program ends: why it stops early ([`Failure`]) and the exit code of each way a run
//! can end ([`run_exit_code`]; docs/exit-codes.md).

use crate::signals;
use shoal_record::run::Ending;
use std::process::ExitCode;

/// Why the program stops early.
pub enum Failure {
    /// Bad user input (exit 2); the message is complete.
    Input(String),
    /// Anything else (exit 1).
    Other(anyhow::Error),
}

impl From<anyhow::Error> for Failure {
    fn from(e: anyhow::Error) -> Self {
        Failure::Other(e)
    }
}

/// The exit code of `shoal run` for a run that ended so.
pub fn run_exit_code(ending: &Ending) -> ExitCode {
    match ending {
        Ending::Complete => ExitCode::SUCCESS,
        Ending::AgentsStopped => ExitCode::from(3),
        Ending::Fault { .. } => ExitCode::from(4),
        Ending::Interrupted(cause) => signals::exit_code(*cause),
    }
}
