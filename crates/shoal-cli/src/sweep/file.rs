//! Sweep files: what to vary, how often, and what to collect (docs/sweeps.md).
//!
//! ```toml
//! name = "smoke"                  # optional: the file's stem
//! world = "../default.toml"       # relative to this file; omitted: the embedded default world
//! seeds = 2                       # seeds 0 and 1 (or a list: [3, 7]); omitted: the world's seed
//! [set]                           # the same in every run
//! duration = 5.0
//! [grid]                          # every combination; the first parameter varies slowest
//! vehicles.0.count = [2, 4]
//! water.attenuation = ["pool", "turbid_harbour"]
//! [metrics]                       # column name = path into summary.json
//! delivery_ratio = "comm.delivery_ratio"
//! ```
//!
//! Instead of `[grid]`, `[[points]]` lists the combinations one by one. Parameter paths may be
//! written as dotted keys (`vehicles.0.count = …`) or quoted (`"vehicles.0.count" = …`); both
//! mean the same path. Whether a path exists in the world format is decided when the sweep is
//! expanded (`super::expand`), by loading every run's world; this module checks the file's own
//! structure. Every problem is reported with the file, line and column, and all of them at once.

use super::metrics::{Metric, parse_metric};
use shoal_world::error::{FieldPath, SourceMap};
use shoal_world::load::{DEFAULT_WORLD, EMBEDDED_NAME};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Most seeds a sweep file may ask for with `seeds = N`.
pub const MAX_SEEDS: i64 = 100_000;
/// Most runs a sweep may expand into.
pub const MAX_RUNS: usize = 1_000_000;

/// Where something is written in the sweep file: 1-based line and column.
pub type Loc = Option<(usize, usize)>;

/// A path into the world file with the value(s) given for it.
#[derive(Clone, Debug)]
pub struct Param {
    /// Dotted path into the world file, as written (`vehicles.0.count`).
    pub path: String,
    /// The values, in the file's order (one for `[set]`).
    pub values: Vec<toml::Value>,
    /// Where the parameter is written.
    pub loc: Loc,
}

/// The runs' parameter values: a grid or a list of points.
#[derive(Clone, Debug)]
pub enum Design {
    /// Every combination of the parameters' values (the first varies slowest).
    Grid(Vec<Param>),
    /// The combinations as listed: the parameters (each with its location in the first
    /// point) and, per point, one value per parameter with where the point starts.
    Points {
        /// The parameters in the first point's order (`values` empty).
        params: Vec<Param>,
        /// Per point: the values in `params` order, and the point's location.
        points: Vec<(Vec<toml::Value>, Loc)>,
    },
}

impl Design {
    /// The varied parameters (paths and locations).
    pub fn params(&self) -> &[Param] {
        match self {
            Design::Grid(p) => p,
            Design::Points { params, .. } => params,
        }
    }

    /// Every combination, in run order: per point its values (in `params()` order).
    pub fn combinations(&self) -> Vec<Vec<toml::Value>> {
        match self {
            Design::Points { points, .. } => points.iter().map(|(v, _)| v.clone()).collect(),
            Design::Grid(params) => {
                let mut out: Vec<Vec<toml::Value>> = vec![Vec::new()];
                for p in params {
                    out = out
                        .into_iter()
                        .flat_map(|prefix| {
                            p.values.iter().map(move |v| {
                                let mut c = prefix.clone();
                                c.push(v.clone());
                                c
                            })
                        })
                        .collect();
                }
                out
            }
        }
    }
}

/// The base world of a sweep.
#[derive(Clone, Debug)]
pub struct Base {
    /// The world file (`None`: the embedded default world).
    pub path: Option<PathBuf>,
    /// Its text.
    pub text: String,
    /// Where `world` is written in the sweep file.
    pub loc: Loc,
}

impl Base {
    /// The name of the base world in messages.
    pub fn name(&self) -> PathBuf {
        self.path
            .clone()
            .unwrap_or_else(|| PathBuf::from(EMBEDDED_NAME))
    }
}

/// A parsed sweep file.
#[derive(Clone, Debug)]
pub struct SweepFile {
    /// The file.
    pub file: PathBuf,
    /// Its text (for locating problems found later).
    pub text: String,
    /// Name of the sweep.
    pub name: String,
    /// The base world.
    pub base: Base,
    /// The seeds (`None`: each run keeps the base world's seed).
    pub seeds: Option<Vec<u64>>,
    /// Changes made in every run (each with one value).
    pub set: Vec<Param>,
    /// The varied parameters.
    pub design: Design,
    /// The columns to collect from each run's summary.json.
    pub metrics: Vec<Metric>,
}

/// Collects located problems of one file.
pub struct Problems<'a> {
    file: &'a Path,
    sm: SourceMap<'a>,
    list: Vec<(Loc, String)>,
}

impl<'a> Problems<'a> {
    /// Problems of `file`, whose text is `text`.
    pub fn new(file: &'a Path, text: &'a str) -> Self {
        Self {
            file,
            sm: SourceMap::new(text),
            list: Vec::new(),
        }
    }

    /// Where the key at `keys` (a chain of table keys and array entries) is written.
    pub fn loc(&self, keys: &FieldPath) -> Loc {
        self.sm.locate(keys)
    }

    /// Records a problem at `loc`.
    pub fn at(&mut self, loc: Loc, message: impl Into<String>) {
        self.list.push((loc, message.into()));
    }

    /// Records a problem at the key `keys`.
    pub fn key(&mut self, keys: &FieldPath, message: impl Into<String>) {
        let loc = self.loc(keys);
        self.at(loc, message);
    }

    /// Whether any problem was recorded.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// Every problem, one a line, in file order: `file:line:col: message`.
    pub fn report(mut self) -> String {
        self.list.sort_by(|a, b| {
            (a.0.unwrap_or((usize::MAX, 0)), &a.1).cmp(&(b.0.unwrap_or((usize::MAX, 0)), &b.1))
        });
        self.list.dedup();
        self.list
            .iter()
            .map(|(loc, m)| match loc {
                Some((l, c)) => format!("{}:{l}:{c}: {m}", self.file.display()),
                None => format!("{}: {m}", self.file.display()),
            })
            .collect::<Vec<_>>()
            .join("\n")
    }
}

/// The top-level keys of a sweep file.
const TOP_KEYS: [&str; 8] = [
    "name",
    "description",
    "world",
    "seeds",
    "set",
    "grid",
    "points",
    "metrics",
];

fn kind(v: &toml::Value) -> &'static str {
    match v {
        toml::Value::String(_) => "text",
        toml::Value::Integer(_) => "an integer",
        toml::Value::Float(_) => "a number",
        toml::Value::Boolean(_) => "true/false",
        toml::Value::Datetime(_) => "a date",
        toml::Value::Array(_) => "a list",
        toml::Value::Table(_) => "a table",
    }
}

/// The parameters of a table of dotted paths: nested tables are walked (`a.b = 1` and
/// `"a.b" = 1` both give the path `a.b`); any other value ends a path. `at` is the table's
/// own key chain in the file.
fn flatten(table: &toml::Table, at: &FieldPath, out: &mut Vec<(String, toml::Value, FieldPath)>) {
    fn walk(
        t: &toml::Table,
        prefix: &str,
        keys: &FieldPath,
        out: &mut Vec<(String, toml::Value, FieldPath)>,
    ) {
        for (k, v) in t {
            let path = if prefix.is_empty() {
                k.clone()
            } else {
                format!("{prefix}.{k}")
            };
            let keys = keys.key(k);
            match v {
                toml::Value::Table(inner) => walk(inner, &path, &keys, out),
                other => out.push((path, other.clone(), keys)),
            }
        }
    }
    walk(table, "", at, out);
}

/// Checks a parameter path's form: dotted, no empty parts, not `seed` (that is `seeds`).
fn check_path(p: &mut Problems<'_>, path: &str, keys: &FieldPath) -> bool {
    if let Err(m) = shoal_world::overrides::split_path(path) {
        p.key(keys, m);
        return false;
    }
    if path == "seed" {
        p.key(
            keys,
            "the seed is not a parameter here: write `seeds = N` (seeds 0 … N−1) or \
             `seeds = [a, b, …]` at the top of the sweep file",
        );
        return false;
    }
    true
}

/// Whether one dotted path is the other or lies inside it.
pub fn overlaps(a: &str, b: &str) -> bool {
    let (short, long) = if a.len() <= b.len() { (a, b) } else { (b, a) };
    long == short || long.starts_with(&format!("{short}."))
}

/// Reads and checks a sweep file.
pub fn read(file: &Path) -> Result<SweepFile, String> {
    let text = std::fs::read_to_string(file)
        .map_err(|e| format!("{}: cannot read the sweep file: {e}", file.display()))?;
    parse(&text, file)
}

/// Parses a sweep file's text (`file` names it in messages and anchors a relative `world`).
pub fn parse(text: &str, file: &Path) -> Result<SweepFile, String> {
    let mut p = Problems::new(file, text);
    let doc: toml::Table = match toml::from_str(text) {
        Ok(d) => d,
        Err(e) => {
            let loc = e.span().map(|s| p.sm.line_col(s.start));
            p.at(
                loc,
                format!("not a valid TOML file: {}", e.message().trim_end()),
            );
            return Err(p.report());
        }
    };
    let root = FieldPath::root();
    for k in doc.keys() {
        if !TOP_KEYS.contains(&k.as_str()) {
            p.key(
                &root.key(k),
                format!(
                    "unknown key `{k}` (a sweep file has: {})",
                    TOP_KEYS.join(", ")
                ),
            );
        }
    }
    let name = match doc.get("name") {
        None => file
            .file_stem()
            .map_or_else(|| "sweep".into(), |s| s.to_string_lossy().into_owned()),
        Some(toml::Value::String(s)) if !s.trim().is_empty() => s.clone(),
        Some(v) => {
            p.key(
                &root.key("name"),
                format!("`name` is the sweep's name as text, not {}", kind(v)),
            );
            String::new()
        }
    };
    if let Some(v) = doc.get("description")
        && !v.is_str()
    {
        p.key(
            &root.key("description"),
            format!("`description` is text, not {}", kind(v)),
        );
    }
    let base = base_world(&doc, file, &mut p);
    let seeds_loc = p.loc(&root.key("seeds"));
    let seeds = doc.get("seeds").and_then(|v| seeds(v, seeds_loc, &mut p));
    let set = set_section(&doc, &mut p);
    let design = design(&doc, &mut p);
    let metrics = metrics(&doc, &mut p, design.as_ref());
    if let (Some(d), Some(s)) = (&design, &set) {
        for q in &s.clone() {
            for v in d.params() {
                if overlaps(&q.path, &v.path) {
                    p.at(
                        q.loc,
                        format!(
                            "`{}` is set in [set] and varied as `{}`: a path is either fixed \
                             or varied",
                            q.path, v.path
                        ),
                    );
                }
            }
        }
    }
    let runs = design
        .as_ref()
        .map_or(0, |d| d.combinations().len())
        .saturating_mul(seeds.as_ref().map_or(1, Vec::len));
    if runs > MAX_RUNS {
        p.at(
            None,
            format!("the sweep expands into {runs} runs; at most {MAX_RUNS} are allowed"),
        );
    }
    match (p.is_empty(), base, design, set, metrics) {
        (true, Some(base), Some(design), Some(set), Some(metrics)) => Ok(SweepFile {
            file: file.to_path_buf(),
            text: text.to_string(),
            name,
            base,
            seeds,
            set,
            design,
            metrics,
        }),
        _ => Err(p.report()),
    }
}

fn base_world(doc: &toml::Table, file: &Path, p: &mut Problems<'_>) -> Option<Base> {
    let keys = FieldPath::root().key("world");
    let loc = p.loc(&keys);
    match doc.get("world") {
        None => Some(Base {
            path: None,
            text: DEFAULT_WORLD.to_string(),
            loc,
        }),
        Some(toml::Value::String(rel)) => {
            let path = file.parent().unwrap_or_else(|| Path::new("")).join(rel);
            match std::fs::read_to_string(&path) {
                Ok(text) => Some(Base {
                    path: Some(path),
                    text,
                    loc,
                }),
                Err(e) => {
                    p.at(
                        loc,
                        format!(
                            "cannot read the world file {} (`world` is relative to the sweep \
                             file): {e}",
                            path.display()
                        ),
                    );
                    None
                }
            }
        }
        Some(v) => {
            p.at(
                loc,
                format!(
                    "`world` is the path of a world file (relative to the sweep file) as text, \
                     not {}; leave it out for the embedded default world",
                    kind(v)
                ),
            );
            None
        }
    }
}

fn seeds(v: &toml::Value, loc: Loc, p: &mut Problems<'_>) -> Option<Vec<u64>> {
    let bad = |p: &mut Problems<'_>, what: String| {
        p.at(
            loc,
            format!(
                "`seeds`: {what}; write a count (`seeds = 20`: seeds 0 … 19, at most \
                 {MAX_SEEDS}) or a list of distinct seeds ≥ 0 (`seeds = [3, 7]`)"
            ),
        );
        None
    };
    match v {
        toml::Value::Integer(n) if (1..=MAX_SEEDS).contains(n) => Some((0..*n as u64).collect()),
        toml::Value::Integer(n) => bad(p, format!("{n} is not a count from 1 to {MAX_SEEDS}")),
        toml::Value::Array(a) if !a.is_empty() => {
            let mut out = Vec::new();
            for x in a {
                match x.as_integer().and_then(|i| u64::try_from(i).ok()) {
                    Some(s) if !out.contains(&s) => out.push(s),
                    Some(s) => return bad(p, format!("seed {s} is listed twice")),
                    None => return bad(p, format!("{x} is not a seed")),
                }
            }
            Some(out)
        }
        other => bad(p, format!("{} is neither a count nor a list", kind(other))),
    }
}

fn set_section(doc: &toml::Table, p: &mut Problems<'_>) -> Option<Vec<Param>> {
    let keys = FieldPath::root().key("set");
    let Some(v) = doc.get("set") else {
        return Some(Vec::new());
    };
    let Some(t) = v.as_table() else {
        p.key(
            &keys,
            format!(
                "`set` is a table of world-file paths and values (`[set]`), not {}",
                kind(v)
            ),
        );
        return None;
    };
    let mut flat = Vec::new();
    flatten(t, &keys, &mut flat);
    let mut out = Vec::new();
    let mut ok = true;
    for (path, value, k) in flat {
        ok &= check_path(p, &path, &k);
        out.push(Param {
            path,
            values: vec![value],
            loc: p.loc(&k),
        });
    }
    ok.then_some(out)
}

fn design(doc: &toml::Table, p: &mut Problems<'_>) -> Option<Design> {
    let root = FieldPath::root();
    match (doc.get("grid"), doc.get("points")) {
        (Some(_), Some(_)) => {
            p.key(
                &root.key("points"),
                "a sweep has either [grid] (every combination) or [[points]] (combinations \
                 listed one by one), not both",
            );
            None
        }
        (None, None) => Some(Design::Grid(Vec::new())),
        (Some(g), None) => grid(g, p),
        (None, Some(pts)) => points(pts, p),
    }
}

fn grid(g: &toml::Value, p: &mut Problems<'_>) -> Option<Design> {
    let keys = FieldPath::root().key("grid");
    let Some(t) = g.as_table() else {
        p.key(
            &keys,
            format!(
                "`grid` is a table of world-file paths, each with a list of values (`[grid]`), \
                 not {}",
                kind(g)
            ),
        );
        return None;
    };
    let mut flat = Vec::new();
    flatten(t, &keys, &mut flat);
    let mut out = Vec::new();
    let mut ok = true;
    for (path, value, k) in flat {
        ok &= check_path(p, &path, &k);
        let values = match value {
            toml::Value::Array(a) if !a.is_empty() => a,
            other => {
                p.key(
                    &k,
                    format!(
                        "`{path}`: a [grid] parameter takes a non-empty list of values, e.g. \
                         `{path} = [10, 100]`, not {}",
                        kind(&other)
                    ),
                );
                ok = false;
                continue;
            }
        };
        for (i, v) in values.iter().enumerate() {
            if values[..i].contains(v) {
                p.key(&k, format!("`{path}`: the value {v} is listed twice"));
                ok = false;
            }
        }
        out.push(Param {
            path,
            values,
            loc: p.loc(&k),
        });
    }
    ok.then_some(Design::Grid(out))
}

fn points(pts: &toml::Value, p: &mut Problems<'_>) -> Option<Design> {
    let keys = FieldPath::root().key("points");
    let list = match pts.as_array() {
        Some(a) if !a.is_empty() && a.iter().all(toml::Value::is_table) => a,
        _ => {
            p.key(
                &keys,
                "`points` is a list of tables (`[[points]]`), each setting the same world-file \
                 paths",
            );
            return None;
        }
    };
    let mut params: Vec<Param> = Vec::new();
    let mut rows: Vec<(Vec<toml::Value>, Loc)> = Vec::new();
    let mut ok = true;
    for (i, item) in list.iter().enumerate() {
        let at = keys.index(i);
        let mut flat = Vec::new();
        if let Some(t) = item.as_table() {
            flatten(t, &at, &mut flat);
        }
        let first_loc = flat.first().and_then(|(_, _, k)| p.loc(k));
        if i == 0 {
            for (path, _, k) in &flat {
                ok &= check_path(p, path, k);
                params.push(Param {
                    path: path.clone(),
                    values: Vec::new(),
                    loc: p.loc(k),
                });
            }
        }
        let names: BTreeSet<&str> = flat.iter().map(|(n, ..)| n.as_str()).collect();
        let want: BTreeSet<&str> = params.iter().map(|q| q.path.as_str()).collect();
        if names != want {
            p.at(
                first_loc,
                format!(
                    "point {i} sets {}; the first point sets {}: every point sets the same paths",
                    list_of(&names),
                    list_of(&want)
                ),
            );
            ok = false;
            continue;
        }
        let values: Vec<toml::Value> = params
            .iter()
            .map(|q| {
                flat.iter()
                    .find(|(n, ..)| *n == q.path)
                    .map(|(_, v, _)| v.clone())
                    .unwrap_or(toml::Value::Boolean(false))
            })
            .collect();
        if let Some(j) = rows.iter().position(|(v, _)| *v == values) {
            p.at(first_loc, format!("point {i} repeats point {j}"));
            ok = false;
        }
        rows.push((values, first_loc));
    }
    ok.then_some(Design::Points {
        params,
        points: rows,
    })
}

fn list_of(names: &BTreeSet<&str>) -> String {
    if names.is_empty() {
        "nothing".into()
    } else {
        names
            .iter()
            .map(|n| format!("`{n}`"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The fixed columns of results.csv (a metric may not take one of these names).
pub const FIXED_COLUMNS: [&str; 7] = [
    "index", "run", "seed", "status", "error", "digest", "wall_s",
];

fn metrics(
    doc: &toml::Table,
    p: &mut Problems<'_>,
    design: Option<&Design>,
) -> Option<Vec<Metric>> {
    let keys = FieldPath::root().key("metrics");
    let Some(v) = doc.get("metrics") else {
        p.at(
            None,
            "the sweep collects no metric: add a [metrics] table, e.g. `delivery_ratio = \
             \"comm.delivery_ratio\"` (a column name and a path into summary.json)",
        );
        return None;
    };
    let Some(t) = v.as_table().filter(|t| !t.is_empty()) else {
        p.key(
            &keys,
            "`metrics` is a non-empty table of column names and paths into summary.json",
        );
        return None;
    };
    let mut out = Vec::new();
    let mut ok = true;
    for (name, spec) in t {
        let k = keys.key(name);
        let valid_name = name
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        if !valid_name {
            p.key(
                &k,
                format!(
                    "metric name `{name}`: use letters, digits and `_`, starting with a letter \
                     (it becomes a column of results.csv)"
                ),
            );
            ok = false;
            continue;
        }
        if FIXED_COLUMNS.contains(&name.as_str())
            || design.is_some_and(|d| d.params().iter().any(|q| q.path == *name))
        {
            p.key(
                &k,
                format!(
                    "metric name `{name}` is already a column of results.csv ({} and the \
                     parameters)",
                    FIXED_COLUMNS.join(", ")
                ),
            );
            ok = false;
            continue;
        }
        match parse_metric(name, spec) {
            Ok(m) => out.push(m),
            Err(m) => {
                p.key(&k, m);
                ok = false;
            }
        }
    }
    ok.then_some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        parse(text, Path::new("s.toml")).unwrap_err()
    }

    const METRICS: &str = "[metrics]\nd = \"comm.delivery_ratio\"\n";

    #[test]
    fn dotted_and_quoted_paths_are_the_same_and_grids_expand_in_order() {
        let s = parse(
            &format!(
                "seeds = 2\n[grid]\nvehicles.0.count = [1, 2]\n\"water.attenuation\" = [\"pool\", \
                 \"coastal\", 0.5]\n{METRICS}"
            ),
            Path::new("s.toml"),
        )
        .unwrap();
        let paths: Vec<&str> = s.design.params().iter().map(|q| q.path.as_str()).collect();
        assert_eq!(paths, ["vehicles.0.count", "water.attenuation"]);
        assert_eq!(s.design.params()[0].loc, Some((3, 12)));
        assert_eq!(s.design.params()[1].loc, Some((4, 1)));
        let c = s.design.combinations();
        assert_eq!(c.len(), 6);
        assert_eq!(c[0], [toml::Value::from(1), toml::Value::from("pool")]);
        assert_eq!(c[1], [toml::Value::from(1), toml::Value::from("coastal")]);
        assert_eq!(c[5], [toml::Value::from(2), toml::Value::from(0.5)]);
        assert_eq!(s.seeds, Some(vec![0, 1]));
        assert_eq!(s.name, "s");
        assert!(s.base.path.is_none());
    }

    #[test]
    fn points_list_combinations_and_must_agree() {
        let s = parse(
            &format!("[[points]]\na.b = 1\nc = \"x\"\n[[points]]\nc = \"y\"\na.b = 2\n{METRICS}"),
            Path::new("s.toml"),
        )
        .unwrap();
        assert_eq!(s.design.combinations().len(), 2);
        assert_eq!(
            s.design.combinations()[1],
            [toml::Value::from(2), toml::Value::from("y")]
        );
        let e = err(&format!(
            "[[points]]\na = 1\n[[points]]\nb = 2\n[[points]]\na = 1\n{METRICS}"
        ));
        assert!(
            e.contains("s.toml:4:1: point 1 sets `b`; the first point sets `a`"),
            "{e}"
        );
        assert!(e.contains("s.toml:6:1: point 2 repeats point 0"), "{e}");
    }

    #[test]
    fn every_problem_is_reported_with_its_line() {
        let e = err(
            "name = 3\nseeds = 0\nworlds = \"x\"\n[grid]\nseed = [1, 2]\n\"a..b\" = [1]\nc = 5\n\
             d = [1, 1]\n[set]\nd.e = 1\n[metrics]\nindex = \"seed\"\n",
        );
        for want in [
            "s.toml:1:1: `name` is the sweep's name as text, not an integer",
            "s.toml:2:1: `seeds`: 0 is not a count from 1 to 100000",
            "s.toml:3:1: unknown key `worlds` (a sweep file has: name,",
            "s.toml:5:1: the seed is not a parameter here",
            "s.toml:6:1: `a..b` is not a dotted path",
            "s.toml:7:1: `c`: a [grid] parameter takes a non-empty list of values",
            "s.toml:8:1: `d`: the value 1 is listed twice",
            "s.toml:12:1: metric name `index` is already a column",
        ] {
            assert!(e.contains(want), "missing «{want}» in\n{e}");
        }
        let e = err(&format!("[grid]\nd = [1]\n[set]\nd.e = 1\n{METRICS}"));
        assert!(
            e.contains("s.toml:4:3: `d.e` is set in [set] and varied as `d`"),
            "{e}"
        );
        let e = err("seeds = 2\n[grid\n");
        assert!(e.starts_with("s.toml:2:"), "{e}");
        let e = err("[grid]\na = [1]\n");
        assert!(e.contains("the sweep collects no metric"), "{e}");
        let e = err(&format!("world = \"nowhere.toml\"\n{METRICS}"));
        assert!(
            e.contains("s.toml:1:1: cannot read the world file nowhere.toml"),
            "{e}"
        );
    }

    #[test]
    fn overlapping_paths() {
        assert!(overlaps("a.b", "a.b"));
        assert!(overlaps("a", "a.b"));
        assert!(overlaps("a.b.c", "a.b"));
        assert!(!overlaps("a.bc", "a.b"));
    }
}
