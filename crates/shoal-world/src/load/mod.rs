//! World files → [`WorldDesc`]: parse (serde with field paths), merge vehicle overrides over
//! presets, validate every number against its allowed range, expand vehicle groups, place
//! them, and reject overlaps and vehicles outside the pool. User input never panics: every
//! problem becomes a [`Problem`] naming the file, line/column and field.
//!
//! One module per concern: `parse` (the serde stage, every unknown key), `messages`
//! (serde/TOML problems made readable), `validator`
//! (located problems, range checks), [`ranges`] (the allowed range of every number), `world`
//! (top level, pool, water, agents, output), `obstacles`, `vehicle` (a model: preset +
//! overrides, every parameter), `behaviour`, `mission`, `placement` (groups, placement,
//! overlaps), `memory` (the estimate that refuses what cannot fit), `advice` (warnings on
//! what is valid but probably not meant), `names` (service names) and `export` (a model back
//! to a world file).

mod advice;
mod behaviour;
mod export;
mod group_link;
mod memory;
mod messages;
mod mission;
mod names;
mod obstacles;
mod parse;
mod placement;
pub mod ranges;
mod validator;
mod vehicle;
mod world;

pub use export::{Flight, flight_world_toml, vehicle_world_toml};
pub use memory::{DEFAULT_BYTES_PER_VEHICLE, MemoryBudget};
pub use messages::{suggest, unit_of};
pub use names::{service_word, valid_service_word};
pub use parse::parse_world_file;
pub use validator::Validator;
pub use vehicle::{merge, vehicle_spec};
pub use world::too_many_steps;

use crate::cancel::{Cancel, Interrupted};
use crate::desc::WorldDesc;
use crate::error::{FieldPath, Problem, ProblemKind, SourceMap, WorldError};
use crate::spec::*;
use shoal_model::prelude::*;
use std::path::Path;
use world::build;

/// The embedded default world (`worlds/default.toml`): a small swarm in a pool.
pub const DEFAULT_WORLD: &str = include_str!("../../../../worlds/default.toml");
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
    load_str_until(&read_text(path)?, path, cancel)
}

/// The result of loading with a [`Cancel`] nobody else can reach.
fn never_interrupted(r: Result<WorldDesc, LoadError>) -> Result<WorldDesc, WorldError> {
    match r {
        Ok(desc) => Ok(desc),
        Err(LoadError::World(e)) => Err(e),
        Err(LoadError::Interrupted(_)) => unreachable!("a private Cancel is never requested"),
    }
}

/// Reads a file as UTF-8 text; a byte sequence that is not UTF-8 is a problem located at its
/// line and column.
pub fn read_text(path: &Path) -> Result<String, WorldError> {
    let io = |message: String, line_col: Option<(usize, usize)>| {
        WorldError::single(
            path,
            Problem {
                kind: ProblemKind::Io,
                field: None,
                line_col,
                message,
            },
        )
    };
    let bytes = std::fs::read(path).map_err(|e| io(format!("cannot read the file: {e}"), None))?;
    String::from_utf8(bytes).map_err(|e| {
        let ok = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        let line = 1 + ok.iter().filter(|&&b| b == b'\n').count();
        let start = ok.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
        let col = 1 + String::from_utf8_lossy(&ok[start..]).chars().count();
        io(
            "the file is not UTF-8 text (a world file is TOML, which is UTF-8)".into(),
            Some((line, col)),
        )
    })
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
    let text = read_text(path)?;
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
    match vehicle_spec(
        (g.preset.as_deref(), g.model.as_ref(), &g.link()),
        &gp,
        &mut v,
    ) {
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

/// Parses `text` as the world file `file` (only used in messages) and validates it; a vehicle
/// count this machine's memory cannot hold is refused ([`MemoryBudget::this_machine`]).
pub fn load_str(text: &str, file: &Path) -> Result<WorldDesc, WorldError> {
    never_interrupted(load_str_until(text, file, &Cancel::new()))
}

/// [`load_str`] that gives up once `cancel` asks it to (see [`load_file_until`]).
pub fn load_str_until(text: &str, file: &Path, cancel: &Cancel) -> Result<WorldDesc, LoadError> {
    load_text(text, file, MemoryBudget::this_machine().as_ref(), cancel)
}

/// [`load_str`] with a given memory budget (`None`: no limit but the count's range).
pub fn load_str_with(
    text: &str,
    file: &Path,
    budget: Option<&MemoryBudget>,
) -> Result<WorldDesc, WorldError> {
    never_interrupted(load_text(text, file, budget, &Cancel::new()))
}

fn load_text(
    text: &str,
    file: &Path,
    budget: Option<&MemoryBudget>,
    cancel: &Cancel,
) -> Result<WorldDesc, LoadError> {
    let sm = SourceMap::new(text);
    // Unknown keys are problems, but the rest of the file is still checked.
    let (wf, unknown) = parse::parse_collecting(text, file, &sm)?;
    cancel.check()?;
    let mut v = Validator {
        sm: &sm,
        problems: unknown,
    };
    let desc = build(&wf, file, budget, &mut v, cancel)?;
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
