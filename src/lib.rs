//! # shoal
//!
//! A swarm simulator for minuscule autonomous underwater vehicles (the DFKI μAUV²). This facade
//! re-exports the workspace crates; the `shoal` binary lives in `crates/shoal-cli`.
//!
//! - [`model`]: pure vehicle physics, sensors, controllers, presets (no IO, no ECS);
//! - [`world`]: world files, validation, pool and obstacle geometry;
//! - [`output`]: output files written whole or not at all, and plots (PNG, SVG);
//! - [`sim`]: the bevy_ecs world, its step schedule, the optical medium, agents' rules;
//! - [`record`]: what a run leaves behind (outputs, plots, replay, MCAP) and the run driver;
//! - [`sysid`]: validation against measured runs: replay, effect search, reports.

pub use shoal_model as model;
pub use shoal_output as output;
pub use shoal_record as record;
pub use shoal_sim as sim;
pub use shoal_sysid as sysid;
pub use shoal_world as world;
