//! # shoal-sim
//!
//! The simulated world of shoal: one bevy_ecs entity per vehicle ([`components`]), a fixed-step
//! schedule of chained system sets ([`systems`]) run by [`sim::Sim`], per-world parallel loops
//! ([`parallel`]) and the time of each phase of a step ([`phases`]), a trajectory recorder ([`recorder`]) and run outputs ([`output`], drawn by
//! [`shoal_output::plot`]; [`map`]: the world seen from above; [`ci_plot`]: means with
//! confidence intervals, for parameter studies), each file written
//! whole or not at all ([`shoal_output::files`]); external agents, independent of their
//! transport ([`agents`]); whole-swarm reads and commands through flat arrays ([`batch`]);
//! the frames and limits of every order from outside the world, both kinds alike ([`orders`]);
//! one colour key for link outcomes wherever they are drawn ([`link_key`]).
//! Long work (building a world, running it, drawing plots) can be
//! stopped early through a [`shoal_world::cancel::Cancel`].

pub mod agents;
pub mod analysis;
pub mod batch;
pub mod behaviour;
pub mod bench;
pub mod ci_plot;
pub mod comm;
pub mod comm_report;
pub mod components;
pub mod connectivity;
pub mod fault;
pub mod fleet;
pub mod link_key;
pub mod map;
pub mod orders;
pub mod output;
pub mod parallel;
pub mod phases;
pub mod recorder;
pub mod replay;
pub mod rng;
pub mod sim;
pub mod systems;
pub mod view;

/// The commonly used types.
pub mod prelude {
    pub use crate::components::*;
    pub use crate::fleet::{Fleet, HotVehicle};
    pub use crate::output::{RunOutput, Summary};

    pub use crate::sim::{Sim, SimOptions, VehicleSnapshot};
    pub use crate::systems::{StepSet, build_schedule};
}
