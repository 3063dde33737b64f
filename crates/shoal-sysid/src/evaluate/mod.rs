//! The open-loop evaluation of a model on measured runs, and its metrics: the second stage of
//! `shoal validate`, what the search scores every candidate model with.
//!
//! * [`open_loop`] — the vehicle model driven open-loop by a run's measured inputs (its
//!   replay), recorded through the sensor models; [`masses`] — the mass properties of each
//!   ballast volume the replays meet;
//! * [`dataset`] — runs split into estimation and validation data and replayed on a model;
//!   [`controlled`] — the runs replayed closed loop with their controller, the logged
//!   commands compared too;
//!   [`evaluation`] — a model compared with them: residuals and per-channel metrics;
//!   [`current`] — the water's wandering current as the noise model of a re-anchored replay;
//! * [`blocks`] — time blocks of residuals: held-out tests and the block bootstrap;
//! * [`lm`], [`stats`] — bounded Levenberg–Marquardt, whiteness tests and friends.
//!
//! It reads runs made by [`crate::log`] and knows nothing of the search or the report.

pub mod anchoring;
pub mod blocks;
pub mod controlled;
pub mod current;
pub mod dataset;
pub mod evaluation;
pub mod lm;
pub mod masses;
pub mod open_loop;
pub mod stats;
