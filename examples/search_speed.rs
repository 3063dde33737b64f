//! How much CPU `shoal validate`'s search spends, case by case: the pinned subset of the
//! misspecified-form test set (`testset::pinned_subset`, 120 s logs searched as the tests search
//! them: `recovery::search_log`, 20 ms replay) and one long log as a user has it (a 600 s μAUV²
//! diving run with a 0.4 s thruster lag hidden in it, searched with the CLI's defaults: the
//! μAUV² preset, 60/40 split, 10 ms replay). A benchmark, not a test: it prints what it
//! measured and asserts nothing about it.
//!
//! ```sh
//! cargo run --release --example search_speed -- [PATTERN…] [--exact] [--quick] [--list] \
//!     [--threads N] [--csv FILE]
//! ```
//!
//! * `PATTERN…` — cases whose name contains one of them (with `--exact`: equals one) [all];
//! * `--quick` — seven representative cases only (a single, a pair and a null of each
//!   experiment, the long log): minutes;
//! * `--list` — print the selected names and stop;
//! * `--threads N` — worker threads of the search [1];
//! * `--csv FILE` — also write `case,cpu_s,wall_s,verdict` rows (verdict: the chosen effect
//!   names sorted and joined by `+`, `none` for none, `error: …` when the log is refused).
//!
//! CPU time is the whole process's (user + system, every thread) from `/proc/self/stat` around
//! the search alone (the log is simulated before), in clock ticks of 10 ms; on a shared machine
//! it is the number to compare, wall time is shown for reference. scripts/search-speed.sh runs
//! this program built from two commits side by side; it uses only API both 6ace9bd and later
//! commits have, so that it builds in either (the test kit's modules were `shoal::sysid::…`
//! before they moved to the shoal-testkit crate: the script rewrites `shoal_testkit::` for a
//! base without that crate). The number of replays is not shown: no version's public API
//! counts them.

use shoal::model::effects::{EffectInstance, Effects, by_name};
use shoal::model::presets;
use shoal::model::rigid_body::Environment;
use shoal::model::vehicle::VehicleModel;
use shoal::sysid::evaluate::dataset::{DataOptions, Dataset};
use shoal::sysid::log::run::MeasuredRun;
use shoal::sysid::search::{SearchOptions, search};
use shoal_testkit::design;
use shoal_testkit::recovery::search_log;
use shoal_testkit::synth::synthesize;
use shoal_testkit::testset::{Conditions, pinned_subset};
use std::process::ExitCode;
use std::time::Instant;

/// Name of the long log's case.
const LONG: &str = "long_h_thruster_lag_600s";

/// The `--quick` selection: from `pinned_subset` a heave and a yaw single, a heave and a yaw pair,
/// a heave and a yaw null; the long log.
const QUICK: [&str; 7] = [
    "h_thruster_lag__underdamped_one_motor_3",
    "y_thrust_gain__two_slope_3",
    "h_pair_buoyancy_offset__gas_compression+thruster_lag__slew_rate_1",
    "y_pair_sensor_delay__sample_hold+thrust_gain__command_dependent_1",
    "h_null_1",
    "y_null_1",
    LONG,
];

/// Clock ticks per second of `/proc/self/stat` (Linux's fixed `USER_HZ`).
const USER_HZ: f64 = 100.0;

/// CPU time of this process so far (user + system, all threads) \[s\].
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").expect("/proc/self/stat (Linux)");
    // Fields after the command name in parentheses: state is field 3, utime 14, stime 15.
    let rest = &stat[stat.rfind(')').expect("stat has a command name") + 1..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| f[i].parse::<f64>().expect("a tick count");
    (ticks(11) + ticks(12)) / USER_HZ
}

/// The long log: 600 s of the designed heave experiment (50 Hz), a 0.4 s thruster lag hidden,
/// simulated at 5 ms with sensor noise, as CSV text.
fn long_csv() -> String {
    let lag = EffectInstance {
        effect: by_name("thruster_lag").expect("catalogue effect"),
        params: vec![0.4],
    };
    let truth = VehicleModel::with_effects(presets::uauv2(), Effects::new(vec![lag]), 1000.0);
    let exp = design::uauv2_heave(1, 600.0);
    synthesize(&truth, &Environment::default(), &exp, 0.005, 1 ^ 0x5eed).to_csv()
}

/// The search on `csv` as `shoal validate RUN.csv` runs it by default (μAUV² preset, default
/// environment, 60/40 split, 10 ms replay, whole catalogue), with `threads`; the chosen
/// effects' names, sorted.
fn search_like_cli(csv: &str, threads: usize) -> Result<Vec<String>, String> {
    let run = MeasuredRun::parse(csv, std::path::Path::new(&format!("{LONG}.csv")))
        .map_err(|e| format!("parse: {e}"))?;
    let base = presets::uauv2();
    let ds = Dataset::new(
        &base,
        Environment::default(),
        vec![run],
        vec![],
        &DataOptions::default(),
    )
    .map_err(|e| format!("dataset: {e}"))?;
    let opts = SearchOptions {
        threads,
        ..Default::default()
    };
    let mut names = search(&ds, &base, &opts, &|_| {}).chosen.names();
    names.sort();
    names.dedup();
    Ok(names)
}

/// Command-line arguments.
struct Args {
    patterns: Vec<String>,
    exact: bool,
    quick: bool,
    list: bool,
    threads: usize,
    csv: Option<String>,
}

fn parse_args() -> Result<Args, String> {
    let mut a = Args {
        patterns: Vec::new(),
        exact: false,
        quick: false,
        list: false,
        threads: 1,
        csv: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        match arg.as_str() {
            "--exact" => a.exact = true,
            "--quick" => a.quick = true,
            "--list" => a.list = true,
            "--threads" => {
                let v = it.next().ok_or("--threads needs a number")?;
                a.threads = v
                    .parse()
                    .ok()
                    .filter(|&n| n >= 1)
                    .ok_or(format!("--threads {v}: allowed a whole number ≥ 1"))?;
            }
            "--csv" => a.csv = Some(it.next().ok_or("--csv needs a file name")?),
            s if s.starts_with("--") => return Err(format!("unknown option {s}")),
            _ => a.patterns.push(arg),
        }
    }
    Ok(a)
}

/// The selected case names, in the test set's order, the long log last (an error when a
/// `--quick` name is not a case).
fn selection(a: &Args) -> Result<Vec<String>, String> {
    let mut all: Vec<String> = pinned_subset().into_iter().map(|c| c.name).collect();
    all.push(LONG.to_string());
    if let Some(q) = QUICK.iter().find(|q| !all.iter().any(|n| n == *q)) {
        return Err(format!("--quick: `{q}` is not a case"));
    }
    Ok(all
        .into_iter()
        .filter(|n| !a.quick || QUICK.contains(&n.as_str()))
        .filter(|n| {
            a.patterns.is_empty()
                || a.patterns.iter().any(|p| {
                    if a.exact {
                        n == p
                    } else {
                        n.contains(p.as_str())
                    }
                })
        })
        .collect())
}

/// One case measured: CPU and wall seconds of the search, and its verdict.
fn measure(name: &str, threads: usize) -> (f64, f64, Result<Vec<String>, String>) {
    let csv = if name == LONG {
        long_csv()
    } else {
        let spec = pinned_subset()
            .into_iter()
            .find(|c| c.name == name)
            .expect("a selected case");
        spec.generate(&Conditions::default()).csv
    };
    let (cpu0, wall0) = (cpu_seconds(), Instant::now());
    let verdict = if name == LONG {
        search_like_cli(&csv, threads)
    } else {
        search_log(&csv, name, threads)
    };
    (cpu_seconds() - cpu0, wall0.elapsed().as_secs_f64(), verdict)
}

fn main() -> ExitCode {
    let (args, names) = match parse_args().and_then(|a| selection(&a).map(|n| (a, n))) {
        Ok(an) => an,
        Err(e) => {
            eprintln!("search_speed: {e}");
            return ExitCode::from(2);
        }
    };
    if args.list {
        names.iter().for_each(|n| println!("{n}"));
        return ExitCode::SUCCESS;
    }
    if names.is_empty() {
        eprintln!("search_speed: no case matches {:?}", args.patterns);
        return ExitCode::from(2);
    }
    let mut rows = String::from("case,cpu_s,wall_s,verdict\n");
    let (mut cpu_total, mut wall_total) = (0.0, 0.0);
    println!("{:<64} {:>9} {:>9}  verdict", "case", "CPU [s]", "wall [s]");
    for name in &names {
        let (cpu, wall, verdict) = measure(name, args.threads);
        let (shown, field) = match &verdict {
            Ok(v) if v.is_empty() => ("{}".to_string(), "none".to_string()),
            Ok(v) => (format!("{{{}}}", v.join(", ")), v.join("+")),
            Err(e) => (
                format!("error: {e}"),
                format!("error: {}", e.replace(',', ";")),
            ),
        };
        println!("{name:<64} {cpu:>9.2} {wall:>9.2}  {shown}");
        rows.push_str(&format!("{name},{cpu:.2},{wall:.3},{field}\n"));
        cpu_total += cpu;
        wall_total += wall;
    }
    println!(
        "{:<64} {cpu_total:>9.2} {wall_total:>9.2}  ({} thread(s))",
        format!("total ({} case(s))", names.len()),
        args.threads
    );
    if let Some(path) = &args.csv
        && let Err(e) = std::fs::write(path, rows)
    {
        eprintln!("search_speed: writing {path}: {e}");
        return ExitCode::FAILURE;
    }
    ExitCode::SUCCESS
}
