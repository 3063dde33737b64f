//! The replay of a run: what `replay.html` shows, gathered while the world runs and written as
//! one self-contained page (three.js and the data embedded; it opens from `file://` with no
//! network).
//!
//! **Data model** ([`ReplayData`]): a JSON header ([`Meta`]: world, pool, obstacles, groups,
//! vehicles, frame rate, quantisation, the per-second timeline) and little-endian binary
//! arrays, each embedded in the page as base64:
//!
//! | array | type | shape | content |
//! |---|---|---|---|
//! | `pos` | u16 | frames × vehicles × 3 | position, `x = q / 65535 · pool.x` (likewise y, z; NED, z down) |
//! | `att` | i16 | frames × vehicles × 3 | roll, pitch, yaw, `angle = q · π / 32767` |
//! | `panel` | f32 | seconds × vehicles × [`PANEL`] | once per second: the values of the vehicle panel |
//! | `links` | f32/u32 | events × 4 | link attempts: t \[s\] (f32), sender, receiver, outcome ([`Outcome`] code) (u32) |
//!
//! Frames are sampled every [`Meta::frame_dt`] seconds, chosen so that the pose arrays stay
//! within [`POSE_BUDGET_BYTES`] (so a 1,000-vehicle, 100-s run keeps 10 frames per second);
//! link events beyond [`LINK_BUDGET`] are thinned evenly (every k-th kept; the timeline
//! counts all of them).

use serde::Serialize;

pub mod capture;
pub mod gif;

/// Bytes of pose data (`pos` + `att`) a replay may hold before the frame rate is lowered.
pub const POSE_BUDGET_BYTES: usize = 12 << 20;
/// Most frames per second of a replay.
pub const MAX_FPS: f64 = 20.0;
/// Most link events kept for the page (thinned evenly beyond).
pub const LINK_BUDGET: usize = 200_000;
/// Values per vehicle and second in the `panel` array, in this order.
pub const PANEL: [&str; 7] = [
    "depth_reading_m",
    "depth_setpoint_m",
    "yaw_setpoint_rad",
    "mode",
    "frames_sent",
    "frames_received",
    "neighbours",
];

/// Outcome of a link attempt as coded in the `links` array.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[repr(u32)]
pub enum Outcome {
    /// Received.
    Delivered = 0,
    /// Lost to a collision with another frame (interference).
    Collided = 1,
    /// The line of sight was blocked (wall, obstacle or hull).
    Occluded = 2,
    /// Out of the link budget: range, angle or bit errors.
    OutOfBudget = 3,
    /// The receiver was transmitting (half-duplex).
    HalfDuplex = 4,
}

/// The JSON header of a replay.
#[derive(Clone, Debug, Serialize)]
pub struct Meta {
    /// Format version (1).
    pub version: u32,
    /// World name.
    pub world: String,
    /// World seed.
    pub seed: u64,
    /// Simulated duration covered \[s\].
    pub duration_s: f64,
    /// Time between frames \[s\].
    pub frame_dt: f64,
    /// Number of frames.
    pub frames: usize,
    /// Number of vehicles.
    pub vehicles: usize,
    /// Pool length (x, north), width (y, east), depth (z, down) \[m\]; corner at the origin,
    /// surface at z = 0.
    pub pool: [f64; 3],
    /// Obstacles.
    pub obstacles: Vec<ObstacleMeta>,
    /// Vehicle groups (index = group number).
    pub groups: Vec<GroupMeta>,
    /// Per vehicle: its group number.
    pub group_of: Vec<u32>,
    /// Per vehicle: its name.
    pub names: Vec<String>,
    /// Hull length, width, height of each group's vehicles \[m\] (index = group number).
    pub hull: Vec<[f64; 3]>,
    /// Cut-off range of the optical modems (beyond it no frame arrives) \[m\]; 0 without
    /// modems.
    pub modem_range_m: f64,
    /// Names of the `panel` values ([`PANEL`]).
    pub panel: Vec<String>,
    /// Names of the modes by code (`mode` in the panel).
    pub modes: Vec<String>,
    /// Link events kept / attempted in all (the page says when it shows a sample).
    pub links_kept: usize,
    /// Link attempts in the run.
    pub links_total: u64,
    /// Per-second link and connectivity series (the timeline strip).
    pub timeline: Timeline,
}

/// An obstacle, as three.js draws it.
#[derive(Clone, Debug, Serialize)]
pub struct ObstacleMeta {
    /// Name.
    pub name: String,
    /// `box` (`size` = full extents), `sphere` (`radius`), `cylinder` (`radius`, `height`,
    /// axis = local y, as three.js and parry), `capsule` (`radius`, `height` of the straight
    /// part, axis = local z).
    pub kind: String,
    /// Full extents of a box \[m\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub size: Option<[f64; 3]>,
    /// Radius \[m\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Height \[m\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    /// Centre in the world \[m\].
    pub position: [f64; 3],
    /// Orientation as a unit quaternion (x, y, z, w).
    pub rotation: [f64; 4],
}

/// A vehicle group.
#[derive(Clone, Debug, Serialize)]
pub struct GroupMeta {
    /// Name.
    pub name: String,
    /// Colour, `#rrggbb` (the same palette as the PNG plots).
    pub color: String,
    /// Vehicles in the group.
    pub count: usize,
}

/// Per-second series; entry `k` covers `[k, k + 1)` s.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Timeline {
    /// Link attempts (receptions in range tried).
    pub attempted: Vec<u64>,
    /// Delivered.
    pub delivered: Vec<u64>,
    /// Lost to collisions.
    pub collided: Vec<u64>,
    /// Lost to occlusion.
    pub occluded: Vec<u64>,
    /// Lost out of the link budget (range, angle, bit errors).
    pub out_of_budget: Vec<u64>,
    /// Lost to half-duplex.
    pub half_duplex: Vec<u64>,
    /// Connected components of the communication graph at the end of the second.
    pub components: Vec<u64>,
    /// Largest component / vehicles.
    pub largest_fraction: Vec<f64>,
    /// Mean degree of the communication graph.
    pub mean_degree: Vec<f64>,
}

/// Everything a replay holds.
#[derive(Clone, Debug)]
pub struct ReplayData {
    /// The header.
    pub meta: Meta,
    /// Quantised positions, frames × vehicles × 3.
    pub pos: Vec<u16>,
    /// Quantised attitudes, frames × vehicles × 3.
    pub att: Vec<i16>,
    /// Panel values, seconds × vehicles × [`PANEL`].len().
    pub panel: Vec<f32>,
    /// Link events: t, sender, receiver, outcome.
    pub links: Vec<LinkEvent>,
}

/// One link attempt.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinkEvent {
    /// When the frame ended \[s\].
    pub t: f32,
    /// Sending vehicle.
    pub from: u32,
    /// Receiving vehicle.
    pub to: u32,
    /// What happened.
    pub outcome: Outcome,
}
