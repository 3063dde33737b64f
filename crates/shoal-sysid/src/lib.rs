//! # shoal-sysid
//!
//! `shoal validate`: given logs of a real vehicle, show what the simulation gets wrong, name
//! the cause, extend the model and measure the gain (`../shared/spec/validation.md`).
//!
//! The pipeline, one folder per stage:
//!
//! 1. [`log`] — reading a log: a measured run ([`log::run`]), the file's vocabulary
//!    ([`log::format`]), the streaming reader ([`log::ingest`]), runs split at gaps in time
//!    ([`log::segments`]) and inputs checked against the actuator limits ([`log::limits`]);
//! 2. [`evaluate`] — a model evaluated open-loop on the runs: the simulation
//!    ([`evaluate::open_loop`]), estimation and validation data ([`evaluate::dataset`]), the
//!    comparison and its metrics ([`evaluate::evaluation`]), time blocks and the bootstrap
//!    ([`evaluate::blocks`]), and the tools they use ([`evaluate::lm`], [`evaluate::stats`],
//!    [`evaluate::masses`]);
//! 3. [`search`] — per-effect fits, BIC and validation scoring, greedy forward selection with a
//!    significance rule, identifiability and stability, the verdict;
//! 4. [`experiment`] — the next experiment: the manoeuvre that best separates the models a
//!    log leaves in question ("A or B", an effect only possible), as a world file;
//! 5. [`report`] — `report.json`, `report.md` with plots, the extended `vehicle.toml` and
//!    `next_experiment.toml`.
//!
//! Each stage uses only the stages before it.
//!
//! [`validate`] is the one entry point, all of the above in one call: settings checked, runs
//! read, searched, judged (what `shoal validate` and Python's `shoal.validate` call).
//!
//! Synthetic runs, the designed μAUV² experiments, effects hidden in forms that differ from
//! the catalogue's, logs written as a real logger writes them, the misspecified-form test set
//! and the scoring of a search's verdicts on it are the test kit, crate `shoal-testkit`
//! (`crates/shoal-testkit`): only tests, examples and benches use them.
//!
//! The effects themselves live in `shoal_model::effects`, so that `shoal run` uses a fitted
//! model unchanged.

pub mod evaluate;
pub mod experiment;
pub mod log;
pub mod report;
pub mod search;
pub mod validate;
