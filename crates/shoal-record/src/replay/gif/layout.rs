//! Where everything goes in a GIF frame: title, the top and side panels with their scales, ticks and the legend.

use super::options::{GifOptions, View};
use super::palette::{OUTCOMES, outcome_color};
use super::scene::Scene;
use plotters::backend::{BitMapBackend, RGBPixel};
use plotters::prelude::*;

/// Image rows above the maps: the title \[px\].
pub(super) const TITLE_H: i32 = 34;
/// Rows above each map: its caption \[px\].
pub(super) const CAPTION_H: i32 = 20;
/// Rows below each map: tick labels \[px\].
pub(super) const TICKS_H: i32 = 24;
/// Columns left of each map: tick labels \[px\].
pub(super) const LEFT_W: i32 = 46;
/// Columns right of each map \[px\].
pub(super) const RIGHT_W: i32 = 16;
/// Height of a legend row \[px\].
pub(super) const LEGEND_ROW: i32 = 20;
/// Most groups named in the legend.
pub(super) const LEGEND_GROUPS: usize = 12;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum PanelKind {
    Top,
    Side,
}

/// One map: which part of the world it shows, where on the image and at what scale.
#[derive(Clone, Copy, Debug)]
pub(super) struct Panel {
    pub(super) kind: PanelKind,
    /// Plotting area on the image: left, top, width, height \[px\].
    pub(super) rect: (i32, i32, i32, i32),
    /// World range across \[m\]: east y (top view) or north x (side view).
    pub(super) h: (f64, f64),
    /// World range up/down \[m\]: north x (top view, up) or depth z (side view, down).
    pub(super) v: (f64, f64),
    /// Scale \[px/m\].
    pub(super) scale: f64,
}

impl Panel {
    /// The map coordinates of the world point `p`: (across, up/down) \[m\].
    #[inline]
    pub(super) fn hv(&self, p: [f64; 3]) -> (f64, f64) {
        match self.kind {
            PanelKind::Top => (p[1], p[0]),
            PanelKind::Side => (p[0], p[2]),
        }
    }

    /// Image position of the map coordinates `(h, v)` \[px\] (not rounded).
    #[inline]
    pub(super) fn px_hv(&self, (h, v): (f64, f64)) -> (f64, f64) {
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
    pub(super) fn px(&self, p: [f64; 3]) -> (i32, i32) {
        let (x, y) = self.px_hv(self.hv(p));
        (x.round() as i32, y.round() as i32)
    }

    /// The pixel of map coordinates.
    #[inline]
    pub(super) fn px_i(&self, hv: (f64, f64)) -> (i32, i32) {
        let (x, y) = self.px_hv(hv);
        (x.round() as i32, y.round() as i32)
    }
}

/// Where everything goes on the image.
pub(super) struct Layout {
    pub(super) size: (u32, u32),
    pub(super) panels: Vec<Panel>,
    /// Legend entries, each with its row and x \[px\].
    pub(super) legend: Vec<(LegendEntry, i32, i32)>,
}

#[derive(Clone, Debug)]
pub(super) enum LegendEntry {
    Group(RGBColor, String),
    Link(RGBColor, String),
    /// Acknowledgement frames: a dashed sample ([`ACK_SAMPLE`] px) and the label.
    Ack(String),
    Note(String),
}

/// `(lo, hi)` widened about its centre to `span`.
pub(super) fn widen(r: (f64, f64), span: f64) -> (f64, f64) {
    let c = 0.5 * (r.0 + r.1);
    (c - 0.5 * span, c + 0.5 * span)
}

/// The scale \[px/m\] and ranges that fit the map `h` × `v` into `pw` pixels across with a
/// height within `[min_h, max_h]` \[px\]: equal scales, one range widened about its centre
/// where the aspect ratio asks for it.
pub(super) fn fit(
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
    pub(super) fn new(scene: &Scene, opts: &GifOptions) -> Self {
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
            entries.extend(OUTCOMES.iter().map(|o| {
                LegendEntry::Link(outcome_color(*o), crate::link_key::style(*o).label.into())
            }));
            entries.push(LegendEntry::Ack(crate::link_key::ACK_LABEL.into()));
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
pub(super) fn text_width(text: &str, size: u32) -> i32 {
    let mut buf = [0u8; 3];
    let area = match BitMapBackend::<RGBPixel>::with_buffer_and_format(&mut buf, (1, 1)) {
        Ok(b) => b.into_drawing_area(),
        Err(_) => return 7 * text.chars().count() as i32,
    };
    let font: TextStyle = ("sans-serif", size).into_font().into();
    area.estimate_text_size(text, &font)
        .map_or(7 * text.chars().count() as i32, |(w, _)| w as i32)
}

pub(super) const LEGEND_FONT: u32 = 13;
pub(super) const LEGEND_SAMPLE: i32 = 18;
/// Width of the dashed sample of acknowledgement frames in the legend \[px\]: room for
/// three dashes and the start of a fourth.
pub(super) const ACK_SAMPLE: i32 = 2 * LEGEND_SAMPLE;

/// Columns a legend entry takes, its gap to the next included \[px\].
pub(super) fn legend_width(e: &LegendEntry) -> i32 {
    match e {
        LegendEntry::Group(_, s) | LegendEntry::Link(_, s) => {
            LEGEND_SAMPLE + 5 + text_width(s, LEGEND_FONT) + 16
        }
        LegendEntry::Ack(s) => ACK_SAMPLE + 5 + text_width(s, LEGEND_FONT) + 16,
        LegendEntry::Note(s) => text_width(s, LEGEND_FONT) + 10,
    }
}
