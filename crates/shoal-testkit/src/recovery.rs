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
    let ds = dataset_of(vec![run], opts, horizon)?;
    Ok(search(&ds, &base, opts, &|_| {}))
}

/// The runs as the tests' searches see them: the μAUV² preset in the test set's water, each
/// run split 60/40, a [`REPLAY_DT`] replay, anchored as `horizon` asks.
pub fn dataset_of(
    runs: Vec<MeasuredRun>,
    opts: &SearchOptions,
    horizon: Horizon,
) -> Result<Dataset, String> {
    let base = presets::uauv2();
    let env = Environment {
        density: DENSITY,
        ..Environment::default()
    };
    let mut ds = Dataset::new(
        &base,
        env,
        runs,
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
    Ok(ds)
}

/// What the search said about one log, next to what it should have said.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Verdict {
    /// The hidden families, sorted.
    pub expected: Vec<String>,
    /// The chosen effects, sorted (empty on error).
    pub found: Vec<String>,
    /// The pairs the verdict reports as "A or B" (neither named), each sorted.
    pub pairs: Vec<[String; 2]>,
    /// Why the log could not be searched, if it could not.
    pub error: Option<String>,
    /// P(family) over the search's resamples as text (`family 75 %, …`, most included first;
    /// empty where nothing was resampled).
    pub inclusion: String,
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
            pairs: Vec::new(),
            error,
            inclusion: String::new(),
        }
    }

    /// The verdict with its "A or B" pairs (each in any order).
    pub fn with_pairs(mut self, pairs: &[[String; 2]]) -> Self {
        self.pairs = pairs
            .iter()
            .map(|p| {
                let mut p = p.clone();
                p.sort();
                p
            })
            .collect();
        self
    }

    /// The chosen set equals the expected set.
    pub fn exact(&self) -> bool {
        self.error.is_none() && self.found == self.expected
    }

    /// Exact, or exact but for hidden families the verdict reports as "A or B" with the other
    /// family of the pair: nothing chosen that is not hidden, every hidden family chosen or in
    /// a pair, and every pair holding a hidden family.
    pub fn exact_or_either(&self) -> bool {
        self.error.is_none()
            && self.extras().is_empty()
            && self.missing_outright().is_empty()
            && self.wrong_pairs() == 0
    }

    /// Hidden families neither chosen nor in an "A or B" pair.
    fn missing_outright(&self) -> Vec<&str> {
        self.missing()
            .into_iter()
            .filter(|m| !self.pairs.iter().any(|p| p.iter().any(|f| f == m)))
            .collect()
    }

    /// "A or B" pairs without a hidden family.
    fn wrong_pairs(&self) -> usize {
        self.pairs
            .iter()
            .filter(|p| !p.iter().any(|f| self.expected.contains(f)))
            .count()
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

    /// Extras, plus hidden families neither chosen nor in an "A or B" pair, plus pairs
    /// without a hidden family.
    pub fn wrong(&self) -> usize {
        self.extras().len() + self.missing_outright().len() + self.wrong_pairs()
    }

    /// The chosen set as text: `{a, b}`, `{}` for none, then each "A or B" pair, `error: …`
    /// on error.
    pub fn found_text(&self) -> String {
        match &self.error {
            Some(e) => format!("error: {e}"),
            None => {
                let pairs: String = self
                    .pairs
                    .iter()
                    .map(|p| format!(" + ({} or {})", p[0], p[1]))
                    .collect();
                format!("{{{}}}{pairs}", self.found.join(", "))
            }
        }
    }
}

/// The search's verdict on `case` with `threads` worker threads, its "A or B" pairs with it.
pub fn judge(case: &Case, threads: usize) -> Verdict {
    judge_log(
        &case.csv,
        &case.name,
        &case.expected,
        threads,
        Horizon::Open,
    )
}

/// The search's verdict on the log `csv` (named `name`) that hides `expected`, with `threads`
/// worker threads and the replay `horizon` asks for, its "A or B" pairs with it.
pub fn judge_log(
    csv: &str,
    name: &str,
    expected: &[String],
    threads: usize,
    horizon: Horizon,
) -> Verdict {
    let opts = SearchOptions {
        threads,
        ..Default::default()
    };
    match search_log_outcome(csv, name, &opts, horizon) {
        Ok(out) => {
            let pairs: Vec<[String; 2]> = out
                .verdict
                .ambiguous
                .iter()
                .map(|a| a.effects.clone())
                .collect();
            let mut v = Verdict::new(expected, Ok(out.chosen.names())).with_pairs(&pairs);
            v.inclusion = out
                .verdict
                .inclusion_ranked()
                .iter()
                .map(|(f, q)| format!("{f} {:.0} %", 100.0 * q))
                .collect::<Vec<_>>()
                .join(", ");
            v
        }
        Err(e) => Verdict::new(expected, Err(e)),
    }
}

/// Verdicts counted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Tally {
    /// Verdicts.
    pub runs: usize,
    /// Exact verdicts.
    pub exact: usize,
    /// Verdicts exact or exact but for an "A or B" with the hidden family inside.
    pub either: usize,
    /// Wrong effects over all verdicts (see [`Verdict::wrong`]).
    pub wrong: usize,
}

impl Tally {
    /// Counts `v`.
    pub fn add(&mut self, v: &Verdict) {
        self.runs += 1;
        self.exact += usize::from(v.exact());
        self.either += usize::from(v.exact_or_either());
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

    /// Fraction of verdicts exact or exact but for an "A or B" with the hidden family inside
    /// (0 for none) \[-\].
    pub fn either_rate(&self) -> f64 {
        if self.runs == 0 {
            0.0
        } else {
            self.either as f64 / self.runs as f64
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

    /// An "A or B" with the hidden family inside is not exact, but exact-or-either and not
    /// wrong; a pair without a hidden family is one wrong effect, and so is a hidden family
    /// neither named nor in a pair.
    #[test]
    fn a_or_b_with_the_truth_inside_is_not_wrong() {
        let pair = |a: &str, b: &str| [a.to_string(), b.to_string()];
        let lag = s(&["thruster_lag"]);
        let v = Verdict::new(&lag, Ok(vec![])).with_pairs(&[pair("thruster_lag", "sensor_delay")]);
        assert!(!v.exact() && v.exact_or_either());
        assert_eq!(v.wrong(), 0);
        assert_eq!(v.found_text(), "{} + (sensor_delay or thruster_lag)");
        let v = Verdict::new(&lag, Ok(vec![])).with_pairs(&[pair("thrust_gain", "battery_sag")]);
        assert!(!v.exact_or_either());
        assert_eq!(v.wrong(), 2);
        let v = Verdict::new(&lag, Ok(s(&["thruster_lag"])))
            .with_pairs(&[pair("thrust_gain", "battery_sag")]);
        assert!(!v.exact_or_either());
        assert_eq!(v.wrong(), 1);
        let mut t = Tally::default();
        t.add(&Verdict::new(&lag, Ok(vec![])).with_pairs(&[pair("sensor_delay", "thruster_lag")]));
        t.add(&Verdict::new(&lag, Ok(lag.clone())));
        assert_eq!((t.runs, t.exact, t.either, t.wrong), (2, 1, 2, 0));
        assert_eq!(t.either_rate(), 1.0);
    }
}
