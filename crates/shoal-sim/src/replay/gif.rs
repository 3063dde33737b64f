//! An animated GIF of a run, drawn from its [`ReplayData`] without a browser: for people who
//! won't open `replay.html`, for READMEs, issues and chat.
//!
//! [`render`] draws every GIF frame with plotters into an RGB buffer and encodes it with the
//! `gif` crate in one fixed palette (built once from the group colours, the link-outcome
//! colours, the map's colours and a grey ramp; each pixel goes to its nearest palette entry
//! through a 32 × 32 × 32 lookup table, exact for every palette colour). After the first,
//! each frame stores only the rectangle that changed, its unchanged pixels transparent, so a
//! still background costs nothing. The file is written through [`AtomicFile`]: an
//! interrupted render never leaves a truncated GIF under the file's name.
//!
//! **What a frame shows** ([`View`]): the map from above (east y to the right, north x up, as
//! the `top` PNG plot) and/or the side view from the east (north x to the right, depth z
//! down); each zooms to where the vehicles went during the whole run (the bounding box of all
//! positions plus a margin, clipped to the pool; equal scales on both axes, so where the
//! image would get too tall or too flat one range is widened about its centre). On it: water,
//! pool walls and surface, obstacles (filled, their true outline from their shape and pose),
//! each vehicle as a pointed body of its group's hull size turned by its attitude (never
//! smaller than [`MIN_BODY_PX`]), its trail of the last [`GifOptions::trail_s`] seconds, and
//! the link attempts of the last [`LINK_WINDOW_S`] s (or of the time between two GIF frames
//! when longer) as lines coloured by outcome, losses drawn over deliveries. A title (world,
//! `t = 12.3 s`, playback speed) and a legend (groups, link outcomes) frame the maps.
//!
//! **Timing**: GIF frame `k` shows simulated time `k · speed / fps` (the nearest replay
//! frame), up to the replay's last frame, so the GIF plays at `speed`× real time. When that
//! would take more than [`GifOptions::max_frames`] frames, that many frames are spread over
//! the whole run and each is shown longer (the playback speed stays). The last frame is held
//! [`END_HOLD_S`] s longer before the loop starts again.
//!
//! Shapes are drawn with hard edges (plotters' blended edge pixels would land on unrelated
//! palette entries, see `Crisp`); only text keeps its smooth edges.
//!
//! **Measured** (`cargo run --release -p shoal-sim --example gif_render`: synthetic 100-s
//! replays of vehicles circling in formation in a 20 × 12 × 4 m or a 60 × 40 × 10 m pool, as
//! many replay frames as the pose budget allows, links to formation neighbours; default
//! options unless said; 251 GIF frames of 800 × about 1,050 px; a 2-core machine at a load of
//! 9 from other builds, so times vary by ±30 %):
//!
//! | run | view, links | render | file |
//! |---|---|---|---|
//! | 12 vehicles, 2,001 replay frames, 3,400 links | both, links | 1.5–2.0 s | 2.7 MB |
//! | | both, no links | 1.4–1.8 s | 1.1 MB |
//! | | top, links | 0.9–1.3 s | 1.7 MB |
//! | | top, no links | 1.0–1.2 s | 0.7 MB |
//! | 1,000 vehicles, 1,048 replay frames, 200,000 links | both, links | 4.1 s | 10.8 MB |
//! | | both, no links | 2.4–3.1 s | 5.4 MB |
//! | | top, links | 1.6–1.7 s | 6.9 MB |
//! | | top, no links | 1.4–1.8 s | 3.7 MB |
//!
//! Per frame (both views, links): drawing 1 ms with 12 vehicles, 7 ms with 1,000; the palette
//! mapping 2 ms; the LZW encoding of the changed rectangle 7 ms. `gif::Frame::from_rgb_speed`
//! took 21–24 ms per such frame (at any speed: these frames have under 256 colours), ten times
//! the lookup table, and its per-frame palettes would rule out the transparent partial frames.

use super::{LinkEvent, ObstacleMeta, Outcome, ReplayData};
use crate::files::{AtomicFile, FileError};
use crate::plot::{clip_polyline, register_font};
use nalgebra::{Quaternion, Rotation3, UnitQuaternion, Vector3};
use plotters::backend::{BitMapBackend, RGBPixel};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
// Through its path: its style traits' methods would clash with plotters' `Color`.
use plotters_backend as backend;
use plotters_backend::{BackendColor, BackendCoord, DrawingErrorKind};
use std::borrow::Cow;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// What a GIF frame shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum View {
    /// The map from above: east (y) to the right, north (x) up.
    Top,
    /// The side view from the east: north (x) to the right, depth (z) down.
    Side,
    /// The map from above with the side view below it.
    #[default]
    Both,
}

/// How to draw the GIF.
#[derive(Clone, Debug)]
pub struct GifOptions {
    /// Which views.
    pub view: View,
    /// Image width \[px\] (240 to 4096); the height follows from the views' aspect ratios.
    pub width_px: u32,
    /// GIF frame rate \[frames per second of playback\] (above 0, at most 50: browsers play
    /// faster GIFs at 10 fps).
    pub fps: f64,
    /// Playback speed \[simulated seconds per second of GIF\]: 4 turns a 100-s run into a
    /// 25-s GIF.
    pub speed: f64,
    /// Most GIF frames (1 to [`MAX_GIF_FRAMES`]); beyond it, frames are spread over the run
    /// and each is shown longer.
    pub max_frames: usize,
    /// Length of the trail behind each vehicle \[s of simulated time\] (0: none).
    pub trail_s: f64,
    /// Draw the link attempts of the last moments as lines.
    pub links: bool,
}

impl Default for GifOptions {
    fn default() -> Self {
        Self {
            view: View::Both,
            width_px: 800,
            fps: 10.0,
            speed: 4.0,
            max_frames: 600,
            trail_s: 5.0,
            links: true,
        }
    }
}

/// Why a GIF could not be rendered; every message names the file.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The replay holds nothing to draw.
    #[error(
        "cannot render {}: the replay is empty ({frames} frames, {vehicles} vehicles)",
        path.display()
    )]
    Empty {
        /// The GIF asked for.
        path: PathBuf,
        /// Frames in the replay.
        frames: usize,
        /// Vehicles in the replay.
        vehicles: usize,
    },
    /// The replay's arrays or header do not fit together.
    #[error("cannot render {}: inconsistent replay: {message}", path.display())]
    Data {
        /// The GIF asked for.
        path: PathBuf,
        /// What does not fit.
        message: String,
    },
    /// An option is out of its range.
    #[error("cannot render {}: {message}", path.display())]
    Options {
        /// The GIF asked for.
        path: PathBuf,
        /// Which option, its value and the allowed range.
        message: String,
    },
    /// Drawing or encoding failed.
    #[error("cannot draw {}: {message}", path.display())]
    Draw {
        /// The GIF being drawn.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// The file could not be written.
    #[error(transparent)]
    File(#[from] FileError),
}

/// Link attempts of the last this many simulated seconds are drawn (or of the time between two
/// GIF frames, when longer, so that every attempt is seen once) \[s\].
pub const LINK_WINDOW_S: f64 = 0.3;
/// Smallest drawn length of a vehicle's body \[px\]: smaller hulls are drawn enlarged.
pub const MIN_BODY_PX: f64 = 9.0;
/// The last frame is held this much longer before the GIF loops \[s\].
pub const END_HOLD_S: f64 = 2.0;
/// Most GIF frame rate \[1/s\]: delays below 2/100 s are played as 1/10 s by browsers.
pub const MAX_GIF_FPS: f64 = 50.0;
/// Largest [`GifOptions::max_frames`].
pub const MAX_GIF_FRAMES: usize = 20_000;
/// Allowed image widths \[px\].
const WIDTH_RANGE: (u32, u32) = (240, 4096);
/// Hull length, width, height when the replay has none for a group \[m\].
const DEFAULT_HULL: [f64; 3] = [0.3, 0.15, 0.1];

// ---------------------------------------------------------------------------------------------
// Colours

const BG: RGBColor = RGBColor(255, 255, 255);
const TEXT: RGBColor = RGBColor(0, 0, 0);
const TEXT_GREY: RGBColor = RGBColor(88, 88, 88);
/// Beyond the pool's walls and below its floor.
const OUTSIDE: RGBColor = RGBColor(224, 224, 224);
const WATER: RGBColor = RGBColor(234, 243, 251);
const GRID: RGBColor = RGBColor(206, 219, 232);
const OBSTACLE: RGBColor = RGBColor(150, 150, 150);
const OBSTACLE_EDGE: RGBColor = RGBColor(96, 96, 96);
const WALL: RGBColor = RGBColor(40, 40, 40);
const SURFACE: RGBColor = RGBColor(70, 130, 200);
const FRAME: RGBColor = RGBColor(128, 128, 128);

/// The colour of a link outcome: deliveries in teal, losses each in their own colour.
fn outcome_color(o: Outcome) -> RGBColor {
    match o {
        Outcome::Delivered => RGBColor(0, 140, 110),
        Outcome::Collided => RGBColor(230, 0, 230),
        Outcome::Occluded => RGBColor(255, 180, 0),
        Outcome::OutOfBudget => RGBColor(110, 110, 255),
        Outcome::HalfDuplex => RGBColor(110, 60, 0),
    }
}

/// Outcomes in drawing order (deliveries first, losses over them) with their legend labels.
const OUTCOMES: [(Outcome, &str); 5] = [
    (Outcome::Delivered, "delivered"),
    (Outcome::Collided, "collided"),
    (Outcome::Occluded, "occluded"),
    (Outcome::OutOfBudget, "out of budget"),
    (Outcome::HalfDuplex, "half-duplex"),
];

/// `#rrggbb` as a colour.
fn parse_hex(s: &str) -> Option<RGBColor> {
    let h = s.strip_prefix('#')?;
    if h.len() != 6 || !h.is_ascii() {
        return None;
    }
    let c = |i: usize| u8::from_str_radix(&h[i..i + 2], 16).ok();
    Some(RGBColor(c(0)?, c(2)?, c(4)?))
}

/// `a` moved the fraction `f` towards `b`.
fn mix(a: RGBColor, b: RGBColor, f: f64) -> RGBColor {
    let m = |x: u8, y: u8| (f64::from(x) + f * (f64::from(y) - f64::from(x))).round() as u8;
    RGBColor(m(a.0, b.0), m(a.1, b.1), m(a.2, b.2))
}

/// The palette index kept free for "unchanged" pixels of a partial frame.
const TRANSPARENT: u8 = 255;

/// The GIF's one palette and the map from any RGB colour to its nearest entry.
struct Palette {
    /// 256 entries, r, g, b each; entries from `len` on are unused.
    rgb: Vec<u8>,
    /// Entries in use (at most 255: the last is [`TRANSPARENT`]).
    #[cfg_attr(not(test), expect(dead_code, reason = "read by the tests"))]
    len: usize,
    /// Nearest entry of each colour with 5 bits per channel.
    lut: Vec<u8>,
}

impl Palette {
    #[inline]
    fn key(r: u8, g: u8, b: u8) -> usize {
        (usize::from(r >> 3) << 10) | (usize::from(g >> 3) << 5) | usize::from(b >> 3)
    }

    /// The palette of `colors` in order of importance: a colour whose 5-bit cell already
    /// holds an earlier one is left out (it is within 8 levels per channel of it); beyond
    /// 255 colours the rest are left out.
    fn new(colors: &[RGBColor]) -> Self {
        let mut taken = vec![false; 1 << 15];
        let mut rgb = Vec::with_capacity(256 * 3);
        let mut len = 0;
        for c in colors {
            let k = Self::key(c.0, c.1, c.2);
            if taken[k] || len == usize::from(TRANSPARENT) {
                continue;
            }
            taken[k] = true;
            rgb.extend_from_slice(&[c.0, c.1, c.2]);
            len += 1;
        }
        rgb.resize(256 * 3, 0);
        let dist = |i: usize, r: i32, g: i32, b: i32| {
            let d = |k: usize, v: i32| i32::from(rgb[3 * i + k]) - v;
            // Weighted for the eye's sensitivity (green most, blue least).
            2 * d(0, r).pow(2) + 4 * d(1, g).pow(2) + 3 * d(2, b).pow(2)
        };
        let mut lut = vec![0u8; 1 << 15];
        for (k, slot) in lut.iter_mut().enumerate() {
            // The cell's centre.
            let (r, g, b) = (
                ((k >> 10) as i32) * 8 + 4,
                (((k >> 5) & 31) as i32) * 8 + 4,
                ((k & 31) as i32) * 8 + 4,
            );
            *slot = (0..len).min_by_key(|&i| dist(i, r, g, b)).unwrap_or(0) as u8;
        }
        // Every palette colour maps to itself.
        for i in 0..len {
            lut[Self::key(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2])] = i as u8;
        }
        Self { rgb, len, lut }
    }

    /// The entry of the colour `c`.
    #[inline]
    fn index(&self, c: [u8; 3]) -> u8 {
        self.lut[Self::key(c[0], c[1], c[2])]
    }

    /// Maps the RGB image `rgb` to palette indices in `out` (one per pixel).
    fn map(&self, rgb: &[u8], out: &mut [u8]) {
        for (px, o) in rgb.chunks_exact(3).zip(out.iter_mut()) {
            *o = self.index([px[0], px[1], px[2]]);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The replay, checked

/// The replay with its arrays checked against its header.
struct Scene<'a> {
    data: &'a ReplayData,
    frames: usize,
    vehicles: usize,
    pool: [f64; 3],
    /// Time between replay frames \[s\].
    dt: f64,
    /// Group of each vehicle.
    group_of: Vec<usize>,
    /// Per group: name (with count), colour, trail colour, hull \[m\].
    groups: Vec<GroupStyle>,
    /// Link events with a finite time, by time.
    links: Cow<'a, [LinkEvent]>,
}

struct GroupStyle {
    label: String,
    color: RGBColor,
    trail: RGBColor,
    hull: [f64; 3],
}

impl<'a> Scene<'a> {
    fn new(data: &'a ReplayData, path: &Path) -> Result<Self, RenderError> {
        let m = &data.meta;
        let bad = |message: String| RenderError::Data {
            path: path.to_path_buf(),
            message,
        };
        if m.frames == 0 || m.vehicles == 0 {
            return Err(RenderError::Empty {
                path: path.to_path_buf(),
                frames: m.frames,
                vehicles: m.vehicles,
            });
        }
        let want = m
            .frames
            .checked_mul(m.vehicles)
            .and_then(|n| n.checked_mul(3))
            .ok_or_else(|| bad(format!("{} frames × {} vehicles", m.frames, m.vehicles)))?;
        for (name, len) in [("pos", data.pos.len()), ("att", data.att.len())] {
            if len != want {
                return Err(bad(format!(
                    "`{name}` holds {len} values, {} frames × {} vehicles × 3 = {want} expected",
                    m.frames, m.vehicles
                )));
            }
        }
        if !m.pool.iter().all(|v| v.is_finite() && *v > 0.0) {
            return Err(bad(format!(
                "pool size {:?} m: each must be finite and > 0",
                m.pool
            )));
        }
        if !(m.frame_dt.is_finite() && m.frame_dt > 0.0) {
            return Err(bad(format!(
                "frame_dt = {} s: must be finite and > 0",
                m.frame_dt
            )));
        }
        if m.group_of.len() != m.vehicles {
            return Err(bad(format!(
                "`group_of` has {} entries for {} vehicles",
                m.group_of.len(),
                m.vehicles
            )));
        }
        let n_groups = m.groups.len().max(1);
        let group_of: Vec<usize> = m.group_of.iter().map(|&g| g as usize).collect();
        if let Some((v, g)) = group_of.iter().enumerate().find(|(_, g)| **g >= n_groups) {
            return Err(bad(format!(
                "vehicle {v} is in group {g}, but there are {n_groups} groups"
            )));
        }
        let mut count = vec![0usize; n_groups];
        for &g in &group_of {
            count[g] += 1;
        }
        let groups = (0..n_groups)
            .map(|g| {
                let meta = m.groups.get(g);
                let color = meta
                    .and_then(|x| parse_hex(&x.color))
                    .unwrap_or_else(|| crate::plot::color(g));
                let hull = m
                    .hull
                    .get(g)
                    .copied()
                    .filter(|h| h.iter().all(|v| v.is_finite() && *v > 0.0))
                    .unwrap_or(DEFAULT_HULL);
                let name = meta.map_or("vehicles", |x| x.name.as_str());
                GroupStyle {
                    label: format!("{name} ({})", count[g]),
                    color,
                    trail: mix(color, WATER, 0.55),
                    hull,
                }
            })
            .collect();
        let finite = data.links.iter().all(|e| e.t.is_finite());
        let sorted = data.links.windows(2).all(|w| w[0].t <= w[1].t);
        let links = if finite && sorted {
            Cow::Borrowed(data.links.as_slice())
        } else {
            let mut v: Vec<LinkEvent> = data
                .links
                .iter()
                .copied()
                .filter(|e| e.t.is_finite())
                .collect();
            v.sort_by(|a, b| a.t.total_cmp(&b.t));
            Cow::Owned(v)
        };
        Ok(Self {
            data,
            frames: m.frames,
            vehicles: m.vehicles,
            pool: m.pool,
            dt: m.frame_dt,
            group_of,
            groups,
            links,
        })
    }

    /// Time of the last replay frame \[s\] (the first is at 0).
    fn last_t(&self) -> f64 {
        (self.frames - 1) as f64 * self.dt
    }

    /// The replay frame nearest to the time `t` \[s\].
    fn frame_at(&self, t: f64) -> usize {
        ((t / self.dt).round().max(0.0) as usize).min(self.frames - 1)
    }

    /// Position of vehicle `v` in replay frame `f` (x north, y east, z down) \[m\].
    #[inline]
    fn pos(&self, f: usize, v: usize) -> [f64; 3] {
        let i = (f * self.vehicles + v) * 3;
        let q = &self.data.pos[i..i + 3];
        [0, 1, 2].map(|k| f64::from(q[k]) / 65535.0 * self.pool[k])
    }

    /// Roll, pitch, yaw of vehicle `v` in replay frame `f` \[rad\].
    #[inline]
    fn att(&self, f: usize, v: usize) -> [f64; 3] {
        let i = (f * self.vehicles + v) * 3;
        let q = &self.data.att[i..i + 3];
        [0, 1, 2].map(|k| f64::from(q[k]) * std::f64::consts::PI / 32767.0)
    }

    /// Smallest and largest position of all vehicles over the whole run, per axis \[m\].
    fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let mut lo = [u16::MAX; 3];
        let mut hi = [0u16; 3];
        for p in self.data.pos.chunks_exact(3) {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let m = |q: [u16; 3]| [0, 1, 2].map(|k| f64::from(q[k]) / 65535.0 * self.pool[k]);
        (m(lo), m(hi))
    }

    /// The link events with `t0 < t ≤ t1`.
    fn links_in(&self, t0: f64, t1: f64) -> &[LinkEvent] {
        let a = self.links.partition_point(|e| f64::from(e.t) <= t0);
        let b = self.links.partition_point(|e| f64::from(e.t) <= t1);
        &self.links[a..b.max(a)]
    }
}

// ---------------------------------------------------------------------------------------------
// Timing

/// The simulated time of each GIF frame \[s\] and its delay \[1/100 s\].
fn schedule(last_t: f64, opts: &GifOptions) -> (Vec<f64>, Vec<u16>) {
    // (A float beyond usize saturates.)
    let natural = ((last_t * opts.fps / opts.speed + 1e-9).floor() as usize).saturating_add(1);
    let n = natural.min(opts.max_frames).max(1);
    let (times, step_cs): (Vec<f64>, f64) = if n == natural {
        let dt = opts.speed / opts.fps;
        ((0..n).map(|k| k as f64 * dt).collect(), 100.0 / opts.fps)
    } else if n == 1 {
        (vec![last_t], 0.0)
    } else {
        let dt = last_t / (n - 1) as f64;
        let times = (0..n).map(|k| k as f64 * dt).collect();
        (times, 100.0 * dt / opts.speed)
    };
    // Delays rounded so that their running sum stays on the exact clock.
    let clock = |k: usize| (k as f64 * step_cs).round();
    let hold = (END_HOLD_S * 100.0).round();
    let delays = (0..n)
        .map(|k| {
            let d = clock(k + 1) - clock(k) + if k + 1 == n { hold } else { 0.0 };
            // (`max` and `min` also turn a NaN of absurd options into a number.)
            d.max(2.0).min(f64::from(u16::MAX)) as u16
        })
        .collect();
    (times, delays)
}

// ---------------------------------------------------------------------------------------------
// Layout

/// Image rows above the maps: the title \[px\].
const TITLE_H: i32 = 34;
/// Rows above each map: its caption \[px\].
const CAPTION_H: i32 = 20;
/// Rows below each map: tick labels \[px\].
const TICKS_H: i32 = 24;
/// Columns left of each map: tick labels \[px\].
const LEFT_W: i32 = 46;
/// Columns right of each map \[px\].
const RIGHT_W: i32 = 16;
/// Height of a legend row \[px\].
const LEGEND_ROW: i32 = 20;
/// Most groups named in the legend.
const LEGEND_GROUPS: usize = 12;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PanelKind {
    Top,
    Side,
}

/// One map: which part of the world it shows, where on the image and at what scale.
#[derive(Clone, Copy, Debug)]
struct Panel {
    kind: PanelKind,
    /// Plotting area on the image: left, top, width, height \[px\].
    rect: (i32, i32, i32, i32),
    /// World range across \[m\]: east y (top view) or north x (side view).
    h: (f64, f64),
    /// World range up/down \[m\]: north x (top view, up) or depth z (side view, down).
    v: (f64, f64),
    /// Scale \[px/m\].
    scale: f64,
}

impl Panel {
    /// The map coordinates of the world point `p`: (across, up/down) \[m\].
    #[inline]
    fn hv(&self, p: [f64; 3]) -> (f64, f64) {
        match self.kind {
            PanelKind::Top => (p[1], p[0]),
            PanelKind::Side => (p[0], p[2]),
        }
    }

    /// Image position of the map coordinates `(h, v)` \[px\] (not rounded).
    #[inline]
    fn px_hv(&self, (h, v): (f64, f64)) -> (f64, f64) {
        let x = f64::from(self.rect.0) + (h - self.h.0) * self.scale;
        let y = match self.kind {
            // North up.
            PanelKind::Top => f64::from(self.rect.1) + (self.v.1 - v) * self.scale,
            // Depth down.
            PanelKind::Side => f64::from(self.rect.1) + (v - self.v.0) * self.scale,
        };
        (x, y)
    }

    /// Image pixel of the world point `p`.
    #[inline]
    fn px(&self, p: [f64; 3]) -> (i32, i32) {
        let (x, y) = self.px_hv(self.hv(p));
        (x.round() as i32, y.round() as i32)
    }

    /// The pixel of map coordinates.
    #[inline]
    fn px_i(&self, hv: (f64, f64)) -> (i32, i32) {
        let (x, y) = self.px_hv(hv);
        (x.round() as i32, y.round() as i32)
    }
}

/// Where everything goes on the image.
struct Layout {
    size: (u32, u32),
    panels: Vec<Panel>,
    /// Legend entries, each with its row and x \[px\].
    legend: Vec<(LegendEntry, i32, i32)>,
}

#[derive(Clone, Debug)]
enum LegendEntry {
    Group(RGBColor, String),
    Link(RGBColor, String),
    Note(String),
}

/// `(lo, hi)` widened about its centre to `span`.
fn widen(r: (f64, f64), span: f64) -> (f64, f64) {
    let c = 0.5 * (r.0 + r.1);
    (c - 0.5 * span, c + 0.5 * span)
}

/// The scale \[px/m\] and ranges that fit the map `h` × `v` into `pw` pixels across with a
/// height within `[min_h, max_h]` \[px\]: equal scales, one range widened about its centre
/// where the aspect ratio asks for it.
fn fit(
    h: (f64, f64),
    v: (f64, f64),
    pw: f64,
    min_h: f64,
    max_h: f64,
) -> ((f64, f64), (f64, f64), f64) {
    let mut s = pw / (h.1 - h.0);
    let (mut h, mut v) = (h, v);
    let ph = (v.1 - v.0) * s;
    if ph > max_h {
        s = max_h / (v.1 - v.0);
        h = widen(h, pw / s);
    } else if ph < min_h {
        v = widen(v, min_h / s);
    }
    (h, v, s)
}

impl Layout {
    fn new(scene: &Scene, opts: &GifOptions) -> Self {
        let w = opts.width_px as i32;
        let pw = w - LEFT_W - RIGHT_W;
        let (lo, hi) = scene.bounds();
        // The largest hull, enlarged as drawn: bodies at the edge stay inside.
        let hull = scene
            .groups
            .iter()
            .map(|g| g.hull[0].max(g.hull[1]).max(g.hull[2]))
            .fold(0.0, f64::max);
        let span = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
        let margin = (0.08 * span).max(1.5 * hull).max(0.3);
        // Beyond the pool only as far as it takes to see its walls.
        let edge = 0.03 * scene.pool[0].max(scene.pool[1]);
        let range = |k: usize| {
            let edge = if k == 2 { 0.05 * scene.pool[2] } else { edge };
            (
                (lo[k] - margin).max(-edge),
                (hi[k] + margin).min(scene.pool[k] + edge),
            )
        };
        let (x, y, z) = (range(0), range(1), range(2));
        let pwf = f64::from(pw);
        let kinds: &[PanelKind] = match opts.view {
            View::Top => &[PanelKind::Top],
            View::Side => &[PanelKind::Side],
            View::Both => &[PanelKind::Top, PanelKind::Side],
        };
        let mut top = TITLE_H;
        let mut panels = Vec::new();
        for &kind in kinds {
            let (h, v, scale) = match kind {
                PanelKind::Top => fit(y, x, pwf, 0.35 * pwf, pwf),
                PanelKind::Side => fit(x, z, pwf, 0.15 * pwf, 0.6 * pwf),
            };
            let ph = ((v.1 - v.0) * scale).round() as i32;
            let rect = (LEFT_W, top + CAPTION_H, pw, ph);
            panels.push(Panel {
                kind,
                rect,
                h,
                v,
                scale,
            });
            top += CAPTION_H + ph + TICKS_H;
        }
        // Legend: groups, then link outcomes, filled into rows.
        let mut entries: Vec<LegendEntry> = scene
            .groups
            .iter()
            .take(LEGEND_GROUPS)
            .map(|g| LegendEntry::Group(g.color, g.label.clone()))
            .collect();
        if scene.groups.len() > LEGEND_GROUPS {
            entries.push(LegendEntry::Note(format!(
                "+ {} groups",
                scene.groups.len() - LEGEND_GROUPS
            )));
        }
        // The link outcomes start a row of their own.
        let links_from = entries.len();
        if opts.links {
            entries.push(LegendEntry::Note("links:".into()));
            entries.extend(
                OUTCOMES
                    .iter()
                    .map(|(o, label)| LegendEntry::Link(outcome_color(*o), (*label).into())),
            );
        }
        let legend_y = top + 4;
        let mut legend = Vec::with_capacity(entries.len());
        let (mut x, mut row) = (LEFT_W, 0);
        for (i, e) in entries.into_iter().enumerate() {
            let need = legend_width(&e);
            if x > LEFT_W && (i == links_from || x + need > w - RIGHT_W) {
                row += 1;
                x = LEFT_W;
            }
            legend.push((e, x, legend_y + row * LEGEND_ROW));
            x += need;
        }
        let rows = legend
            .last()
            .map_or(0, |l| (l.2 - legend_y) / LEGEND_ROW + 1);
        let height = legend_y + rows * LEGEND_ROW + 6;
        Self {
            size: (opts.width_px, height.max(1) as u32),
            panels,
            legend,
        }
    }
}

/// Width of a text in the legend font \[px\], estimated without drawing.
fn text_width(text: &str, size: u32) -> i32 {
    let mut buf = [0u8; 3];
    let area = match BitMapBackend::<RGBPixel>::with_buffer_and_format(&mut buf, (1, 1)) {
        Ok(b) => b.into_drawing_area(),
        Err(_) => return 7 * text.chars().count() as i32,
    };
    let font: TextStyle = ("sans-serif", size).into_font().into();
    area.estimate_text_size(text, &font)
        .map_or(7 * text.chars().count() as i32, |(w, _)| w as i32)
}

const LEGEND_FONT: u32 = 13;
const LEGEND_SAMPLE: i32 = 18;

/// Columns a legend entry takes, its gap to the next included \[px\].
fn legend_width(e: &LegendEntry) -> i32 {
    match e {
        LegendEntry::Group(_, s) | LegendEntry::Link(_, s) => {
            LEGEND_SAMPLE + 5 + text_width(s, LEGEND_FONT) + 16
        }
        LegendEntry::Note(s) => text_width(s, LEGEND_FONT) + 10,
    }
}

// ---------------------------------------------------------------------------------------------
// Geometry helpers

/// The part of the convex polygon `poly` inside the box `h` × `v` (Sutherland–Hodgman).
fn clip_convex(poly: &[(f64, f64)], h: (f64, f64), v: (f64, f64)) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = poly.to_vec();
    // Each edge of the box: inside test and intersection.
    let planes: [(usize, f64, bool); 4] = [
        (0, h.0, true),
        (0, h.1, false),
        (1, v.0, true),
        (1, v.1, false),
    ];
    for (axis, bound, keep_above) in planes {
        let inside = |p: &(f64, f64)| {
            let c = if axis == 0 { p.0 } else { p.1 };
            if keep_above { c >= bound } else { c <= bound }
        };
        let input = std::mem::take(&mut out);
        let n = input.len();
        for i in 0..n {
            let (a, b) = (input[i], input[(i + 1) % n]);
            let (ia, ib) = (inside(&a), inside(&b));
            if ia {
                out.push(a);
            }
            if ia != ib {
                let (ca, cb) = if axis == 0 { (a.0, b.0) } else { (a.1, b.1) };
                let t = (bound - ca) / (cb - ca);
                out.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
            }
        }
        if out.is_empty() {
            break;
        }
    }
    out
}

/// The convex hull of `pts` (Andrew's monotone chain) into `out`, counter-clockwise in image
/// coordinates' sense of orientation; `pts` is sorted in place.
fn convex_hull(pts: &mut [(f64, f64)], out: &mut Vec<(i32, i32)>) {
    out.clear();
    if pts.is_empty() {
        return;
    }
    pts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let cross = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut hull: [(f64, f64); 32] = [(0.0, 0.0); 32];
    let mut k = 0usize;
    let n = pts.len().min(15);
    for &p in &pts[..n] {
        while k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 0.0 {
            k -= 1;
        }
        hull[k] = p;
        k += 1;
    }
    let lower = k + 1;
    for &p in pts[..n].iter().rev().skip(1) {
        while k >= lower && cross(hull[k - 2], hull[k - 1], p) <= 0.0 {
            k -= 1;
        }
        hull[k] = p;
        k += 1;
    }
    out.extend(
        hull[..k.saturating_sub(1).max(1)]
            .iter()
            .map(|p| (p.0.round() as i32, p.1.round() as i32)),
    );
}

/// A unit quaternion from (x, y, z, w); `None` unless finite and non-zero.
fn rotation_of(q: [f64; 4]) -> Option<UnitQuaternion<f64>> {
    let q = Quaternion::new(q[3], q[0], q[1], q[2]);
    (q.coords.iter().all(|c| c.is_finite()) && q.norm() > 1e-12)
        .then(|| UnitQuaternion::from_quaternion(q))
}

/// The support point of the obstacle `o` in the world direction `d` (the point of the shape
/// farthest along `d`) \[m\], or `None` for an unknown kind or missing or bad dimensions.
/// Shapes as parry builds them: box of full extents `size`, sphere, cylinder along local y of
/// full `height`, capsule along local z with a straight part of `height`.
fn support(o: &ObstacleMeta, rot: &UnitQuaternion<f64>, d: Vector3<f64>) -> Option<Vector3<f64>> {
    let l = rot.inverse_transform_vector(&d);
    let pos_f = |v: f64| v.is_finite() && v >= 0.0;
    let sign = |v: f64| if v < 0.0 { -1.0 } else { 1.0 };
    let local = match o.kind.as_str() {
        "box" => {
            let s = o.size.filter(|s| s.iter().all(|v| pos_f(*v)))?;
            Vector3::new(
                0.5 * s[0] * sign(l.x),
                0.5 * s[1] * sign(l.y),
                0.5 * s[2] * sign(l.z),
            )
        }
        "sphere" => {
            let r = o.radius.filter(|r| pos_f(*r))?;
            l.try_normalize(1e-12).unwrap_or_else(Vector3::zeros) * r
        }
        "cylinder" => {
            let (r, h) = (
                o.radius.filter(|r| pos_f(*r))?,
                o.height.filter(|h| pos_f(*h))?,
            );
            let radial = Vector3::new(l.x, 0.0, l.z);
            radial.try_normalize(1e-12).unwrap_or_else(Vector3::zeros) * r
                + Vector3::new(0.0, 0.5 * h * sign(l.y), 0.0)
        }
        "capsule" => {
            let (r, h) = (
                o.radius.filter(|r| pos_f(*r))?,
                o.height.filter(|h| pos_f(*h))?,
            );
            l.try_normalize(1e-12).unwrap_or_else(Vector3::zeros) * r
                + Vector3::new(0.0, 0.0, 0.5 * h * sign(l.z))
        }
        _ => return None,
    };
    let p = Vector3::from(o.position);
    p.iter()
        .all(|c| c.is_finite())
        .then(|| rot.transform_vector(&local) + p)
}

/// The outline of the obstacle `o` seen by the panel (its projection: from above on x–y, from
/// the side on x–z) in map coordinates, as a convex polygon of 48 support points.
fn obstacle_outline(o: &ObstacleMeta, kind: PanelKind) -> Option<Vec<(f64, f64)>> {
    let rot = rotation_of(o.rotation)?;
    (0..48)
        .map(|k| {
            let a = std::f64::consts::TAU * f64::from(k) / 48.0;
            let (c, s) = (a.cos(), a.sin());
            let d = match kind {
                PanelKind::Top => Vector3::new(c, s, 0.0),
                PanelKind::Side => Vector3::new(c, 0.0, s),
            };
            let p = support(o, &rot, d)?;
            Some(match kind {
                PanelKind::Top => (p.y, p.x),
                PanelKind::Side => (p.x, p.z),
            })
        })
        .collect()
}

/// A nice tick step for `span` metres over `px` pixels: about one tick per 60 px.
fn tick_step(span: f64, px: f64) -> f64 {
    let raw = (span * 60.0 / px.max(1.0)).max(1e-6);
    let mag = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag)
}

fn tick_label(v: f64, step: f64) -> String {
    let decimals = if step >= 1.0 {
        0
    } else if step >= 0.1 {
        1
    } else {
        2
    };
    let v = if v.abs() < 0.5 * step * 1e-6 { 0.0 } else { v };
    format!("{v:.decimals$}")
}

/// The body of a vehicle in its own frame (x forward, y right, z down) \[m\]: a pointed
/// prism of the hull's length, width and height.
fn body_points(hull: [f64; 3]) -> [Vector3<f64>; 10] {
    let (l, w, h) = (0.5 * hull[0], 0.5 * hull[1], 0.5 * hull[2]);
    let outline = [(l, 0.0), (l / 3.0, w), (-l, w), (-l, -w), (l / 3.0, -w)];
    let mut pts = [Vector3::zeros(); 10];
    for (i, (x, y)) in outline.into_iter().enumerate() {
        pts[i] = Vector3::new(x, y, -h);
        pts[i + 5] = Vector3::new(x, y, h);
    }
    pts
}

// ---------------------------------------------------------------------------------------------
// Drawing

/// A plotters error as text.
fn de<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> String {
    e.to_string()
}

/// The bitmap the GIF is drawn on: plotters' RGB bitmap with hard-edged shapes. plotters
/// blends the edge pixels of lines and polygons with what lies under them, and in a palette
/// image such blends go to unrelated entries (the edge of a teal link to a group's blue);
/// here an edge pixel is drawn in full where it is at least half covered, else not at all.
/// Text keeps its smooth edges: black or grey on white, which the grey ramp holds.
struct Crisp<'a>(BitMapBackend<'a, RGBPixel>);

type CrispError<'a> = DrawingErrorKind<<BitMapBackend<'a, RGBPixel> as DrawingBackend>::ErrorType>;

impl<'a> DrawingBackend for Crisp<'a> {
    type ErrorType = <BitMapBackend<'a, RGBPixel> as DrawingBackend>::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.0.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), CrispError<'a>> {
        self.0.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), CrispError<'a>> {
        self.0.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), CrispError<'a>> {
        if color.alpha < 0.5 {
            return Ok(());
        }
        self.0.draw_pixel(
            point,
            BackendColor {
                alpha: 1.0,
                rgb: color.rgb,
            },
        )
    }

    fn draw_rect<S: backend::BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), CrispError<'a>> {
        // Axis-aligned: hard edges already, and the bitmap's own fill is fast.
        self.0.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_text<T: backend::BackendTextStyle>(
        &mut self,
        text: &str,
        style: &T,
        pos: BackendCoord,
    ) -> Result<(), CrispError<'a>> {
        self.0.draw_text(text, style, pos)
    }

    fn estimate_text_size<T: backend::BackendTextStyle>(
        &self,
        text: &str,
        style: &T,
    ) -> Result<(u32, u32), CrispError<'a>> {
        self.0.estimate_text_size(text, style)
    }
}

type Area<'a> = DrawingArea<Crisp<'a>, Shift>;

/// An RGB buffer of `size` as a drawing area.
fn area_of(buf: &mut [u8], size: (u32, u32)) -> Result<Area<'_>, String> {
    BitMapBackend::<RGBPixel>::with_buffer_and_format(buf, size)
        .map(|b| Crisp(b).into_drawing_area())
        .map_err(|e| e.to_string())
}

fn rect_px(p: &Panel, h: (f64, f64), v: (f64, f64)) -> [(i32, i32); 2] {
    let a = p.px_i((h.0.max(p.h.0), v.0.max(p.v.0)));
    let b = p.px_i((h.1.min(p.h.1), v.1.min(p.v.1)));
    [(a.0.min(b.0), a.1.min(b.1)), (a.0.max(b.0), a.1.max(b.1))]
}

/// Whether the map ranges `h` × `v` overlap the panel's.
fn overlaps(p: &Panel, h: (f64, f64), v: (f64, f64)) -> bool {
    h.0 < p.h.1 && h.1 > p.h.0 && v.0 < p.v.1 && v.1 > p.v.0
}

/// Draws what does not change: maps with water, walls, obstacles, grid and ticks, and the
/// legend.
fn draw_background(area: &Area, scene: &Scene, lay: &Layout) -> Result<(), String> {
    area.fill(&BG).map_err(de)?;
    let pool = scene.pool;
    let small = |c: RGBColor| ("sans-serif", 11).into_font().color(&c);
    for p in &lay.panels {
        let (x0, y0, w, h) = p.rect;
        let full = [(x0, y0), (x0 + w, y0 + h)];
        area.draw(&Rectangle::new(full, OUTSIDE.filled()))
            .map_err(de)?;
        let (water_v, caption) = match p.kind {
            PanelKind::Top => (
                (0.0, pool[0]),
                "from above: north x ↑, east y → [m]".to_string(),
            ),
            PanelKind::Side => (
                (0.0, pool[2]),
                "from the east: north x →, depth z ↓ [m]".to_string(),
            ),
        };
        let water_h = match p.kind {
            PanelKind::Top => (0.0, pool[1]),
            PanelKind::Side => (0.0, pool[0]),
        };
        if p.kind == PanelKind::Side && p.v.0 < 0.0 {
            // Air above the surface.
            area.draw(&Rectangle::new(rect_px(p, p.h, (p.v.0, 0.0)), BG.filled()))
                .map_err(de)?;
        }
        if overlaps(p, water_h, water_v) {
            area.draw(&Rectangle::new(
                rect_px(p, water_h, water_v),
                WATER.filled(),
            ))
            .map_err(de)?;
        }
        // Grid and ticks.
        let hs = tick_step(p.h.1 - p.h.0, f64::from(w));
        let vs = tick_step(p.v.1 - p.v.0, f64::from(h));
        let ticks = |r: (f64, f64), s: f64| {
            let first = (r.0 / s).ceil() as i64;
            let last = (r.1 / s).floor() as i64;
            (first..=last).map(move |i| i as f64 * s)
        };
        for t in ticks(p.h, hs) {
            let (x, _) = p.px_i((t, p.v.0));
            area.draw(&PathElement::new(vec![(x, y0), (x, y0 + h)], GRID))
                .map_err(de)?;
            area.draw(&PathElement::new(vec![(x, y0 + h), (x, y0 + h + 4)], FRAME))
                .map_err(de)?;
            area.draw(&Text::new(
                tick_label(t, hs),
                (x, y0 + h + 6),
                small(TEXT_GREY).pos(Pos::new(HPos::Center, VPos::Top)),
            ))
            .map_err(de)?;
        }
        for t in ticks(p.v, vs) {
            let (_, y) = p.px_i((p.h.0, t));
            area.draw(&PathElement::new(vec![(x0, y), (x0 + w, y)], GRID))
                .map_err(de)?;
            area.draw(&PathElement::new(vec![(x0 - 4, y), (x0, y)], FRAME))
                .map_err(de)?;
            area.draw(&Text::new(
                tick_label(t, vs),
                (x0 - 6, y),
                small(TEXT_GREY).pos(Pos::new(HPos::Right, VPos::Center)),
            ))
            .map_err(de)?;
        }
        // Obstacles.
        for o in &scene.data.meta.obstacles {
            let Some(outline) = obstacle_outline(o, p.kind) else {
                continue;
            };
            let clipped = clip_convex(&outline, p.h, p.v);
            if clipped.len() < 3 {
                continue;
            }
            let mut pts: Vec<(i32, i32)> = clipped.iter().map(|&q| p.px_i(q)).collect();
            area.draw(&Polygon::new(pts.clone(), OBSTACLE.filled()))
                .map_err(de)?;
            pts.push(pts[0]);
            area.draw(&PathElement::new(pts, OBSTACLE_EDGE))
                .map_err(de)?;
        }
        // Walls (and the surface, from the side).
        let walls: Vec<(f64, f64)> = match p.kind {
            PanelKind::Top => vec![
                (0.0, 0.0),
                (pool[1], 0.0),
                (pool[1], pool[0]),
                (0.0, pool[0]),
                (0.0, 0.0),
            ],
            PanelKind::Side => vec![
                (0.0, 0.0),
                (0.0, pool[2]),
                (pool[0], pool[2]),
                (pool[0], 0.0),
            ],
        };
        for piece in clip_polyline(&walls, p.h, p.v) {
            let px: Vec<(i32, i32)> = piece.iter().map(|&q| p.px_i(q)).collect();
            area.draw(&PathElement::new(px, WALL.stroke_width(2)))
                .map_err(de)?;
        }
        if p.kind == PanelKind::Side {
            for piece in clip_polyline(&[(0.0, 0.0), (pool[0], 0.0)], p.h, p.v) {
                let px: Vec<(i32, i32)> = piece.iter().map(|&q| p.px_i(q)).collect();
                area.draw(&PathElement::new(px, SURFACE.stroke_width(2)))
                    .map_err(de)?;
            }
        }
        area.draw(&Rectangle::new(full, FRAME.stroke_width(1)))
            .map_err(de)?;
        area.draw(&Text::new(
            caption,
            (x0, y0 - 4),
            ("sans-serif", 13)
                .into_font()
                .color(&TEXT_GREY)
                .pos(Pos::new(HPos::Left, VPos::Bottom)),
        ))
        .map_err(de)?;
    }
    // Legend.
    let font = ("sans-serif", LEGEND_FONT).into_font();
    for (e, x, y) in &lay.legend {
        let yc = y + LEGEND_ROW / 2;
        let text_at = |s: &str, x: i32, c: RGBColor| {
            area.draw(&Text::new(
                s.to_string(),
                (x, yc),
                font.clone()
                    .color(&c)
                    .pos(Pos::new(HPos::Left, VPos::Center)),
            ))
            .map_err(de)
        };
        match e {
            LegendEntry::Group(c, s) => {
                area.draw(&Rectangle::new(
                    [(x + 2, yc - 5), (x + LEGEND_SAMPLE - 2, yc + 5)],
                    c.filled(),
                ))
                .map_err(de)?;
                text_at(s, x + LEGEND_SAMPLE + 5, TEXT)?;
            }
            LegendEntry::Link(c, s) => {
                area.draw(&PathElement::new(
                    vec![(*x, yc), (x + LEGEND_SAMPLE, yc)],
                    c.stroke_width(2),
                ))
                .map_err(de)?;
                text_at(s, x + LEGEND_SAMPLE + 5, TEXT)?;
            }
            LegendEntry::Note(s) => text_at(s, *x, TEXT_GREY)?,
        }
    }
    Ok(())
}

/// What changes from frame to frame, drawn over the background.
struct Dynamic<'s> {
    scene: &'s Scene<'s>,
    opts: &'s GifOptions,
    /// Per group: the body's corners in the body frame \[m\].
    bodies: Vec<[Vector3<f64>; 10]>,
    /// Trail length in replay frames, and the step between trail points.
    trail: (usize, usize),
    /// Link window \[s\].
    window: f64,
    /// Scratch.
    pts: Vec<(f64, f64)>,
    hull: Vec<(i32, i32)>,
}

impl<'s> Dynamic<'s> {
    fn new(scene: &'s Scene<'s>, opts: &'s GifOptions) -> Self {
        let frames = (opts.trail_s / scene.dt).round() as usize;
        let step = frames.div_ceil(24).max(1);
        Self {
            scene,
            opts,
            bodies: scene.groups.iter().map(|g| body_points(g.hull)).collect(),
            trail: (frames, step),
            window: LINK_WINDOW_S.max(opts.speed / opts.fps),
            pts: Vec::with_capacity(16),
            hull: Vec::with_capacity(16),
        }
    }

    fn draw(&mut self, area: &Area, lay: &Layout, t: f64) -> Result<(), String> {
        let scene = self.scene;
        let f = scene.frame_at(t);
        let n = scene.vehicles;
        let thin = n > 60;
        for p in &lay.panels {
            // Trails.
            let (len, step) = self.trail;
            if len > 0 && f > 0 {
                let first = f.saturating_sub(len);
                for v in 0..n {
                    let mut line: Vec<(i32, i32)> = (first..f)
                        .step_by(step)
                        .map(|k| p.px(scene.pos(k, v)))
                        .collect();
                    line.push(p.px(scene.pos(f, v)));
                    let c = scene.groups[scene.group_of[v]].trail;
                    area.draw(&PathElement::new(
                        line,
                        c.stroke_width(if thin { 1 } else { 2 }),
                    ))
                    .map_err(de)?;
                }
            }
            // Links, losses over deliveries.
            if self.opts.links {
                let events = scene.links_in(t - self.window, t);
                for (o, _) in OUTCOMES {
                    let c = outcome_color(o);
                    for e in events.iter().filter(|e| e.outcome == o) {
                        let (a, b) = (e.from as usize, e.to as usize);
                        if a >= n || b >= n {
                            continue;
                        }
                        let seg = vec![p.px(scene.pos(f, a)), p.px(scene.pos(f, b))];
                        area.draw(&PathElement::new(seg, c)).map_err(de)?;
                    }
                }
            }
            // Bodies.
            for v in 0..n {
                let g = scene.group_of[v];
                let hull = scene.groups[g].hull;
                let grow = (MIN_BODY_PX / (hull[0] * p.scale)).max(1.0);
                let [roll, pitch, yaw] = scene.att(f, v);
                let r = Rotation3::from_euler_angles(roll, pitch, yaw);
                let c = Vector3::from(scene.pos(f, v));
                self.pts.clear();
                for b in &self.bodies[g] {
                    let w = c + r * (b * grow);
                    self.pts.push(p.px_hv(p.hv([w.x, w.y, w.z])));
                }
                convex_hull(&mut self.pts, &mut self.hull);
                let color = scene.groups[g].color;
                area.draw(&Polygon::new(self.hull.clone(), color.filled()))
                    .map_err(de)?;
            }
        }
        // Title.
        let meta = &scene.data.meta;
        area.draw(&Text::new(
            format!("{}   t = {:.1} s", meta.world, t),
            (LEFT_W, TITLE_H / 2),
            ("sans-serif", 17)
                .into_font()
                .color(&TEXT)
                .pos(Pos::new(HPos::Left, VPos::Center)),
        ))
        .map_err(de)?;
        let speed = format!("{}× speed", trim(self.opts.speed));
        area.draw(&Text::new(
            speed,
            (lay.size.0 as i32 - RIGHT_W, TITLE_H / 2),
            ("sans-serif", 13)
                .into_font()
                .color(&TEXT_GREY)
                .pos(Pos::new(HPos::Right, VPos::Center)),
        ))
        .map_err(de)?;
        Ok(())
    }
}

/// A number without trailing zeros (`4`, `0.5`, `2.25`).
fn trim(v: f64) -> String {
    let s = format!("{v:.2}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

// ---------------------------------------------------------------------------------------------
// Encoding

/// Writes frames into the GIF: the first whole, later ones as the rectangle that changed with
/// unchanged pixels transparent.
struct Frames {
    prev: Vec<u8>,
    sub: Vec<u8>,
    width: usize,
    height: usize,
    first: bool,
}

impl Frames {
    fn write<W: Write>(
        &mut self,
        enc: &mut ::gif::Encoder<W>,
        cur: &[u8],
        delay: u16,
    ) -> Result<(), ::gif::EncodingError> {
        let (w, h) = (self.width, self.height);
        let mut frame = ::gif::Frame {
            delay,
            dispose: ::gif::DisposalMethod::Keep,
            ..::gif::Frame::default()
        };
        if self.first {
            self.first = false;
            frame.width = w as u16;
            frame.height = h as u16;
            frame.buffer = Cow::Borrowed(cur);
            enc.write_frame(&frame)?;
            self.prev.copy_from_slice(cur);
            return Ok(());
        }
        // The rectangle that changed.
        let (mut x0, mut y0, mut x1, mut y1) = (w, h, 0, 0);
        for (y, (a, b)) in cur
            .chunks_exact(w)
            .zip(self.prev.chunks_exact(w))
            .enumerate()
        {
            if a == b {
                continue;
            }
            let first = a.iter().zip(b).position(|(p, q)| p != q).unwrap_or(0);
            let last = w - a
                .iter()
                .rev()
                .zip(b.iter().rev())
                .position(|(p, q)| p != q)
                .unwrap_or(0);
            x0 = x0.min(first);
            x1 = x1.max(last);
            y0 = y0.min(y);
            y1 = y1.max(y + 1);
        }
        self.sub.clear();
        frame.transparent = Some(TRANSPARENT);
        if x1 <= x0 {
            // Nothing changed: one transparent pixel.
            self.sub.push(TRANSPARENT);
            frame.width = 1;
            frame.height = 1;
        } else {
            for y in y0..y1 {
                let row = y * w;
                self.sub.extend(
                    cur[row + x0..row + x1]
                        .iter()
                        .zip(&self.prev[row + x0..row + x1])
                        .map(|(&c, &p)| if c == p { TRANSPARENT } else { c }),
                );
            }
            frame.left = x0 as u16;
            frame.top = y0 as u16;
            frame.width = (x1 - x0) as u16;
            frame.height = (y1 - y0) as u16;
        }
        frame.buffer = Cow::Borrowed(&self.sub);
        enc.write_frame(&frame)?;
        self.prev.copy_from_slice(cur);
        Ok(())
    }
}

fn check_options(opts: &GifOptions, path: &Path) -> Result<(), RenderError> {
    let bad = |message: String| {
        Err(RenderError::Options {
            path: path.to_path_buf(),
            message,
        })
    };
    if !(WIDTH_RANGE.0..=WIDTH_RANGE.1).contains(&opts.width_px) {
        return bad(format!(
            "width_px = {} px: must be {} to {}",
            opts.width_px, WIDTH_RANGE.0, WIDTH_RANGE.1
        ));
    }
    if !(opts.fps.is_finite() && opts.fps > 0.0 && opts.fps <= MAX_GIF_FPS) {
        return bad(format!(
            "fps = {}: must be above 0 and at most {MAX_GIF_FPS}",
            opts.fps
        ));
    }
    if !(opts.speed.is_finite() && opts.speed > 0.0) {
        return bad(format!(
            "speed = {}: must be finite and above 0 (simulated seconds per GIF second)",
            opts.speed
        ));
    }
    if !(1..=MAX_GIF_FRAMES).contains(&opts.max_frames) {
        return bad(format!(
            "max_frames = {}: must be 1 to {MAX_GIF_FRAMES}",
            opts.max_frames
        ));
    }
    if !(opts.trail_s.is_finite() && opts.trail_s >= 0.0) {
        return bad(format!(
            "trail_s = {} s: must be finite and at least 0",
            opts.trail_s
        ));
    }
    Ok(())
}

/// Renders the replay `data` as an animated GIF at `path` (written whole or not at all) and
/// returns `path`. See the module documentation for what it shows and how long it plays.
///
/// Errors name the file: an empty replay (no frames or no vehicles), arrays that do not fit
/// the header, options out of range, or the file system's reason.
pub fn render(data: &ReplayData, path: &Path, opts: &GifOptions) -> Result<PathBuf, RenderError> {
    check_options(opts, path)?;
    let scene = Scene::new(data, path)?;
    register_font();
    let lay = Layout::new(&scene, opts);
    let draw_err = |message: String| RenderError::Draw {
        path: path.to_path_buf(),
        message,
    };
    let (w, h) = lay.size;
    if h > u32::from(u16::MAX) {
        return Err(draw_err(format!("the image would be {h} px high")));
    }
    let (times, delays) = schedule(scene.last_t(), opts);
    // Palette: what matters most first (see `Palette::new`).
    let mut colors: Vec<RGBColor> = vec![BG, TEXT];
    colors.extend(scene.groups.iter().map(|g| g.color));
    colors.extend(OUTCOMES.iter().map(|(o, _)| outcome_color(*o)));
    colors.extend([
        TEXT_GREY,
        OUTSIDE,
        WATER,
        GRID,
        OBSTACLE,
        OBSTACLE_EDGE,
        WALL,
        SURFACE,
        FRAME,
    ]);
    colors.extend(scene.groups.iter().map(|g| g.trail));
    colors.extend((0..32u8).map(|i| RGBColor(i * 8, i * 8, i * 8)));
    // Anti-aliased text and tints for the map's blends.
    colors.extend((1..8).map(|i| mix(WATER, TEXT, f64::from(i) / 8.0)));
    colors.extend(scene.groups.iter().map(|g| mix(g.color, BG, 0.5)));
    let palette = Palette::new(&colors);

    let npx = w as usize * h as usize;
    let mut base = vec![0u8; npx * 3];
    {
        let area = area_of(&mut base, lay.size).map_err(draw_err)?;
        draw_background(&area, &scene, &lay).map_err(draw_err)?;
    }
    let file = AtomicFile::create(path)?;
    let enc_err = |e: ::gif::EncodingError| match e {
        ::gif::EncodingError::Io(reason) => RenderError::File(FileError {
            path: path.to_path_buf(),
            reason,
        }),
        other => draw_err(other.to_string()),
    };
    let mut enc = ::gif::Encoder::new(
        BufWriter::with_capacity(1 << 16, file),
        w as u16,
        h as u16,
        &palette.rgb,
    )
    .map_err(enc_err)?;
    enc.set_repeat(::gif::Repeat::Infinite).map_err(enc_err)?;
    let mut frames = Frames {
        prev: vec![0u8; npx],
        sub: Vec::with_capacity(npx),
        width: w as usize,
        height: h as usize,
        first: true,
    };
    let mut dynamic = Dynamic::new(&scene, opts);
    let mut rgb = base.clone();
    let mut idx = vec![0u8; npx];
    for (&t, &delay) in times.iter().zip(&delays) {
        rgb.copy_from_slice(&base);
        {
            let area = area_of(&mut rgb, lay.size).map_err(draw_err)?;
            dynamic.draw(&area, &lay, t).map_err(draw_err)?;
        }
        palette.map(&rgb, &mut idx);
        frames.write(&mut enc, &idx, delay).map_err(enc_err)?;
    }
    let buffered = enc.into_inner().map_err(enc_err)?;
    let file = buffered.into_inner().map_err(|e| {
        RenderError::File(FileError {
            path: path.to_path_buf(),
            reason: e.into_error(),
        })
    })?;
    Ok(file.commit()?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::replay::{GroupMeta, Meta, Timeline};
    use std::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_2};

    const POOL: [f64; 3] = [10.0, 8.0, 3.0];
    const HULL: [f64; 3] = [0.6, 0.2, 0.15];
    const COLORS: [&str; 3] = ["#1f77b4", "#ff7f0e", "#2ca02c"];

    /// Start and end (x, y, z) \[m\] and attitude (roll, pitch, yaw) \[rad\] of each vehicle of
    /// the synthetic run: one goes north, one east, one north and down.
    fn paths() -> [([f64; 3], [f64; 3], [f64; 3]); 3] {
        [
            ([2.0, 2.0, 1.0], [8.0, 2.0, 1.0], [0.0, 0.0, 0.0]),
            ([2.0, 3.0, 1.5], [2.0, 7.0, 1.5], [0.0, 0.0, FRAC_PI_2]),
            (
                [4.0, 6.0, 0.5],
                [7.0, 6.0, 2.5],
                [0.0, -(2.0f64 / 3.0).atan(), 0.0],
            ),
        ]
    }

    fn ev(t: f32, from: u32, to: u32, outcome: Outcome) -> LinkEvent {
        LinkEvent {
            t,
            from,
            to,
            outcome,
        }
    }

    /// A 20-s replay at 10 frames per second of three vehicles on straight paths (each its
    /// own group), one vertical cylinder and a few link attempts.
    fn synthetic() -> ReplayData {
        let (frames, dt) = (201usize, 0.1);
        let paths = paths();
        let n = paths.len();
        let mut pos = Vec::with_capacity(frames * n * 3);
        let mut att = Vec::with_capacity(frames * n * 3);
        for f in 0..frames {
            let s = f as f64 / (frames - 1) as f64;
            for (a, b, rpy) in &paths {
                for k in 0..3 {
                    let p = a[k] + s * (b[k] - a[k]);
                    pos.push((p / POOL[k] * 65535.0).round() as u16);
                    att.push((rpy[k] / std::f64::consts::PI * 32767.0).round() as i16);
                }
            }
        }
        let meta = Meta {
            version: 1,
            world: "synthetic".into(),
            seed: 1,
            duration_s: 20.0,
            frame_dt: dt,
            frames,
            vehicles: n,
            pool: POOL,
            obstacles: vec![ObstacleMeta {
                name: "pillar".into(),
                kind: "cylinder".into(),
                size: None,
                radius: Some(0.4),
                height: Some(3.0),
                position: [5.0, 4.0, 1.5],
                // Local y (the cylinder's axis) turned onto z: a vertical pillar.
                rotation: [FRAC_1_SQRT_2, 0.0, 0.0, FRAC_1_SQRT_2],
            }],
            groups: ["north", "east", "dive"]
                .iter()
                .zip(COLORS)
                .map(|(name, color)| GroupMeta {
                    name: (*name).into(),
                    color: color.into(),
                    count: 1,
                })
                .collect(),
            group_of: vec![0, 1, 2],
            names: vec!["a".into(), "b".into(), "c".into()],
            hull: vec![HULL; 3],
            modem_range_m: 5.0,
            panel: Vec::new(),
            modes: Vec::new(),
            links_kept: 4,
            links_total: 4,
            timeline: Timeline::default(),
        };
        ReplayData {
            meta,
            pos,
            att,
            panel: Vec::new(),
            links: vec![
                ev(1.0, 0, 1, Outcome::Occluded),
                ev(10.0, 1, 2, Outcome::OutOfBudget),
                ev(19.8, 0, 2, Outcome::Delivered),
                ev(19.9, 2, 1, Outcome::Collided),
            ],
        }
    }

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("shoal-gif-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    /// A decoded GIF: size, global palette, each frame composed on the canvas (palette
    /// indices) and each frame's delay \[1/100 s\].
    struct Decoded {
        w: usize,
        h: usize,
        palette: Vec<u8>,
        frames: Vec<Vec<u8>>,
        delays: Vec<u16>,
    }

    impl Decoded {
        fn rgb(&self, frame: usize, (x, y): (i32, i32)) -> [u8; 3] {
            let i = usize::from(self.frames[frame][y as usize * self.w + x as usize]);
            [
                self.palette[3 * i],
                self.palette[3 * i + 1],
                self.palette[3 * i + 2],
            ]
        }

        /// Pixels of colour `c` in frame `frame` inside `rect`: count, centroid, bounding box
        /// (x0, y0, x1, y1).
        fn blob(&self, frame: usize, rect: (i32, i32, i32, i32), c: RGBColor) -> Blob {
            let mut b = Blob {
                n: 0,
                cx: 0.0,
                cy: 0.0,
                bbox: (i32::MAX, i32::MAX, i32::MIN, i32::MIN),
            };
            for y in rect.1..rect.1 + rect.3 {
                for x in rect.0..rect.0 + rect.2 {
                    if self.rgb(frame, (x, y)) == [c.0, c.1, c.2] {
                        b.n += 1;
                        b.cx += f64::from(x);
                        b.cy += f64::from(y);
                        b.bbox = (
                            b.bbox.0.min(x),
                            b.bbox.1.min(y),
                            b.bbox.2.max(x),
                            b.bbox.3.max(y),
                        );
                    }
                }
            }
            b.cx /= b.n.max(1) as f64;
            b.cy /= b.n.max(1) as f64;
            b
        }
    }

    #[derive(Debug)]
    struct Blob {
        n: usize,
        cx: f64,
        cy: f64,
        bbox: (i32, i32, i32, i32),
    }

    impl Blob {
        fn size(&self) -> (i32, i32) {
            (self.bbox.2 - self.bbox.0 + 1, self.bbox.3 - self.bbox.1 + 1)
        }
        fn centre(&self) -> (f64, f64) {
            (
                0.5 * f64::from(self.bbox.0 + self.bbox.2),
                0.5 * f64::from(self.bbox.1 + self.bbox.3),
            )
        }
    }

    fn decode(path: &Path) -> Decoded {
        let mut o = ::gif::DecodeOptions::new();
        o.set_color_output(::gif::ColorOutput::Indexed);
        let mut d = o.read_info(std::fs::File::open(path).unwrap()).unwrap();
        let (w, h) = (usize::from(d.width()), usize::from(d.height()));
        let palette = d.global_palette().unwrap().to_vec();
        let mut canvas = vec![0u8; w * h];
        let (mut frames, mut delays) = (Vec::new(), Vec::new());
        while let Some(f) = d.read_next_frame().unwrap() {
            assert_eq!(f.dispose, ::gif::DisposalMethod::Keep);
            let (fw, left, top) = (
                usize::from(f.width),
                usize::from(f.left),
                usize::from(f.top),
            );
            for (i, &c) in f.buffer.iter().enumerate() {
                if Some(c) != f.transparent {
                    canvas[(top + i / fw) * w + left + i % fw] = c;
                }
            }
            frames.push(canvas.clone());
            delays.push(f.delay);
        }
        Decoded {
            w,
            h,
            palette,
            frames,
            delays,
        }
    }

    fn opts() -> GifOptions {
        GifOptions {
            width_px: 600,
            ..GifOptions::default()
        }
    }

    /// The frame count, size and timing follow from the options; the maps show the vehicles
    /// where they are, turned as they head, east to the right and north up; obstacles and
    /// links are drawn; no temporary is left.
    #[test]
    fn a_gif_shows_the_run_where_it_happened() {
        let d = dir("geometry");
        let path = d.join("run.gif");
        let data = synthetic();
        let opts = opts();
        assert_eq!(render(&data, &path, &opts).unwrap(), path);
        let names: Vec<_> = std::fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("run.gif")]);

        let gif = decode(&path);
        // 20 s at 4× and 10 fps: a frame every 0.4 s, at 0, 0.4, …, 20 s, each shown 0.1 s,
        // the last 2 s longer.
        assert_eq!(gif.frames.len(), 51);
        assert!(
            gif.delays[..50].iter().all(|&d| d == 10),
            "{:?}",
            gif.delays
        );
        assert_eq!(gif.delays[50], 10 + 200);
        let scene = Scene::new(&data, &path).unwrap();
        let lay = Layout::new(&scene, &opts);
        assert_eq!((gif.w, gif.h), (600, lay.size.1 as usize));
        let last = gif.frames.len() - 1;
        assert_ne!(gif.frames[0], gif.frames[last]);
        if let Ok(out) = std::env::var("SHOAL_GIF_DEBUG_PNG") {
            let mut img = Vec::new();
            for y in 0..gif.h {
                for x in 0..gif.w {
                    img.extend(gif.rgb(last, (x as i32, y as i32)));
                }
            }
            image::save_buffer(
                &out,
                &img,
                gif.w as u32,
                gif.h as u32,
                image::ColorType::Rgb8,
            )
            .unwrap();
            std::fs::copy(&path, format!("{out}.gif")).unwrap();
        }

        let [top, side] = [lay.panels[0], lay.panels[1]];
        assert_eq!((top.kind, side.kind), (PanelKind::Top, PanelKind::Side));
        let ends = paths().map(|p| p.1);
        let color = |g: usize| parse_hex(COLORS[g]).unwrap();
        let rgb = |c: RGBColor| [c.0, c.1, c.2];
        // Each vehicle's own colour where the layout puts it, in both views.
        for (v, end) in ends.iter().enumerate() {
            assert_eq!(
                gif.rgb(last, top.px(*end)),
                rgb(color(v)),
                "vehicle {v} top"
            );
            assert_eq!(
                gif.rgb(last, side.px(*end)),
                rgb(color(v)),
                "vehicle {v} side"
            );
        }
        // The same, found from the pixels alone: the northbound vehicle (8, 2) is above the
        // eastbound one (2, 7), which is to its right, at equal scales (Δeast 5 m across,
        // Δnorth 6 m up).
        let blobs: Vec<Blob> = (0..3).map(|v| gif.blob(last, top.rect, color(v))).collect();
        assert!(blobs.iter().all(|b| b.n > 20), "{blobs:?}");
        let (north, east) = (&blobs[0], &blobs[1]);
        assert!(
            north.cy < east.cy - 100.0,
            "north is up: {north:?} {east:?}"
        );
        assert!(
            east.cx > north.cx + 100.0,
            "east is right: {north:?} {east:?}"
        );
        let ratio = (east.cx - north.cx) / (east.cy - north.cy);
        assert!((ratio - 5.0 / 6.0).abs() < 0.03, "aspect {ratio}");
        // Pointed bodies along the heading: long the way they go, the wide tail behind.
        let (nw, nh) = north.size();
        let (ew, eh) = east.size();
        assert!(nh > 2 * nw && ew > 2 * eh, "{north:?} {east:?}");
        assert!(north.cy > north.centre().1, "tail to the south: {north:?}");
        assert!(east.cx < east.centre().0, "tail to the west: {east:?}");
        // The hull's length at the map's scale.
        let len = HULL[0] * top.scale;
        assert!((f64::from(nh) - len).abs() < 3.0, "{nh} px for {len} px");
        // Side view: north to the right, depth down; the diver (7, depth 2.5) is below and
        // left of the northbound one (8, depth 1).
        let sb: Vec<Blob> = (0..3)
            .map(|v| gif.blob(last, side.rect, color(v)))
            .collect();
        assert!(
            sb[2].cy > sb[0].cy + 50.0 && sb[2].cx < sb[0].cx - 20.0,
            "{sb:?}"
        );
        assert!(sb[1].cx < sb[2].cx, "{sb:?}");

        // The pillar: filled at its centre, not beyond its radius.
        let grey = rgb(OBSTACLE);
        assert_eq!(gif.rgb(last, top.px([5.0, 4.0, 1.5])), grey);
        assert_eq!(gif.rgb(last, top.px([5.3, 4.0, 1.5])), grey);
        assert_eq!(gif.rgb(last, top.px([5.0, 4.3, 1.5])), grey);
        assert_ne!(gif.rgb(last, top.px([5.55, 4.0, 1.5])), grey);
        assert_eq!(gif.rgb(last, side.px([5.0, 4.0, 1.5])), grey);
        assert_ne!(gif.rgb(last, side.px([5.6, 4.0, 1.5])), grey);
        // Water inside the pool.
        assert_eq!(gif.rgb(last, top.px([6.3, 5.3, 1.0])), rgb(WATER));

        // Links of the last moments, each in its outcome's colour, near their midpoints; the
        // old ones are gone.
        let near = |panel: &Panel, a: [f64; 3], b: [f64; 3], c: RGBColor| {
            let m = [0, 1, 2].map(|k| 0.5 * (a[k] + b[k]));
            let (x, y) = panel.px(m);
            (-2..=2).any(|dy| (-2..=2).any(|dx| gif.rgb(last, (x + dx, y + dy)) == rgb(c)))
        };
        let delivered = outcome_color(Outcome::Delivered);
        let collided = outcome_color(Outcome::Collided);
        assert!(near(&top, ends[0], ends[2], delivered));
        assert!(near(&top, ends[2], ends[1], collided));
        assert!(near(&side, ends[0], ends[2], delivered));
        assert!(!near(
            &top,
            ends[0],
            ends[1],
            outcome_color(Outcome::Occluded)
        ));
        let _ = std::fs::remove_dir_all(&d);
    }

    /// Beyond `max_frames`, that many frames cover the whole run at the same speed.
    #[test]
    fn frames_are_capped_and_the_end_is_still_shown() {
        let d = dir("cap");
        let path = d.join("cap.gif");
        let data = synthetic();
        let opts = GifOptions {
            max_frames: 12,
            view: View::Top,
            ..opts()
        };
        render(&data, &path, &opts).unwrap();
        let gif = decode(&path);
        assert_eq!(gif.frames.len(), 12);
        // 5 s of playback from the first frame to the last, as uncapped.
        let total: u32 = gif.delays[..11].iter().map(|&d| u32::from(d)).sum();
        assert_eq!(total, 500);
        let scene = Scene::new(&data, &path).unwrap();
        let lay = Layout::new(&scene, &opts);
        assert_eq!(lay.panels.len(), 1);
        let c = parse_hex(COLORS[0]).unwrap();
        assert_eq!(gif.rgb(11, lay.panels[0].px(paths()[0].1)), [c.0, c.1, c.2]);
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn the_side_view_alone_renders() {
        let d = dir("side");
        let path = d.join("side.gif");
        let opts = GifOptions {
            view: View::Side,
            max_frames: 3,
            links: false,
            trail_s: 0.0,
            ..opts()
        };
        render(&synthetic(), &path, &opts).unwrap();
        let gif = decode(&path);
        assert_eq!(gif.frames.len(), 3);
        let _ = std::fs::remove_dir_all(&d);
    }

    /// Empty or inconsistent replays and bad options are errors naming the file; nothing is
    /// written.
    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        let d = dir("errors");
        let path = d.join("bad.gif");
        let mut empty = synthetic();
        empty.meta.frames = 0;
        empty.pos.clear();
        empty.att.clear();
        let e = render(&empty, &path, &opts()).unwrap_err();
        assert!(matches!(e, RenderError::Empty { .. }), "{e}");
        assert!(
            e.to_string().contains("bad.gif") && e.to_string().contains("empty"),
            "{e}"
        );
        let mut none = synthetic();
        none.meta.vehicles = 0;
        assert!(matches!(
            render(&none, &path, &opts()),
            Err(RenderError::Empty { .. })
        ));
        let mut short = synthetic();
        short.pos.pop();
        let e = render(&short, &path, &opts()).unwrap_err();
        assert!(e.to_string().contains("`pos`"), "{e}");
        let mut group = synthetic();
        group.meta.group_of[1] = 7;
        let e = render(&group, &path, &opts()).unwrap_err();
        assert!(e.to_string().contains("group 7"), "{e}");
        for (o, field) in [
            (GifOptions { fps: 0.0, ..opts() }, "fps"),
            (
                GifOptions {
                    fps: 100.0,
                    ..opts()
                },
                "fps",
            ),
            (
                GifOptions {
                    speed: f64::NAN,
                    ..opts()
                },
                "speed",
            ),
            (
                GifOptions {
                    width_px: 10,
                    ..opts()
                },
                "width_px",
            ),
            (
                GifOptions {
                    max_frames: 0,
                    ..opts()
                },
                "max_frames",
            ),
            (
                GifOptions {
                    max_frames: usize::MAX,
                    ..opts()
                },
                "max_frames",
            ),
            (
                GifOptions {
                    trail_s: -1.0,
                    ..opts()
                },
                "trail_s",
            ),
        ] {
            let e = render(&synthetic(), &path, &o).unwrap_err();
            assert!(matches!(e, RenderError::Options { .. }), "{e}");
            assert!(
                e.to_string().contains(field) && e.to_string().contains("bad.gif"),
                "{e}"
            );
        }
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 0);
        // A folder that does not exist: the file system's reason, with the file's name.
        let missing = d.join("no-such-folder").join("x.gif");
        let e = render(&synthetic(), &missing, &opts()).unwrap_err();
        assert!(matches!(e, RenderError::File(_)), "{e}");
        assert!(e.to_string().contains("x.gif"), "{e}");
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn the_schedule_keeps_the_playback_clock() {
        let o = GifOptions::default();
        // 100 s at 4× and 10 fps: 0, 0.4, …, 100 s.
        let (t, d) = schedule(100.0, &o);
        assert_eq!(t.len(), 251);
        assert!((t[250] - 100.0).abs() < 1e-9);
        assert!(d[..250].iter().all(|&d| d == 10) && d[250] == 10 + 200);
        // The last frame at 99.9 s: the 100-s frame is not there.
        assert_eq!(schedule(99.9, &o).0.len(), 250);
        // 15 fps: delays of 6 and 7 hundredths that add up to the exact clock.
        let (t, d) = schedule(
            30.0,
            &GifOptions {
                fps: 15.0,
                ..o.clone()
            },
        );
        assert_eq!(t.len(), 113);
        let sum: u32 = d[..112].iter().map(|&d| u32::from(d)).sum();
        assert_eq!(sum, (112.0f64 * 100.0 / 15.0).round() as u32);
        assert!(d[..112].iter().all(|&d| d == 6 || d == 7));
        // Capped: the whole run in 5 frames, the same playback time.
        let (t, d) = schedule(
            100.0,
            &GifOptions {
                max_frames: 5,
                ..o.clone()
            },
        );
        assert_eq!(t, vec![0.0, 25.0, 50.0, 75.0, 100.0]);
        assert_eq!(d, vec![625, 625, 625, 625, 625 + 200]);
        // A speed that would take more frames than there are numbers: capped.
        let tiny = GifOptions {
            speed: 1e-300,
            max_frames: 3,
            ..o.clone()
        };
        assert_eq!(schedule(100.0, &tiny).0, vec![0.0, 50.0, 100.0]);
        // One frame: the end.
        let (t, _) = schedule(100.0, &GifOptions { max_frames: 1, ..o });
        assert_eq!(t, vec![100.0]);
    }

    #[test]
    fn every_palette_colour_maps_to_itself() {
        let data = synthetic();
        let scene = Scene::new(&data, Path::new("x.gif")).unwrap();
        let mut colors = vec![BG, TEXT, OBSTACLE, WATER];
        colors.extend(scene.groups.iter().map(|g| g.color));
        colors.extend((0..32u8).map(|i| RGBColor(i * 8, i * 8, i * 8)));
        let p = Palette::new(&colors);
        for i in 0..p.len {
            let c = [p.rgb[3 * i], p.rgb[3 * i + 1], p.rgb[3 * i + 2]];
            assert_eq!(usize::from(p.index(c)), i, "{c:?}");
        }
        // A colour off the palette goes to its nearest entry, never to the transparent one.
        let blue = p.index([31, 119, 180]);
        assert_eq!(p.index([35, 115, 185]), blue);
        assert!((0..=255u8).all(|v| p.index([v, 255 - v, v / 2]) != TRANSPARENT));
    }

    #[test]
    fn obstacle_outlines_follow_shape_and_pose() {
        let o = |kind: &str, rotation: [f64; 4]| ObstacleMeta {
            name: "o".into(),
            kind: kind.into(),
            size: Some([2.0, 1.0, 0.5]),
            radius: Some(0.5),
            height: Some(2.0),
            position: [3.0, 4.0, 1.0],
            rotation,
        };
        let ident = [0.0, 0.0, 0.0, 1.0];
        let extent = |pts: &[(f64, f64)]| {
            let f = |g: fn(&(f64, f64)) -> f64| {
                let v: Vec<f64> = pts.iter().map(g).collect();
                (
                    v.iter().copied().fold(f64::INFINITY, f64::min),
                    v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                )
            };
            (f(|p| p.0), f(|p| p.1))
        };
        let close =
            |a: (f64, f64), b: (f64, f64)| (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9;
        // A box 2 m along x (north, up in the top view), 1 m along y (east, across).
        let (h, v) = extent(&obstacle_outline(&o("box", ident), PanelKind::Top).unwrap());
        assert!(close(h, (3.5, 4.5)) && close(v, (2.0, 4.0)), "{h:?} {v:?}");
        // Turned 90° about z (down): now 2 m along east.
        let s = FRAC_1_SQRT_2;
        let (h, v) =
            extent(&obstacle_outline(&o("box", [0.0, 0.0, s, s]), PanelKind::Top).unwrap());
        assert!(close(h, (3.0, 5.0)) && close(v, (2.5, 3.5)), "{h:?} {v:?}");
        // A cylinder with its axis (local y) untouched lies along east: 2 m across from above,
        // a 1-m disc seen from the side.
        let (h, v) = extent(&obstacle_outline(&o("cylinder", ident), PanelKind::Top).unwrap());
        assert!(close(h, (3.0, 5.0)) && close(v, (2.5, 3.5)), "{h:?} {v:?}");
        let (h, v) = extent(&obstacle_outline(&o("cylinder", ident), PanelKind::Side).unwrap());
        assert!(close(h, (2.5, 3.5)) && close(v, (0.5, 1.5)), "{h:?} {v:?}");
        // A capsule along z: 3 m tall from the side (2 m straight + two 0.5-m caps).
        let (_, v) = extent(&obstacle_outline(&o("capsule", ident), PanelKind::Side).unwrap());
        assert!(close(v, (-0.5, 2.5)), "{v:?}");
        // Unknown kinds, missing sizes and bad rotations are skipped, not drawn wrong.
        assert!(obstacle_outline(&o("torus", ident), PanelKind::Top).is_none());
        assert!(obstacle_outline(&o("box", [0.0; 4]), PanelKind::Top).is_none());
        let mut no_r = o("sphere", ident);
        no_r.radius = None;
        assert!(obstacle_outline(&no_r, PanelKind::Top).is_none());
    }
}
