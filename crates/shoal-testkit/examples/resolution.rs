//! Resolution benchmark of the next experiment: on the recovery benchmark's independent draws
//! (every designed truth form and the null runs, seeded draws as `recovery` draws them), every
//! log whose verdict leaves a question open ("A or B", an effect only possible) gets its
//! suggested flight (`shoal_sysid::experiment`), flown on the same hidden truth with fresh
//! sensor noise; the two logs are searched together, and the share of cases whose verdict is
//! then exact is the share the suggestion resolves.
//!
//! ```sh
//! cargo run --release -p shoal-testkit --example resolution -- \
//!     --draws 1 --noise 1 --length 120 --threads 2 --out resolution.md
//! ```
//!
//! Options as `recovery`'s (`shoal_testkit::draws`): `--draws N` (seed 1000 + d, default 1),
//! `--noise X` and `--length S` (the first of a list; default 1 and 120 s), `--threads T`,
//! `--forms TEXT`, `--out FILE`. Each case is one full catalogue search, and a
//! second one on two logs where a question is open: the 52 rows take about 20 minutes on two
//! cores. Not run in CI.

use shoal_model::presets;
use shoal_sysid::evaluate::anchoring::Horizon;
use shoal_sysid::experiment::next_experiment;
use shoal_sysid::log::run::MeasuredRun;
use shoal_sysid::search::{Outcome, SearchOptions, search};
use shoal_testkit::draws::DrawOptions;
use shoal_testkit::next_flight::experiment_of;
use shoal_testkit::recovery::dataset_of;
use shoal_testkit::testset::{CaseSpec, Conditions, null, single};
use shoal_testkit::truth_forms::{self, ExpKind};
use std::path::Path;
use std::process::ExitCode;

/// First seed of the draws (as the recovery benchmark's).
const SEED0: u64 = 1000;

/// What happened to one case.
struct Row {
    /// The case.
    name: String,
    /// The hidden families.
    expected: Vec<String>,
    /// The first verdict's named effects, sorted.
    first: Vec<String>,
    /// Its "A or B" pairs.
    pairs: Vec<[String; 2]>,
    /// Its questions (`a or b`).
    questions: Vec<String>,
    /// The manoeuvre suggested, if any.
    manoeuvre: Option<String>,
    /// The verdict on both logs, sorted.
    both: Option<Vec<String>>,
}

impl Row {
    fn first_exact(&self) -> bool {
        self.first == self.expected
    }
    fn resolved(&self) -> bool {
        self.both.as_ref() == Some(&self.expected)
    }
    /// An "A or B" with a hidden family inside.
    fn truth_inside(&self) -> bool {
        self.pairs
            .iter()
            .any(|p| p.iter().any(|f| self.expected.contains(f)))
    }
}

fn names(out: &Outcome) -> Vec<String> {
    let mut n = out.chosen.names();
    n.sort();
    n.dedup();
    n
}

fn usage() -> ExitCode {
    eprintln!(
        "usage: resolution [--draws N] [--noise X] [--length S] [--threads T] [--forms TEXT] \
         [--out FILE]"
    );
    ExitCode::from(2)
}

/// One case: the first search, and where a question is open the flight and the second.
fn case(spec: &CaseSpec, cond: &Conditions, opts: &SearchOptions) -> Result<Row, String> {
    let base = presets::uauv2();
    let parse = |run: &MeasuredRun| {
        let csv = shoal_testkit::logger::logger_csv(run);
        MeasuredRun::parse(&csv, Path::new(&format!("{}.csv", run.name)))
            .map_err(|e| format!("parse: {e}"))
    };
    let first_run = parse(&spec.run(cond))?;
    let ds = dataset_of(vec![first_run.clone()], opts, Horizon::Open)?;
    let out = search(&ds, &base, opts, &|_| {});
    let x = next_experiment(&ds, &base, opts, &out);
    let mut row = Row {
        name: spec.name.clone(),
        expected: spec.expected(),
        first: names(&out),
        pairs: out
            .verdict
            .ambiguous
            .iter()
            .map(|a| a.effects.clone())
            .collect(),
        questions: out
            .rivals
            .iter()
            .map(|r| format!("{} or {}", r.a, r.b))
            .collect(),
        manoeuvre: x.as_ref().map(|x| x.manoeuvre.clone()),
        both: None,
    };
    if let Some(x) = x {
        let like = spec.kind.experiment(spec.seed, cond.duration);
        let exp = experiment_of(&x, &format!("{}_next", spec.name), &like);
        let second = parse(&spec.run_of(cond, &exp))?;
        let ds2 = dataset_of(vec![first_run, second], opts, Horizon::Open)?;
        row.both = Some(names(&search(&ds2, &base, opts, &|_| {})));
    }
    Ok(row)
}

fn main() -> ExitCode {
    let defaults = DrawOptions {
        draws: 1,
        noise: vec![1.0],
        length: vec![120.0],
        ..DrawOptions::default()
    };
    let o = match DrawOptions::parse(defaults, std::env::args().skip(1)) {
        Ok(o) => o,
        Err(e) => {
            eprintln!("{e}");
            return usage();
        }
    };
    let (draws, threads, filter, out) = (o.draws, o.threads, o.forms, o.out);
    let (noise, length) = (o.noise[0], o.length[0]);
    let mut specs: Vec<CaseSpec> = Vec::new();
    for d in 0..draws {
        let seed = SEED0 + d as u64;
        for f in truth_forms::designed() {
            let kind = f.excites[d % f.excites.len()];
            specs.push(single(&f, kind, seed));
        }
        specs.push(null(ExpKind::ALL[d % ExpKind::ALL.len()], seed));
    }
    if let Some(text) = &filter {
        specs.retain(|s| s.name.contains(text.as_str()));
    }
    let cond = Conditions {
        duration: length,
        noise,
    };
    let opts = SearchOptions {
        threads,
        ..Default::default()
    };
    let total = specs.len();
    let mut rows = Vec::new();
    for (i, spec) in specs.iter().enumerate() {
        match case(spec, &cond, &opts) {
            Ok(r) => {
                eprintln!(
                    "[{}/{total}] {}: first {:?}{}, questions {:?} → {} → {:?} {}",
                    i + 1,
                    r.name,
                    r.first,
                    if r.first_exact() { " (exact)" } else { "" },
                    r.questions,
                    r.manoeuvre.as_deref().unwrap_or("—"),
                    r.both,
                    if r.both.is_none() {
                        ""
                    } else if r.resolved() {
                        "exact"
                    } else {
                        "not exact"
                    }
                );
                rows.push(r);
            }
            Err(e) => eprintln!("[{}/{total}] {}: {e}", i + 1, spec.name),
        }
    }
    let open: Vec<&Row> = rows.iter().filter(|r| r.manoeuvre.is_some()).collect();
    let ambiguous: Vec<&Row> = open
        .iter()
        .copied()
        .filter(|r| !r.pairs.is_empty())
        .collect();
    let count = |v: &[&Row], f: &dyn Fn(&Row) -> bool| v.iter().filter(|r| f(r)).count();
    let mut md = format!(
        "Resolution of the next experiment on {} logs (noise ×{noise}, {length} s, {draws} \
         draw(s) from seed {SEED0}): {} leave a question open, {} of them an \"A or B\" ({} \
         with a hidden family inside).\n\n\
         - of the open cases, exact with the suggested flight: {} of {} (first verdict exact: \
         {} of {});\n\
         - of the \"A or B\" cases: {} of {} exact with the flight.\n\n\
         | case | hidden | first verdict | questions | flight | both logs |\n|---|---|---|---|---|---|\n",
        rows.len(),
        open.len(),
        ambiguous.len(),
        count(&ambiguous, &|r| r.truth_inside()),
        count(&open, &|r| r.resolved()),
        open.len(),
        count(&open, &|r| r.first_exact()),
        open.len(),
        count(&ambiguous, &|r| r.resolved()),
        ambiguous.len(),
    );
    let set = |v: &[String]| {
        if v.is_empty() {
            "—".to_string()
        } else {
            v.join(", ")
        }
    };
    for r in &open {
        md.push_str(&format!(
            "| {} | {} | {} | {} | {} | {}{} |\n",
            r.name,
            set(&r.expected),
            set(&r.first),
            r.questions.join("; "),
            r.manoeuvre.as_deref().unwrap_or("—"),
            r.both.as_deref().map_or("—".to_string(), set),
            if r.resolved() { " ✓" } else { "" }
        ));
    }
    println!("{md}");
    if let Some(path) = out
        && let Err(e) = std::fs::write(&path, &md)
    {
        eprintln!("cannot write {}: {e}", path.display());
        return ExitCode::FAILURE;
    }
    ExitCode::SUCCESS
}
