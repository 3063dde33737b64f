//! The long closed-loop test set (`shoal_testkit::closed_loop`): writes each mission log, runs
//! the search on it open loop and re-anchored (`auto` horizon), and prints both verdicts beside
//! the hidden family.
//!
//! ```sh
//! cargo run --release -p shoal-testkit --example closed_loop -- --out out/closed_loop
//! cargo run --release -p shoal-testkit --example closed_loop -- --out out/cl --cases null --length 300
//! ```
//!
//! Options: `--out DIR` (logs, `expected.json` and the table `verdicts.md`), `--length S`
//! mission length in seconds (default 600), `--cases TEXT` only cases whose name contains TEXT,
//! `--threads T` search worker threads (default 2), `--horizons LIST` of `open`, `auto`,
//! `closed` (the logs carry their references), `choose` (the default replay), `choose-norefs`
//! (the default replay of the logs with their references dropped) or seconds (default
//! `open,auto`), `--write-only` (logs without searching), `--calm` (still water: no wandering current, the
//! parameter noise kept — what the gusts cost). Each search on a
//! 10-minute log takes minutes: the whole set is an hour or more on two cores. Not run in CI.

use shoal_sysid::evaluate::anchoring::Horizon;
use shoal_testkit::closed_loop::{MISSION_S, cases};
use shoal_testkit::mission::Disturbance;
use shoal_testkit::recovery::{Tally, judge_log};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

fn usage() -> ExitCode {
    eprintln!(
        "usage: closed_loop --out DIR [--length SECONDS] [--cases TEXT] [--threads T] \
         [--horizons open,auto,closed,choose,choose-norefs,SECONDS] [--write-only] [--calm]"
    );
    ExitCode::from(2)
}

fn horizon(s: &str) -> Option<Horizon> {
    match s {
        "open" => Some(Horizon::Open),
        "auto" => Some(Horizon::Auto),
        "closed" => Some(Horizon::Closed),
        "choose" | "choose-norefs" => Some(Horizon::Choose),
        x => x
            .parse::<f64>()
            .ok()
            .filter(|h| (Horizon::MIN_S..=Horizon::MAX_S).contains(h))
            .map(Horizon::Every),
    }
}

/// `csv` without its `r.` columns.
fn without_references(csv: &str) -> String {
    let mut lines = csv.lines();
    let Some(header) = lines.next() else {
        return String::new();
    };
    let keep: Vec<bool> = header.split(',').map(|c| !c.starts_with("r.")).collect();
    let pick = |line: &str| {
        line.split(',')
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(c, _)| c)
            .collect::<Vec<_>>()
            .join(",")
    };
    let mut out = pick(header);
    for line in lines {
        out.push('\n');
        out.push_str(&pick(line));
    }
    out.push('\n');
    out
}

/// The command line.
struct Options {
    out: PathBuf,
    length: f64,
    filter: String,
    threads: usize,
    horizons: Vec<(String, Horizon)>,
    write_only: bool,
    calm: bool,
}

/// Reads the command line; the usage exit code when it is wrong.
fn options() -> Result<Options, ExitCode> {
    let mut out: Option<PathBuf> = None;
    let mut length = MISSION_S;
    let mut filter = String::new();
    let mut threads = 2usize;
    let mut horizons = vec![
        ("open".to_string(), Horizon::Open),
        ("auto".into(), Horizon::Auto),
    ];
    let mut write_only = false;
    let mut calm = false;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        if a == "--write-only" {
            write_only = true;
            continue;
        }
        if a == "--calm" {
            calm = true;
            continue;
        }
        let Some(v) = args.next() else {
            eprintln!("{a} needs a value");
            return Err(usage());
        };
        match a.as_str() {
            "--out" => out = Some(PathBuf::from(v)),
            "--cases" => filter = v,
            "--length" => match v.parse::<f64>() {
                Ok(x) if x.is_finite() && x >= 30.0 => length = x,
                _ => {
                    eprintln!("--length takes seconds ≥ 30, got `{v}`");
                    return Err(usage());
                }
            },
            "--threads" => match v.parse::<usize>() {
                Ok(t) if t >= 1 => threads = t,
                _ => {
                    eprintln!("--threads takes a whole number ≥ 1, got `{v}`");
                    return Err(usage());
                }
            },
            "--horizons" => {
                let parsed: Option<Vec<(String, Horizon)>> = v
                    .split(',')
                    .map(|s| horizon(s.trim()).map(|h| (s.trim().to_string(), h)))
                    .collect();
                match parsed {
                    Some(h) if !h.is_empty() => horizons = h,
                    _ => {
                        eprintln!(
                            "--horizons takes open, auto, closed, choose, choose-norefs or \
                             seconds in [{}, {}], got `{v}`",
                            Horizon::MIN_S,
                            Horizon::MAX_S
                        );
                        return Err(usage());
                    }
                }
            }
            _ => {
                eprintln!("unknown option `{a}`");
                return Err(usage());
            }
        }
    }
    let Some(out) = out else {
        return Err(usage());
    };
    Ok(Options {
        out,
        length,
        filter,
        threads,
        horizons,
        write_only,
        calm,
    })
}

fn main() -> ExitCode {
    let Options {
        out: dir,
        length,
        filter,
        threads,
        horizons,
        write_only,
        calm,
    } = match options() {
        Ok(o) => o,
        Err(code) => return code,
    };
    if let Err(e) = std::fs::create_dir_all(&dir) {
        eprintln!("cannot create {}: {e}", dir.display());
        return ExitCode::FAILURE;
    }
    let dist = if calm {
        Disturbance {
            gust_horizontal: 0.0,
            gust_vertical: 0.0,
            ..Disturbance::default()
        }
    } else {
        Disturbance::default()
    };
    let chosen: Vec<_> = cases(length)
        .into_iter()
        .filter(|c| c.name.contains(&filter))
        .collect();
    let mut table = format!(
        "| case | hidden | {} |\n|---|---|{}\n",
        horizons
            .iter()
            .map(|(n, _)| format!("{n}: verdict (time)"))
            .collect::<Vec<_>>()
            .join(" | "),
        "---|".repeat(horizons.len())
    );
    let mut tallies = vec![Tally::default(); horizons.len()];
    let mut expected = serde_json::Map::new();
    for case in &chosen {
        let csv = case.csv(&dist);
        let path = dir.join(format!("{}.csv", case.name));
        if let Err(e) = std::fs::write(&path, &csv) {
            eprintln!("cannot write {}: {e}", path.display());
            return ExitCode::FAILURE;
        }
        let exp = case.expected();
        expected.insert(case.name.clone(), serde_json::json!(exp));
        if write_only {
            continue;
        }
        let hidden: Vec<String> = case.hidden.iter().map(|h| h.describe()).collect();
        let mut row = format!("| {} | {} |", case.name, hidden.join("; "));
        for ((name, h), tally) in horizons.iter().zip(&mut tallies) {
            let t0 = Instant::now();
            // `choose-norefs`: the same log with its references dropped.
            let text = if name == "choose-norefs" {
                without_references(&csv)
            } else {
                csv.clone()
            };
            let v = judge_log(&text, &case.name, &exp, threads, *h);
            let secs = t0.elapsed().as_secs_f64();
            tally.add(&v);
            let mark = if v.exact() { "exact" } else { "wrong" };
            eprintln!(
                "{} [{name}] {mark} {} ({secs:.0} s)",
                case.name,
                v.found_text()
            );
            if !v.exact() && !v.inclusion.is_empty() {
                eprintln!("    P(family) over resamples: {}", v.inclusion);
            }
            row.push_str(&format!(" {mark}: {} ({secs:.0} s) |", v.found_text()));
        }
        table.push_str(&row);
        table.push('\n');
    }
    let write = |name: &str, text: &str| {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|e| eprintln!("cannot write {}: {e}", path.display()))
    };
    let json = serde_json::to_string_pretty(&expected).unwrap_or_default();
    if write("expected.json", &json).is_err() {
        return ExitCode::FAILURE;
    }
    if write_only {
        println!("wrote {} mission logs to {}", chosen.len(), dir.display());
        return ExitCode::SUCCESS;
    }
    for ((name, _), t) in horizons.iter().zip(&tallies) {
        table.push_str(&format!(
            "\n{name}: {} of {} exact ({:.0} %), {} exact or an \"A or B\" with the hidden \
             family inside, {:.2} wrong effects per verdict",
            t.exact,
            t.runs,
            100.0 * t.rate(),
            t.either,
            t.mean_wrong()
        ));
    }
    table.push('\n');
    print!("{table}");
    if write("verdicts.md", &table).is_err() {
        return ExitCode::FAILURE;
    }
    ExitCode::SUCCESS
}
