//! # shoal-sim
//!
//! The simulated world of shoal: one bevy_ecs entity per vehicle ([`components`]), a fixed-step
//! schedule of chained system sets ([`systems`]) run by [`sim::Sim`], per-world parallel loops
//! ([`parallel`]) and the time of each phase of a step ([`phases`]); the optical medium
//! ([`comm`]) and the communication graph ([`connectivity`]); built-in behaviours
//! ([`behaviour`]); external agents, independent of their transport ([`agents`]), and the
//! frames and limits of every order from outside the world, both kinds alike ([`orders`]);
//! whole-swarm reads and commands through flat arrays ([`batch`]); what a run records while it
//! runs: trajectory rows ([`recorder`]) and the replay's samples ([`replay`]), read without
//! copying through [`view`]. Workloads for benchmarks are [`bench`].
//!
//! What a run leaves behind — its files, plots, replay page, MCAP — and the run driver are
//! crate `shoal-record`, one layer up: this crate writes no file.
//! Long work (building a world, running it) can be stopped early through a
//! [`shoal_world::cancel::Cancel`].

pub mod agents;
pub mod batch;
pub mod behaviour;
pub mod bench;
pub mod comm;
pub mod components;
pub mod connectivity;
pub mod fault;
pub mod fleet;
pub mod mac_laws;
pub mod orders;
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

    pub use crate::sim::{Sim, SimOptions, VehicleSnapshot};
    pub use crate::systems::{StepSet, build_schedule};
}
