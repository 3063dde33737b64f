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
//!
//! `--closed-loop S` takes the long closed-loop set instead (`shoal_testkit::closed_loop`,
//! missions of S seconds in gusting water, replayed as `shoal validate` replays them by
//! default): the suggested flight is the `next_experiment.toml` the report writes, loaded
//! through the world loader and flown by the mission's own truth and hull in the same water
//! (fresh gusts and sensor noise); `--forms` then filters the case names.
//!
//! ```sh
//! cargo run --release -p shoal-testkit --example resolution -- \
//!     --closed-loop 300 --threads 2 --out resolution_closed_loop.md
//! ```

use shoal_model::presets;
use shoal_sysid::evaluate::anchoring::Horizon;
use shoal_sysid::experiment::{NextExperiment, next_experiment, world_toml};
use shoal_sysid::log::run::MeasuredRun;
use shoal_sysid::search::{Outcome, SearchOptions, search};
use shoal_testkit::closed_loop::{self, MissionCase};
use shoal_testkit::draws::DrawOptions;
use shoal_testkit::mission::Disturbance;
use shoal_testkit::next_flight::experiment_of;
use shoal_testkit::recovery::dataset_of;
use shoal_testkit::testset::{CaseSpec, Conditions, null, single};
use shoal_testkit::truth_forms::{self, ExpKind};
use shoal_world::load::load_str;
use shoal_world::spec::VehicleSpec;
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
         [--out FILE] [--closed-loop S]"
    );
    ExitCode::from(2)
}

/// Where a case's logs come from.
enum Source<'a> {
    /// A recovery draw: a designed experiment, and the flight as a designed one.
    Draw(&'a CaseSpec, &'a Conditions),
    /// A closed-loop mission, and the flight from `next_experiment.toml` in the same water.
    Mission(&'a MissionCase, &'a Disturbance),
}

impl Source<'_> {
    fn name(&self) -> &str {
        match self {
            Source::Draw(spec, _) => &spec.name,
            Source::Mission(m, _) => &m.name,
        }
    }

    fn expected(&self) -> Vec<String> {
        match self {
            Source::Draw(spec, _) => spec.expected(),
            Source::Mission(m, _) => m.expected(),
        }
    }

    /// How `shoal validate` replays its logs: the draws open loop (as the recovery benchmark),
    /// the missions as it chooses.
    fn horizon(&self) -> Horizon {
        match self {
            Source::Draw(..) => Horizon::Open,
            Source::Mission(..) => Horizon::Choose,
        }
    }

    fn first(&self) -> MeasuredRun {
        match self {
            Source::Draw(spec, cond) => spec.run(cond),
            Source::Mission(m, dist) => m.run(dist),
        }
    }

    /// The flight `x` suggests, flown on the case's truth.
    fn flight(&self, x: &NextExperiment) -> Result<MeasuredRun, String> {
        let name = format!("{}_next", self.name());
        match self {
            Source::Draw(spec, cond) => {
                let like = spec.kind.experiment(spec.seed, cond.duration);
                Ok(spec.run_of(cond, &experiment_of(x, &name, &like)))
            }
            Source::Mission(m, dist) => {
                let spec = VehicleSpec::from_params(&presets::uauv2());
                let text = world_toml(x, &spec, &m.name).map_err(|e| format!("world: {e}"))?;
                let path = Path::new("next_experiment.toml");
                let world = load_str(&text, path).map_err(|e| format!("world: {e}"))?;
                Ok(m.fly_world(dist, &world, &name))
            }
        }
    }
}

/// One case: the first search, and where a question is open the flight and the second.
fn case(src: &Source, opts: &SearchOptions) -> Result<Row, String> {
    let base = presets::uauv2();
    let parse = |run: &MeasuredRun| {
        let csv = shoal_testkit::logger::logger_csv(run);
        MeasuredRun::parse(&csv, Path::new(&format!("{}.csv", run.name)))
            .map_err(|e| format!("parse: {e}"))
    };
    let first_run = parse(&src.first())?;
    let ds = dataset_of(vec![first_run.clone()], opts, src.horizon())?;
    let out = search(&ds, &base, opts, &|_| {});
    let x = next_experiment(&ds, &base, opts, &out);
    let mut row = Row {
        name: src.name().to_string(),
        expected: src.expected(),
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
        let second = parse(&src.flight(&x)?)?;
        let ds2 = dataset_of(vec![first_run, second], opts, src.horizon())?;
        row.both = Some(names(&search(&ds2, &base, opts, &|_| {})));
    }
    Ok(row)
}

/// `args` without `--closed-loop S`, and S \[s\] if it was there.
fn closed_loop_option(args: Vec<String>) -> Result<(Vec<String>, Option<f64>), String> {
    let mut rest = Vec::new();
    let mut length = None;
    let mut it = args.into_iter();
    while let Some(a) = it.next() {
        if a != "--closed-loop" {
            rest.push(a);
            continue;
        }
        let v = it.next().unwrap_or_default();
        match v.parse::<f64>() {
            Ok(x) if x.is_finite() && x >= 30.0 => length = Some(x),
            _ => {
                return Err(format!(
                    "--closed-loop takes a mission length ≥ 30 s, got `{v}`"
                ));
            }
        }
    }
    Ok((rest, length))
}

fn main() -> ExitCode {
    let defaults = DrawOptions {
        draws: 1,
        noise: vec![1.0],
        length: vec![120.0],
        ..DrawOptions::default()
    };
    let (args, closed) = match closed_loop_option(std::env::args().skip(1).collect()) {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{e}");
            return usage();
        }
    };
    let o = match DrawOptions::parse(defaults, args) {
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
    let dist = Disturbance::default();
    let missions: Vec<MissionCase> = closed.map_or_else(Vec::new, |length| {
        closed_loop::cases(length)
            .into_iter()
            .filter(|m| filter.as_ref().is_none_or(|f| m.name.contains(f.as_str())))
            .collect()
    });
    let sources: Vec<Source> = if closed.is_some() {
        missions.iter().map(|m| Source::Mission(m, &dist)).collect()
    } else {
        specs.iter().map(|s| Source::Draw(s, &cond)).collect()
    };
    let total = sources.len();
    let mut rows = Vec::new();
    for (i, src) in sources.iter().enumerate() {
        match case(src, &opts) {
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
            Err(e) => eprintln!("[{}/{total}] {}: {e}", i + 1, src.name()),
        }
    }
    let open: Vec<&Row> = rows.iter().filter(|r| r.manoeuvre.is_some()).collect();
    let ambiguous: Vec<&Row> = open
        .iter()
        .copied()
        .filter(|r| !r.pairs.is_empty())
        .collect();
    let count = |v: &[&Row], f: &dyn Fn(&Row) -> bool| v.iter().filter(|r| f(r)).count();
    let what = match closed {
        Some(l) => format!(
            "the closed-loop set's missions ({l} s, gusts and a hull ±3 % off, replayed as \
             `choose` replays them)"
        ),
        None => format!("noise ×{noise}, {length} s, {draws} draw(s) from seed {SEED0}"),
    };
    let mut md = format!(
        "Resolution of the next experiment on {} logs ({what}): {} leave a question open, {} \
         of them an \"A or B\" ({} with a hidden family inside).\n\n\
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
