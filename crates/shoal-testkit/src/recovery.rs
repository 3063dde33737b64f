//! Scoring the search against a known truth: hand a log (CSV text only) to the search with the
//! μAUV² preset as baseline, compare the effects it chooses with the families hidden in the
//! log, and count. Used by the misspecified-form test and the recovery benchmark
//! (`examples/recovery.rs`).
//!
//! A verdict is **exact** when the set of chosen effect names equals the expected set: none
//! missing, none extra. Its **wrong count** is extras + missing (a log the tool cannot read
//! counts every expected family as missing).

use crate::testset::{Case, DENSITY};
use shoal_model::presets;
use shoal_model::rigid_body::Environment;
use shoal_sysid::evaluate::anchoring::Horizon;
use shoal_sysid::evaluate::dataset::{DataOptions, Dataset};
use shoal_sysid::evaluate::open_loop::ReplayOptions;
use shoal_sysid::log::run::MeasuredRun;
use shoal_sysid::search::{Outcome, SearchOptions, search};
use std::collections::BTreeSet;
use std::path::Path;

/// Replay step of the search \[s\] (the tests' setting).
pub const REPLAY_DT: f64 = 0.02;

/// The search on one log as the tests run it: parsed from `csv` (named `name` in messages),
/// the μAUV² preset as baseline, the default 60/40 estimation/validation split, a
/// [`REPLAY_DT`] replay, `threads` worker threads. Returns the chosen effects' names, sorted,
/// or why the log could not be searched.
pub fn search_log(csv: &str, name: &str, threads: usize) -> Result<Vec<String>, String> {
    search_log_with(csv, name, threads, Horizon::Open)
}

/// [`search_log`] with the runs replayed as `horizon` asks (re-anchored, or open loop).
pub fn search_log_with(
    csv: &str,
    name: &str,
    threads: usize,
    horizon: Horizon,
) -> Result<Vec<String>, String> {
    let opts = SearchOptions {
        threads,
        ..Default::default()
    };
    let out = search_log_outcome(csv, name, &opts, horizon)?;
    let mut names = out.chosen.names();
    names.sort();
    names.dedup();
    Ok(names)
}

/// The whole outcome of the search on one log, as [`search_log_with`] runs it but with the
/// search settings `opts` (the effects it considers, its threads, its thresholds).
pub fn search_log_outcome(
    csv: &str,
    name: &str,
    opts: &SearchOptions,
    horizon: Horizon,
) -> Result<Outcome, String> {
    let run = MeasuredRun::parse(csv, Path::new(&format!("{name}.csv")))
        .map_err(|e| format!("parse: {e}"))?;
    search_run_outcome(run, opts, horizon)
}

/// [`search_log_outcome`] on a run already read.
pub fn search_run_outcome(
    run: MeasuredRun,
    opts: &SearchOptions,
    horizon: Horizon,
) -> Result<Outcome, String> {
    let base = presets::uauv2();
    let env = Environment {
        density: DENSITY,
        ..Environment::default()
    };
    let mut ds = Dataset::new(
        &base,
        env,
        vec![run],
        vec![],
        &DataOptions {
            replay: ReplayOptions {
                dt: REPLAY_DT,
                ..Default::default()
            },
            ..Default::default()
        },
    )
    .map_err(|e| format!("dataset: {e}"))?;
    ds.anchor(horizon, &opts.baseline_model(&base, ds.env.density));
    Ok(search(&ds, &base, opts, &|_| {}))
}

/// What the search said about one log, next to what it should have said.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Verdict {
    /// The hidden families, sorted.
    pub expected: Vec<String>,
    /// The chosen effects, sorted (empty on error).
    pub found: Vec<String>,
    /// Why the log could not be searched, if it could not.
    pub error: Option<String>,
}

impl Verdict {
    /// Compares `found` (any order) with `expected` (any order).
    pub fn new(expected: &[String], found: Result<Vec<String>, String>) -> Self {
        let sorted = |v: &[String]| -> Vec<String> {
            let s: BTreeSet<&String> = v.iter().collect();
            s.into_iter().cloned().collect()
        };
        let (found, error) = match found {
            Ok(f) => (sorted(&f), None),
            Err(e) => (Vec::new(), Some(e)),
        };
        Self {
            expected: sorted(expected),
            found,
            error,
        }
    }

    /// The chosen set equals the expected set.
    pub fn exact(&self) -> bool {
        self.error.is_none() && self.found == self.expected
    }

    /// Chosen but not hidden.
    pub fn extras(&self) -> Vec<&str> {
        self.found
            .iter()
            .filter(|f| !self.expected.contains(f))
            .map(String::as_str)
            .collect()
    }

    /// Hidden but not chosen.
    pub fn missing(&self) -> Vec<&str> {
        self.expected
            .iter()
            .filter(|e| !self.found.contains(e))
            .map(String::as_str)
            .collect()
    }

    /// Extras plus missing.
    pub fn wrong(&self) -> usize {
        self.extras().len() + self.missing().len()
    }

    /// The chosen set as text: `{a, b}`, `{}` for none, `error: …` on error.
    pub fn found_text(&self) -> String {
        match &self.error {
            Some(e) => format!("error: {e}"),
            None => format!("{{{}}}", self.found.join(", ")),
        }
    }
}

/// The search's verdict on `case` with `threads` worker threads.
pub fn judge(case: &Case, threads: usize) -> Verdict {
    Verdict::new(&case.expected, search_log(&case.csv, &case.name, threads))
}

/// Verdicts counted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Tally {
    /// Verdicts.
    pub runs: usize,
    /// Exact verdicts.
    pub exact: usize,
    /// Wrong effects over all verdicts (extras + missing).
    pub wrong: usize,
}

impl Tally {
    /// Counts `v`.
    pub fn add(&mut self, v: &Verdict) {
        self.runs += 1;
        self.exact += usize::from(v.exact());
        self.wrong += v.wrong();
    }

    /// Fraction of exact verdicts (0 for none) \[-\].
    pub fn rate(&self) -> f64 {
        if self.runs == 0 {
            0.0
        } else {
            self.exact as f64 / self.runs as f64
        }
    }

    /// Mean wrong effects per verdict (0 for none) \[-\].
    pub fn mean_wrong(&self) -> f64 {
        if self.runs == 0 {
            0.0
        } else {
            self.wrong as f64 / self.runs as f64
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(v: &[&str]) -> Vec<String> {
        v.iter().map(|x| x.to_string()).collect()
    }

    #[test]
    fn verdicts_count_extras_and_missing() {
        let v = Verdict::new(
            &s(&["thruster_lag", "buoyancy_offset"]),
            Ok(s(&["buoyancy_offset", "thruster_lag"])),
        );
        assert!(v.exact());
        assert_eq!(v.wrong(), 0);
        let v = Verdict::new(
            &s(&["thruster_lag"]),
            Ok(s(&["damping_error", "thrust_gain"])),
        );
        assert!(!v.exact());
        assert_eq!(v.extras(), vec!["damping_error", "thrust_gain"]);
        assert_eq!(v.missing(), vec!["thruster_lag"]);
        assert_eq!(v.wrong(), 3);
        let v = Verdict::new(&s(&["thruster_lag"]), Err("parse: bad".into()));
        assert!(!v.exact());
        assert_eq!(v.wrong(), 1);
        assert_eq!(v.found_text(), "error: parse: bad");
        let null = Verdict::new(&[], Ok(vec![]));
        assert!(null.exact());
        assert_eq!(null.found_text(), "{}");
        let mut t = Tally::default();
        t.add(&v);
        t.add(&null);
        assert_eq!((t.runs, t.exact, t.wrong), (2, 1, 1));
        assert_eq!(t.rate(), 0.5);
        assert_eq!(t.mean_wrong(), 0.5);
    }
}
