//! # shoal-testkit
//!
//! The test kit of `shoal validate` (`shoal_sysid`): what the tests, examples and benches
//! simulate, hide and score, kept out of the product. Nothing here is part of the tool; the
//! crate is a dev-dependency of shoal-sysid, shoal-cli and the root `shoal` crate.
//!
//! * [`synth`], [`design`] — synthetic runs with hidden effects and the μAUV² experiments
//!   that excite every effect; [`mission`] — long closed-loop missions flown by the μAUV²'s
//!   own controllers in gusting water;
//! * [`truth_forms`], [`logger`] — effects hidden in forms that differ from the catalogue's,
//!   and logs written the way a real logger writes them;
//! * [`testset`], [`recovery`] — the misspecified-form test set built from them, and how a
//!   search's verdicts on it are scored ([`draws`]: the options of the benchmarks on
//!   independent draws); [`closed_loop`] — the long closed-loop test set;
//! * [`next_flight`] — a log that leaves "A or B" open, and the flight a suggested
//!   `next_experiment.toml` describes, flown on the hidden truth.

pub mod closed_loop;
pub mod design;
pub mod draws;
pub mod logger;
pub mod mission;
pub mod next_flight;
pub mod recovery;
pub mod synth;
pub mod testset;
pub mod truth_forms;
