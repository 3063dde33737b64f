//! Simple, dependable plots (PNG and SVG from one description) with plotters and an embedded
//! DejaVu Sans font, so plots render on machines without system fonts.
//!
//! Three rules keep a plot honest whatever the data:
//! * the axes cover every point that is drawn ([`data_range`]: all finite points of all series
//!   and outlines, with a margin), and where a range is fixed, lines are clipped at the plot
//!   area's edge ([`clip_polyline`]) — plotters itself would squash them onto the edge or draw
//!   them over the axes;
//! * a nearly constant, quantised signal does not fill the plot with its quantisation steps:
//!   [`Plot::min_y_span`] sets the smallest vertical span of an autoscaled axis;
//! * the legend never covers data: it goes into a corner that nothing drawn passes through,
//!   or below the plot when there is none ([`legend_place`]).
//!
//! Dots and markers are drawn after every line, so an interval bar or a reference curve never
//! hides a point; a map ([`Plot::equal_aspect`]) has one scale on both axes.

use crate::files::{FileError, write_whole};
use image::ColorType;
use image::ImageEncoder;
use image::codecs::png::PngEncoder;
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Once;

mod legend;
mod map;

use legend::{
    Entry, LEGEND_FONT, LEGEND_INSET, corner_box, draw_legend_below, draw_legend_corner,
    strip_height,
};
pub use legend::{LegendPlace, legend_place, touches};
pub use map::map_view;

static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

/// Registers the embedded font as plotters' "sans-serif" (once per process); call it before
/// drawing text with plotters.
pub fn register_font() {
    REGISTER.call_once(|| {
        // The embedded font is known to be valid; a failure would only lose text in plots.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// A plotting failure.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The picture could not be drawn or encoded.
    #[error("cannot draw {}: {message}", path.display())]
    Draw {
        /// The file being drawn.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// The drawn file could not be written.
    #[error(transparent)]
    File(#[from] FileError),
}

/// Why drawing ended early.
enum DrawFail {
    /// The caller's `stop` said so.
    Stopped,
    /// plotters failed, with its message.
    Failed(String),
}

impl From<String> for DrawFail {
    fn from(message: String) -> Self {
        DrawFail::Failed(message)
    }
}

/// One line (or cloud of dots) of a plot.
#[derive(Clone, Debug, Default)]
pub struct Series {
    /// Legend label (none: not in the legend).
    pub label: Option<String>,
    /// Points (x, y) in data units. A non-finite point breaks the line.
    pub points: Vec<(f64, f64)>,
    /// Palette index of the colour.
    pub color: usize,
    /// A colour of its own (red, green, blue) instead of the palette's, e.g. a link outcome's
    /// from `shoal_sim::link_key`.
    pub rgb: Option<(u8, u8, u8)>,
    /// Dashed (for setpoints and references).
    pub dashed: bool,
    /// Mark the first point with a dot.
    pub mark_start: bool,
    /// Line width \[px\] (0: the default, 2 for solid and 1 for dashed lines); with `dots`,
    /// the dots' radius \[px\] (0: 1 px; from 3 px on, markers with a white ring).
    pub width: u32,
    /// Draw each point as a dot instead of joining the points (measured samples, scatter
    /// plots, markers). Dots are drawn after every line, so lines never cover them.
    pub dots: bool,
}

/// An outline drawn under the series (pool walls, obstacles): a closed polygon.
#[derive(Clone, Debug)]
pub struct Outline {
    /// Corners in data units.
    pub points: Vec<(f64, f64)>,
    /// Filled grey (obstacles) or a black line (walls).
    pub filled: bool,
}

/// A 2-D line plot.
#[derive(Clone, Debug, Default)]
pub struct Plot {
    /// Title.
    pub title: String,
    /// Horizontal axis label (with unit).
    pub x_label: String,
    /// Vertical axis label (with unit).
    pub y_label: String,
    /// Lines.
    pub series: Vec<Series>,
    /// Polygons drawn first.
    pub outlines: Vec<Outline>,
    /// Vertical axis grows downwards (depth).
    pub y_down: bool,
    /// Fixed ranges; `None` = from the data.
    pub x_range: Option<(f64, f64)>,
    /// Fixed ranges; `None` = from the data.
    pub y_range: Option<(f64, f64)>,
    /// Smallest span of an autoscaled vertical axis, in data units (0: none).
    pub min_y_span: f64,
    /// Image size \[px\] (the legend, when it must go below the plot, adds a strip).
    pub size: (u32, u32),
    /// One unit is as long on screen horizontally as vertically (maps: 1 m north = 1 m
    /// east): the axis that would be drawn at the larger scale gets a wider range about its
    /// centre ([`Plot::ranges_drawn`]).
    pub equal_aspect: bool,
}

/// The colours of lines and groups, in order (matplotlib's "tab10"); the replay's groups use
/// the same ones.
pub const PALETTE: [(u8, u8, u8); 10] = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (127, 127, 127),
    (188, 189, 34),
    (23, 190, 207),
];

/// Colour `i` of [`PALETTE`], wrapping around (red, green, blue).
pub fn rgb(i: usize) -> (u8, u8, u8) {
    PALETTE[i % PALETTE.len()]
}

/// Colour `i` of [`PALETTE`] as a plotters colour.
pub fn color(i: usize) -> RGBColor {
    let (r, g, b) = rgb(i);
    RGBColor(r, g, b)
}

impl Series {
    /// The colour it is drawn in: its own, or the palette's.
    pub fn drawn_rgb(&self) -> (u8, u8, u8) {
        self.rgb.unwrap_or_else(|| rgb(self.color))
    }

    fn drawn_color(&self) -> RGBColor {
        let (r, g, b) = self.drawn_rgb();
        RGBColor(r, g, b)
    }
}

/// Size of a plot's title \[px\], and the smallest it is shrunk to so that it fits.
const TITLE_PX: u32 = 20;
const TITLE_MIN_PX: u32 = 11;

/// Dots of at least this radius \[px\] are markers, drawn with a white ring.
const MARKER_RING_FROM: u32 = 3;

/// Relative margin added on each side of an autoscaled axis.
const PAD: f64 = 0.05;

/// The axis range for `values`: from the smallest to the largest finite value, widened to at
/// least `min_span` about its centre, plus a margin of 5 % of the span on each side. Covers
/// every finite value; (0, 1) when there is none.
pub fn data_range(values: impl IntoIterator<Item = f64>, min_span: f64) -> (f64, f64) {
    let (lo, hi) = values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if lo > hi {
        return (0.0, 1.0);
    }
    let centre = 0.5 * (lo + hi);
    // Never narrower than a few ulps of the values (a constant series).
    let floor = 1e-9 * centre.abs().max(1.0);
    let span = (hi - lo).max(min_span.max(0.0)).max(floor);
    let (lo, hi) = if hi - lo < span {
        (centre - 0.5 * span, centre + 0.5 * span)
    } else {
        (lo, hi)
    };
    (lo - PAD * span, hi + PAD * span)
}

/// The part of the segment a–b inside the box `x` × `y` (Liang–Barsky), if any.
fn clip_segment(
    a: (f64, f64),
    b: (f64, f64),
    x: (f64, f64),
    y: (f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let mut t0 = 0.0_f64;
    let mut t1 = 1.0_f64;
    for (p, q) in [
        (-dx, a.0 - x.0),
        (dx, x.1 - a.0),
        (-dy, a.1 - y.0),
        (dy, y.1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    if t0 > t1 {
        return None;
    }
    let at = |t: f64| {
        if t == 0.0 {
            a
        } else if t == 1.0 {
            b
        } else {
            (a.0 + t * dx, a.1 + t * dy)
        }
    };
    Some((at(t0), at(t1)))
}

/// The pieces of the polyline `points` inside the box `x` × `y` (each `(min, max)`): lines
/// are cut where they leave the box and at non-finite points. A single point is kept if it is
/// inside.
pub fn clip_polyline(points: &[(f64, f64)], x: (f64, f64), y: (f64, f64)) -> Vec<Vec<(f64, f64)>> {
    let finite = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite();
    let inside = |p: &(f64, f64)| finite(p) && p.0 >= x.0 && p.0 <= x.1 && p.1 >= y.0 && p.1 <= y.1;
    if points.len() == 1 {
        return if inside(&points[0]) {
            vec![points.to_vec()]
        } else {
            Vec::new()
        };
    }
    let mut out = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    let mut flush = |cur: &mut Vec<(f64, f64)>| {
        if !cur.is_empty() {
            out.push(std::mem::take(cur));
        }
    };
    for w in points.windows(2) {
        let (a, b) = (w[0], w[1]);
        if !finite(&a) || !finite(&b) {
            flush(&mut cur);
            continue;
        }
        match clip_segment(a, b, x, y) {
            None => flush(&mut cur),
            Some((p, q)) => {
                if cur.last() != Some(&p) {
                    flush(&mut cur);
                    cur.push(p);
                }
                cur.push(q);
                if q != b {
                    flush(&mut cur);
                }
            }
        }
    }
    flush(&mut cur);
    out
}

/// The axis ranges of a plot as drawn, and its scales ([`Plot::ranges_drawn`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RangesDrawn {
    /// Horizontal range (min, max), data units.
    pub x: (f64, f64),
    /// Vertical range (min, max), data units.
    pub y: (f64, f64),
    /// Pixels per data unit, horizontally and vertically \[px\].
    pub scale: (f64, f64),
    /// The plot area's width and height \[px\].
    pub area: (f64, f64),
    /// The plot area's upper left corner in the image \[px\].
    pub origin: (f64, f64),
    /// The vertical axis grows downwards ([`Plot::y_down`]).
    pub y_down: bool,
}

impl RangesDrawn {
    /// Where the data point `p` is drawn in the image \[px\] (x to the right, y down).
    pub fn pixel(&self, p: (f64, f64)) -> (f64, f64) {
        let fy = (p.1 - self.y.0) / (self.y.1 - self.y.0);
        let fy = if self.y_down { fy } else { 1.0 - fy };
        (
            self.origin.0 + (p.0 - self.x.0) * self.scale.0,
            self.origin.1 + fy * self.area.1,
        )
    }
}

/// How a plot is laid out, decided once and used for both the PNG and the SVG.
#[derive(Clone, Debug)]
struct Layout {
    x: (f64, f64),
    y: (f64, f64),
    legend: LegendPlace,
    /// Each legend entry.
    entries: Vec<Entry>,
    /// Width of each entry's text \[px\].
    text_w: Vec<i32>,
    /// Height of the strip below the plot \[px\] (0 unless the legend is below).
    strip: u32,
}

impl Plot {
    /// The axis ranges (x, y), each `(min, max)`: the fixed ones, or [`data_range`] of every
    /// point drawn (series and outlines; vertically at least [`Plot::min_y_span`]).
    pub fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let pts = || {
            self.series
                .iter()
                .flat_map(|s| s.points.iter())
                .chain(self.outlines.iter().flat_map(|o| o.points.iter()))
                .filter(|p| p.0.is_finite() && p.1.is_finite())
        };
        (
            self.x_range
                .unwrap_or_else(|| data_range(pts().map(|p| p.0), 0.0)),
            self.y_range
                .unwrap_or_else(|| data_range(pts().map(|p| p.1), self.min_y_span)),
        )
    }

    fn size(&self) -> (u32, u32) {
        if self.size == (0, 0) {
            (900, 600)
        } else {
            self.size
        }
    }

    fn chart<'a, DB: DrawingBackend>(
        &self,
        area: &'a DrawingArea<DB, Shift>,
        x: (f64, f64),
        y: (f64, f64),
    ) -> Result<ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>, String> {
        let (ya, yb) = if self.y_down { (y.1, y.0) } else { (y.0, y.1) };
        // The title in 20 px, smaller where that would not fit the width (never cut off).
        let room = i64::from(area.dim_in_pixel().0) - 2 * 12;
        let fits = |px: u32| {
            area.estimate_text_size(&self.title, &("sans-serif", px).into_font().into())
                .is_ok_and(|(w, _)| i64::from(w) <= room)
        };
        let title_px = (TITLE_MIN_PX..=TITLE_PX)
            .rev()
            .find(|&px| fits(px))
            .unwrap_or(TITLE_MIN_PX);
        ChartBuilder::on(area)
            .caption(&self.title, ("sans-serif", title_px))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(x.0..x.1, ya..yb)
            .map_err(|e| e.to_string())
    }

    /// Everything drawn, in plot-area fractions (y from the top), clipped to the ranges.
    fn paths(&self, x: (f64, f64), y: (f64, f64)) -> Vec<Vec<(f64, f64)>> {
        let fx = |v: f64| (v - x.0) / (x.1 - x.0);
        let fy = |v: f64| {
            if self.y_down {
                (v - y.0) / (y.1 - y.0)
            } else {
                (y.1 - v) / (y.1 - y.0)
            }
        };
        let norm = |p: &Vec<(f64, f64)>| p.iter().map(|&(a, b)| (fx(a), fy(b))).collect();
        let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
        for o in &self.outlines {
            let mut pts = o.points.clone();
            if let Some(first) = pts.first().copied() {
                pts.push(first);
            }
            out.extend(clip_polyline(&pts, x, y).iter().map(norm));
        }
        for s in &self.series {
            if s.dots {
                out.extend(
                    s.points
                        .iter()
                        .filter(|p| p.0 >= x.0 && p.0 <= x.1 && p.1 >= y.0 && p.1 <= y.1)
                        .map(|&(a, b)| vec![(fx(a), fy(b))]),
                );
            } else {
                out.extend(clip_polyline(&s.points, x, y).iter().map(norm));
            }
        }
        out
    }

    /// The axis ranges as drawn (x, y), each `(min, max)`: [`Plot::ranges`], and with
    /// [`Plot::equal_aspect`] one of them widened about its centre so that both axes have
    /// the same scale; and the scales \[px per unit\] of the plot area, horizontal and
    /// vertical.
    pub fn ranges_drawn(&self) -> Result<RangesDrawn, String> {
        register_font();
        let size = self.size();
        let mut buf = vec![0u8; size.0 as usize * size.1 as usize * 3];
        let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
        let (x, y) = self.ranges();
        // The plot area's size does not depend on the ranges (label areas are fixed).
        let chart = self.chart(&root, x, y)?;
        let (px, py) = chart.plotting_area().get_pixel_range();
        let (pw, ph) = (f64::from(px.end - px.start), f64::from(py.end - py.start));
        let widen = |r: (f64, f64), span: f64| {
            let c = 0.5 * (r.0 + r.1);
            (c - 0.5 * span, c + 0.5 * span)
        };
        let (mut x, mut y) = (x, y);
        let (sx, sy) = (pw / (x.1 - x.0), ph / (y.1 - y.0));
        if self.equal_aspect && sx.is_finite() && sy.is_finite() && sx > 0.0 && sy > 0.0 {
            if sx > sy {
                x = widen(x, pw / sy);
            } else {
                y = widen(y, ph / sx);
            }
        }
        Ok(RangesDrawn {
            x,
            y,
            scale: (pw / (x.1 - x.0), ph / (y.1 - y.0)),
            area: (pw, ph),
            origin: (f64::from(px.start), f64::from(py.start)),
            y_down: self.y_down,
        })
    }

    /// Decides ranges and the legend's place, measuring text and the plot area on an
    /// off-screen bitmap of the final size.
    fn layout(&self) -> Result<Layout, String> {
        register_font();
        let RangesDrawn { x, y, area, .. } = self.ranges_drawn()?;
        let entries: Vec<Entry> = self
            .series
            .iter()
            .filter_map(|s| {
                s.label
                    .as_ref()
                    .map(|l| (l.clone(), s.drawn_color(), s.dashed, s.dots, s.width))
            })
            .collect();
        let size = self.size();
        // Text is measured the same on any bitmap.
        let mut buf = vec![0u8; 3];
        let root = BitMapBackend::with_buffer(&mut buf, (1, 1)).into_drawing_area();
        let font: TextStyle = ("sans-serif", LEGEND_FONT).into_font().into();
        let text_w: Vec<i32> = entries
            .iter()
            .map(|(l, ..)| {
                root.estimate_text_size(l, &font)
                    .map_or(8 * l.chars().count() as i32, |(w, _)| w as i32)
            })
            .collect();
        if entries.is_empty() {
            return Ok(Layout {
                x,
                y,
                legend: LegendPlace::Below,
                entries,
                text_w,
                strip: 0,
            });
        }
        let (pw, ph) = area;
        let (bw, bh) = corner_box(&text_w);
        // The box with its inset from the plot area's edge, as fractions.
        let frac = (
            f64::from(bw + LEGEND_INSET) / pw.max(1.0),
            f64::from(bh + LEGEND_INSET) / ph.max(1.0),
        );
        let legend = legend_place(&self.paths(x, y), frac);
        let strip = if legend == LegendPlace::Below {
            strip_height(&text_w, size.0 as i32)
        } else {
            0
        };
        Ok(Layout {
            x,
            y,
            legend,
            entries,
            text_w,
            strip,
        })
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
        lay: &Layout,
        stop: &dyn Fn() -> bool,
    ) -> Result<(), DrawFail> {
        register_font();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let (area, strip) = if lay.strip > 0 {
            let (a, b) = root.split_vertically(self.size().1);
            (a, Some(b))
        } else {
            (root.clone(), None)
        };
        let (x, y) = (lay.x, lay.y);
        let mut chart = self.chart(&area, x, y)?;
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(|e| e.to_string())?;
        let inside = |p: &(f64, f64)| p.0 >= x.0 && p.0 <= x.1 && p.1 >= y.0 && p.1 <= y.1;
        for o in &self.outlines {
            let mut pts = o.points.clone();
            if let Some(first) = pts.first().copied() {
                pts.push(first);
            }
            if o.filled && pts.iter().all(inside) {
                chart
                    .draw_series(std::iter::once(Polygon::new(
                        pts,
                        RGBColor(170, 170, 170).filled(),
                    )))
                    .map_err(|e| e.to_string())?;
            } else {
                for piece in clip_polyline(&pts, x, y) {
                    chart
                        .draw_series(LineSeries::new(piece, BLACK.stroke_width(2)))
                        .map_err(|e| e.to_string())?;
                }
            }
        }
        // Lines first, then dots: a marker is never hidden under a line drawn after it (an
        // interval bar, a reference curve).
        let lines = self.series.iter().filter(|s| !s.dots);
        for s in lines.chain(self.series.iter().filter(|s| s.dots)) {
            // A plot of every vehicle of a large world is a long loop: look here.
            if stop() {
                return Err(DrawFail::Stopped);
            }
            let c = s.drawn_color();
            if s.dots {
                let r = s.width.max(1);
                let pts = || s.points.iter().filter(|p| inside(p));
                if r >= MARKER_RING_FROM {
                    // Markers get a white ring, so they stand out from the lines under them.
                    chart
                        .draw_series(pts().map(|p| Circle::new(*p, r + 1, WHITE.filled())))
                        .map_err(|e| e.to_string())?;
                }
                chart
                    .draw_series(pts().map(|p| Circle::new(*p, r, c.filled())))
                    .map_err(|e| e.to_string())?;
            } else {
                for piece in clip_polyline(&s.points, x, y) {
                    if s.dashed {
                        let w = if s.width == 0 { 1 } else { s.width };
                        chart.draw_series(DashedLineSeries::new(piece, 6, 4, c.stroke_width(w)))
                    } else {
                        let w = if s.width == 0 { 2 } else { s.width };
                        chart.draw_series(LineSeries::new(piece, c.stroke_width(w)))
                    }
                    .map_err(|e| e.to_string())?;
                }
            }
            if s.mark_start
                && let Some(p) = s.points.first().filter(|p| inside(p))
            {
                chart
                    .draw_series(std::iter::once(Circle::new(*p, 3, c.filled())))
                    .map_err(|e| e.to_string())?;
            }
        }
        if !lay.entries.is_empty() {
            match (lay.legend, &strip) {
                (LegendPlace::Below, Some(strip)) => draw_legend_below(strip, lay)?,
                _ => {
                    // The chart's area starts at the image's origin: its pixels are the
                    // area's coordinates.
                    let (px, py) = chart.plotting_area().get_pixel_range();
                    draw_legend_corner(&area, lay, (px.start, px.end), (py.start, py.end))?;
                }
            }
        }
        Ok(root.present().map_err(|e| e.to_string())?)
    }

    /// Writes `<stem>.png` and `<stem>.svg` (each drawn in memory, then written whole
    /// through [`crate::files`]); returns both paths.
    pub fn write(&self, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
        self.write_until(stem, &|| false, &|_| {})
    }

    /// [`Plot::write`] that gives up, between series and between the two files, once `stop`
    /// says so, and calls `begin` with each file's name before it draws it; returns the
    /// files written (both, one or none). A file is never left half written.
    pub fn write_until(
        &self,
        stem: &Path,
        stop: &dyn Fn() -> bool,
        begin: &dyn Fn(&Path),
    ) -> Result<Vec<PathBuf>, PlotError> {
        let png = stem.with_extension("png");
        let svg = stem.with_extension("svg");
        let mut written = Vec::new();
        let err = |p: &Path, message: String| PlotError::Draw {
            path: p.to_path_buf(),
            message,
        };
        // Whether a drawing is complete (false: stopped).
        let complete = |drawn: Result<(), DrawFail>, p: &Path| match drawn {
            Ok(()) => Ok(true),
            Err(DrawFail::Stopped) => Ok(false),
            Err(DrawFail::Failed(m)) => Err(err(p, m)),
        };
        let lay = self.layout().map_err(|m| err(&png, m))?;
        let (w, h) = self.size();
        let size = (w, h + lay.strip);
        begin(&png);
        let mut pixels = vec![0u8; size.0 as usize * size.1 as usize * 3];
        let root = BitMapBackend::with_buffer(&mut pixels, size).into_drawing_area();
        if !complete(self.draw(root, &lay, stop), &png)? {
            return Ok(written);
        }
        let mut encoded = Vec::new();
        PngEncoder::new(&mut encoded)
            .write_image(&pixels, size.0, size.1, ColorType::Rgb8)
            .map_err(|e| err(&png, e.to_string()))?;
        written.push(write_whole(&png, &encoded)?);
        if stop() {
            return Ok(written);
        }
        begin(&svg);
        let mut text = String::new();
        let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
        if !complete(self.draw(root, &lay, stop), &svg)? {
            return Ok(written);
        }
        written.push(write_whole(&svg, text.as_bytes())?);
        Ok(written)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn range_covers_every_value_with_a_margin() {
        let v = [3.0, -2.0, f64::NAN, 7.5, f64::INFINITY];
        let (lo, hi) = data_range(v, 0.0);
        assert!(lo < -2.0 && hi > 7.5);
        assert!((lo - (-2.0 - 0.05 * 9.5)).abs() < 1e-12);
        // A constant series gets a non-empty range.
        let (lo, hi) = data_range([1.0; 5], 0.0);
        assert!(lo < 1.0 && hi > 1.0);
        // The smallest span widens about the centre.
        let (lo, hi) = data_range([1.0, 1.002], 0.05);
        assert!((hi - lo - 1.1 * 0.05).abs() < 1e-12);
        assert!((0.5 * (lo + hi) - 1.001).abs() < 1e-12);
        assert_eq!(data_range([f64::NAN], 1.0), (0.0, 1.0));
    }

    #[test]
    fn clipping_cuts_lines_at_the_box_and_at_gaps() {
        let pts = [
            (0.0, 0.0),
            (1.0, 2.0),
            (2.0, 0.0),
            (f64::NAN, 1.0),
            (3.0, 0.5),
            (4.0, 0.5),
        ];
        let pieces = clip_polyline(&pts, (0.0, 10.0), (0.0, 1.0));
        // Up and out at (0.5, 1), back in at (1.5, 1); the gap splits off the last segment.
        assert_eq!(pieces.len(), 3, "{pieces:?}");
        assert_eq!(pieces[0], vec![(0.0, 0.0), (0.5, 1.0)]);
        assert_eq!(pieces[1], vec![(1.5, 1.0), (2.0, 0.0)]);
        assert_eq!(pieces[2], vec![(3.0, 0.5), (4.0, 0.5)]);
        for p in pieces.iter().flatten() {
            assert!(p.0 >= 0.0 && p.0 <= 10.0 && p.1 >= 0.0 && p.1 <= 1.0);
        }
        assert!(clip_polyline(&[(5.0, 5.0)], (0.0, 1.0), (0.0, 1.0)).is_empty());
    }

    /// A title too long for the image is drawn smaller, not cut off at the image's edges.
    #[test]
    fn a_long_title_fits_the_image() {
        let dir = std::env::temp_dir().join(format!("shoal_plot_title_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let plot = Plot {
            title: "a title far too long for a plot 600 pixels wide, written in 20-pixel \
                    letters it would run past both edges of the image"
                .into(),
            series: vec![Series {
                points: vec![(0.0, 0.0), (1.0, 1.0)],
                ..Default::default()
            }],
            size: (600, 300),
            ..Default::default()
        };
        plot.write(&dir.join("title")).unwrap();
        let img = image::open(dir.join("title.png")).unwrap().to_rgb8();
        // The caption band: some text in it, none in the outer 4 px on either side.
        let dark = |x: u32, y: u32| img.get_pixel(x, y).0.iter().all(|&c| c < 128);
        let inked = (0..30).flat_map(|y| (0..600).map(move |x| (x, y)));
        assert!(inked.clone().any(|(x, y)| dark(x, y)), "no title drawn");
        assert!(
            !inked
                .filter(|&(x, _)| !(4..596).contains(&x))
                .any(|(x, y)| dark(x, y)),
            "the title runs off the image"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn plots_with_legends_anywhere_are_written() {
        let dir = std::env::temp_dir().join(format!("shoal_plot_test_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let line = |c, y0: f64| Series {
            label: Some(format!("series {c}")),
            points: (0..200)
                .map(|i| (i as f64, y0 + (i as f64 * 0.1).sin()))
                .collect(),
            color: c,
            ..Default::default()
        };
        // A noisy signal fills the area: legend below, image taller.
        let noisy = Series {
            label: Some("noisy".into()),
            points: (0..200).map(|i| (i as f64, f64::from(i % 2))).collect(),
            ..Default::default()
        };
        let full = Plot {
            title: "full".into(),
            series: vec![noisy],
            size: (600, 300),
            ..Default::default()
        };
        let lay = full.layout().unwrap();
        assert_eq!(lay.legend, LegendPlace::Below);
        assert!(lay.strip > 0);
        let files = full.write(&dir.join("full")).unwrap();
        assert_eq!(files, [dir.join("full.png"), dir.join("full.svg")]);
        // The PNG is the plot and the strip below it, the line drawn above the strip and its
        // legend sample in the strip; the SVG has the same size.
        let blue = blue_rows(&files[0], (600, 300 + lay.strip as u32));
        assert!(
            blue[..300].iter().sum::<usize>() > 1000,
            "the line is not drawn"
        );
        assert!(
            blue[300..].iter().sum::<usize>() >= 24,
            "no legend in the strip"
        );
        let svg = std::fs::read_to_string(&files[1]).unwrap();
        assert!(svg.starts_with(&format!(
            "<svg width=\"600\" height=\"{}\"",
            300 + lay.strip
        )));
        // Room above the data: legend in a corner, image as asked.
        let roomy = Plot {
            title: "roomy".into(),
            series: vec![line(0, 0.0)],
            y_range: Some((-1.0, 6.0)),
            size: (600, 300),
            ..Default::default()
        };
        let lay = roomy.layout().unwrap();
        assert_ne!(lay.legend, LegendPlace::Below);
        assert_eq!(lay.strip, 0);
        let files = roomy.write(&dir.join("roomy")).unwrap();
        let blue = blue_rows(&files[0], (600, 300));
        assert!(blue.iter().sum::<usize>() > 1000, "the line is not drawn");
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// Decodes the PNG `path`, checks its size and counts the pixels of palette colour 0 in
    /// each row.
    fn blue_rows(path: &Path, size: (u32, u32)) -> Vec<usize> {
        let img = image::open(path).unwrap().to_rgb8();
        assert_eq!(img.dimensions(), size, "{}", path.display());
        let (r, g, b) = rgb(0);
        let mut rows = vec![0; size.1 as usize];
        for (_, y, p) in img.enumerate_pixels() {
            if p.0 == [r, g, b] {
                rows[y as usize] += 1;
            }
        }
        rows
    }
}
