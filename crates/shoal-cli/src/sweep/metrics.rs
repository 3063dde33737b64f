//! Metrics: columns of results.csv read from each run's `summary.json` by path.
//!
//! A path is dotted like a parameter path: keys, and for lists an entry number (negative from
//! the end: `-1` is the last) or `*` for every entry, which needs a `reduce` (`mean`, `min`,
//! `max`, `sum`). `divide_by` divides by another (single) value of the summary:
//!
//! ```toml
//! [metrics]
//! delivery_ratio_in_range = "comm.delivery_ratio"
//! final_largest = { path = "comm.connectivity.-1.largest", divide_by = "vehicles" }
//! mean_largest = { path = "comm.connectivity.*.largest", reduce = "mean", divide_by = "vehicles" }
//! impacts = { path = "groups.*.impacts", reduce = "sum" }
//! ```
//!
//! Paths are checked against [`SCHEMA`], the fields summary.json can have, when the sweep file
//! is read, so a typo is an error with its line before anything runs. A field that a run's
//! summary does not have (`comm` when no frame was sent, a `null` latency) leaves the cell
//! empty. A test runs real worlds and checks that every field their summaries have is in
//! [`SCHEMA`], so the list cannot fall behind the summary.

use serde_json::Value;

/// Every field of summary.json a metric may read, as dotted paths with `[]` where a list's
/// entries are (`comm.connectivity[].largest`). Text fields may be collected; only numbers
/// are reduced, divided and plotted. (External agents' fields are absent: sweeps run worlds
/// without agents.)
pub const SCHEMA: &[&str] = &[
    "world",
    "source",
    "seed",
    "vehicles",
    "threads",
    "dt_s",
    "steps",
    "simulated_s",
    "planned_s",
    "wall_s",
    "real_time_factor",
    "peak_memory_bytes",
    "interrupted",
    "failed",
    "signal",
    "output_error",
    "digest",
    "trajectory_rows",
    "parallel_dispatches.behaviour",
    "parallel_dispatches.vehicles",
    "parallel_dispatches.delivery",
    "parallel_dispatches.links",
    "parallel_dispatches.walk",
    "phases_s.ingest",
    "phases_s.vehicles",
    "phases_s.medium_snapshot",
    "phases_s.medium_transmit",
    "phases_s.medium_delivery",
    "phases_s.recorder",
    "phases_s.outputs",
    "groups[].name",
    "groups[].count",
    "groups[].mode",
    "groups[].mean_abs_depth_error_m",
    "groups[].mean_abs_yaw_error_deg",
    "groups[].mean_distance_m",
    "groups[].impacts",
    "files[]",
    "comm.attenuation_per_m",
    "comm.cutoff_range_m",
    "comm.frames_sent",
    "comm.queue_overflow",
    "comm.oversize",
    "comm.cs_deferrals",
    "comm.receptions.attempts",
    "comm.receptions.delivered",
    "comm.receptions.lost_range",
    "comm.receptions.lost_occlusion",
    "comm.receptions.lost_collision",
    "comm.receptions.lost_half_duplex",
    "comm.receptions.latency_sum_s",
    "comm.delivery_ratio",
    "comm.latency_mean_s",
    "comm.latency_median_s",
    "comm.latency_p95_s",
    "comm.mean_frame_bits",
    "comm.by_distance[].from_m",
    "comm.by_distance[].to_m",
    "comm.by_distance[].attempts",
    "comm.by_distance[].delivered",
    "comm.by_distance[].ratio",
    "comm.connectivity[].t",
    "comm.connectivity[].largest",
    "comm.connectivity[].components",
    "comm.connectivity[].edges",
    "comm.gossip.vehicles",
    "comm.gossip.informed",
    "comm.gossip.start_s",
    "comm.gossip.time_to_all_s",
    "comm.gossip.time_to_half_s",
    "comm.gossip.max_hops",
    "comm.gossip.mean_hops",
    "comm.gossip.mean_time_per_hop_s",
    "comm.gossip.informed_over_time[][]",
    "comm.link_layer.acknowledged",
    "comm.link_layer.gave_up",
    "comm.link_layer.delivery_after_retries",
    "comm.link_layer.retransmissions",
    "comm.link_layer.acks_sent",
    "comm.link_layer.latency_p50_s",
    "comm.link_layer.latency_p95_s",
    "comm.link_layer.latency_p99_s",
    "comm.link_layer.flows_total",
    "comm.link_layer.least_delivered.from",
    "comm.link_layer.least_delivered.to",
    "comm.link_layer.least_delivered.offered",
    "comm.link_layer.least_delivered.delivered",
    "comm.link_layer.least_delivered.delivery_ratio",
    "comm.link_layer.least_delivered.offered_bps",
    "comm.link_layer.least_delivered.goodput_bps",
    "comm.link_layer.least_delivered.acknowledged",
    "comm.link_layer.least_delivered.gave_up",
    "comm.link_layer.least_delivered.delivery_after_retries",
    "comm.link_layer.least_delivered.retransmissions",
    "comm.link_layer.least_delivered.latency_p50_s",
    "comm.link_layer.least_delivered.latency_p95_s",
    "comm.link_layer.least_delivered.latency_p99_s",
    "comm.link_layer.least_delivered.led_on_s",
    "comm.link_layer.least_delivered.led_energy_j",
    "comm.link_layer.flows[].from",
    "comm.link_layer.flows[].to",
    "comm.link_layer.flows[].offered",
    "comm.link_layer.flows[].delivered",
    "comm.link_layer.flows[].delivery_ratio",
    "comm.link_layer.flows[].offered_bps",
    "comm.link_layer.flows[].goodput_bps",
    "comm.link_layer.flows[].acknowledged",
    "comm.link_layer.flows[].gave_up",
    "comm.link_layer.flows[].delivery_after_retries",
    "comm.link_layer.flows[].retransmissions",
    "comm.link_layer.flows[].latency_p50_s",
    "comm.link_layer.flows[].latency_p95_s",
    "comm.link_layer.flows[].latency_p99_s",
    "comm.link_layer.flows[].led_on_s",
    "comm.link_layer.flows[].led_energy_j",
    "comm.led_on_s",
    "comm.led_energy_j",
];

/// What summary fields measure where their names alone would mislead, for the figures' axes:
/// (path, meaning). The delivery ratio counts only receptions by vehicles within the water's
/// cut-off range (`comm.cutoff_range_m`, 5.4 m in pool water, 1.4 m in a turbid harbour), so
/// it rises in turbid water, where only the nearest neighbours are in range.
pub const MEANINGS: &[(&str, &str)] = &[
    (
        "comm.delivery_ratio",
        "delivered / receptions by vehicles within the cut-off range",
    ),
    (
        "comm.receptions.attempts",
        "receptions by vehicles within the cut-off range",
    ),
];

/// The meaning of the summary field `path` from [`MEANINGS`], if it has one.
pub fn meaning(path: &str) -> Option<&'static str> {
    MEANINGS.iter().find(|(p, _)| *p == path).map(|(_, m)| *m)
}

/// How the entries selected by `*` become one value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Reduce {
    /// Arithmetic mean (empty: no value).
    Mean,
    /// Smallest (empty: no value).
    Min,
    /// Largest (empty: no value).
    Max,
    /// Sum (empty: 0).
    Sum,
}

impl Reduce {
    const NAMES: [(&'static str, Reduce); 4] = [
        ("mean", Reduce::Mean),
        ("min", Reduce::Min),
        ("max", Reduce::Max),
        ("sum", Reduce::Sum),
    ];

    fn apply(self, xs: &[f64]) -> Option<f64> {
        match self {
            Reduce::Sum => Some(xs.iter().sum()),
            _ if xs.is_empty() => None,
            Reduce::Mean => Some(xs.iter().sum::<f64>() / xs.len() as f64),
            Reduce::Min => xs.iter().copied().reduce(f64::min),
            Reduce::Max => xs.iter().copied().reduce(f64::max),
        }
    }
}

/// One column of results.csv.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Metric {
    /// Column name.
    pub name: String,
    /// Dotted path into summary.json.
    pub path: String,
    /// How `*` entries become one value.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reduce: Option<Reduce>,
    /// Dotted path of a number to divide by.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub divide_by: Option<String>,
}

/// One part of a metric path.
#[derive(Clone, Debug, PartialEq)]
enum Part {
    Key(String),
    /// Entry number; negative counts from the end.
    Entry(i64),
    All,
}

fn parts(path: &str) -> Result<Vec<Part>, String> {
    if path.is_empty() || path.split('.').any(str::is_empty) {
        return Err(format!(
            "`{path}` is not a dotted path into summary.json (e.g. `comm.delivery_ratio`)"
        ));
    }
    Ok(path
        .split('.')
        .map(|s| {
            if s == "*" {
                Part::All
            } else if let Ok(i) = s.parse::<i64>() {
                Part::Entry(i)
            } else {
                Part::Key(s.to_string())
            }
        })
        .collect())
}

/// Checks `path` against [`SCHEMA`]; returns whether it selects several entries (`*`).
fn check(path: &str) -> Result<bool, String> {
    let parts = parts(path)?;
    let mut prefix = String::new();
    let mut many = false;
    for part in &parts {
        let next = match part {
            Part::Key(k) if prefix.is_empty() => k.clone(),
            Part::Key(k) => format!("{prefix}.{k}"),
            Part::Entry(_) | Part::All => format!("{prefix}[]"),
        };
        let known = |p: &str| {
            SCHEMA.iter().any(|s| {
                *s == p || s.starts_with(&format!("{p}.")) || s.starts_with(&format!("{p}["))
            })
        };
        if !known(&next) {
            let here: Vec<String> = children(&prefix);
            return Err(match part {
                Part::Key(k) if here.iter().any(|c| c == "[]") => format!(
                    "`{path}`: `{}` is a list: after it comes an entry number (`0`, `-1` for \
                     the last) or `*` for every entry, not `{k}`",
                    display(&prefix)
                ),
                Part::Key(k) => format!(
                    "`{path}`: summary.json has no field `{k}`{} (there: {})",
                    if prefix.is_empty() {
                        String::new()
                    } else {
                        format!(" in `{}`", display(&prefix))
                    },
                    listed(&here)
                ),
                _ => format!(
                    "`{path}`: `{}` is not a list (its fields: {})",
                    display(&prefix),
                    listed(&here)
                ),
            });
        }
        many |= *part == Part::All;
        prefix = next;
    }
    if SCHEMA
        .iter()
        .any(|s| s.len() > prefix.len() && s.starts_with(&prefix))
    {
        return Err(format!(
            "`{path}` is not a single value of summary.json but holds {}",
            listed(&children(&prefix))
        ));
    }
    Ok(many)
}

/// The schema path `p` (with `[]`) as a user writes it.
fn display(p: &str) -> String {
    p.replace("[]", ".*")
}

/// The names one level below `prefix` in [`SCHEMA`] (`[]` for list entries).
fn children(prefix: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for s in SCHEMA {
        let rest = if prefix.is_empty() {
            Some(*s)
        } else {
            s.strip_prefix(prefix).and_then(|r| {
                r.strip_prefix('.')
                    .or_else(|| r.starts_with('[').then_some(r))
            })
        };
        let Some(rest) = rest else { continue };
        let name = if rest.starts_with("[]") {
            "[]".to_string()
        } else {
            rest.split(['.', '[']).next().unwrap_or("").to_string()
        };
        if !name.is_empty() && !out.contains(&name) {
            out.push(name);
        }
    }
    out
}

/// `names` as a list for messages (`[]` shown as `*`).
fn listed(names: &[String]) -> String {
    names
        .iter()
        .map(|n| format!("`{}`", if n == "[]" { "*" } else { n }))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Reads a metric from its sweep-file form: a path, or `{ path, reduce, divide_by }`.
pub fn parse_metric(name: &str, spec: &toml::Value) -> Result<Metric, String> {
    let (path, reduce, divide_by) = match spec {
        toml::Value::String(p) => (p.clone(), None, None),
        toml::Value::Table(t) => {
            for k in t.keys() {
                if !["path", "reduce", "divide_by"].contains(&k.as_str()) {
                    return Err(format!(
                        "metric `{name}`: unknown key `{k}` (allowed: path, reduce, divide_by)"
                    ));
                }
            }
            let Some(path) = t.get("path").and_then(toml::Value::as_str) else {
                return Err(format!(
                    "metric `{name}` needs `path`, a dotted path into summary.json as text"
                ));
            };
            let reduce = match t.get("reduce") {
                None => None,
                Some(toml::Value::String(r)) => match Reduce::NAMES.iter().find(|(n, _)| n == r) {
                    Some((_, red)) => Some(*red),
                    None => {
                        return Err(format!(
                            "metric `{name}`: reduce = \"{r}\" is not one of mean, min, max, sum"
                        ));
                    }
                },
                Some(_) => {
                    return Err(format!(
                        "metric `{name}`: `reduce` is one of \"mean\", \"min\", \"max\", \"sum\""
                    ));
                }
            };
            let divide_by = match t.get("divide_by") {
                None => None,
                Some(toml::Value::String(d)) => Some(d.clone()),
                Some(_) => {
                    return Err(format!(
                        "metric `{name}`: `divide_by` is a dotted path into summary.json as text"
                    ));
                }
            };
            (path.to_string(), reduce, divide_by)
        }
        _ => {
            return Err(format!(
                "metric `{name}`: write a path into summary.json as text, or a table \
                 `{{ path = \"…\", reduce = \"mean\", divide_by = \"…\" }}`"
            ));
        }
    };
    let many = check(&path).map_err(|m| format!("metric `{name}`: {m}"))?;
    match (many, reduce) {
        (true, None) => {
            return Err(format!(
                "metric `{name}`: `{path}` selects every entry of a list (`*`): add \
                 `reduce = \"mean\"` (or min, max, sum), e.g. `{name} = {{ path = \"{path}\", \
                 reduce = \"mean\" }}`"
            ));
        }
        (false, Some(_)) => {
            return Err(format!(
                "metric `{name}`: `reduce` needs a path with `*` (it combines a list's entries)"
            ));
        }
        _ => {}
    }
    if let Some(d) = &divide_by {
        match check(d) {
            Ok(false) => {}
            Ok(true) => {
                return Err(format!(
                    "metric `{name}`: divide_by `{d}` must be a single value, without `*`"
                ));
            }
            Err(m) => return Err(format!("metric `{name}`: divide_by {m}")),
        }
    }
    Ok(Metric {
        name: name.to_string(),
        path,
        reduce,
        divide_by,
    })
}

/// A collected value: a number, or text (`digest`, `world`, …).
#[derive(Clone, Debug, PartialEq)]
pub enum Cell {
    /// A number.
    Num(f64),
    /// Text or true/false.
    Text(String),
}

impl Cell {
    /// The value as results.csv writes it (numbers in the shortest form that reads back
    /// exactly).
    pub fn to_csv(&self) -> String {
        match self {
            Cell::Num(x) => format!("{x}"),
            Cell::Text(s) => s.clone(),
        }
    }
}

/// Every value `parts` selects in `v` (one without `*`); missing fields and `null`s select
/// nothing.
fn select<'a>(v: &'a Value, parts: &[Part], out: &mut Vec<&'a Value>) {
    let Some((first, rest)) = parts.split_first() else {
        if !v.is_null() {
            out.push(v);
        }
        return;
    };
    match (first, v) {
        (Part::Key(k), Value::Object(m)) => {
            if let Some(x) = m.get(k) {
                select(x, rest, out);
            }
        }
        (Part::Entry(i), Value::Array(a)) => {
            let idx = if *i < 0 {
                a.len().checked_sub(i.unsigned_abs() as usize)
            } else {
                Some(*i as usize)
            };
            if let Some(x) = idx.and_then(|j| a.get(j)) {
                select(x, rest, out);
            }
        }
        (Part::All, Value::Array(a)) => {
            for x in a {
                select(x, rest, out);
            }
        }
        _ => {}
    }
}

fn num(v: &Value) -> Option<f64> {
    v.as_f64()
}

/// The value of `m` in a summary (`None`: the summary does not have it).
pub fn extract(m: &Metric, summary: &Value) -> Option<Cell> {
    let p = parts(&m.path).ok()?;
    let mut found = Vec::new();
    select(summary, &p, &mut found);
    let value = match m.reduce {
        Some(r) => Cell::Num(r.apply(&found.iter().filter_map(|v| num(v)).collect::<Vec<_>>())?),
        None => match found.first()? {
            Value::Number(n) => Cell::Num(n.as_f64()?),
            Value::String(s) => Cell::Text(s.clone()),
            Value::Bool(b) => Cell::Text(b.to_string()),
            _ => return None,
        },
    };
    let Some(d) = &m.divide_by else {
        return Some(value);
    };
    let mut div = Vec::new();
    select(summary, &parts(d).ok()?, &mut div);
    let d = num(div.first()?)?;
    match value {
        Cell::Num(x) if d != 0.0 => Some(Cell::Num(x / d)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shoal_record::run::{Changes, Quiet, Ran, Run, load_world};
    use shoal_world::cancel::Cancel;

    /// Every leaf path of a JSON value in [`SCHEMA`]'s form (`[]` for list entries).
    fn leaf_paths(v: &Value) -> Vec<String> {
        fn walk(v: &Value, prefix: &str, out: &mut Vec<String>) {
            match v {
                Value::Object(m) => {
                    for (k, x) in m {
                        let p = if prefix.is_empty() {
                            k.clone()
                        } else {
                            format!("{prefix}.{k}")
                        };
                        walk(x, &p, out);
                    }
                }
                Value::Array(a) => {
                    for x in a {
                        walk(x, &format!("{prefix}[]"), out);
                    }
                }
                // `null` is a field the run does not have.
                Value::Null => {}
                _ => {
                    if !out.iter().any(|p| p == prefix) {
                        out.push(prefix.to_string());
                    }
                }
            }
        }
        let mut out = Vec::new();
        walk(v, "", &mut out);
        out
    }

    /// Every field the summaries of real runs have (communication, gossip, link layer, groups) is in
    /// SCHEMA, so a field added to summary.json cannot be missed by metric paths.
    #[test]
    fn the_schema_holds_every_field_of_real_summaries() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let tmp = std::env::temp_dir().join(format!("shoal_schema_{}", std::process::id()));
        let mut seen = Vec::new();
        for (world, seconds) in [
            ("worlds/gossip.toml", 4.0),
            ("worlds/default.toml", 3.0),
            ("worlds/reliable_gossip.toml", 4.0),
        ] {
            let changes = Changes {
                duration: Some(seconds),
                plots: Some(false),
                replay: Some(false),
                ..Changes::default()
            };
            let cancel = Cancel::new();
            let desc = load_world(Some(root.join(world).as_path()), &changes, &cancel).unwrap();
            let out = tmp.join(world.replace('/', "_"));
            let ran = Run::new(&desc, &out).execute(&mut Quiet, &cancel);
            assert!(matches!(ran, Ok(Ran::Finished { .. })));
            let text = std::fs::read_to_string(out.join("summary.json")).unwrap();
            let v: Value = serde_json::from_str(&text).unwrap();
            seen.extend(leaf_paths(&v));
        }
        let _ = std::fs::remove_dir_all(&tmp);
        assert!(seen.iter().any(|p| p == "comm.gossip.max_hops"), "{seen:?}");
        assert!(seen.iter().any(|p| p == "comm.connectivity[].largest"));
        assert!(seen.iter().any(|p| p == "comm.link_layer.latency_p99_s"));
        let missing: Vec<&String> = seen
            .iter()
            .filter(|p| !SCHEMA.contains(&p.as_str()))
            .collect();
        assert!(
            missing.is_empty(),
            "summary.json fields missing from SCHEMA: {missing:?}"
        );
    }

    fn metric(spec: &str) -> Result<Metric, String> {
        let v: toml::Table = toml::from_str(&format!("m = {spec}")).unwrap();
        parse_metric("m", &v["m"])
    }

    #[test]
    fn paths_are_checked_against_the_summary_fields() {
        assert!(metric("\"comm.delivery_ratio\"").is_ok());
        assert!(metric("\"comm.connectivity.-1.largest\"").is_ok());
        let e = metric("\"comm.delivery_rate\"").unwrap_err();
        assert!(
            e.contains("summary.json has no field `delivery_rate` in `comm`")
                && e.contains("delivery_ratio"),
            "{e}"
        );
        let e = metric("\"comm.connectivity.largest\"").unwrap_err();
        assert!(e.contains("`comm.connectivity` is a list"), "{e}");
        let e = metric("\"comm.receptions\"").unwrap_err();
        assert!(e.contains("is not a single value"), "{e}");
        let e = metric("\"comm.connectivity.*.largest\"").unwrap_err();
        assert!(e.contains("add `reduce = \"mean\"`"), "{e}");
        let e = metric("{ path = \"vehicles\", reduce = \"mean\" }").unwrap_err();
        assert!(e.contains("`reduce` needs a path with `*`"), "{e}");
        let e =
            metric("{ path = \"comm.frames_sent\", divide_by = \"groups.*.count\" }").unwrap_err();
        assert!(e.contains("must be a single value"), "{e}");
        let e = metric("{ path = \"x\", per = 1 }").unwrap_err();
        assert!(e.contains("unknown key `per`"), "{e}");
    }

    #[test]
    fn values_are_selected_reduced_and_divided() {
        let s: Value = serde_json::json!({
            "vehicles": 4,
            "digest": "ab12",
            "comm": {
                "delivery_ratio": 0.25,
                "latency_mean_s": null,
                "connectivity": [
                    {"largest": 1}, {"largest": 2}, {"largest": 4}
                ]
            },
            "groups": [{"impacts": 2}, {"impacts": 3}]
        });
        let get = |spec: &str| extract(&metric(spec).unwrap(), &s);
        assert_eq!(get("\"comm.delivery_ratio\""), Some(Cell::Num(0.25)));
        assert_eq!(get("\"digest\""), Some(Cell::Text("ab12".into())));
        assert_eq!(get("\"comm.latency_mean_s\""), None);
        assert_eq!(get("\"comm.gossip.max_hops\""), None);
        assert_eq!(
            get("{ path = \"comm.connectivity.-1.largest\", divide_by = \"vehicles\" }"),
            Some(Cell::Num(1.0))
        );
        assert_eq!(
            get(
                "{ path = \"comm.connectivity.*.largest\", reduce = \"mean\", divide_by = \"vehicles\" }"
            ),
            Some(Cell::Num(7.0 / 12.0))
        );
        assert_eq!(
            get("{ path = \"groups.*.impacts\", reduce = \"sum\" }"),
            Some(Cell::Num(5.0))
        );
        assert_eq!(
            get("{ path = \"groups.*.impacts\", reduce = \"max\" }"),
            Some(Cell::Num(3.0))
        );
        assert_eq!(get("\"comm.connectivity.-4.largest\""), None);
        assert_eq!(Cell::Num(0.1 + 0.2).to_csv(), "0.30000000000000004");
        assert_eq!(Cell::Num(12.0).to_csv(), "12");
    }
}
