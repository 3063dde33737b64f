//! The run driver: what `shoal run`, each run of `shoal sweep` and Python's `shoal.run` do, as
//! one library call.
//!
//! A run's own options ([`Changes`]: seed, duration, which outputs, agents' timing) become
//! dotted-path overrides of the world file ([`load_world`], checked by the world loader like
//! any world file, so an option takes exactly the values the file may hold); then a [`Run`]
//! builds the world, runs it to its duration — or to a stop request, an agents' fallback
//! `stop`, a state that became non-finite — and writes its outputs
//! ([`crate::output::RunOutput`]). The caller sees its progress through a [`Watch`] and may
//! hand it the run's external agents ([`shoal_sim::agents::AgentHost`]); what it returns
//! ([`Ran`]) says how it ended ([`Ending`]).
//!
//! One file per concern: `changes` (options → overrides → a world), `watch` (progress),
//! `ending` (how a run ended), `driver` (the run itself), `out_dir` (the default folder).

mod changes;
mod driver;
mod ending;
mod out_dir;
mod watch;

pub use changes::{Changes, LoadWorldError, RunOption, WorldSource, load_world};
pub use driver::{Run, RunError};
pub use ending::{Ending, Ran};
pub use out_dir::default_out;
pub use watch::{Progress, Quiet, Watch};
