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

use crate::files::{FileError, write_whole};
use image::ColorType;
use image::ImageEncoder;
use image::codecs::png::PngEncoder;
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::{Path, PathBuf};
use std::sync::Once;

static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

pub(crate) fn register_font() {
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
    /// Dashed (for setpoints and references).
    pub dashed: bool,
    /// Mark the first point with a dot.
    pub mark_start: bool,
    /// Line width \[px\] (0: the default, 2 for solid and 1 for dashed lines); with `dots`,
    /// the dots' radius \[px\] (0: 1 px).
    pub width: u32,
    /// Draw each point as a small dot instead of joining the points (measured samples,
    /// scatter plots).
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

pub(crate) fn color(i: usize) -> RGBColor {
    let (r, g, b) = rgb(i);
    RGBColor(r, g, b)
}

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

/// The region a map (east to the right, north up) shows: the bounding box of `points`
/// ((east, north) \[m\]) grown by a margin (10 % of its extent, at least 0.5 m), within the
/// pool (plus 5 % of its size, so the walls show when the vehicles are near them), with the
/// same scale on both axes. Returns the east range, the north range and an image size
/// \[px\] (`height` high, as wide as the aspect ratio needs, within 560 … 1800 px). Without
/// finite points the whole pool is shown.
pub fn map_view(
    pool: (f64, f64),
    points: impl IntoIterator<Item = (f64, f64)>,
    height: u32,
) -> ((f64, f64), (f64, f64), (u32, u32)) {
    let (north, east) = pool;
    let edge = 0.05 * north.max(east);
    let (mut e0, mut e1, mut n0, mut n1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for (e, n) in points {
        if e.is_finite() && n.is_finite() {
            (e0, e1, n0, n1) = (e0.min(e), e1.max(e), n0.min(n), n1.max(n));
        }
    }
    let (er, nr) = if e0 <= e1 && n0 <= n1 {
        let grow = |lo: f64, hi: f64, span: f64| {
            let m = (0.1 * (hi - lo)).max(0.5);
            ((lo - m).max(-edge), (hi + m).min(span + edge))
        };
        (grow(e0, e1, east), grow(n0, n1, north))
    } else {
        ((-edge, east + edge), (-edge, north + edge))
    };
    let w =
        ((f64::from(height) - 60.0) * (er.1 - er.0) / (nr.1 - nr.0) + 80.0).clamp(560.0, 1800.0);
    (er, nr, (w as u32, height))
}

/// Where the legend goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LegendPlace {
    /// Upper right corner of the plot area.
    UpperRight,
    /// Upper left corner of the plot area.
    UpperLeft,
    /// Lower right corner of the plot area.
    LowerRight,
    /// Lower left corner of the plot area.
    LowerLeft,
    /// In a strip below the plot, outside the data.
    Below,
}

impl LegendPlace {
    /// The legend box of `size` in this corner, in plot-area fractions (x0, y0, x1, y1), y
    /// from the top; `None` for [`LegendPlace::Below`].
    pub fn rect(self, size: (f64, f64)) -> Option<(f64, f64, f64, f64)> {
        let (w, h) = size;
        match self {
            LegendPlace::UpperRight => Some((1.0 - w, 0.0, 1.0, h)),
            LegendPlace::UpperLeft => Some((0.0, 0.0, w, h)),
            LegendPlace::LowerRight => Some((1.0 - w, 1.0 - h, 1.0, 1.0)),
            LegendPlace::LowerLeft => Some((0.0, 1.0 - h, w, 1.0)),
            LegendPlace::Below => None,
        }
    }
}

/// Largest share of the plot area's width or height a corner legend may take.
const MAX_CORNER: f64 = 0.5;

/// Whether the polyline `path` (or its single point) touches the box `r` = (x0, y0, x1, y1).
pub fn touches(path: &[(f64, f64)], r: (f64, f64, f64, f64)) -> bool {
    !clip_polyline(path, (r.0, r.2), (r.1, r.3)).is_empty()
}

/// Picks the legend's place: the first corner (upper right, upper left, lower right, lower
/// left) where a box of `size` — fractions of the plot area's width and height, its margin
/// included — touches none of `paths`, else [`LegendPlace::Below`]. `paths` are everything
/// drawn (lines, dots as one-point paths, outlines) in plot-area fractions, (0, 0) the upper
/// left corner and (1, 1) the lower right one.
pub fn legend_place(paths: &[Vec<(f64, f64)>], size: (f64, f64)) -> LegendPlace {
    if size.0 > MAX_CORNER || size.1 > MAX_CORNER {
        return LegendPlace::Below;
    }
    [
        LegendPlace::UpperRight,
        LegendPlace::UpperLeft,
        LegendPlace::LowerRight,
        LegendPlace::LowerLeft,
    ]
    .into_iter()
    .find(|c| {
        let r = c.rect(size).unwrap_or((0.0, 0.0, 1.0, 1.0));
        !paths.iter().any(|p| touches(p, r))
    })
    .unwrap_or(LegendPlace::Below)
}

/// Legend geometry \[px\].
const LEGEND_FONT: u32 = 13;
const LEGEND_ROW: i32 = 18;
const LEGEND_SAMPLE: i32 = 24;
const LEGEND_PAD: i32 = 6;
/// Gap between the plot area's edge and a corner legend \[px\].
const LEGEND_INSET: i32 = 8;

/// A legend entry: label, colour, dashed, dots, line width or dot radius \[px\] (0: default).
type Entry = (String, RGBColor, bool, bool, u32);

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
        ChartBuilder::on(area)
            .caption(&self.title, ("sans-serif", 20))
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

    /// Decides ranges and the legend's place, measuring text and the plot area on an
    /// off-screen bitmap of the final size.
    fn layout(&self) -> Result<Layout, String> {
        register_font();
        let (x, y) = self.ranges();
        let entries: Vec<Entry> = self
            .series
            .iter()
            .filter_map(|s| {
                s.label
                    .as_ref()
                    .map(|l| (l.clone(), color(s.color), s.dashed, s.dots, s.width))
            })
            .collect();
        let size = self.size();
        let mut buf = vec![0u8; size.0 as usize * size.1 as usize * 3];
        let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
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
        let chart = self.chart(&root, x, y)?;
        let (px, py) = chart.plotting_area().get_pixel_range();
        let (pw, ph) = (f64::from(px.end - px.start), f64::from(py.end - py.start));
        let (bw, bh) = corner_box(&text_w);
        // The box with its inset from the plot area's edge, as fractions.
        let frac = (
            f64::from(bw + LEGEND_INSET) / pw.max(1.0),
            f64::from(bh + LEGEND_INSET) / ph.max(1.0),
        );
        let legend = legend_place(&self.paths(x, y), frac);
        let strip = if legend == LegendPlace::Below {
            let rows = below_rows(&text_w, size.0 as i32).len() as i32;
            (rows * LEGEND_ROW + 2 * LEGEND_PAD) as u32
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
        for s in &self.series {
            // A plot of every vehicle of a large world is a long loop: look here.
            if stop() {
                return Err(DrawFail::Stopped);
            }
            let c = color(s.color);
            if s.dots {
                let r = s.width.max(1);
                chart
                    .draw_series(
                        s.points
                            .iter()
                            .filter(|p| inside(p))
                            .map(|p| Circle::new(*p, r, c.filled())),
                    )
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

/// Size of a corner legend with entries of text widths `text_w` \[px\].
fn corner_box(text_w: &[i32]) -> (i32, i32) {
    let w = LEGEND_SAMPLE + LEGEND_PAD + text_w.iter().copied().max().unwrap_or(0) + 2 * LEGEND_PAD;
    let h = text_w.len() as i32 * LEGEND_ROW + LEGEND_PAD;
    (w, h)
}

/// The entries of each row of a legend below the plot, filling rows of `width` \[px\].
fn below_rows(text_w: &[i32], width: i32) -> Vec<Vec<usize>> {
    let mut rows: Vec<Vec<usize>> = vec![Vec::new()];
    let mut used = 0;
    let avail = width - 2 * 12 - 60;
    for (i, w) in text_w.iter().enumerate() {
        let need = LEGEND_SAMPLE + LEGEND_PAD + w + 3 * LEGEND_PAD;
        if used > 0 && used + need > avail {
            rows.push(Vec::new());
            used = 0;
        }
        used += need;
        if let Some(r) = rows.last_mut() {
            r.push(i);
        }
    }
    rows
}

/// One legend entry: its sample line or dot at (x, y) (the row's vertical centre), the text
/// after it.
fn draw_entry<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    (label, c, dashed, dots, width): &Entry,
    (x, y): (i32, i32),
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    // As drawn in the plot, a little bolder for dots and dashes so they read at legend size.
    if *dots {
        area.draw(&Circle::new((x + LEGEND_SAMPLE / 2, y), 3, c.filled()))
            .map_err(e)?;
    } else if *dashed {
        for k in 0..3 {
            let a = x + k * 9;
            area.draw(&PathElement::new(
                vec![(a, y), ((a + 6).min(x + LEGEND_SAMPLE), y)],
                c.stroke_width(2),
            ))
            .map_err(e)?;
        }
    } else {
        let w = if *width == 0 { 2 } else { *width };
        area.draw(&PathElement::new(
            vec![(x, y), (x + LEGEND_SAMPLE, y)],
            c.stroke_width(w),
        ))
        .map_err(e)?;
    }
    let style = ("sans-serif", LEGEND_FONT)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    area.draw(&Text::new(
        label.clone(),
        (x + LEGEND_SAMPLE + LEGEND_PAD, y),
        style,
    ))
    .map_err(e)
}

fn draw_legend_corner<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    lay: &Layout,
    px: (i32, i32),
    py: (i32, i32),
) -> Result<(), String> {
    let (bw, bh) = corner_box(&lay.text_w);
    let left = matches!(lay.legend, LegendPlace::UpperLeft | LegendPlace::LowerLeft);
    let top = matches!(lay.legend, LegendPlace::UpperLeft | LegendPlace::UpperRight);
    let x0 = if left {
        px.0 + LEGEND_INSET
    } else {
        px.1 - LEGEND_INSET - bw
    };
    let y0 = if top {
        py.0 + LEGEND_INSET
    } else {
        py.1 - LEGEND_INSET - bh
    };
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    area.draw(&Rectangle::new(
        [(x0, y0), (x0 + bw, y0 + bh)],
        WHITE.filled(),
    ))
    .map_err(e)?;
    area.draw(&Rectangle::new(
        [(x0, y0), (x0 + bw, y0 + bh)],
        RGBColor(160, 160, 160).stroke_width(1),
    ))
    .map_err(e)?;
    for (i, entry) in lay.entries.iter().enumerate() {
        let y = y0 + LEGEND_PAD / 2 + i as i32 * LEGEND_ROW + LEGEND_ROW / 2;
        draw_entry(area, entry, (x0 + LEGEND_PAD, y))?;
    }
    Ok(())
}

fn draw_legend_below<DB: DrawingBackend>(
    strip: &DrawingArea<DB, Shift>,
    lay: &Layout,
) -> Result<(), String> {
    let width = strip.dim_in_pixel().0 as i32;
    for (r, row) in below_rows(&lay.text_w, width).iter().enumerate() {
        // Rows start under the plot area (right of the y label area).
        let mut x = 12 + 60;
        let y = LEGEND_PAD + r as i32 * LEGEND_ROW + LEGEND_ROW / 2;
        for &i in row {
            draw_entry(strip, &lay.entries[i], (x, y))?;
            x += LEGEND_SAMPLE + LEGEND_PAD + lay.text_w[i] + 3 * LEGEND_PAD;
        }
    }
    Ok(())
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
    fn map_view_zooms_to_the_points_within_the_pool() {
        // A 100 × 60 m pool (north × east); vehicles within 2 m around (north 50, east 30).
        let pts = [(29.0, 49.0), (31.0, 51.0), (f64::NAN, 0.0)];
        let (e, n, (w, h)) = map_view((100.0, 60.0), pts, 700);
        assert_eq!((e, n), ((28.5, 31.5), (48.5, 51.5)));
        assert_eq!(h, 700);
        assert!((560..=1800).contains(&w));
        // Near a wall the view stops 5 % of the pool's larger side beyond it.
        let (e, n, _) = map_view((100.0, 60.0), [(0.0, 99.0), (60.0, 90.0)], 700);
        assert_eq!(e, (-5.0, 65.0));
        assert!(
            (n.0 - 89.1).abs() < 1e-12 && (n.1 - 99.9).abs() < 1e-12,
            "{n:?}"
        );
        // Nothing to show: the whole pool.
        let (e, n, _) = map_view((100.0, 60.0), std::iter::empty(), 700);
        assert_eq!((e, n), ((-5.0, 65.0), (-5.0, 105.0)));
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

    /// A legend in a corner never touches anything drawn; a plot full of data gets its legend
    /// below.
    #[test]
    fn the_legend_goes_where_there_is_no_data() {
        let size = (0.3, 0.2);
        // A line through the upper half only: the upper corners are taken.
        let upper: Vec<(f64, f64)> = (0..=100).map(|i| (i as f64 / 100.0, 0.1)).collect();
        let place = legend_place(std::slice::from_ref(&upper), size);
        assert_eq!(place, LegendPlace::LowerRight);
        // A rising line from the lower left to the upper right: upper left is free.
        let diag: Vec<(f64, f64)> = (0..=100)
            .map(|i| (i as f64 / 100.0, 1.0 - i as f64 / 100.0))
            .collect();
        assert_eq!(
            legend_place(std::slice::from_ref(&diag), size),
            LegendPlace::UpperLeft
        );
        // A segment that crosses a corner box without a vertex inside it counts.
        let cross = vec![(0.6, 0.0), (1.0, 0.4)];
        assert_ne!(
            legend_place(std::slice::from_ref(&cross), size),
            LegendPlace::UpperRight
        );
        // A noisy signal filling the whole area: below.
        let full: Vec<(f64, f64)> = (0..=1000)
            .map(|i| (i as f64 / 1000.0, if i % 2 == 0 { 0.02 } else { 0.98 }))
            .collect();
        assert_eq!(
            legend_place(std::slice::from_ref(&full), size),
            LegendPlace::Below
        );
        // Too big for a corner: below.
        assert_eq!(legend_place(&[], (0.6, 0.1)), LegendPlace::Below);
        // Whatever the corner, its box touches no path.
        for paths in [vec![upper], vec![diag], vec![cross], vec![full]] {
            let place = legend_place(&paths, size);
            if let Some(r) = place.rect(size) {
                assert!(paths.iter().all(|p| !touches(p, r)), "{place:?}");
            }
        }
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
