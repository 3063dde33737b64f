//! Friendlier messages for what serde and TOML report: the problem's kind, the field's unit,
//! and a "did you mean" from the allowed names (edit distance, or the `_deg` form of a
//! unit-less name).

use crate::error::{FieldPath, Problem, ProblemKind, SourceMap};

pub(super) fn toml_problem(
    e: &toml::de::Error,
    path: Option<FieldPath>,
    sm: &SourceMap<'_>,
    default: ProblemKind,
) -> Problem {
    let line_col = e
        .span()
        .map(|s| sm.line_col(s.start))
        .or_else(|| path.as_ref().and_then(|p| sm.locate(p)));
    let (kind, message) = explain(e.message(), path.as_ref(), default);
    Problem {
        kind,
        field: path,
        line_col,
        message,
    }
}

/// Turns a serde message into a kind and a friendlier message with units and suggestions.
pub(super) fn explain(
    msg: &str,
    path: Option<&FieldPath>,
    default: ProblemKind,
) -> (ProblemKind, String) {
    let msg = msg.trim();
    if let Some(rest) = msg.strip_prefix("unknown field `") {
        let name = rest.split('`').next().unwrap_or("");
        let expected: Vec<&str> = rest
            .split_once("expected")
            .map(|(_, e)| e.split('`').skip(1).step_by(2).collect())
            .unwrap_or_default();
        let mut m = format!("unknown field `{name}`");
        if let Some(s) = suggest(name, &expected) {
            m.push_str(&format!(" — did you mean `{s}`?"));
        }
        if !expected.is_empty() {
            m.push_str(&format!(" (allowed here: {})", expected.join(", ")));
        }
        if let Some(hint) = moved_into_access(name) {
            m.push_str(&format!(" — {hint}"));
        }
        return (ProblemKind::UnknownField, m);
    }
    if msg.starts_with("missing field") {
        return (ProblemKind::MissingField, msg.to_string());
    }
    if let Some(rest) = msg.strip_prefix("unknown variant `") {
        let name = rest.split('`').next().unwrap_or("");
        let expected: Vec<&str> = rest
            .split_once("expected")
            .map(|(_, e)| e.split('`').skip(1).step_by(2).collect())
            .unwrap_or_default();
        let mut m = format!("unknown value `{name}`");
        if let Some(s) = suggest(name, &expected) {
            m.push_str(&format!(" — did you mean `{s}`?"));
        }
        m.push_str(&format!(" (allowed: {})", expected.join(", ")));
        return (ProblemKind::Reference, m);
    }
    if msg.starts_with("invalid type") || msg.starts_with("invalid length") {
        let unit = path.and_then(|p| p.last_key()).and_then(unit_of);
        let mut m = msg.to_string();
        if let Some(u) = unit {
            m = format!("{msg}; this field takes {u}");
            if msg.contains("string") {
                m.push_str(" — units are implied by the field name, not written in the value");
            }
        }
        return (ProblemKind::Type, m);
    }
    (default, msg.to_string())
}

pub(super) fn levenshtein(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1];
        for (j, cb) in b.iter().enumerate() {
            cur.push(
                (prev[j] + usize::from(ca != *cb))
                    .min(prev[j + 1] + 1)
                    .min(cur[j] + 1),
            );
        }
        prev = cur;
    }
    prev[b.len()]
}

/// The allowed name `name` was probably meant to be (its `_deg` form, or the nearest by edit
/// distance, within a third of its length), for a "did you mean" in messages.
pub fn suggest<'a>(name: &str, expected: &[&'a str]) -> Option<&'a str> {
    // A unit-less name whose `_deg` form exists: the classic wrong-unit mistake.
    if let Some(e) = expected.iter().find(|e| **e == format!("{name}_deg")) {
        return Some(e);
    }
    expected
        .iter()
        .map(|e| (levenshtein(name, e), *e))
        .filter(|(d, e)| *d <= (e.len() / 3).max(2))
        .min()
        .map(|(_, e)| e)
}

/// What a field's number means, for messages.
pub fn unit_of(key: &str) -> Option<&'static str> {
    Some(match key {
        "duration" | "t" | "dt" | "period" | "lag" | "rate_filter" => "a number in seconds",
        "size" | "position" | "origin" | "min" | "max" | "hull_size" | "cog" | "cob"
        | "spacing" => "numbers in metres",
        "radius" | "height" | "dead_zone" | "c2" | "depth_step" | "noise_std" => {
            "a number in metres"
        }
        "depth" => "a number in metres (depth of the pressure sensor, positive down)",
        "density" => "a number in kg/m³",
        "attenuation" => "a number in 1/m or a water type name",
        "current" => "numbers in m/s (north, east, down)",
        "mass" => "a number in kg",
        "volume" | "capacity" | "initial_volume" => "a number in m³",
        "flow" => "a number in m³/s",
        "surge" | "sway" => "a number in newtons",
        "rotation_deg" | "heading_deg" | "yaw_deg" | "min_deg" | "max_deg"
        | "auto_tilt_max_deg" | "attitude_noise_deg" => "a number in degrees",
        "rate_deg_s" => "a number in degrees per second",
        "seed" => "a whole number ≥ 0",
        "count" | "columns" | "filter_window" | "bits" => "a whole number",
        "record_hz" => "a number in Hz",
        "ct_pos" | "ct_neg" => "a number in N/%²",
        "max_command" => "a number in percent of full scale",
        "omega" => "a number in rad/s",
        "zeta" => "a dimensionless number",
        "c1" => "a number in m/V",
        "gyro_noise" | "gyro_bias" => "a number in rad/s",
        "accel_noise" => "a number in m/s²",
        "inertia" => "numbers in kg·m² (3 diagonal values or 3 rows)",
        "added_mass" => "numbers (6 diagonal values or 6 rows) in kg, kg·m, kg·m²",
        "damping_linear" | "damping_quadratic" => {
            "6 numbers (surge, sway, heave, roll, pitch, yaw)"
        }
        _ => return None,
    })
}

/// Where a modem's medium-access setting of older world files went: into the table of
/// `access` (renamed where its protocol's table names it otherwise).
fn moved_into_access(name: &str) -> Option<String> {
    let (kind, now) = match name {
        "cs_threshold" => ("carrier_sense", "threshold"),
        "backoff_max" => ("carrier_sense", "backoff_max"),
        "slot" | "clock_drift_ppm" => ("slotted_aloha", name),
        "tdma_slots" => ("tdma", "slots"),
        "tdma_slot" => ("tdma", "own_slot"),
        "backoff_slot" | "difs" | "cw_min" | "cw_max" => ("csma_ca", name),
        _ => return None,
    };
    Some(format!(
        "a medium-access setting goes in the table of `access`, e.g. \
         access = {{ kind = \"{kind}\", {now} = … }} (docs/mac.md)"
    ))
}
