//! The mapping file: which topic and field of a bag feed each input and channel of a run.
//!
//! ```toml
//! [defaults]
//! namespace = "/auv1"     # topics not starting with `/` are under it (`imu` → `/auv1/imu`)
//! clock = "header"        # or "log"; per entry as well (default: header when the type has one)
//! frame = "enu"           # ROS's REP 103 (x forward, y left, z up); or "ned" as shoal
//!
//! [inputs]
//! "u.port" = { topic = "/thrusters", field = "data[1]", scale = 0.25, offset = -375.0 }
//!
//! [channels]
//! "y.depth" = { topic = "/pressure", field = "fluid_pressure",
//!               depth_from_pressure = { density_kg_m3 = 998.0, surface_pa = 101325.0 } }
//! "y.yaw"   = { topic = "/imu", field = "orientation" }     # a quaternion → the channel's angle
//! "y.r"     = { topic = "/imu", field = "angular_velocity.z" }
//!
//! [references]            # optional: what the vehicle's controller was told
//! "r.depth" = { topic = "/setpoints", field = "depth" }
//! "r.mode"  = { topic = "/setpoints", field = "mode" }     # the mode's code, 0 … 6
//! ```
//!
//! * `inputs`: `u.<actuator>` as in a CSV run (the vehicle's thrusters, tilt drives, `pump`);
//!   `channels`: `y.<channel>` (`depth roll pitch yaw p q r x y u v w`); `references`: the
//!   controller's references `r.<reference>` as in a CSV run (`depth yaw surge sway mode`,
//!   [`ReferenceKind::ALL`]), held like inputs; `r.mode` is a number field holding the mode's
//!   code (`shoal_model::control::Mode::code`: 0 off, 1 diving … 5 auto, 6 raw) — a value
//!   that is not one is an error naming the message.
//! * `field`: a path into the message (`crate::select`): a number, or for `y.roll`, `y.pitch`
//!   and `y.yaw` a quaternion.
//! * value = `scale` × field + `offset` (defaults 1 and 0), in shoal's units (% for thruster
//!   commands, rad, m, m/s, −1/0/+1 for the pump, N for force references); `depth_from_pressure` instead turns an
//!   absolute pressure in Pa into a depth: (p − surface_pa)/(density_kg_m3 · gravity_m_s2).
//! * `clock`: `header` takes the message's `header.stamp` (the time the sensor sampled),
//!   `log` the time the bag received it; the default is `header` for types that have one.
//! * `frame`: `enu` (ROS's convention, REP 103: body x forward, y left, z up; world east,
//!   north, up) or `ned` (shoal's: body x forward, y right, z down; world north, east, down).
//!   With `enu`, attitudes from quaternions become shoal's roll, pitch, yaw (roll = roll,
//!   pitch = −pitch, yaw = π/2 − yaw) and the body rates and velocities about or along y and
//!   z change sign (`y.q`, `y.r`, `y.v`, `y.w`); positions are taken as written (map the
//!   north coordinate to `y.x`, the east one to `y.y`), and so are references (`r.depth`
//!   positive down and `r.yaw` in shoal's NED heading: convert with `scale` and `offset`).
//!
//! Every problem names the file, the entry and the allowed values; unknown keys are errors.

use serde::Deserialize;
use shoal_sysid::log::run::{ChannelKind, ReferenceKind};
use shoal_world::load::suggest;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Which time a message is placed at.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Clock {
    /// The message's `header.stamp`.
    Header,
    /// The bag's receive time (MCAP log time).
    Log,
}

/// The axes a message's attitudes, rates and velocities are written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Frame {
    /// ROS's REP 103: body forward-left-up, world east-north-up.
    Enu,
    /// shoal's: body forward-right-down, world north-east-down.
    Ned,
}

/// What an entry feeds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feeds {
    /// An input column (`u.`).
    Input,
    /// A measurement channel.
    Channel(ChannelKind),
    /// A reference of the vehicle's controller (`r.`).
    Reference(ReferenceKind),
}

/// One mapping entry, checked.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    /// Its key, e.g. `u.port` or `y.depth`.
    pub key: String,
    /// What it feeds.
    pub feeds: Feeds,
    /// The topic.
    pub topic: String,
    /// The field path in the topic's messages.
    pub field: String,
    /// Multiplier from the field's value to shoal's unit.
    pub scale: f64,
    /// Added after scaling (shoal's unit).
    pub offset: f64,
    /// The clock asked for (`None`: the type's default).
    pub clock: Option<Clock>,
    /// The axes of attitudes, rates and velocities.
    pub frame: Frame,
}

/// A checked mapping file.
#[derive(Clone, Debug, PartialEq)]
pub struct Mapping {
    /// The file (for messages).
    pub path: PathBuf,
    /// Inputs, then channels, then references, each sorted by key.
    pub entries: Vec<Entry>,
}

/// A problem with a mapping file.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}: {message}", file.display())]
pub struct MappingError {
    /// The mapping file.
    pub file: PathBuf,
    /// What is wrong, naming the entry and what is allowed.
    pub message: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileDoc {
    #[serde(default)]
    defaults: DefaultsDoc,
    #[serde(default)]
    inputs: BTreeMap<String, EntryDoc>,
    #[serde(default)]
    channels: BTreeMap<String, EntryDoc>,
    #[serde(default)]
    references: BTreeMap<String, EntryDoc>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct DefaultsDoc {
    namespace: Option<String>,
    clock: Option<Clock>,
    frame: Option<Frame>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct EntryDoc {
    topic: String,
    field: String,
    scale: Option<f64>,
    offset: Option<f64>,
    clock: Option<Clock>,
    frame: Option<Frame>,
    depth_from_pressure: Option<PressureDoc>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PressureDoc {
    density_kg_m3: f64,
    #[serde(default = "surface")]
    surface_pa: f64,
    #[serde(default = "gravity")]
    gravity_m_s2: f64,
}

fn surface() -> f64 {
    101_325.0
}
fn gravity() -> f64 {
    9.80665
}

/// Allowed water density for `depth_from_pressure` \[kg/m³\].
pub const DENSITY_RANGE: (f64, f64) = (900.0, 1100.0);
/// Allowed surface pressure \[Pa\].
pub const SURFACE_RANGE: (f64, f64) = (0.0, 200_000.0);
/// Allowed gravity \[m/s²\].
pub const GRAVITY_RANGE: (f64, f64) = (9.7, 9.9);

impl Mapping {
    /// Reads and checks a mapping file.
    pub fn read(path: &Path) -> Result<Mapping, MappingError> {
        let text = std::fs::read_to_string(path).map_err(|e| MappingError {
            file: path.to_path_buf(),
            message: format!("cannot read the mapping file: {e}"),
        })?;
        Mapping::parse(&text, path)
    }

    /// Parses and checks mapping text; `path` names it in messages.
    pub fn parse(text: &str, path: &Path) -> Result<Mapping, MappingError> {
        let err = |message: String| MappingError {
            file: path.to_path_buf(),
            message,
        };
        let doc: FileDoc = toml::from_str(text).map_err(|e| err(e.to_string()))?;
        let mut entries = Vec::new();
        for (key, e) in &doc.inputs {
            let Some(name) = key.strip_prefix("u.").filter(|n| !n.is_empty()) else {
                return Err(err(format!(
                    "[inputs] `{key}`: an input is named `u.<actuator>` (e.g. `u.port`, \
                     `u.pump`), as in a CSV run"
                )));
            };
            let _ = name;
            entries.push(entry(key, Feeds::Input, e, &doc.defaults).map_err(&err)?);
        }
        for (key, e) in &doc.channels {
            let kind = key
                .strip_prefix("y.")
                .and_then(ChannelKind::from_name)
                .ok_or_else(|| {
                    let names = ChannelKind::ALL.iter().map(|(_, n)| *n);
                    err(not_one_of("channels", key, "a channel", "y.", names))
                })?;
            entries.push(entry(key, Feeds::Channel(kind), e, &doc.defaults).map_err(&err)?);
        }
        for (key, e) in &doc.references {
            let kind = key
                .strip_prefix("r.")
                .and_then(ReferenceKind::from_name)
                .ok_or_else(|| {
                    let names = ReferenceKind::ALL.iter().map(|(_, n, _)| *n);
                    err(not_one_of("references", key, "a reference", "r.", names))
                })?;
            entries.push(entry(key, Feeds::Reference(kind), e, &doc.defaults).map_err(&err)?);
        }
        if !entries.iter().any(|e| matches!(e.feeds, Feeds::Channel(_))) {
            return Err(err(
                "no [channels]: map at least one measurement, e.g. `\"y.depth\" = { topic = \
                 \"/pressure\", field = \"fluid_pressure\", depth_from_pressure = { \
                 density_kg_m3 = 998.0 } }`"
                    .into(),
            ));
        }
        Ok(Mapping {
            path: path.to_path_buf(),
            entries,
        })
    }

    /// The topics the mapping reads, sorted, each once.
    pub fn topics(&self) -> Vec<&str> {
        let mut t: Vec<&str> = self.entries.iter().map(|e| e.topic.as_str()).collect();
        t.sort_unstable();
        t.dedup();
        t
    }
}

/// "[channels] `y.dpth`: not a channel — did you mean `y.depth`? (allowed: y.depth, …)".
fn not_one_of<'a>(
    section: &str,
    key: &str,
    what: &str,
    prefix: &str,
    names: impl Iterator<Item = &'a str>,
) -> String {
    let names: Vec<String> = names.map(|n| format!("{prefix}{n}")).collect();
    let all: Vec<&str> = names.iter().map(String::as_str).collect();
    let hint = suggest(key, &all)
        .map(|s| format!(" — did you mean `{s}`?"))
        .unwrap_or_default();
    format!(
        "[{section}] `{key}`: not {what}{hint} (allowed: {})",
        names.join(", ")
    )
}

fn entry(key: &str, feeds: Feeds, e: &EntryDoc, d: &DefaultsDoc) -> Result<Entry, String> {
    let (mut scale, mut offset) = (e.scale.unwrap_or(1.0), e.offset.unwrap_or(0.0));
    for (name, v) in [("scale", scale), ("offset", offset)] {
        if !v.is_finite() {
            return Err(format!("`{key}`: {name} = {v}: allowed a finite number"));
        }
    }
    if scale == 0.0 {
        return Err(format!(
            "`{key}`: scale = 0 would make every value the offset"
        ));
    }
    if e.topic.trim().is_empty() || e.field.trim().is_empty() {
        return Err(format!("`{key}`: topic and field must not be empty"));
    }
    let topic = match (&d.namespace, e.topic.starts_with('/')) {
        (_, true) => e.topic.clone(),
        (Some(ns), false) => format!("/{}/{}", ns.trim_matches('/'), e.topic),
        (None, false) => format!("/{}", e.topic),
    };
    if let Some(p) = &e.depth_from_pressure {
        if feeds != Feeds::Channel(ChannelKind::Depth) {
            return Err(format!(
                "`{key}`: depth_from_pressure is for `y.depth` only (use scale and offset)"
            ));
        }
        if e.scale.is_some() || e.offset.is_some() {
            return Err(format!(
                "`{key}`: give either depth_from_pressure or scale/offset, not both"
            ));
        }
        for (name, v, (lo, hi)) in [
            ("density_kg_m3", p.density_kg_m3, DENSITY_RANGE),
            ("surface_pa", p.surface_pa, SURFACE_RANGE),
            ("gravity_m_s2", p.gravity_m_s2, GRAVITY_RANGE),
        ] {
            if !(lo..=hi).contains(&v) {
                return Err(format!(
                    "`{key}`: depth_from_pressure.{name} = {v}: allowed {lo} … {hi}"
                ));
            }
        }
        scale = 1.0 / (p.density_kg_m3 * p.gravity_m_s2);
        offset = -p.surface_pa * scale;
    }
    Ok(Entry {
        key: key.to_string(),
        feeds,
        topic,
        field: e.field.trim().to_string(),
        scale,
        offset,
        clock: e.clock.or(d.clock),
        frame: e.frame.or(d.frame).unwrap_or(Frame::Enu),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(t: &str) -> Result<Mapping, MappingError> {
        Mapping::parse(t, Path::new("m.toml"))
    }

    #[test]
    fn a_mapping_with_pressure_and_pwm() {
        let m = parse(
            "[defaults]\nclock = \"log\"\n[inputs]\n\"u.port\" = { topic = \"/t\", field = \
             \"data[1]\", scale = 0.25, offset = -375.0 }\n[channels]\n\"y.depth\" = { topic \
             = \"/p\", field = \"fluid_pressure\", clock = \"header\", depth_from_pressure = { \
             density_kg_m3 = 1000.0, surface_pa = 100000.0, gravity_m_s2 = 9.8 } }\n",
        )
        .unwrap();
        assert_eq!(m.entries.len(), 2);
        let port = &m.entries[0];
        // 1900 µs → 100 %, 1500 µs → 0 %.
        assert_eq!(1900.0 * port.scale + port.offset, 100.0);
        assert_eq!(port.clock, Some(Clock::Log));
        let depth = &m.entries[1];
        // 100 000 Pa + 1000·9.8·2 Pa → 2 m.
        assert!((119_600.0 * depth.scale + depth.offset - 2.0).abs() < 1e-12);
        assert_eq!(depth.clock, Some(Clock::Header));
        assert_eq!(depth.frame, Frame::Enu);
        assert_eq!(m.topics(), ["/p", "/t"]);
    }

    #[test]
    fn relative_topics_are_under_the_namespace() {
        let m = parse(
            "[defaults]\nnamespace = \"/auv1/\"\n[channels]\n\"y.r\" = { topic = \"imu\", \
             field = \"angular_velocity.z\" }\n\"y.yaw\" = { topic = \"/tracker/imu\", field = \
             \"orientation\" }\n",
        )
        .unwrap();
        assert_eq!(m.topics(), ["/auv1/imu", "/tracker/imu"]);
    }

    #[test]
    fn mistakes_are_named() {
        let cases = [
            (
                "[channels]\n\"y.dpth\" = { topic = \"/p\", field = \"a\" }\n",
                "not a channel",
            ),
            (
                "[inputs]\nport = { topic = \"/p\", field = \"a\" }\n",
                "`u.<actuator>`",
            ),
            (
                "[inputs]\n\"u.a\" = { topic = \"/p\", field = \"a\" }\n",
                "no [channels]",
            ),
            (
                "[channels]\n\"y.r\" = { topic = \"/p\", feld = \"a\" }\n",
                "unknown field `feld`",
            ),
            (
                "[channels]\n\"y.r\" = { topic = \"/p\", field = \"a\", clock = \"wall\" }\n",
                "unknown variant `wall`",
            ),
            (
                "[channels]\n\"y.r\" = { topic = \"/p\", field = \"a\", \
                 depth_from_pressure = { density_kg_m3 = 1000.0 } }\n",
                "for `y.depth` only",
            ),
            (
                "[channels]\n\"y.depth\" = { topic = \"/p\", field = \"a\", \
                 depth_from_pressure = { density_kg_m3 = 10.0 } }\n",
                "allowed 900 … 1100",
            ),
            (
                "[channels]\n\"y.r\" = { topic = \"/p\", field = \"a\", scale = 0.0 }\n",
                "scale = 0",
            ),
        ];
        for (text, want) in cases {
            let e = parse(text).unwrap_err();
            assert!(e.to_string().contains(want), "{text}: {e}");
            assert!(e.to_string().starts_with("m.toml: "), "{e}");
        }
    }
}
