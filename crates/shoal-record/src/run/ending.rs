//! How a run ended ([`Ending`]) and what [`super::Run::execute`] gives back ([`Ran`]).

use crate::output::Summary;
use shoal_world::cancel::Cause;

/// How a run that started ended (its outputs are written either way).
#[derive(Clone, Debug, PartialEq)]
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

/// What a run did.
#[derive(Debug)]
pub enum Ran {
    /// A stop request came while the world was being built: nothing was written; the cause.
    StoppedBeforeStart(Cause),
    /// The run started; its outputs are written.
    Finished {
        /// What `summary.json` says.
        summary: Box<Summary>,
        /// How it ended.
        ending: Ending,
    },
}
