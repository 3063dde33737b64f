//! World files → [`WorldDesc`]: parse (serde with field paths), merge vehicle overrides over
//! presets, validate every number against its allowed range, expand vehicle groups, place
//! them, and reject overlaps and vehicles outside the pool. User input never panics: every
//! problem becomes a [`Problem`] naming the file, line/column and field.

use crate::cancel::{Cancel, Interrupted};
use crate::desc::{AgentsDesc, OutputDesc, VehicleDesc, WorldDesc};
use crate::error::{FieldPath, Problem, ProblemKind, SourceMap, WorldError};
use crate::geometry::{Geometry, hull_shape, hulls_intersect, to_pose};
use crate::spec::*;
use parry3d_f64::shape::SharedShape;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use shoal_model::optics::Ambient;
use shoal_model::prelude::*;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The embedded default world (`worlds/default.toml`): a small swarm in a pool.
pub const DEFAULT_WORLD: &str = include_str!("../../../worlds/default.toml");
/// Name used in messages for the embedded default world.
pub const EMBEDDED_NAME: &str = "<embedded default world>";

/// Why a world could not be loaded when loading may be stopped early.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file is unreadable or invalid.
    #[error(transparent)]
    World(#[from] WorldError),
    /// A stop was asked for (through the [`Cancel`] given) before the world was complete.
    #[error("interrupted while loading the world")]
    Interrupted(#[from] Interrupted),
}

/// Loads and validates a world file.
pub fn load_file(path: &Path) -> Result<WorldDesc, WorldError> {
    never_interrupted(load_file_until(path, &Cancel::new()))
}

/// [`load_file`] that gives up with [`LoadError::Interrupted`] once `cancel` asks it to (it
/// looks before each vehicle group, vehicle placement and overlap check, so even worlds of
/// 10⁶ vehicles stop within moments).
pub fn load_file_until(path: &Path, cancel: &Cancel) -> Result<WorldDesc, LoadError> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        WorldError::single(
            path,
            Problem {
                kind: ProblemKind::Io,
                field: None,
                line_col: None,
                message: format!("cannot read the file: {e}"),
            },
        )
    })?;
    load_str_until(&text, path, cancel)
}

/// The result of loading with a [`Cancel`] nobody else can reach.
fn never_interrupted(r: Result<WorldDesc, LoadError>) -> Result<WorldDesc, WorldError> {
    match r {
        Ok(desc) => Ok(desc),
        Err(LoadError::World(e)) => Err(e),
        Err(LoadError::Interrupted(_)) => unreachable!("a private Cancel is never requested"),
    }
}

/// The embedded default world.
pub fn default_world() -> Result<WorldDesc, WorldError> {
    load_str(DEFAULT_WORLD, Path::new(EMBEDDED_NAME))
}

/// A vehicle model taken from a world file: the merged model of its first vehicle group and
/// the world's water.
#[derive(Clone, Debug)]
pub struct VehicleFile {
    /// The model in file form (preset and overrides merged).
    pub spec: VehicleSpec,
    /// The world's water (density, gravity, current).
    pub env: Environment,
}

/// Loads a vehicle model "in the world-file format": a world file whose first vehicle group
/// describes the vehicle (as `shoal preset` prints it and `shoal validate` writes it). The
/// whole world is validated.
pub fn load_vehicle(path: &Path) -> Result<VehicleFile, WorldError> {
    let desc = load_file(path)?;
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let sm = SourceMap::new(&text);
    let wf = parse_world_file(&text, path, &sm)?;
    let mut v = Validator {
        sm: &sm,
        problems: Vec::new(),
    };
    let Some(g) = wf.vehicles.first() else {
        return Err(WorldError::single(
            path,
            Problem {
                kind: ProblemKind::MissingField,
                field: Some(FieldPath::root().key("vehicles")),
                line_col: None,
                message: "no vehicle group: a vehicle file needs one [[vehicles]] entry".into(),
            },
        ));
    };
    let gp = FieldPath::root().key("vehicles").index(0);
    match vehicle_spec(g.preset.as_deref(), g.model.as_ref(), &gp, &mut v) {
        Some(spec) => Ok(VehicleFile {
            spec,
            env: desc.env,
        }),
        None => Err(WorldError {
            file: path.to_path_buf(),
            problems: v.problems,
        }),
    }
}

/// Parses `text` as the world file `file` (only used in messages) and validates it.
pub fn load_str(text: &str, file: &Path) -> Result<WorldDesc, WorldError> {
    never_interrupted(load_str_until(text, file, &Cancel::new()))
}

/// [`load_str`] that gives up once `cancel` asks it to (see [`load_file_until`]).
pub fn load_str_until(text: &str, file: &Path, cancel: &Cancel) -> Result<WorldDesc, LoadError> {
    let sm = SourceMap::new(text);
    let wf = parse_world_file(text, file, &sm)?;
    cancel.check()?;
    let mut v = Validator {
        sm: &sm,
        problems: Vec::new(),
    };
    let desc = build(&wf, file, &mut v, cancel)?;
    if v.problems.is_empty() {
        Ok(desc.ok_or_else(|| WorldError {
            file: file.to_path_buf(),
            problems: Vec::new(),
        })?)
    } else {
        v.problems
            .sort_by_key(|p| p.line_col.unwrap_or((usize::MAX, 0)));
        Err(WorldError {
            file: file.to_path_buf(),
            problems: v.problems,
        }
        .into())
    }
}

/// The serde stage alone: TOML → [`WorldFile`] with located errors.
pub fn parse_world_file(
    text: &str,
    file: &Path,
    sm: &SourceMap<'_>,
) -> Result<WorldFile, WorldError> {
    let de = toml::de::Deserializer::parse(text)
        .map_err(|e| WorldError::single(file, toml_problem(&e, None, sm, ProblemKind::Syntax)))?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = FieldPath::parse(&e.path().to_string());
        let inner = e.into_inner();
        WorldError::single(
            file,
            toml_problem(&inner, Some(path), sm, ProblemKind::Invalid),
        )
    })
}

fn toml_problem(
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
fn explain(msg: &str, path: Option<&FieldPath>, default: ProblemKind) -> (ProblemKind, String) {
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

fn levenshtein(a: &str, b: &str) -> usize {
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

fn suggest<'a>(name: &str, expected: &[&'a str]) -> Option<&'a str> {
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

/// Whether `s` can be part of a service name: 1–64 of `[A-Za-z0-9_.-]`.
pub fn valid_service_word(s: &str) -> bool {
    !s.is_empty()
        && s.len() <= 64
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
}

/// `name` made into a valid service word (other characters become `_`, at most 64).
pub fn service_word(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.') {
                c
            } else {
                '_'
            }
        })
        .take(64)
        .collect();
    if s.is_empty() { "world".into() } else { s }
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

/// Collects problems with their locations.
pub struct Validator<'a> {
    sm: &'a SourceMap<'a>,
    /// Problems found so far.
    pub problems: Vec<Problem>,
}

/// An end of an allowed range.
#[derive(Clone, Copy)]
enum End {
    Open(f64),
    Closed(f64),
    None,
}

impl Validator<'_> {
    fn push(&mut self, kind: ProblemKind, path: &FieldPath, message: String) {
        self.problems.push(Problem {
            kind,
            field: Some(path.clone()),
            line_col: self.sm.locate(path),
            message,
        });
    }

    /// Checks `lo ⋚ x ⋚ hi`; returns whether it passed.
    fn num(&mut self, path: &FieldPath, x: f64, lo: End, hi: End, unit: &str) -> bool {
        let name = path.last_key().unwrap_or("value");
        let ok_lo = match lo {
            End::Open(a) => x > a,
            End::Closed(a) => x >= a,
            End::None => true,
        };
        let ok_hi = match hi {
            End::Open(b) => x < b,
            End::Closed(b) => x <= b,
            End::None => true,
        };
        if x.is_finite() && ok_lo && ok_hi {
            return true;
        }
        let mut allowed = String::new();
        match lo {
            End::Open(a) => allowed.push_str(&format!("{a} < ")),
            End::Closed(a) => allowed.push_str(&format!("{a} ≤ ")),
            End::None => {}
        }
        allowed.push_str(name);
        match hi {
            End::Open(b) => allowed.push_str(&format!(" < {b}")),
            End::Closed(b) => allowed.push_str(&format!(" ≤ {b}")),
            End::None => {}
        }
        let what = if x.is_finite() {
            format!("{x} is out of range")
        } else {
            format!("{x} is not a finite number")
        };
        self.push(
            ProblemKind::Range,
            path,
            format!("{what}; allowed: {allowed} {unit}")
                .trim_end()
                .to_string(),
        );
        false
    }

    /// `0 < x ≤ max` for the field `key` of `p`.
    fn pos(&mut self, p: &FieldPath, key: &str, x: f64, max: f64, unit: &str) -> bool {
        self.num(&p.key(key), x, End::Open(0.0), End::Closed(max), unit)
    }

    /// `0 ≤ x ≤ max` for the field `key` of `p`.
    fn nonneg(&mut self, p: &FieldPath, key: &str, x: f64, max: f64, unit: &str) -> bool {
        self.num(&p.key(key), x, End::Closed(0.0), End::Closed(max), unit)
    }

    /// `lo ≤ x ≤ hi` for the field `key` of `p`.
    fn within(&mut self, p: &FieldPath, key: &str, x: f64, lo: f64, hi: f64, unit: &str) -> bool {
        self.num(&p.key(key), x, End::Closed(lo), End::Closed(hi), unit)
    }

    /// `lo ≤ xᵢ ≤ hi` for every element of the field `key` of `p`.
    fn within_all(
        &mut self,
        p: &FieldPath,
        key: &str,
        xs: &[f64],
        lo: f64,
        hi: f64,
        unit: &str,
    ) -> bool {
        self.vec(&p.key(key), xs, End::Closed(lo), End::Closed(hi), unit)
    }

    fn vec(&mut self, path: &FieldPath, xs: &[f64], lo: End, hi: End, unit: &str) -> bool {
        let mut ok = true;
        for (i, x) in xs.iter().enumerate() {
            ok &= self.num(&path.index(i), *x, lo, hi, unit);
        }
        ok
    }
}

const BIG: f64 = 1e6;

fn build(
    wf: &WorldFile,
    file: &Path,
    v: &mut Validator<'_>,
    cancel: &Cancel,
) -> Result<Option<WorldDesc>, Interrupted> {
    let root = FieldPath::root();
    v.num(
        &root.key("duration"),
        wf.duration,
        End::Open(0.0),
        End::Closed(1e7),
        "s",
    );
    let dt_ok = v.num(
        &root.key("dt"),
        wf.dt,
        End::Open(0.0),
        End::Closed(0.1),
        "s",
    );
    if dt_ok && wf.duration / wf.dt > 1e10 {
        v.push(
            ProblemKind::Range,
            &root.key("duration"),
            "more than 10¹⁰ steps; raise dt or shorten the run".into(),
        );
    }
    let pool = root.key("pool");
    v.vec(
        &pool.key("size"),
        &wf.pool.size,
        End::Open(0.0),
        End::Closed(1e4),
        "m",
    );
    let water = root.key("water");
    v.num(
        &water.key("density"),
        wf.water.density,
        End::Closed(500.0),
        End::Closed(2000.0),
        "kg/m³",
    );
    v.vec(
        &water.key("current"),
        &wf.water.current,
        End::Closed(-5.0),
        End::Closed(5.0),
        "m/s",
    );
    v.num(
        &water.key("ambient_irradiance"),
        wf.water.ambient_irradiance,
        End::Closed(0.0),
        End::Closed(2000.0),
        "W/m²",
    );
    v.num(
        &water.key("diffuse_attenuation"),
        wf.water.diffuse_attenuation,
        End::Closed(0.0),
        End::Closed(100.0),
        "1/m",
    );
    let attenuation = match &wf.water.attenuation {
        AttenuationSpec::Coefficient(c) => {
            v.num(
                &water.key("attenuation"),
                *c,
                End::Closed(0.0),
                End::Closed(100.0),
                "1/m",
            );
            *c
        }
        AttenuationSpec::Named(n) => match WATER_TYPES.iter().find(|w| w.0 == n) {
            Some(w) => w.1,
            None => {
                let names: Vec<&str> = WATER_TYPES.iter().map(|w| w.0).collect();
                let hint = suggest(n, &names)
                    .map(|s| format!(" — did you mean `{s}`?"))
                    .unwrap_or_default();
                v.push(
                    ProblemKind::Reference,
                    &water.key("attenuation"),
                    format!(
                        "unknown water type `{n}`{hint} (allowed: {}, or a number in 1/m)",
                        names.join(", ")
                    ),
                );
                0.0
            }
        },
    };
    let ag = root.key("agents");
    if let Some(pfx) = &wf.agents.prefix
        && !valid_service_word(pfx)
    {
        v.push(
            ProblemKind::Invalid,
            &ag.key("prefix"),
            format!("prefix `{pfx}`: use 1–64 letters, digits, `_`, `-` or `.`"),
        );
    }
    v.num(
        &ag.key("timeout"),
        wf.agents.timeout,
        End::Open(0.0),
        End::Closed(3600.0),
        "s",
    );
    v.num(
        &ag.key("attach_timeout"),
        wf.agents.attach_timeout,
        End::Closed(0.0),
        End::Closed(86400.0),
        "s",
    );
    v.num(
        &ag.key("pace"),
        wf.agents.pace,
        End::Closed(0.0),
        End::Closed(1e6),
        "simulated s per wall s",
    );
    let out = root.key("output");
    v.num(
        &out.key("record_hz"),
        wf.output.record_hz,
        End::Open(0.0),
        End::Closed(1000.0),
        "Hz",
    );
    if !v.problems.is_empty() {
        return Ok(None);
    }
    let env = Environment {
        density: wf.water.density,
        gravity: shoal_model::math::GRAVITY,
        current: Vec3::from(wf.water.current),
    };
    let pool_size = Vec3::from(wf.pool.size);

    // Obstacles.
    let mut obstacles = Vec::new();
    for (i, o) in wf.obstacles.iter().enumerate() {
        let p = root.key("obstacles").index(i);
        if let Some(ob) = obstacle(o, &p, i, v) {
            let lo = ob.aabb.mins;
            let hi = ob.aabb.maxs;
            if hi.x < 0.0
                || hi.y < 0.0
                || lo.x > pool_size.x
                || lo.y > pool_size.y
                || lo.z > pool_size.z
            {
                v.push(
                    ProblemKind::Outside,
                    &p.key("position"),
                    format!(
                        "obstacle `{}` lies entirely outside the pool (0…{} × 0…{} × 0…{} m)",
                        ob.name, pool_size.x, pool_size.y, pool_size.z
                    ),
                );
            }
            obstacles.push(ob);
        }
    }
    let geometry = Geometry::new(pool_size, obstacles);

    // Vehicle groups.
    let mut vehicles = Vec::new();
    let mut groups = Vec::new();
    for (gi, g) in wf.vehicles.iter().enumerate() {
        groups.push(group(g, gi, wf, &env, &geometry, v, &mut vehicles, cancel)?);
    }
    check_overlaps(&vehicles, v, cancel)?;
    if !v.problems.is_empty() {
        return Ok(None);
    }

    let name = wf.name.clone().unwrap_or_else(|| {
        file.file_stem()
            .map_or_else(|| "world".into(), |s| s.to_string_lossy().into_owned())
    });
    let mut agent_names: Vec<String> = vehicles.iter().filter_map(|d| d.agent.clone()).collect();
    agent_names.sort();
    agent_names.dedup();
    let prefix = wf
        .agents
        .prefix
        .clone()
        .unwrap_or_else(|| service_word(&name));
    let agents = AgentsDesc {
        prefix,
        lockstep: wf.agents.timing == TimingSpec::Lockstep,
        timeout: wf.agents.timeout,
        attach_timeout: wf.agents.attach_timeout,
        fallback: wf.agents.fallback,
        grant_position: wf.agents.grant_position,
        pace: wf.agents.pace,
        names: agent_names,
    };
    Ok(Some(WorldDesc {
        agents,
        name,
        source: PathBuf::from(file),
        seed: wf.seed,
        duration: wf.duration,
        dt: wf.dt,
        integrator: match wf.integrator {
            IntegratorSpec::Rk4 => Integrator::Rk4,
            IntegratorSpec::SemiImplicitEuler => Integrator::SemiImplicitEuler,
        },
        env,
        attenuation,
        ambient: Ambient {
            surface_irradiance: wf.water.ambient_irradiance,
            diffuse_attenuation: wf.water.diffuse_attenuation,
        },
        geometry,
        vehicles,
        groups,
        output: OutputDesc {
            record_hz: wf.output.record_hz,
            plots: wf.output.plots,
        },
    }))
}

fn obstacle(
    o: &ObstacleSpec,
    p: &FieldPath,
    i: usize,
    v: &mut Validator<'_>,
) -> Option<crate::geometry::Obstacle> {
    let n0 = v.problems.len();
    v.vec(
        &p.key("position"),
        &o.position,
        End::Closed(-BIG),
        End::Closed(BIG),
        "m",
    );
    v.vec(
        &p.key("rotation_deg"),
        &o.rotation_deg,
        End::Closed(-360.0),
        End::Closed(360.0),
        "deg",
    );
    let need = |v: &mut Validator<'_>, key: &str, val: Option<f64>| -> f64 {
        match val {
            Some(x) => {
                v.num(&p.key(key), x, End::Open(0.0), End::Closed(1e4), "m");
                x
            }
            None => {
                v.push(
                    ProblemKind::MissingField,
                    p,
                    format!("a {:?} obstacle needs `{key}` [m]", o.shape).to_lowercase(),
                );
                1.0
            }
        }
    };
    let shape = match o.shape {
        ShapeKind::Box => {
            let s = match o.size {
                Some(s) => {
                    v.vec(&p.key("size"), &s, End::Open(0.0), End::Closed(1e4), "m");
                    s
                }
                None => {
                    v.push(
                        ProblemKind::MissingField,
                        p,
                        "a box obstacle needs `size` = [x, y, z] [m]".into(),
                    );
                    [1.0; 3]
                }
            };
            SharedShape::cuboid(0.5 * s[0], 0.5 * s[1], 0.5 * s[2])
        }
        ShapeKind::Sphere => SharedShape::ball(need(v, "radius", o.radius)),
        ShapeKind::Cylinder => {
            let r = need(v, "radius", o.radius);
            let h = need(v, "height", o.height);
            SharedShape::cylinder(0.5 * h, r)
        }
        ShapeKind::Capsule => {
            let r = need(v, "radius", o.radius);
            let h = need(v, "height", o.height);
            SharedShape::capsule_z(0.5 * h, r)
        }
    };
    if v.problems.len() > n0 {
        return None;
    }
    let [r, pi, y] = o.rotation_deg.map(f64::to_radians);
    let mut att = quat_from_rpy(r, pi, y);
    if o.shape == ShapeKind::Cylinder {
        // parry's cylinder axis is local y; the file's is local z.
        att *= Quat::from_axis_angle(&Vec3::x_axis(), std::f64::consts::FRAC_PI_2);
    }
    let name = o.name.clone().unwrap_or_else(|| format!("obstacle-{i}"));
    Some(Geometry::obstacle(
        &name,
        shape,
        &Vec3::from(o.position),
        &att,
    ))
}

/// Recursively merges `over` into `base`: tables merge, everything else replaces.
pub fn merge(base: &mut toml::Table, over: &toml::Table) {
    for (k, v) in over {
        match (base.get_mut(k), v) {
            (Some(toml::Value::Table(b)), toml::Value::Table(o)) => merge(b, o),
            _ => {
                base.insert(k.clone(), v.clone());
            }
        }
    }
}

/// Builds and validates the vehicle model of a group: `preset` (default `uauv2`, or `custom`)
/// with the `model` overrides merged over it. `path` is the group's field path (for messages).
pub fn vehicle_spec(
    preset: Option<&str>,
    model: Option<&toml::Table>,
    path: &FieldPath,
    v: &mut Validator<'_>,
) -> Option<VehicleSpec> {
    let preset_name = preset.unwrap_or("uauv2");
    let mut base = if preset_name == "custom" {
        toml::Table::new()
    } else {
        match presets::by_name(preset_name) {
            Some(p) => match toml::Value::try_from(VehicleSpec::from_params(&p)) {
                Ok(toml::Value::Table(t)) => t,
                _ => toml::Table::new(),
            },
            None => {
                let mut names: Vec<&str> = presets::NAMES.to_vec();
                names.push("custom");
                let hint = suggest(preset_name, &names)
                    .map(|s| format!(" — did you mean `{s}`?"))
                    .unwrap_or_default();
                v.push(
                    ProblemKind::Reference,
                    &path.key("preset"),
                    format!(
                        "unknown preset `{preset_name}`{hint} (allowed: {})",
                        names.join(", ")
                    ),
                );
                return None;
            }
        }
    };
    if let Some(m) = model {
        merge(&mut base, m);
    }
    let mpath = path.key("model");
    let spec: VehicleSpec = match serde_path_to_error::deserialize(toml::Value::Table(base)) {
        Ok(s) => s,
        Err(e) => {
            let field = mpath.join(&FieldPath::parse(&e.path().to_string()));
            let (kind, message) = explain(e.inner().message(), Some(&field), ProblemKind::Invalid);
            let message = if kind == ProblemKind::MissingField && preset_name == "custom" {
                format!("{message} (a `custom` vehicle must give its whole model)")
            } else {
                message
            };
            v.push(kind, &field, message);
            return None;
        }
    };
    validate_vehicle(&spec, &mpath, v).then_some(spec)
}

fn validate_vehicle(s: &VehicleSpec, p: &FieldPath, v: &mut Validator<'_>) -> bool {
    let n0 = v.problems.len();
    let b = p.key("body");
    let sb = &s.body;
    v.pos(&b, "mass", sb.mass, 1e5, "kg");
    match &sb.inertia {
        Mat3Spec::Diagonal(d) => {
            v.vec(
                &b.key("inertia"),
                d,
                End::Open(0.0),
                End::Closed(1e5),
                "kg·m²",
            );
        }
        Mat3Spec::Full(r) => {
            for (i, row) in r.iter().enumerate() {
                v.vec(
                    &b.key("inertia").index(i),
                    row,
                    End::Closed(-1e5),
                    End::Closed(1e5),
                    "kg·m²",
                );
            }
        }
    }
    v.within_all(&b, "cog", &sb.cog, -100.0, 100.0, "m");
    v.within_all(&b, "cob", &sb.cob, -100.0, 100.0, "m");
    v.pos(&b, "volume", sb.volume, 1e3, "m³");
    match &sb.added_mass {
        Mat6Spec::Diagonal(d) => {
            v.within_all(&b, "added_mass", d, 0.0, 1e5, "kg or kg·m²");
        }
        Mat6Spec::Full(r) => {
            for (i, row) in r.iter().enumerate() {
                v.vec(
                    &b.key("added_mass").index(i),
                    row,
                    End::Closed(-1e5),
                    End::Closed(1e5),
                    "",
                );
            }
        }
    }
    v.within_all(
        &b,
        "damping_linear",
        &sb.damping_linear,
        0.0,
        1e5,
        "N·s/m or N·m·s",
    );
    v.within_all(
        &b,
        "damping_quadratic",
        &sb.damping_quadratic,
        0.0,
        1e5,
        "N·s²/m² or N·m·s²",
    );
    v.vec(
        &b.key("hull_size"),
        &sb.hull_size,
        End::Open(0.0),
        End::Closed(100.0),
        "m",
    );

    let mut tilt_names: Vec<&str> = Vec::new();
    for (i, t) in s.tilts.iter().enumerate() {
        let tp = p.key("tilts").index(i);
        if tilt_names.contains(&t.name.as_str()) {
            v.push(
                ProblemKind::Invalid,
                &tp.key("name"),
                format!("tilt name `{}` is used twice", t.name),
            );
        }
        tilt_names.push(&t.name);
        axis(v, &tp.key("axis"), &t.axis);
        v.within(&tp, "min_deg", t.min_deg, -360.0, 360.0, "deg");
        v.within(
            &tp,
            "max_deg",
            t.max_deg,
            t.min_deg.max(-360.0),
            360.0,
            "deg",
        );
        v.pos(&tp, "rate_deg_s", t.rate_deg_s, 1e4, "deg/s");
    }
    let mut thruster_names: Vec<&str> = Vec::new();
    for (i, t) in s.thrusters.iter().enumerate() {
        let tp = p.key("thrusters").index(i);
        if thruster_names.contains(&t.name.as_str()) {
            v.push(
                ProblemKind::Invalid,
                &tp.key("name"),
                format!("thruster name `{}` is used twice", t.name),
            );
        }
        thruster_names.push(&t.name);
        v.within_all(&tp, "position", &t.position, -100.0, 100.0, "m");
        axis(v, &tp.key("direction"), &t.direction);
        if let Some(n) = &t.tilt
            && !tilt_names.contains(&n.as_str())
        {
            let defined = if tilt_names.is_empty() {
                "none".into()
            } else {
                tilt_names.join(", ")
            };
            v.push(
                ProblemKind::Reference,
                &tp.key("tilt"),
                format!("no tilt drive named `{n}` (defined: {defined})"),
            );
        }
        v.pos(&tp, "max_command", t.max_command, 1e4, "%");
        v.nonneg(&tp, "lag", t.lag, 100.0, "s");
        let cp = tp.key("curve");
        match &t.curve {
            CurveSpec::Quadratic { ct_pos, ct_neg } => {
                v.nonneg(&cp, "ct_pos", *ct_pos, 1e3, "N/%²");
                v.nonneg(&cp, "ct_neg", *ct_neg, 1e3, "N/%²");
            }
            CurveSpec::Table { points } => {
                if points.len() < 2 {
                    v.push(
                        ProblemKind::Invalid,
                        &cp.key("points"),
                        "a thrust table needs at least 2 [command, thrust] points".into(),
                    );
                }
                for (k, w) in points.windows(2).enumerate() {
                    if w[1][0].partial_cmp(&w[0][0]) != Some(std::cmp::Ordering::Greater)
                        || w[1][1] < w[0][1]
                    {
                        v.push(
                            ProblemKind::Invalid,
                            &cp.key("points").index(k + 1),
                            "thrust table points must increase in command and must not decrease in thrust".into(),
                        );
                    }
                }
                for (k, pt) in points.iter().enumerate() {
                    if !pt[0].is_finite() || !pt[1].is_finite() {
                        v.push(
                            ProblemKind::Range,
                            &cp.key("points").index(k),
                            "not a finite number".into(),
                        );
                    }
                }
            }
        }
    }
    if let Some(bl) = &s.ballast {
        let bp = p.key("ballast");
        v.pos(&bp, "capacity", bl.capacity, 10.0, "m³");
        v.nonneg(&bp, "flow", bl.flow, 1.0, "m³/s");
        v.within_all(&bp, "position", &bl.position, -100.0, 100.0, "m");
        v.nonneg(
            &bp,
            "initial_volume",
            bl.initial_volume,
            bl.capacity.max(0.0),
            "m³ (the tank capacity)",
        );
    }
    let pp = p.key("pressure");
    let ps = &s.pressure;
    v.pos(&pp, "c1", ps.c1, 1e4, "m/V");
    v.within(&pp, "c2", ps.c2, -1e4, 1e4, "m");
    v.pos(&pp, "depth_step", ps.depth_step, 10.0, "m");
    v.within(&pp, "bits", f64::from(ps.bits), 1.0, 32.0, "bits");
    v.nonneg(&pp, "noise_std", ps.noise_std, 10.0, "m");
    v.within_all(&pp, "position", &ps.position, -100.0, 100.0, "m");
    let ip = p.key("imu");
    v.nonneg(
        &ip,
        "attitude_noise_deg",
        s.imu.attitude_noise_deg,
        90.0,
        "deg",
    );
    v.nonneg(&ip, "gyro_noise", s.imu.gyro_noise, 10.0, "rad/s");
    v.within_all(&ip, "gyro_bias", &s.imu.gyro_bias, -10.0, 10.0, "rad/s");
    v.nonneg(&ip, "accel_noise", s.imu.accel_noise, 100.0, "m/s²");
    let c = p.key("control");
    let sc = &s.control;
    v.pos(&c, "period", sc.period, 10.0, "s");
    for (k, pd) in [
        ("heave", &sc.heave),
        ("heave_buoyancy", &sc.heave_buoyancy),
        ("yaw", &sc.yaw),
    ] {
        let kp = c.key(k);
        v.pos(&kp, "omega", pd.omega, 100.0, "rad/s");
        v.pos(&kp, "zeta", pd.zeta, 100.0, "");
        if let Some(x) = pd.kp {
            v.nonneg(&kp, "kp", x, 1e6, "");
        }
        if let Some(x) = pd.kd {
            v.nonneg(&kp, "kd", x, 1e6, "");
        }
    }
    v.nonneg(&c, "dead_zone", sc.dead_zone, 10.0, "m");
    v.within(
        &c,
        "filter_window",
        sc.filter_window as f64,
        1.0,
        1000.0,
        "samples",
    );
    v.nonneg(&c, "auto_tilt_max_deg", sc.auto_tilt_max_deg, 90.0, "deg");
    v.nonneg(&c, "rate_filter", sc.rate_filter, 100.0, "s");
    let mut modem_names: Vec<&str> = Vec::new();
    for (i, m) in s.modems.iter().enumerate() {
        let mp = p.key("modems").index(i);
        validate_modem(m, &mp, v);
        if modem_names.contains(&m.name.as_str()) {
            v.push(
                ProblemKind::Invalid,
                &mp.key("name"),
                format!("modem name `{}` is used twice", m.name),
            );
        }
        modem_names.push(&m.name);
    }
    if v.problems.len() > n0 {
        return false;
    }
    // Physical consistency: the mass matrix must be symmetric positive definite.
    let params = s.to_params();
    let m = params
        .mass_properties(params.initial_ballast(), 1000.0)
        .m_total;
    if (m - m.transpose()).abs().max() > 1e-9 * m.abs().max() || m.cholesky().is_none() {
        v.push(ProblemKind::Invalid, &b.key("added_mass"),
            "mass matrix M_RB + M_A is not symmetric positive definite (check inertia and added_mass)".into());
        return false;
    }
    for (i, e) in s.effects.iter().enumerate() {
        validate_effect(e, &params, &p.key("effects").index(i), v);
    }
    v.problems.len() == n0
}

fn validate_effect(e: &EffectSpec, vehicle: &VehicleParams, p: &FieldPath, v: &mut Validator<'_>) {
    let Some(effect) = shoal_model::effects::by_name(&e.name) else {
        let names = shoal_model::effects::names();
        let hint = suggest(&e.name, &names)
            .map(|s| format!(" — did you mean `{s}`?"))
            .unwrap_or_default();
        v.push(
            ProblemKind::Reference,
            &p.key("name"),
            format!(
                "unknown effect `{}`{hint} (allowed: {})",
                e.name,
                names.join(", ")
            ),
        );
        return;
    };
    let effect = match e.form.as_deref() {
        None => effect,
        Some(f) => match shoal_model::effects::by_name_form(&e.name, Some(f)) {
            Some(x) => x,
            None => {
                v.push(
                    ProblemKind::Reference,
                    &p.key("form"),
                    format!(
                        "effect `{}` has no form `{f}` (allowed: {})",
                        e.name,
                        shoal_model::effects::forms(&e.name).join(", ")
                    ),
                );
                return;
            }
        },
    };
    if let Some(why) = effect.not_applicable(vehicle) {
        v.push(
            ProblemKind::Invalid,
            &p.key("name"),
            format!("effect `{}` does not apply: {why}", e.name),
        );
        return;
    }
    let infos = effect.params(vehicle);
    let names: Vec<&str> = infos.iter().map(|i| i.name).collect();
    let pp = p.key("params");
    for (k, &x) in &e.params {
        match infos.iter().find(|i| i.name == k) {
            Some(i) => {
                v.within(&pp, k, x, i.lo, i.hi, i.unit);
            }
            None => {
                let hint = suggest(k, &names)
                    .map(|s| format!(" — did you mean `{s}`?"))
                    .unwrap_or_default();
                v.push(
                    ProblemKind::UnknownField,
                    &pp.key(k),
                    format!(
                        "unknown parameter `{k}` of effect `{}`{hint} (allowed: {})",
                        e.name,
                        names.join(", ")
                    ),
                );
            }
        }
    }
    for i in &infos {
        if !e.params.contains_key(i.name) {
            v.push(
                ProblemKind::MissingField,
                &pp,
                format!(
                    "effect `{}` needs parameter `{}` [{}] ({}; {} … {}, {} = no effect)",
                    e.name, i.name, i.unit, i.doc, i.lo, i.hi, i.null
                ),
            );
        }
    }
}

fn validate_modem(m: &ModemSpec, p: &FieldPath, v: &mut Validator<'_>) {
    v.within_all(p, "position", &m.position, -100.0, 100.0, "m");
    axis(v, &p.key("direction"), &m.direction);
    v.pos(p, "led_power", m.led_power, 1e3, "W");
    v.num(
        &p.key("led_half_angle_deg"),
        m.led_half_angle_deg,
        End::Open(0.0),
        End::Open(90.0),
        "deg",
    );
    v.pos(p, "rx_area", m.rx_area, 1.0, "m²");
    v.pos(p, "rx_fov_deg", m.rx_fov_deg, 90.0, "deg");
    v.pos(p, "responsivity", m.responsivity, 10.0, "A/W");
    v.nonneg(p, "noise_density", m.noise_density, 1e-6, "A/√Hz");
    v.pos(p, "bandwidth", m.bandwidth, 1e10, "Hz");
    v.nonneg(p, "dark_current", m.dark_current, 1e-3, "A");
    v.pos(p, "bit_rate", m.bit_rate, 1e10, "bit/s");
    v.within(
        p,
        "bits_per_byte",
        f64::from(m.bits_per_byte),
        8.0,
        16.0,
        "bits",
    );
    v.nonneg(p, "header_bytes", m.header_bytes as f64, 64.0, "bytes");
    v.within(
        p,
        "max_payload",
        m.max_payload as f64,
        1.0,
        65536.0,
        "bytes",
    );
    v.within(p, "queue_frames", m.queue_frames as f64, 1.0, 1e5, "frames");
    v.within(
        p,
        "capture_ratio",
        m.capture_ratio,
        1.0,
        1e6,
        "(power ratio)",
    );
    v.pos(p, "cs_threshold", m.cs_threshold, 1.0, "W");
    v.pos(p, "backoff_max", m.backoff_max, 100.0, "s");
}

/// Validates a behaviour against the vehicle it runs on.
fn validate_behaviour(
    b: &BehaviourSpec,
    model: &VehicleModel,
    p: &FieldPath,
    duration: f64,
    v: &mut Validator<'_>,
) {
    if model.params.modems.is_empty() {
        v.push(ProblemKind::Invalid, p, "a behaviour talks through optical modems, but this vehicle has none (add [[vehicles.model.modems]])".into());
        return;
    }
    let max_payload = model
        .params
        .modems
        .iter()
        .map(|m| m.max_payload)
        .min()
        .unwrap_or(0);
    match b {
        BehaviourSpec::Beacon {
            period,
            payload_bytes,
            jitter,
        } => {
            v.pos(p, "period", *period, 1e6, "s");
            v.within(
                p,
                "payload_bytes",
                *payload_bytes as f64,
                1.0,
                max_payload as f64,
                "bytes (the modems' max_payload)",
            );
            v.nonneg(p, "jitter", *jitter, 1e6, "s");
        }
        BehaviourSpec::Gossip {
            start,
            repeats,
            interval,
            jitter,
            ..
        } => {
            v.nonneg(p, "start", *start, duration, "s (0 … duration)");
            v.within(p, "repeats", f64::from(*repeats), 1.0, 1e4, "");
            v.pos(p, "interval", *interval, 1e6, "s");
            v.nonneg(p, "jitter", *jitter, 1e6, "s");
            if max_payload < 8 {
                v.push(
                    ProblemKind::Invalid,
                    p,
                    "gossip frames need 8 bytes of payload".into(),
                );
            }
        }
        BehaviourSpec::Flock {
            surge,
            period,
            too_close,
            too_far,
            cohesion,
        } => {
            v.within(p, "surge", *surge, -1.0, 1.0, "N");
            v.pos(p, "period", *period, 1e6, "s");
            v.pos(p, "too_close", *too_close, 1.0, "W");
            v.num(
                &p.key("too_far"),
                *too_far,
                End::Open(0.0),
                End::Open(*too_close),
                "W (below too_close)",
            );
            v.nonneg(p, "cohesion", *cohesion, 100.0, "");
            if model.uauv2.is_none() {
                v.push(
                    ProblemKind::Invalid,
                    p,
                    "flocking steers in auto mode and needs the μAUV² layout".into(),
                );
            }
        }
    }
}

fn axis(v: &mut Validator<'_>, path: &FieldPath, a: &[f64; 3]) {
    if v.vec(path, a, End::Closed(-1e3), End::Closed(1e3), "")
        && (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt() < 1e-9
    {
        v.push(
            ProblemKind::Range,
            path,
            "must be a non-zero vector (it is normalised on load)".into(),
        );
    }
}

fn group(
    g: &VehicleGroupSpec,
    gi: usize,
    wf: &WorldFile,
    env: &Environment,
    geometry: &Geometry,
    v: &mut Validator<'_>,
    out: &mut Vec<VehicleDesc>,
    cancel: &Cancel,
) -> Result<String, Interrupted> {
    let base = group_name(g, gi);
    group_vehicles(g, gi, &base, wf, env, geometry, v, out, cancel)?;
    Ok(base)
}

/// The base name of a group: its `name`, or `<preset>-g<index>`.
fn group_name(g: &VehicleGroupSpec, gi: usize) -> String {
    g.name
        .clone()
        .unwrap_or_else(|| format!("{}-g{gi}", g.preset.as_deref().unwrap_or("uauv2")))
}

fn group_vehicles(
    g: &VehicleGroupSpec,
    gi: usize,
    base: &str,
    wf: &WorldFile,
    env: &Environment,
    geometry: &Geometry,
    v: &mut Validator<'_>,
    out: &mut Vec<VehicleDesc>,
    cancel: &Cancel,
) -> Result<(), Interrupted> {
    cancel.check()?;
    let gp = FieldPath::root().key("vehicles").index(gi);
    let n0 = v.problems.len();
    v.num(
        &gp.key("count"),
        g.count as f64,
        End::Closed(1.0),
        End::Closed(1e7),
        "vehicles",
    );
    v.num(
        &gp.key("heading_deg"),
        g.heading_deg,
        End::Closed(-360.0),
        End::Closed(360.0),
        "deg",
    );
    let Some(spec) = vehicle_spec(g.preset.as_deref(), g.model.as_ref(), &gp, v) else {
        return Ok(());
    };
    let params = spec.to_params();
    // The control period must be a whole number of physics steps.
    let k = (params.control.period / wf.dt).round();
    if k < 1.0 || (k * wf.dt - params.control.period).abs() > 1e-9 * params.control.period.max(1.0)
    {
        v.push(
            ProblemKind::Invalid,
            &gp.key("model").key("control").key("period"),
            format!(
                "{} s is not a whole multiple of dt = {} s",
                params.control.period, wf.dt
            ),
        );
    }
    let effects = spec.effects(&params);
    let model = Arc::new(VehicleModel::with_effects(params, effects, env.density));
    let mission = Arc::new(mission(g, &gp, wf, &model, v));
    if let Some(b) = &g.behaviour {
        validate_behaviour(b, &model, &gp.key("behaviour"), wf.duration, v);
    }
    if let Some(a) = &g.agent {
        if !valid_service_word(a) {
            v.push(
                ProblemKind::Invalid,
                &gp.key("agent"),
                format!("agent name `{a}`: use 1–64 letters, digits, `_`, `-` or `.`"),
            );
        }
        if g.behaviour.is_some() {
            v.push(
                ProblemKind::Invalid,
                &gp.key("behaviour"),
                "a group driven by an `agent` takes its setpoints and frames from the agent: \
                 give either `agent` or `behaviour`"
                    .into(),
            );
        }
        if !g.mission.is_empty() {
            v.push(
                ProblemKind::Invalid,
                &gp.key("mission"),
                "a group driven by an `agent` takes its setpoints from the agent (and from \
                 `[agents] fallback` while it is absent): remove `mission`"
                    .into(),
            );
        }
    }
    if v.problems.len() > n0 {
        return Ok(());
    }
    // Placement.

    let names = |i: usize| {
        if g.count == 1 {
            base.to_string()
        } else {
            format!("{base}-{i}")
        }
    };
    let choices = usize::from(g.position.is_some())
        + usize::from(g.grid.is_some())
        + usize::from(g.random.is_some());
    if choices != 1 {
        v.push(ProblemKind::Invalid, &gp, format!(
            "give exactly one placement: `position` (one vehicle), `grid` or `random` ({} given)", choices));
        return Ok(());
    }
    let hull = hull_shape(&model.params.body.hull_size);
    let pool = geometry.pool;
    let yaw0 = g.heading_deg.to_radians();
    let mut place = |v: &mut Validator<'_>,
                     field: FieldPath,
                     i: usize,
                     pos: Vec3,
                     yaw: f64|
     -> bool {
        let att = quat_from_rpy(0.0, 0.0, yaw);
        let pose = to_pose(&pos, &att);
        if !geometry.inside_pool(&hull, &pose) {
            v.push(ProblemKind::Outside, &field, format!(
                "vehicle `{}` at ({:.3}, {:.3}, {:.3}) m is not inside the pool: its hull must lie within 0 ≤ x ≤ {}, 0 ≤ y ≤ {} and above the floor at z = {} m",
                names(i), pos.x, pos.y, pos.z, pool.x, pool.y, pool.z));
            return false;
        }
        if let Some(k) = geometry.overlapping_obstacle(&hull, &pose) {
            v.push(
                ProblemKind::Overlap,
                &field,
                format!(
                    "vehicle `{}` at ({:.3}, {:.3}, {:.3}) m overlaps obstacle `{}`",
                    names(i),
                    pos.x,
                    pos.y,
                    pos.z,
                    geometry.obstacles[k].name
                ),
            );
            return false;
        }
        out.push(VehicleDesc {
            name: names(i),
            group: gi,
            model: model.clone(),
            mission: mission.clone(),
            behaviour: g.behaviour.clone(),
            agent: g.agent.clone(),
            position: pos,
            attitude: att,
        });
        true
    };
    if let Some(p) = g.position {
        if !v.vec(
            &gp.key("position"),
            &p,
            End::Closed(-BIG),
            End::Closed(BIG),
            "m",
        ) {
            return Ok(());
        }
        if g.count != 1 {
            v.push(
                ProblemKind::Invalid,
                &gp.key("count"),
                format!(
                    "`position` places one vehicle but count = {}; use `grid` or `random`",
                    g.count
                ),
            );
            return Ok(());
        }
        place(v, gp.key("position"), 0, Vec3::from(p), yaw0);
    } else if let Some(grid) = &g.grid {
        let gr = gp.key("grid");
        let ok = v.vec(
            &gr.key("origin"),
            &grid.origin,
            End::Closed(-BIG),
            End::Closed(BIG),
            "m",
        ) & v.vec(
            &gr.key("spacing"),
            &grid.spacing,
            End::Closed(-BIG),
            End::Closed(BIG),
            "m",
        ) & v.num(
            &gr.key("columns"),
            grid.columns as f64,
            End::Closed(1.0),
            End::None,
            "",
        );
        if !ok {
            return Ok(());
        }
        for i in 0..g.count {
            cancel.check()?;
            let (c, r) = ((i % grid.columns) as f64, (i / grid.columns) as f64);
            let pos =
                Vec3::from(grid.origin) + Vec3::new(c * grid.spacing[0], r * grid.spacing[1], 0.0);
            if !place(v, gr.clone(), i, pos, yaw0) {
                return Ok(());
            }
        }
    } else if let Some(r) = &g.random {
        let rp = gp.key("random");
        let ok = v.vec(
            &rp.key("min"),
            &r.min,
            End::Closed(-BIG),
            End::Closed(BIG),
            "m",
        ) & v.vec(
            &rp.key("max"),
            &r.max,
            End::Closed(-BIG),
            End::Closed(BIG),
            "m",
        );
        if !ok {
            return Ok(());
        }
        if (0..3).any(|k| r.max[k] < r.min[k]) {
            v.push(
                ProblemKind::Range,
                &rp.key("max"),
                "each coordinate of `max` must be ≥ the same coordinate of `min`".into(),
            );
            return Ok(());
        }
        // Placement draws from its own stream of the world seed, so vehicle RNG streams are
        // unaffected by how many tries placement needed.
        let mut rng = ChaCha8Rng::seed_from_u64(wf.seed);
        rng.set_stream(u64::MAX - gi as u64);
        let others: Vec<(Cuboid3, parry3d_f64::math::Pose)> = out
            .iter()
            .map(|d| {
                (
                    hull_shape(&d.model.params.body.hull_size),
                    to_pose(&d.position, &d.attitude),
                )
            })
            .collect();
        let mut mine: Vec<parry3d_f64::math::Pose> = Vec::new();
        for i in 0..g.count {
            let mut placed = false;
            for _ in 0..1000 {
                // Each try compares with every vehicle placed so far: look before each one.
                cancel.check()?;
                let u: [f64; 3] = [rng.random(), rng.random(), rng.random()];
                let pos = Vec3::new(
                    r.min[0] + u[0] * (r.max[0] - r.min[0]),
                    r.min[1] + u[1] * (r.max[1] - r.min[1]),
                    r.min[2] + u[2] * (r.max[2] - r.min[2]),
                );
                let yaw = if r.random_heading {
                    rng.random::<f64>() * std::f64::consts::TAU
                } else {
                    yaw0
                };
                let att = quat_from_rpy(0.0, 0.0, yaw);
                let pose = to_pose(&pos, &att);
                if !geometry.inside_pool(&hull, &pose)
                    || geometry.overlapping_obstacle(&hull, &pose).is_some()
                {
                    continue;
                }
                if mine.iter().any(|q| hulls_intersect(&hull, &pose, &hull, q))
                    || others
                        .iter()
                        .any(|(h, q)| hulls_intersect(&hull, &pose, h, q))
                {
                    continue;
                }
                mine.push(pose);
                out.push(VehicleDesc {
                    name: names(i),
                    group: gi,
                    model: model.clone(),
                    mission: mission.clone(),
                    behaviour: g.behaviour.clone(),
                    agent: g.agent.clone(),
                    position: pos,
                    attitude: att,
                });
                placed = true;
                break;
            }
            if !placed {
                v.push(ProblemKind::Overlap, &rp, format!(
                    "could place only {i} of {} vehicles in the box without overlaps (1000 tries for the next); enlarge the box or lower `count`",
                    g.count));
                return Ok(());
            }
        }
    }
    Ok(())
}

type Cuboid3 = parry3d_f64::shape::Cuboid;

fn mission(
    g: &VehicleGroupSpec,
    gp: &FieldPath,
    wf: &WorldFile,
    model: &VehicleModel,
    v: &mut Validator<'_>,
) -> Mission {
    let p = &model.params;
    let mut steps = Vec::new();
    let mut last_t = 0.0;
    for (i, s) in g.mission.iter().enumerate() {
        let mp = gp.key("mission").index(i);
        if v.num(
            &mp.key("t"),
            s.t,
            End::Closed(0.0),
            End::Closed(wf.duration),
            "s (0 … duration)",
        ) && s.t < last_t
        {
            v.push(
                ProblemKind::Invalid,
                &mp.key("t"),
                format!(
                    "mission steps must be in time order ({} s comes after {} s)",
                    s.t, last_t
                ),
            );
        }
        last_t = s.t;
        if let Some(d) = s.depth {
            v.num(
                &mp.key("depth"),
                d,
                End::Closed(0.0),
                End::Closed(wf.pool.size[2]),
                "m (0 … pool depth)",
            );
        }
        if let Some(y) = s.yaw_deg {
            v.num(
                &mp.key("yaw_deg"),
                y,
                End::Closed(-720.0),
                End::Closed(720.0),
                "deg",
            );
        }
        for (k, x) in [("surge", s.surge), ("sway", s.sway)] {
            if let Some(x) = x {
                v.num(&mp.key(k), x, End::Closed(-1e3), End::Closed(1e3), "N");
            }
        }
        let mode: Option<Mode> = s.mode.map(Into::into);
        if let Some(m) = mode
            && m.needs_layout()
            && model.uauv2.is_none()
        {
            v.push(ProblemKind::Invalid, &mp.key("mode"), format!(
                "mode `{}` needs the μAUV² layout (thrusters `top`, `port`, `stbd` on tilts `alpha`, `beta`); this vehicle accepts `off` and `raw`",
                m.name()));
        }
        let mut thrusters = Vec::new();
        for (name, c) in &s.thrusters {
            let tp = mp.key("thrusters").key(name);
            match p.thrusters.iter().position(|t| &t.name == name) {
                Some(k) => {
                    let lim = p.thrusters[k].max_command;
                    if v.num(&tp, *c, End::Closed(-lim), End::Closed(lim), "%") {
                        thrusters.push((k, *c));
                    }
                }
                None => {
                    let names: Vec<&str> = p.thrusters.iter().map(|t| t.name.as_str()).collect();
                    v.push(
                        ProblemKind::Reference,
                        &tp,
                        format!(
                            "no thruster named `{name}` (this vehicle has: {})",
                            names.join(", ")
                        ),
                    );
                }
            }
        }
        let mut tilts = Vec::new();
        for (name, a) in &s.tilts_deg {
            let tp = mp.key("tilts_deg").key(name);
            match p.tilts.iter().position(|t| &t.name == name) {
                Some(k) => {
                    let t = &p.tilts[k];
                    if v.num(
                        &tp,
                        *a,
                        End::Closed(t.min.to_degrees()),
                        End::Closed(t.max.to_degrees()),
                        "deg",
                    ) {
                        tilts.push((k, a.to_radians()));
                    }
                }
                None => {
                    let names: Vec<&str> = p.tilts.iter().map(|t| t.name.as_str()).collect();
                    v.push(
                        ProblemKind::Reference,
                        &tp,
                        format!(
                            "no tilt drive named `{name}` (this vehicle has: {})",
                            names.join(", ")
                        ),
                    );
                }
            }
        }
        steps.push(MissionStep {
            t: s.t,
            mode,
            depth: s.depth,
            yaw: s.yaw_deg.map(f64::to_radians),
            surge: s.surge,
            sway: s.sway,
            thrusters,
            tilts,
            pump: s.pump.map(Into::into),
        });
    }
    Mission { steps }
}

/// Rejects overlapping vehicles (spatial hash, so large swarms stay fast).
fn check_overlaps(
    vehicles: &[VehicleDesc],
    v: &mut Validator<'_>,
    cancel: &Cancel,
) -> Result<(), Interrupted> {
    let Some(cell) = vehicles
        .iter()
        .map(|d| d.model.params.body.hull_size.norm())
        .reduce(f64::max)
    else {
        return Ok(());
    };
    let key = |p: &Vec3| {
        (
            (p.x / cell).floor() as i64,
            (p.y / cell).floor() as i64,
            (p.z / cell).floor() as i64,
        )
    };
    let mut grid: HashMap<(i64, i64, i64), Vec<usize>> = HashMap::new();
    let shapes: Vec<_> = vehicles
        .iter()
        .map(|d| {
            (
                hull_shape(&d.model.params.body.hull_size),
                to_pose(&d.position, &d.attitude),
            )
        })
        .collect();
    for (i, d) in vehicles.iter().enumerate() {
        cancel.check()?;
        let (kx, ky, kz) = key(&d.position);
        let mut hit = None;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    for &j in grid
                        .get(&(kx + dx, ky + dy, kz + dz))
                        .map_or(&[][..], |c| c.as_slice())
                    {
                        if hulls_intersect(&shapes[i].0, &shapes[i].1, &shapes[j].0, &shapes[j].1) {
                            hit = Some(j);
                            break 'search;
                        }
                    }
                }
            }
        }
        if let Some(j) = hit {
            let gp = FieldPath::root().key("vehicles").index(d.group);
            v.push(ProblemKind::Overlap, &gp, format!(
                "vehicle `{}` at ({:.3}, {:.3}, {:.3}) m overlaps vehicle `{}` at ({:.3}, {:.3}, {:.3}) m; hulls need room ({} m long)",
                d.name, d.position.x, d.position.y, d.position.z,
                vehicles[j].name, vehicles[j].position.x, vehicles[j].position.y, vehicles[j].position.z,
                d.model.params.body.hull_size.x));
            return Ok(());
        }
        grid.entry((kx, ky, kz)).or_default().push(i);
    }
    Ok(())
}

/// Writes a vehicle model as a world file with one vehicle group (`preset = "custom"`), which
/// `shoal run` can load directly.
pub fn vehicle_world_toml(
    spec: &VehicleSpec,
    position: [f64; 3],
) -> Result<String, toml::ser::Error> {
    let model = match toml::Value::try_from(spec)? {
        toml::Value::Table(t) => t,
        _ => toml::Table::new(),
    };
    let wf = WorldFile {
        name: Some(spec.name.clone()),
        seed: 0,
        duration: d_duration_pub(),
        dt: 0.01,
        integrator: IntegratorSpec::Rk4,
        pool: PoolSpec::default(),
        water: WaterSpec::default(),
        obstacles: Vec::new(),
        vehicles: vec![VehicleGroupSpec {
            name: Some(spec.name.clone()),
            preset: Some("custom".into()),
            count: 1,
            position: Some(position),
            grid: None,
            random: None,
            heading_deg: 0.0,
            mission: Vec::new(),
            model: Some(model),
            behaviour: None,
            agent: None,
        }],
        output: OutputSpec::default(),
        agents: AgentsSpec::default(),
    };
    toml::to_string(&wf)
}

fn d_duration_pub() -> f64 {
    60.0
}
