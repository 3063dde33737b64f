//! Changing a world file by dotted paths, then validating the result like any world file.
//!
//! A path names a field the way a world file nests it, with array entries by number:
//! `vehicles.0.count`, `water.attenuation`, `vehicles.1.model.modems.0.led_power`,
//! `pool.size.2`. [`apply`] sets each path to its value in a copy of the base world's TOML
//! document, writes the copy out as a complete world file (so it can be run on its own) and
//! loads it with [`crate::load::load_str`]: unknown fields, wrong types, values out of range
//! and vehicles that no longer fit are found exactly as in a hand-written world file.
//!
//! Problems are traced back to the override that caused them ([`Located::by`]) by loading the
//! base world again with each override alone: the first override that brings the problem
//! back by itself is its cause, however far apart the fields are (`duration = 20` makes a
//! mission step at `t = 70` invalid). A problem that only a combination of overrides causes
//! names none. A caller with the overrides' own source lines (a sweep file) can then point at
//! them. The extra loading happens only for a world that fails.

use crate::cancel::{Cancel, Interrupted};
use crate::desc::WorldDesc;
use crate::error::{FieldPath, Problem, Seg, WorldError};
use crate::load::{LoadError, load_str, load_str_until};
use std::path::Path;

/// One change: set the field at `path` (dotted, e.g. `vehicles.0.count`) to `value`.
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    /// Dotted path into the world file.
    pub path: String,
    /// The new value (it replaces what the base world has there, tables included).
    pub value: toml::Value,
}

/// A world problem after the overrides, with the override it belongs to.
#[derive(Clone, Debug, PartialEq)]
pub struct Located {
    /// Index into the overrides given to [`apply`]: the first override that causes the
    /// problem when it is applied alone to the base world (`None`: only a combination does).
    pub by: Option<usize>,
    /// The problem as the world loader reported it. Its line and column refer to the written
    /// world text, not to a file the user wrote, so they are cleared.
    pub problem: Problem,
}

/// An override whose path does not lead anywhere in the base world (an array entry it does
/// not have, a field inside a plain value) or is not a dotted path at all.
#[derive(Clone, Debug, PartialEq)]
pub struct PathProblem {
    /// Index into the overrides given to [`apply`].
    pub index: usize,
    /// The path as given.
    pub path: String,
    /// What is wrong, with what exists there.
    pub message: String,
}

/// Why overrides could not be applied.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum OverrideError {
    /// Overrides that lead nowhere, and the problems of the world with the other overrides
    /// applied (so one pass reports everything).
    #[error("{}", .paths.iter().map(|p| format!("`{}`: {}", p.path, p.message)).chain(.world.iter().map(|p| p.problem.message.clone())).collect::<Vec<_>>().join("; "))]
    Problems {
        /// Overrides whose path leads nowhere (not applied).
        paths: Vec<PathProblem>,
        /// Problems of the changed world.
        world: Vec<Located>,
    },
    /// The changed document cannot be written as TOML (a value TOML cannot hold).
    #[error("cannot write the changed world as TOML: {0}")]
    Write(String),
}

/// A world file after overrides: its complete text and the validated world.
#[derive(Clone, Debug)]
pub struct Applied {
    /// The whole world file, runnable on its own.
    pub text: String,
    /// The world it describes.
    pub desc: WorldDesc,
}

/// The segments of a dotted path (`vehicles.0.count` → `vehicles`, `0`, `count`); empty
/// segments (`a..b`, a leading or trailing dot) are refused.
pub fn split_path(path: &str) -> Result<Vec<&str>, String> {
    let segs: Vec<&str> = path.split('.').collect();
    if path.is_empty() || segs.iter().any(|s| s.is_empty()) {
        return Err(format!(
            "`{path}` is not a dotted path (write it like `vehicles.0.count` or \
             `water.attenuation`)"
        ));
    }
    Ok(segs)
}

/// Sets `path` to `value` in `doc`, creating missing tables on the way (the loader then says
/// whether the world format knows them); returns the field path it resolved, with array
/// entries as indices.
pub fn set(doc: &mut toml::Table, path: &str, value: toml::Value) -> Result<FieldPath, String> {
    let segs = split_path(path)?;
    let mut resolved = FieldPath::root();
    let mut here = TableOrArray::Table(doc);
    for (k, seg) in segs.iter().enumerate() {
        let last = k + 1 == segs.len();
        here = match here {
            TableOrArray::Table(t) => {
                resolved = resolved.key(seg);
                if last {
                    t.insert((*seg).to_string(), value);
                    return Ok(resolved);
                }
                let entry = t
                    .entry((*seg).to_string())
                    .or_insert_with(|| toml::Value::Table(toml::Table::new()));
                descend(entry, &resolved)?
            }
            TableOrArray::Array(a) => {
                let Ok(i) = seg.parse::<usize>() else {
                    return Err(format!(
                        "`{resolved}` is a list: the next part of the path must be an entry \
                         number (0 … {}), not `{seg}`",
                        a.len().saturating_sub(1)
                    ));
                };
                if i >= a.len() {
                    return Err(format!(
                        "`{resolved}` has {} entr{} in the base world{}, so there is no entry {i}",
                        a.len(),
                        if a.len() == 1 { "y" } else { "ies" },
                        if a.is_empty() {
                            String::new()
                        } else {
                            format!(" (0 … {})", a.len() - 1)
                        }
                    ));
                }
                resolved = resolved.index(i);
                if last {
                    a[i] = value;
                    return Ok(resolved);
                }
                descend(&mut a[i], &resolved)?
            }
        };
    }
    // `split_path` never returns an empty list, and the loop returns at the last segment.
    Err(format!("`{path}` is empty"))
}

/// Where a path walk is: in a table or in an array.
enum TableOrArray<'a> {
    Table(&'a mut toml::Table),
    Array(&'a mut Vec<toml::Value>),
}

fn descend<'a>(v: &'a mut toml::Value, at: &FieldPath) -> Result<TableOrArray<'a>, String> {
    match v {
        toml::Value::Table(t) => Ok(TableOrArray::Table(t)),
        toml::Value::Array(a) => Ok(TableOrArray::Array(a)),
        other => Err(format!(
            "`{at}` is a value ({other}), not a table or a list, so nothing inside it can be \
             set"
        )),
    }
}

/// The problems of `base` with `overrides` applied (`None`: a path leads nowhere or the text
/// cannot be written).
fn problems_with(base: &toml::Table, overrides: &[&Override], file: &Path) -> Option<Vec<Problem>> {
    let mut doc = base.clone();
    for o in overrides {
        set(&mut doc, &o.path, o.value.clone()).ok()?;
    }
    let text = toml::to_string(&doc).ok()?;
    Some(
        load_str(&text, file)
            .err()
            .map_or_else(Vec::new, |e| e.problems),
    )
}

/// Applies `overrides` in order to `base` (a parsed world file) and validates the result as
/// the world file `file` (a name for messages). Overrides whose path leads nowhere are
/// reported and left out, and the world is still loaded with the others, so every problem is
/// found at once.
pub fn apply(
    base: &toml::Table,
    overrides: &[Override],
    file: &Path,
) -> Result<Applied, OverrideError> {
    let mut doc = base.clone();
    let mut applied = Vec::with_capacity(overrides.len());
    let mut paths = Vec::new();
    for (index, o) in overrides.iter().enumerate() {
        match set(&mut doc, &o.path, o.value.clone()) {
            Ok(_) => applied.push(index),
            Err(message) => paths.push(PathProblem {
                index,
                path: o.path.clone(),
                message,
            }),
        }
    }
    let text = toml::to_string(&doc).map_err(|e| OverrideError::Write(e.to_string()))?;
    match load_str(&text, file) {
        Ok(desc) if paths.is_empty() => Ok(Applied { text, desc }),
        Ok(_) => Err(OverrideError::Problems {
            paths,
            world: Vec::new(),
        }),
        Err(e) => {
            // Each override alone, loaded once, to see which problems it causes by itself.
            let alone: Vec<(usize, Vec<Problem>)> = applied
                .iter()
                .filter_map(|&i| Some((i, problems_with(base, &[&overrides[i]], file)?)))
                .collect();
            let same = |a: &Problem, b: &Problem| a.field == b.field && a.message == b.message;
            Err(OverrideError::Problems {
                paths,
                world: e
                    .problems
                    .into_iter()
                    .map(|mut problem| {
                        let by = alone
                            .iter()
                            .find(|(_, ps)| ps.iter().any(|p| same(p, &problem)))
                            .map(|(i, _)| *i);
                        problem.line_col = None;
                        Located { by, problem }
                    })
                    .collect(),
            })
        }
    }
}

/// Why [`load_until`] could not load a world.
#[derive(Debug, thiserror::Error)]
pub enum ChangedError {
    /// The world text itself has problems (they keep their lines and columns in the file).
    #[error(transparent)]
    World(#[from] WorldError),
    /// The text is a valid world, but not with the overrides: each problem with the override
    /// that causes it.
    #[error(transparent)]
    Overrides(#[from] OverrideError),
    /// A stop was asked for before the world was complete.
    #[error("interrupted while loading the world")]
    Interrupted(#[from] Interrupted),
}

impl From<LoadError> for ChangedError {
    fn from(e: LoadError) -> Self {
        match e {
            LoadError::World(e) => ChangedError::World(e),
            LoadError::Interrupted(i) => ChangedError::Interrupted(i),
        }
    }
}

/// The world file `text` (named `file` in messages and for its relative paths) with
/// `overrides` applied, loaded until `cancel` asks for a stop: what a run's own options (a
/// seed, a duration, …) make of a world file. Without overrides it is exactly
/// [`load_str_until`] of the text. A world that fails is checked again without the overrides,
/// so the problems of the file itself are reported with their lines and those the overrides
/// cause with the override ([`Located::by`]).
pub fn load_until(
    text: &str,
    file: &Path,
    overrides: &[Override],
    cancel: &Cancel,
) -> Result<WorldDesc, ChangedError> {
    if overrides.is_empty() {
        return Ok(load_str_until(text, file, cancel)?);
    }
    let base: toml::Table = match toml::from_str(text) {
        Ok(t) => t,
        // The loader says where the text is not TOML.
        Err(_) => return Ok(load_str_until(text, file, cancel)?),
    };
    let mut doc = base.clone();
    let mut paths = Vec::new();
    for (index, o) in overrides.iter().enumerate() {
        if let Err(message) = set(&mut doc, &o.path, o.value.clone()) {
            paths.push(PathProblem {
                index,
                path: o.path.clone(),
                message,
            });
        }
    }
    if paths.is_empty() {
        let changed = toml::to_string(&doc).map_err(|e| OverrideError::Write(e.to_string()))?;
        match load_str_until(&changed, file, cancel) {
            Ok(desc) => return Ok(desc),
            Err(LoadError::Interrupted(i)) => return Err(i.into()),
            Err(LoadError::World(_)) => {}
        }
    }
    // Something is wrong: the file's own problems first, with their lines.
    load_str_until(text, file, cancel)?;
    match apply(&base, overrides, file) {
        Err(e) => Err(e.into()),
        // (Not reached: the overrides failed above; the loader is deterministic.)
        Ok(applied) => Ok(applied.desc),
    }
}

/// The dotted form of a field path (`vehicles[0].count` → `vehicles.0.count`).
pub fn dotted(path: &FieldPath) -> String {
    path.0
        .iter()
        .map(|s| match s {
            Seg::Key(k) => k.clone(),
            Seg::Index(i) => i.to_string(),
        })
        .collect::<Vec<_>>()
        .join(".")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::ProblemKind;

    const BASE: &str = r#"
name = "base"
duration = 5.0
[pool]
size = [10.0, 10.0, 3.0]
[[vehicles]]
name = "a"
count = 2
grid = { origin = [1.0, 1.0, 1.0], spacing = [1.0, 1.0], columns = 2 }
[[vehicles]]
name = "b"
position = [5.0, 5.0, 1.0]
"#;

    fn base() -> toml::Table {
        toml::from_str(BASE).unwrap()
    }

    fn ov(path: &str, value: impl Into<toml::Value>) -> Override {
        Override {
            path: path.into(),
            value: value.into(),
        }
    }

    #[test]
    fn overrides_change_the_world_and_the_text_runs_alone() {
        let a = apply(
            &base(),
            &[
                ov("vehicles.0.count", 4),
                ov("water.attenuation", "coastal"),
                ov("pool.size.0", 12.0),
                ov("seed", 9),
            ],
            Path::new("t.toml"),
        )
        .unwrap();
        assert_eq!(a.desc.vehicles.len(), 5);
        assert_eq!(a.desc.seed, 9);
        assert_eq!(a.desc.geometry.pool.x, 12.0);
        assert!((a.desc.attenuation - 0.398).abs() < 1e-12);
        // The written text is a complete world: loading it again gives the same world.
        let again = load_str(&a.text, Path::new("again.toml")).unwrap();
        assert_eq!(again.vehicles.len(), 5);
        assert_eq!(again.seed, 9);
        assert_eq!(again.attenuation, a.desc.attenuation);
    }

    #[test]
    fn a_path_that_leads_nowhere_is_refused_with_what_is_there() {
        let path_problem = |o: Override| {
            let e = apply(&base(), &[ov("name", "x"), o], Path::new("t"));
            let Err(OverrideError::Problems { paths, world }) = e else {
                panic!("{e:?}")
            };
            assert!(world.is_empty(), "{world:?}");
            assert_eq!(paths.len(), 1);
            assert_eq!(paths[0].index, 1);
            paths[0].message.clone()
        };
        let m = path_problem(ov("vehicles.2.count", 1));
        assert!(
            m.contains("`vehicles` has 2 entries in the base world (0 … 1)"),
            "{m}"
        );
        let m = path_problem(ov("duration.x", 1));
        assert!(m.contains("`duration` is a value (5.0)"), "{m}");
        let m = path_problem(ov("vehicles.first.count", 1));
        assert!(m.contains("must be an entry number (0 … 1)"), "{m}");
        // A path that leads nowhere does not hide the world's problems.
        let e = apply(
            &base(),
            &[ov("vehicles.5.count", 1), ov("dt", -1.0)],
            Path::new("t"),
        );
        let Err(OverrideError::Problems { paths, world }) = e else {
            panic!("{e:?}")
        };
        assert_eq!(paths.len(), 1);
        assert!(world.iter().any(|p| p.by == Some(1)), "{world:?}");
        assert!(split_path("a..b").is_err() && split_path("").is_err());
    }

    #[test]
    fn world_problems_point_at_the_override_that_caused_them() {
        // An unknown field, a value out of range and a group that no longer fits.
        let e = apply(
            &base(),
            &[
                ov("water.attenuaton", "pool"),
                ov("dt", -1.0),
                ov("name", "x"),
            ],
            Path::new("t"),
        );
        let Err(OverrideError::Problems {
            world: problems, ..
        }) = e
        else {
            panic!("{e:?}")
        };
        let unknown = problems
            .iter()
            .find(|p| p.problem.kind == ProblemKind::UnknownField)
            .unwrap();
        assert_eq!(unknown.by, Some(0));
        assert!(
            unknown.problem.message.contains("attenuation"),
            "{:?}",
            unknown.problem
        );
        assert!(problems.iter().all(|p| p.problem.line_col.is_none()));
        let e = apply(&base(), &[ov("dt", -1.0)], Path::new("t"));
        let Err(OverrideError::Problems {
            world: problems, ..
        }) = e
        else {
            panic!("{e:?}")
        };
        assert!(
            problems
                .iter()
                .any(|p| p.by == Some(0) && p.problem.kind == ProblemKind::Range),
            "{problems:?}"
        );
        // A problem far from the override that causes it: a shorter duration makes a mission
        // step too late.
        let mut b = base();
        set(
            &mut b,
            "vehicles.0.mission",
            toml::Value::Array(vec![toml::Value::Table(
                toml::from_str("t = 4.0\nmode = \"diving\"").unwrap(),
            )]),
        )
        .unwrap();
        let e = apply(
            &b,
            &[ov("vehicles.0.count", 2), ov("duration", 3.0)],
            Path::new("t"),
        );
        let Err(OverrideError::Problems {
            world: problems, ..
        }) = e
        else {
            panic!("{e:?}")
        };
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert_eq!(problems[0].by, Some(1), "{problems:?}");
        // 40 vehicles on a 2-column grid at 1 m run out of the 10 m pool.
        let e = apply(&base(), &[ov("vehicles.0.count", 40)], Path::new("t"));
        let Err(OverrideError::Problems {
            world: problems, ..
        }) = e
        else {
            panic!("{e:?}")
        };
        assert!(problems.iter().any(|p| p.by == Some(0)), "{problems:?}");
    }

    #[test]
    fn dotted_paths_round_trip() {
        let p = FieldPath::root().key("vehicles").index(3).key("count");
        assert_eq!(dotted(&p), "vehicles.3.count");
    }
}
