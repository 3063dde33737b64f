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
//! smaller than [`MIN_BODY_PX`], less in a crowded map: [`CROWDED_BODY_SHARE`]), its trail
//! of the last [`GifOptions::trail_s`] seconds, and
//! the link attempts of the last [`LINK_WINDOW_S`] s (or of the time between two GIF frames
//! when longer) as lines coloured by outcome, losses drawn over deliveries; those of
//! acknowledgement frames dashed (6-px dashes, 5-px gaps), as in `replay.html`. A title
//! (world, `t = 12.3 s`, playback speed) and a legend (groups, link outcomes, and one entry
//! for the dashed acknowledgements, [`crate::link_key::ACK_LABEL`]) frame the maps.
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
//! **Measured** (`cargo run --release -p shoal-record --example gif_render`: synthetic 100-s
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
//!
//! **Files**, each using only the ones before it: `options` (what the caller chooses, the fixed
//! limits) and `error`; `palette`; `scene` (the replay decoded); `layout` (where everything
//! goes); `geometry`; `draw` (the frames); `encode`. This file renders with them and re-exports
//! the public items.

mod draw;
mod encode;
mod error;
mod geometry;
mod layout;
mod options;
mod palette;
mod scene;
#[cfg(test)]
mod tests;

pub use error::RenderError;
pub use options::{
    CROWDED_BODY_SHARE, END_HOLD_S, GifOptions, LINK_WINDOW_S, MAX_GIF_FPS, MAX_GIF_FRAMES,
    MIN_BODY_PX, View,
};

use super::ReplayData;
use draw::{Dynamic, area_of, draw_background};
use encode::Frames;
use layout::Layout;
use palette::{
    BG, FRAME, GRID, GifPalette, OBSTACLE, OBSTACLE_EDGE, OUTCOMES, OUTSIDE, SURFACE, TEXT,
    TEXT_GREY, WALL, WATER, mix, outcome_color,
};
use plotters::prelude::*;
use scene::Scene;
use shoal_output::files::{AtomicFile, FileError};
use shoal_output::plot::register_font;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// Allowed image widths \[px\].
const WIDTH_RANGE: (u32, u32) = (240, 4096);

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
    // The palette: what matters most first (see `GifPalette::new`).
    let mut colors: Vec<RGBColor> = vec![BG, TEXT];
    colors.extend(scene.groups.iter().map(|g| g.color));
    colors.extend(OUTCOMES.iter().map(|o| outcome_color(*o)));
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
    let palette = GifPalette::new(&colors);

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
