//! # shoal-record
//!
//! What a shoal run leaves behind, and the run that makes it: the layer above the simulation
//! core (`shoal-sim`, which writes no file).
//!
//! - [`run`]: the run driver — a world built, run to its end (or a stop request, an agents'
//!   `stop`, a non-finite state) and its outputs written, as one library call ([`run::Run`]) that
//!   `shoal run`, each run of `shoal sweep` and Python's `shoal.run` share;
//! - [`output`]: the run's folder — `trajectories.csv` streamed, `summary.json`,
//!   `vehicles.csv`, the plots — written whole or not at all ([`shoal_output::files`]);
//! - [`mcap`]: `run.mcap` for Foxglove and ROS 2 tools;
//! - [`replay`]: `replay.html`, the 3D replay page, and its GIF;
//! - [`comm_report`]: the communication tables, plots and summary of a run with traffic;
//! - [`link_key`]: the one colour key of link outcomes; [`map`]: a world seen from above;
//!   [`ci_plot`]: means with confidence intervals, the figure of a parameter study;
//! - [`analysis`]: step-response metrics of recorded trajectories.

pub mod analysis;
pub mod ci_plot;
pub mod comm_report;
pub mod link_key;
pub mod map;
pub mod mcap;
pub mod output;
pub mod replay;
pub mod run;
