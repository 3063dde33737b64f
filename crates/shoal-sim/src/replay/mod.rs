//! The replay of a run: what `replay.html` shows, gathered while the world runs
//! ([`capture`]). Crate `shoal-record` writes it as one self-contained page (three.js and the
//! data embedded; it opens from `file://` with no network), reads it back and draws its GIF.
//!
//! **Data model** ([`ReplayData`]): a JSON header ([`Meta`]: world, pool, obstacles, groups,
//! vehicles, frame rate, quantisation, the per-second timeline) and little-endian binary
//! arrays, each embedded in the page as base64:
//!
//! | array | type | shape | content |
//! |---|---|---|---|
//! | `pos` | u16 | frames × vehicles × 3 | position, `x = q / 65535 · pool.x` (likewise y, z; NED, z down) |
//! | `att` | i16 | frames × vehicles × 3 | roll, pitch, yaw, `angle = q · π / 32767` |
//! | `panel` | f32 | rows × vehicles × [`PANEL`] | every [`Meta::panel_dt`] s: the values of the vehicle panel |
//! | `links` | f32/u32 | events × 4 | link attempts: t \[s\] (f32), sender, receiver, outcome word (u32: [`LinkEvent::word`]) |
//!
//! A link event's outcome word is its [`Outcome`] code, with its top bit ([`ACK_BIT`],
//! `0x8000_0000`) set when the frame was an acknowledgement ([`LinkEvent::ack`]); the page and
//! the GIF draw those dashed, in their outcome's colour. The other bits are 0.
//!
//! Frames are sampled every [`Meta::frame_dt`] seconds ([`frame_dt`]: the finest of 0.05, 0.1,
//! 0.2, 0.25, 0.5, 1, 2, 5 … s whose pose arrays stay within [`POSE_BUDGET_BYTES`], so a
//! 1,000-vehicle, 100-s run keeps 10 frames per second); frame `k` is at `t = k · frame_dt`.
//! Link events (in time order) beyond [`LINK_BUDGET`] are thinned evenly (every k-th kept;
//! the timeline counts all of them). The `panel` holds a row every [`Meta::panel_dt`]
//! seconds ([`panel_dt`]: 1 s, or 2, 5, 10 … s when [`PANEL_BUDGET_BYTES`] requires it): row
//! `k` describes `t = k · panel_dt` (the page shows row `⌊t / panel_dt⌋`). [`ReplayData::check`] says whether the arrays agree
//! with the header; the page writer refuses data that does not.
//!
//! **Size budget** (base64 adds a third; measured with shoal-record's synthetic replay,
//! `crates/shoal-record/examples/replay_demo.rs`; see `docs/replay.md`):
//!
//! | part | bytes in the page |
//! |---|---|
//! | page, style, viewer, three.js | 0.63 MB, fixed |
//! | poses | frames × vehicles × 12 × 4/3, at most [`POSE_BUDGET_BYTES`] · 4/3 = 16.8 MB |
//! | panel | rows × vehicles × 7 × 4 × 4/3 = 37 B per vehicle and row, at most [`PANEL_BUDGET_BYTES`] · 4/3 = 8.4 MB |
//! | links | events × 16 × 4/3, at most [`LINK_BUDGET`] · 21.3 B = 4.3 MB |
//! | header | ≈ 15 B per vehicle (name, group) + 100 B per second (timeline) |
//!
//! | demo | frame_dt | file | poses | panel | links (kept of all) |
//! |---|---|---|---|---|---|
//! | 12 vehicles × 60 s | 0.05 s | 0.93 MB | 0.23 MB | 0.03 MB | 0.04 MB (1,810 of 1,810) |
//! | 1,000 × 100 s | 0.1 s | 23.4 MB | 16.0 MB | 3.7 MB | 3.0 MB (140,184 of 420,551) |
//! | 10,000 × 100 s | 1 s | 28.5 MB | 16.2 MB | 7.5 MB (every 5 s) | 4.1 MB (191,374 of 4.4 M) |
//!
//! Every array is bounded, so a page stays under ≈ 30 MB for any swarm and duration, plus its
//! header (≈ 15 B per vehicle and 100 B per second).

use serde::{Deserialize, Serialize};

pub mod capture;

/// Bytes of pose data (`pos` + `att`) a replay may hold before the frame rate is lowered.
pub const POSE_BUDGET_BYTES: usize = 12 << 20;
/// Most frames per second of a replay.
pub const MAX_FPS: f64 = 20.0;
/// Most link events kept for the page (thinned evenly beyond).
pub const LINK_BUDGET: usize = 200_000;
/// Bytes of panel values a replay may hold before the panel is sampled less often than once
/// a second ([`panel_dt`]).
pub const PANEL_BUDGET_BYTES: usize = 6 << 20;
/// Values per vehicle and panel row in the `panel` array, in this order: depth reading \[m\],
/// depth setpoint \[m\], heading (yaw) setpoint \[rad\], mode (code into [`Meta::modes`]),
/// frames sent and frames received since the start of the run, and neighbours (distinct
/// senders delivered to the vehicle in the second before the row's time). NaN where a value does not exist (no
/// setpoint in this mode): the page shows "—". The page finds the values by these names in
/// [`Meta::panel`], so a header may list others.
pub const PANEL: [&str; 7] = [
    "depth_reading_m",
    "depth_setpoint_m",
    "yaw_setpoint_rad",
    "mode",
    "frames_sent",
    "frames_received",
    "neighbours",
];

pub use crate::comm::Outcome;

/// The bit of a link event's outcome word ([`LinkEvent::word`]) that marks an
/// acknowledgement frame.
pub const ACK_BIT: u32 = 0x8000_0000;

/// Bytes of pose data per vehicle and frame: `pos` (3 × u16) and `att` (3 × i16).
pub const POSE_BYTES_PER_VEHICLE_FRAME: usize = 12;

/// Frame intervals a replay may use \[s\], finest first: `1 / MAX_FPS` and round values
/// above it (so a frame falls on a whole number of simulation steps for the usual steps).
const FRAME_DTS: [f64; 12] = [
    0.05, 0.1, 0.2, 0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 30.0, 60.0,
];

/// Panel intervals a replay may use \[s\], finest first: whole seconds.
const PANEL_DTS: [f64; 7] = [1.0, 2.0, 5.0, 10.0, 20.0, 30.0, 60.0];

/// Frames of a replay of `duration_s` sampled every `frame_dt` s: t = 0, `frame_dt`, …,
/// up to `duration_s` (inclusive, with a 1e-9 relative tolerance).
pub fn frame_count(duration_s: f64, frame_dt: f64) -> usize {
    if !(duration_s > 0.0 && frame_dt > 0.0 && duration_s.is_finite()) {
        return 1;
    }
    // Truncation intended: the last whole frame interval within the duration.
    (duration_s / frame_dt * (1.0 + 1e-9)).floor() as usize + 1
}

/// The time between frames \[s\] of a replay of `vehicles` over `duration_s` s: the finest of
/// `1 / MAX_FPS` (0.05 s), 0.1, 0.2, 0.25, 0.5, 1, 2, 5, 10, 20, 30, 60 s (then whole minutes)
/// whose pose arrays ([`frame_count`] × `vehicles` × [`POSE_BYTES_PER_VEHICLE_FRAME`]) fit in
/// [`POSE_BUDGET_BYTES`]. 12 vehicles × 60 s: 0.05 s (20 fps); 1,000 × 100 s: 0.1 s;
/// 10,000 × 100 s: 1 s. When not even two frames fit (over a million vehicles), the
/// duration: the first and the last frame only.
pub fn frame_dt(vehicles: usize, duration_s: f64) -> f64 {
    let per_frame = vehicles.saturating_mul(POSE_BYTES_PER_VEHICLE_FRAME).max(1);
    sample_interval(&FRAME_DTS, duration_s, POSE_BUDGET_BYTES / per_frame)
}

/// The time between panel rows \[s\] of a replay of `vehicles` over `duration_s` s: the
/// finest of 1, 2, 5, 10, 20, 30, 60 s (then whole minutes) whose panel array (rows ×
/// `vehicles` × [`PANEL`] × 4 bytes) fits in [`PANEL_BUDGET_BYTES`]. 1,000 vehicles × 100 s:
/// 1 s; 10,000 × 100 s: 5 s.
pub fn panel_dt(vehicles: usize, duration_s: f64) -> f64 {
    let per_row = vehicles.saturating_mul(PANEL.len() * 4).max(1);
    sample_interval(&PANEL_DTS, duration_s, PANEL_BUDGET_BYTES / per_row)
}

/// The finest of `candidates` (ascending, \[s\]), then of whole minutes, at which at most
/// `max_samples` samples ([`frame_count`]) cover `duration_s`; when not even two fit, the
/// duration (the first and the last sample only, over budget).
fn sample_interval(candidates: &[f64], duration_s: f64, max_samples: usize) -> f64 {
    let fits = |dt: f64| frame_count(duration_s, dt) <= max_samples;
    if let Some(dt) = candidates.iter().copied().find(|&dt| fits(dt)) {
        return dt;
    }
    if max_samples < 2 || !duration_s.is_finite() {
        return if duration_s.is_finite() {
            duration_s.max(candidates[0])
        } else {
            candidates[0]
        };
    }
    // Whole minutes (the rounding of frame_count may need one more).
    let dt = (duration_s / (max_samples - 1) as f64 / 60.0).ceil() * 60.0;
    if fits(dt) { dt } else { dt + 60.0 }
}

fn one_second() -> f64 {
    1.0
}

/// The JSON header of a replay.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
    /// Time between panel rows \[s\]: row `k` holds the values at `t = k · panel_dt`
    /// ([`panel_dt`]; 1 s in pages written before it existed).
    #[serde(default = "one_second")]
    pub panel_dt: f64,
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
    /// How the page shows each link outcome, by outcome code: the one colour key, which the
    /// page writer (crate `shoal-record`) puts here; empty while the replay is gathered (a
    /// page written before the key existed gets today's key when it is read back).
    #[serde(default)]
    pub outcomes: Vec<OutcomeMeta>,
    /// The legend's entry for the link events of acknowledgement frames ([`LinkEvent::ack`]:
    /// drawn dashed, in their outcome's colour), which the page writer puts here with the
    /// colour key; empty while the replay is gathered (a page written before it existed gets
    /// today's entry when it is read back).
    #[serde(default)]
    pub ack_label: String,
}

/// How the page shows one link outcome.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OutcomeMeta {
    /// Legend label.
    pub name: String,
    /// Colour, `#rrggbb`.
    pub color: String,
}

/// An obstacle, as three.js draws it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GroupMeta {
    /// Name.
    pub name: String,
    /// Colour, `#rrggbb` (the same palette as the PNG plots).
    pub color: String,
    /// Vehicles in the group.
    pub count: usize,
}

/// Per-second series; entry `k` covers `[k, k + 1)` s.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
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
#[derive(Clone, Debug, PartialEq)]
pub struct ReplayData {
    /// The header.
    pub meta: Meta,
    /// Quantised positions, frames × vehicles × 3.
    pub pos: Vec<u16>,
    /// Quantised attitudes, frames × vehicles × 3.
    pub att: Vec<i16>,
    /// Panel values, seconds × vehicles × [`PANEL`].len().
    pub panel: Vec<f32>,
    /// Link events: t, sender, receiver, outcome, acknowledgement or not.
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
    /// Whether the frame was an acknowledgement ([`crate::comm::Heard::ack`]): drawn
    /// dashed.
    pub ack: bool,
}

impl LinkEvent {
    /// The fourth word of the event in the `links` array: the outcome's code, with
    /// [`ACK_BIT`] set for an acknowledgement.
    pub fn word(&self) -> u32 {
        self.outcome.code() | if self.ack { ACK_BIT } else { 0 }
    }

    /// The outcome and the acknowledgement flag of an outcome word ([`LinkEvent::word`]);
    /// `None` when its code (the word without [`ACK_BIT`]) is no outcome's.
    pub fn outcome_of(word: u32) -> Option<(Outcome, bool)> {
        Outcome::from_code(word & !ACK_BIT).map(|o| (o, word & ACK_BIT != 0))
    }
}

impl ReplayData {
    /// Whether the arrays agree with the header: `pos` and `att` hold `frames × vehicles × 3`
    /// values, `panel` whole rows of `meta.panel.len()` values per vehicle, every vehicle has
    /// a name and an existing group, every group a hull, link events name existing vehicles,
    /// `links_kept` counts them and the timeline's series have one length. The error says
    /// what disagrees.
    pub fn check(&self) -> Result<(), String> {
        let m = &self.meta;
        let poses = m
            .frames
            .checked_mul(m.vehicles)
            .and_then(|n| n.checked_mul(3));
        if poses != Some(self.pos.len()) || poses != Some(self.att.len()) {
            return Err(format!(
                "{} frames × {} vehicles × 3 do not match pos ({} values) and att ({} values)",
                m.frames,
                m.vehicles,
                self.pos.len(),
                self.att.len()
            ));
        }
        if m.frames > 1 && !(m.frame_dt > 0.0 && m.frame_dt.is_finite()) {
            return Err(format!("frame_dt {} s is not positive", m.frame_dt));
        }
        if !m.pool.iter().all(|v| v.is_finite() && *v > 0.0) {
            return Err(format!("pool {:?} m is not positive", m.pool));
        }
        let row = m
            .vehicles
            .checked_mul(m.panel.len())
            .ok_or_else(|| format!("{} vehicles are too many", m.vehicles))?;
        if (row == 0 && !self.panel.is_empty())
            || (row > 0 && !self.panel.len().is_multiple_of(row))
        {
            return Err(format!(
                "panel holds {} values, not whole seconds of {} vehicles × {} values",
                self.panel.len(),
                m.vehicles,
                m.panel.len()
            ));
        }
        if m.names.len() != m.vehicles || m.group_of.len() != m.vehicles {
            return Err(format!(
                "{} vehicles but {} names and {} group numbers",
                m.vehicles,
                m.names.len(),
                m.group_of.len()
            ));
        }
        if let Some(g) = m.group_of.iter().find(|&&g| g as usize >= m.groups.len()) {
            return Err(format!("group {g} of {} groups", m.groups.len()));
        }
        if m.hull.len() != m.groups.len() {
            return Err(format!(
                "{} groups but {} hulls",
                m.groups.len(),
                m.hull.len()
            ));
        }
        let n = m.vehicles as u64;
        if let Some(e) = self
            .links
            .iter()
            .find(|e| u64::from(e.from) >= n || u64::from(e.to) >= n || !e.t.is_finite())
        {
            return Err(format!("link event {e:?} of {} vehicles", m.vehicles));
        }
        if m.links_kept != self.links.len() {
            return Err(format!(
                "links_kept {} but {} link events",
                m.links_kept,
                self.links.len()
            ));
        }
        let t = &m.timeline;
        let lens = [
            t.attempted.len(),
            t.delivered.len(),
            t.collided.len(),
            t.occluded.len(),
            t.out_of_budget.len(),
            t.half_duplex.len(),
            t.components.len(),
            t.largest_fraction.len(),
            t.mean_degree.len(),
        ];
        if lens.iter().any(|&l| l != lens[0]) {
            return Err(format!("timeline series of different lengths {lens:?}"));
        }
        Ok(())
    }

    /// Rows of panel values (`panel.len() / (vehicles × meta.panel.len())`), one every
    /// [`Meta::panel_dt`] s.
    pub fn panel_rows(&self) -> usize {
        let row = self.meta.vehicles.saturating_mul(self.meta.panel.len());
        self.panel.len().checked_div(row).unwrap_or(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pose_bytes(vehicles: usize, duration_s: f64) -> usize {
        frame_count(duration_s, frame_dt(vehicles, duration_s)) * vehicles * 12
    }

    #[test]
    fn the_frame_rate_follows_the_pose_budget() {
        assert_eq!(frame_dt(12, 60.0), 0.05);
        assert_eq!(frame_count(60.0, 0.05), 1201);
        assert_eq!(frame_dt(1000, 100.0), 0.1);
        assert_eq!(frame_dt(10_000, 100.0), 1.0);
        assert_eq!(frame_dt(0, 100.0), 0.05);
        assert_eq!(frame_dt(5, f64::NAN), 0.05);
        for (n, s) in [
            (1000, 100.0),
            (3000, 700.0),
            (100, 86_400.0),
            (50_000, 3600.0),
        ] {
            let dt = frame_dt(n, s);
            assert!(pose_bytes(n, s) <= POSE_BUDGET_BYTES, "{n} × {s}: dt {dt}");
            let finer = FRAME_DTS.iter().rev().find(|&&d| d < dt).copied();
            if let Some(f) = finer {
                assert!(
                    frame_count(s, f) * n * 12 > POSE_BUDGET_BYTES,
                    "{n} × {s}: {f} fits"
                );
            }
        }
        // A day of 1,000 vehicles: whole minutes (the finest that fits).
        assert_eq!(frame_dt(1000, 86_400.0), 120.0);
        assert!(pose_bytes(1000, 86_400.0) <= POSE_BUDGET_BYTES);
        assert!(frame_count(86_400.0, 60.0) * 1000 * 12 > POSE_BUDGET_BYTES);
        // More vehicles than one frame's budget: first and last frame, quickly.
        assert_eq!(frame_dt(2_000_000, 100.0), 100.0);
        assert_eq!(frame_count(100.0, 100.0), 2);
    }

    #[test]
    fn the_panel_rate_follows_the_panel_budget() {
        let bytes = |n: usize, s: f64| frame_count(s, panel_dt(n, s)) * n * PANEL.len() * 4;
        assert_eq!(panel_dt(12, 100.0), 1.0);
        assert_eq!(panel_dt(1000, 100.0), 1.0);
        // 10,000 × 100 s: 21 rows of 280 kB (5.9 MB), where 2 s would take 51 rows.
        assert_eq!(panel_dt(10_000, 100.0), 5.0);
        assert_eq!(panel_dt(1000, 600.0), 5.0);
        for (n, s) in [
            (10_000, 100.0),
            (1000, 600.0),
            (100, 86_400.0),
            (100_000, 60.0),
        ] {
            assert!(bytes(n, s) <= PANEL_BUDGET_BYTES, "{n} × {s}");
        }
        // A million vehicles: more than a row's budget, the first and the last row.
        assert_eq!(panel_dt(1_000_000, 100.0), 100.0);
    }

    /// The outcome word keeps the outcome in its low bits and the acknowledgement flag in
    /// its top bit; words with other bits set are no outcome's.
    #[test]
    fn the_outcome_word_carries_the_acknowledgement_flag() {
        for outcome in Outcome::ALL {
            for ack in [false, true] {
                let e = LinkEvent {
                    t: 1.0,
                    from: 0,
                    to: 1,
                    outcome,
                    ack,
                };
                let w = e.word();
                assert_eq!(w & !ACK_BIT, outcome.code());
                assert_eq!(w & ACK_BIT != 0, ack);
                assert_eq!(LinkEvent::outcome_of(w), Some((outcome, ack)));
            }
        }
        assert_eq!(LinkEvent::outcome_of(ACK_BIT | 5), None);
        assert_eq!(LinkEvent::outcome_of(0x4000_0000), None);
    }
}
