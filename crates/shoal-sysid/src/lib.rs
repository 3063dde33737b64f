//! # shoal-sysid
//!
//! `shoal validate`: given logs of a real vehicle, show what the simulation gets wrong, name
//! the cause, extend the model and measure the gain (`../shared/spec/validation.md`).
//!
//! * [`run`] — a measured run: time, inputs, measurements, with errors that name line and
//!   column;
//! * [`format`] — the vocabulary of a run file (separator, time unit, read options, what
//!   reading found); [`ingest`] — reading runs as loggers write them (separators, comments,
//!   time units), streaming and linear in the rows; [`segments`] — runs split at gaps in time;
//!   [`limits`] — inputs checked against the actuator limits, rounding clamped and counted;
//! * [`open_loop`] — the vehicle model driven open-loop by the measured inputs (a run's replay);
//! * [`blocks`] — time blocks of residuals: held-out tests and the block bootstrap;
//! * [`dataset`] — runs split into estimation and validation data and replayed on a model;
//!   [`evaluation`] — a model compared with them: residuals and per-channel metrics;
//! * [`lm`], [`stats`] — bounded Levenberg–Marquardt, whiteness tests and friends;
//! * [`search`] — per-effect fits, BIC and validation scoring, greedy forward selection with a
//!   significance rule;
//! * [`report`] — `report.json`, `report.md` with plots, and the extended `vehicle.toml`;
//! * [`validate`] — all of the above in one call: settings checked, runs read, searched,
//!   judged (what `shoal validate` and Python's `shoal.validate` call);
//! * [`synth`], [`design`] — synthetic runs with hidden effects and the μAUV² experiments
//!   that excite every effect.
//! * [`truth_forms`], [`logger`] — effects hidden in forms that differ from the catalogue's,
//!   and logs written the way a real logger writes them;
//! * [`testset`], [`recovery`] — the misspecified-form test set built from them, and how a
//!   search's verdicts on it are scored.
//!
//! The effects themselves live in `shoal_model::effects`, so that `shoal run` uses a fitted
//! model unchanged.

pub mod blocks;
mod data_lines;
pub mod dataset;
pub mod design;
pub mod evaluation;
pub mod format;
mod header;
pub mod ingest;
pub mod limits;
pub mod lm;
pub mod logger;
pub mod masses;
mod numbers;
pub mod open_loop;
pub mod recovery;
pub mod report;
pub mod run;
pub mod search;
pub mod segments;
pub mod stats;
pub mod synth;
pub mod testset;
pub mod truth_forms;
pub mod validate;
