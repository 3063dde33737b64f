//! A sweep file → numbered runs, each a complete world file.
//!
//! Run `index = point × seeds + seed_number`: points in the design's order (a grid's first
//! parameter varies slowest), seeds innermost. Each run's world is the base world with its
//! seed and, in order, the sweep's defaults for runs (no plots, no replay — unless `[set]`
//! says otherwise), `[set]` and the point's values, applied with [`shoal_world::overrides`]
//! and loaded like any world file. So every value of every run is validated before anything runs,
//! and each problem is reported at the line of the sweep file that caused it (an unknown path,
//! a value out of range, a count that no longer fits the pool). Worlds are loaded on several
//! threads; the result does not depend on how many.

use super::file::{Loc, Param, Problems, SweepFile, overlaps};
use super::plan::{Plan, PlannedRun, WORLD, hash_hex, run_dir, write_if_changed};
use shoal_world::error::ProblemKind;
use shoal_world::load::load_str;
use shoal_world::overrides::{Located, Override, OverrideError, apply, dotted};
use std::path::Path;

/// Most problems listed before the rest are counted.
const MAX_LISTED: usize = 40;

/// Changes every run gets unless the sweep's `[set]` decides: a sweep wants summaries, not a
/// figure and a 3D page per run.
const RUN_DEFAULTS: [(&str, bool); 2] = [("output.plots", false), ("output.replay", false)];

/// The runs of a sweep with their world files.
#[derive(Debug)]
pub struct Expanded {
    /// The plan (runs, parameters, metrics).
    pub plan: Plan,
    /// Per run (by index): the world file's text.
    pub worlds: Vec<String>,
}

/// How a value is written in results.csv and messages: text as is, anything else as TOML.
pub fn show(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// One change with where it comes from.
struct Source {
    path: String,
    value: toml::Value,
    loc: Loc,
}

/// Expands `sweep` (with `jobs` threads loading worlds). `sweep_file` is the sweep file as
/// given on the command line (recorded in the plan).
pub fn expand(sweep: &SweepFile, sweep_file: &str, jobs: usize) -> Result<Expanded, String> {
    let base_name = sweep.base.name();
    let base_desc = load_str(&sweep.base.text, &base_name).map_err(|e| e.to_string())?;
    let mut p = Problems::new(&sweep.file, &sweep.text);
    if !base_desc.agents.names.is_empty() {
        p.at(
            sweep.base.loc,
            format!(
                "the world {} is driven by external agents ({}); a sweep runs worlds on their \
                 own, without agents",
                base_name.display(),
                base_desc.agents.names.join(", ")
            ),
        );
        return Err(p.report());
    }
    let base: toml::Table = toml::from_str(&sweep.base.text).map_err(|e| e.to_string())?;
    let mut fixed: Vec<Source> = RUN_DEFAULTS
        .iter()
        .filter(|(path, _)| !sweep.set.iter().any(|q| overlaps(&q.path, path)))
        .map(|(path, v)| Source {
            path: (*path).to_string(),
            value: toml::Value::Boolean(*v),
            loc: None,
        })
        .collect();
    fixed.extend(sweep.set.iter().map(|q: &Param| Source {
        path: q.path.clone(),
        value: q.values[0].clone(),
        loc: q.loc,
    }));
    let params = sweep.design.params();
    let combos = sweep.design.combinations();
    let seeds = sweep.seeds.clone().unwrap_or_else(|| vec![base_desc.seed]);
    let n = combos.len() * seeds.len();
    // Every run's changes, in index order.
    let runs: Vec<(Vec<Source>, &Vec<toml::Value>, u64)> = combos
        .iter()
        .flat_map(|c| seeds.iter().map(move |s| (c, *s)))
        .map(|(combo, seed)| {
            let mut sources: Vec<Source> = fixed
                .iter()
                .map(|f| Source {
                    path: f.path.clone(),
                    value: f.value.clone(),
                    loc: f.loc,
                })
                .collect();
            sources.extend(params.iter().zip(combo).map(|(q, v)| Source {
                path: q.path.clone(),
                value: v.clone(),
                loc: q.loc,
            }));
            (sources, combo, seed)
        })
        .collect();
    let outcomes = apply_all(&base, &runs, &base_name, jobs);
    let mut worlds = Vec::with_capacity(n);
    let mut planned = Vec::with_capacity(n);
    // Distinct problems (the same one in many runs is one); the first MAX_LISTED are listed.
    let mut seen: Vec<(Loc, String)> = Vec::new();
    for (index, ((sources, combo, seed), outcome)) in runs.iter().zip(outcomes).enumerate() {
        match outcome {
            Ok(text) => {
                let values: Vec<String> = combo.iter().map(show).collect();
                let header = format!(
                    "# One run of the shoal sweep `{}`: {}seed = {seed}.\n# Run it alone: shoal \
                     run world.toml --out <folder>\n\n",
                    sweep.name,
                    params
                        .iter()
                        .zip(combo.iter())
                        .map(|(q, v)| format!("{} = {v}, ", q.path))
                        .collect::<String>()
                );
                let world = header + &text;
                planned.push(PlannedRun {
                    index,
                    run: hash_hex(world.as_bytes()),
                    values,
                    seed: *seed,
                });
                worlds.push(world);
            }
            Err(e) => {
                for problem in describe(&e, sources, index, params, combo, *seed) {
                    if !seen.contains(&problem) {
                        if seen.len() < MAX_LISTED {
                            p.at(problem.0, problem.1.clone());
                        }
                        seen.push(problem);
                    }
                }
            }
        }
    }
    if !p.is_empty() {
        let mut report = p.report();
        let more = seen.len().saturating_sub(MAX_LISTED);
        if more > 0 {
            report.push_str(&format!("\n… and {more} more problems"));
        }
        return Err(report);
    }
    Ok(Expanded {
        plan: Plan {
            name: sweep.name.clone(),
            sweep_file: sweep_file.to_string(),
            parameters: params.iter().map(|q| q.path.clone()).collect(),
            metrics: sweep.metrics.clone(),
            runs: planned,
        },
        worlds,
    })
}

/// Applies each run's changes to the base world with the run's seed, on `jobs` threads;
/// results in run order. (The seed is part of the base each change is tried alone on, so a
/// random placement that fails is traced to the change that made it fail.)
fn apply_all(
    base: &toml::Table,
    runs: &[(Vec<Source>, &Vec<toml::Value>, u64)],
    file: &Path,
    jobs: usize,
) -> Vec<Result<String, OverrideError>> {
    let one = |(sources, _, seed): &(Vec<Source>, &Vec<toml::Value>, u64)| {
        let overrides: Vec<Override> = sources
            .iter()
            .map(|s| Override {
                path: s.path.clone(),
                value: s.value.clone(),
            })
            .collect();
        let mut seeded = base.clone();
        seeded.insert(
            "seed".into(),
            toml::Value::Integer(i64::try_from(*seed).unwrap_or(i64::MAX)),
        );
        apply(&seeded, &overrides, file).map(|a| a.text)
    };
    let jobs = jobs.clamp(1, runs.len().max(1));
    let chunk = runs.len().div_ceil(jobs).max(1);
    std::thread::scope(|s| {
        let handles: Vec<_> = runs
            .chunks(chunk)
            .map(|part| s.spawn(move || part.iter().map(one).collect::<Vec<_>>()))
            .collect();
        handles
            .into_iter()
            .flat_map(|h| {
                h.join().unwrap_or_else(|_| {
                    vec![Err(OverrideError::Write("a loader thread stopped".into()))]
                })
            })
            .collect()
    })
}

/// The located messages of one run's failure.
fn describe(
    e: &OverrideError,
    sources: &[Source],
    index: usize,
    params: &[Param],
    combo: &[toml::Value],
    seed: u64,
) -> Vec<(Loc, String)> {
    let run = || {
        format!(
            "run {index} ({}seed {seed})",
            params
                .iter()
                .zip(combo)
                .map(|(q, v)| format!("{} = {v}, ", q.path))
                .collect::<String>()
        )
    };
    let what = |s: &Source| format!("`{}` = {}", s.path, s.value);
    // A path that leads nowhere is wrong whatever its value: named without it, so that the
    // problem is one line, not one per value.
    let path_of = |s: &Source| format!("`{}`", s.path);
    match e {
        OverrideError::Write(m) => vec![(None, format!("{}: {m}", run()))],
        OverrideError::Problems { paths, world } => paths
            .iter()
            .map(|p| {
                let s = &sources[p.index];
                (s.loc, format!("{}: {}", path_of(s), p.message))
            })
            .chain(world.iter().map(|Located { by, problem }| {
                let field = problem.field.as_ref().map(dotted);
                let source = by.map(|i| &sources[i]);
                let at = match (&field, source) {
                    (Some(f), Some(s)) if *f == s.path => String::new(),
                    (Some(f), _) if problem.kind == ProblemKind::UnknownField => {
                        let parent = f.rsplit_once('.').map_or("", |(p, _)| p);
                        if parent.is_empty() {
                            "at the top level: ".to_string()
                        } else {
                            format!("in `{parent}`: ")
                        }
                    }
                    (Some(f), _) if !f.is_empty() => format!("`{f}`: "),
                    _ => String::new(),
                };
                match source {
                    Some(s) if problem.kind == ProblemKind::UnknownField => {
                        (s.loc, format!("{}: {at}{}", path_of(s), problem.message))
                    }
                    // A problem that depends on the seed (a random placement that fails)
                    // names it.
                    Some(s) if matches!(problem.kind, ProblemKind::Overlap) => (
                        s.loc,
                        format!("{} (seed {seed}): {at}{}", what(s), problem.message),
                    ),
                    Some(s) => (s.loc, format!("{}: {at}{}", what(s), problem.message)),
                    None => (None, format!("{}: {at}{}", run(), problem.message)),
                }
            }))
            .collect(),
    }
}

/// Writes each run's world file (unchanged ones are left alone), the plan and a copy of the
/// sweep file into `dir`.
pub fn write(dir: &Path, ex: &Expanded, sweep_text: &str) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir)
        .map_err(|e| anyhow::anyhow!("cannot create the folder {}: {e}", dir.display()))?;
    for (r, text) in ex.plan.runs.iter().zip(&ex.worlds) {
        let rdir = run_dir(dir, &r.run);
        std::fs::create_dir_all(&rdir)
            .map_err(|e| anyhow::anyhow!("cannot create the folder {}: {e}", rdir.display()))?;
        write_if_changed(&rdir.join(WORLD), text)?;
    }
    write_if_changed(&dir.join("sweep.toml"), sweep_text)?;
    ex.plan.write(dir)
}

#[cfg(test)]
mod tests {
    use super::super::file::parse;
    use super::*;

    const BASE: &str = r#"name = "b"
duration = 2.0
[pool]
size = [10.0, 10.0, 3.0]
[[vehicles]]
name = "a"
count = 2
grid = { origin = [1.0, 1.0, 1.0], spacing = [1.0, 1.0], columns = 2 }
"#;

    /// Expands a sweep over `BASE`, in a folder of its own (tests run in parallel threads of
    /// one process: a shared base file could be read while another test rewrites it).
    fn sweep(body: &str) -> Result<Expanded, String> {
        static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("shoal_expand_{}_{call}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("base.toml"), BASE).unwrap();
        let text = format!("world = \"base.toml\"\n{body}\n[metrics]\nv = \"vehicles\"\n");
        let out = parse(&text, &dir.join("s.toml"))
            .map_err(|e| format!("parse: {e}"))
            .and_then(|s| expand(&s, "s.toml", 2));
        let _ = std::fs::remove_dir_all(&dir);
        out
    }

    #[test]
    fn runs_are_numbered_points_then_seeds_and_their_worlds_are_whole() {
        let ex = sweep("seeds = [5, 6]\n[grid]\nvehicles.0.count = [1, 3]\n").unwrap();
        let r = &ex.plan.runs;
        assert_eq!(r.len(), 4);
        assert_eq!(
            r.iter()
                .map(|r| (r.values[0].as_str(), r.seed))
                .collect::<Vec<_>>(),
            [("1", 5), ("1", 6), ("3", 5), ("3", 6)]
        );
        // Distinct worlds, named by their hash; each loads alone with its values.
        for (run, text) in r.iter().zip(&ex.worlds) {
            assert_eq!(run.run, hash_hex(text.as_bytes()));
            let d = load_str(text, Path::new("w")).unwrap();
            assert_eq!(d.seed, run.seed);
            assert_eq!(d.vehicles.len().to_string(), run.values[0]);
            assert!(!d.output.plots && !d.output.replay, "the run defaults");
        }
        let mut names: Vec<&str> = r.iter().map(|r| r.run.as_str()).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), 4);
        // The same sweep expands to the same runs; [set] can turn plots back on.
        let again = sweep("seeds = [5, 6]\n[grid]\nvehicles.0.count = [1, 3]\n").unwrap();
        assert_eq!(again.plan, ex.plan);
        let plots = sweep("[set]\noutput.plots = true\n[grid]\nvehicles.0.count = [1]\n").unwrap();
        assert!(
            load_str(&plots.worlds[0], Path::new("w"))
                .unwrap()
                .output
                .plots
        );
    }

    #[test]
    fn problems_point_at_the_sweep_lines_that_caused_them() {
        // An unknown field and a list entry the base world does not have, in one pass.
        let e = sweep("seeds = 1\n[grid]\nwater.attenuaton = [\"pool\"]\nvehicles.3.count = [1]\n")
            .unwrap_err();
        assert!(
            e.contains(
                "s.toml:4:7: `water.attenuaton`: unknown field `attenuaton` — did you mean \
                 `attenuation`?"
            ),
            "{e}"
        );
        assert!(
            e.contains("s.toml:5:12: `vehicles.3.count`: `vehicles` has 1 entry"),
            "{e}"
        );
        // A count that no longer fits the pool, only for the value that does not.
        let e = sweep("[grid]\nvehicles.0.count = [2, 40]\n").unwrap_err();
        assert!(e.contains("s.toml:3:12: `vehicles.0.count` = 40: "), "{e}");
        assert!(!e.contains("= 2:"), "{e}");
        // A value the world format refuses.
        let e = sweep("[grid]\ndt = [0.01, -1.0]\n").unwrap_err();
        assert!(e.contains("s.toml:3:1: `dt` = -1.0: "), "{e}");
        assert!(!e.contains("0.01"), "{e}");
    }

    /// The shipped sweeps expand, and so does every complete sweep file of docs/sweeps.md
    /// (read as if it were in worlds/sweeps/): the documentation cannot drift from the format.
    #[test]
    fn the_shipped_and_documented_sweeps_expand() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        for (file, runs) in [("smoke.toml", 8), ("study.toml", 160)] {
            let path = root.join("worlds/sweeps").join(file);
            let s = super::super::file::read(&path).unwrap();
            let ex = expand(&s, file, 2).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(ex.plan.runs.len(), runs, "{file}");
        }
        let docs = std::fs::read_to_string(root.join("docs/sweeps.md")).unwrap();
        let blocks: Vec<&str> = docs
            .split("```toml")
            .skip(1)
            .map(|b| b.split("```").next().unwrap_or(""))
            .collect();
        let mut complete = 0;
        for b in blocks {
            if b.contains("[metrics]") {
                let s = parse(b, &root.join("worlds/sweeps/docs.toml"))
                    .unwrap_or_else(|e| panic!("{e}\n{b}"));
                expand(&s, "docs.toml", 2).unwrap_or_else(|e| panic!("{e}\n{b}"));
                complete += 1;
            } else {
                // A fragment: valid TOML at least.
                toml::from_str::<toml::Table>(b).unwrap_or_else(|e| panic!("{e}\n{b}"));
            }
        }
        assert!(complete >= 1);
    }
}
