//! How a plot is laid out before it is drawn: the axis ranges ([`Plot::ranges`], and as
//! drawn, with one scale on both axes for maps: [`Plot::ranges_drawn`]), the chart with its
//! title, and where the legend goes ([`Layout`]), decided once for both the PNG and the SVG.

use super::description::Plot;
use super::legend::{
    Entry, LEGEND_FONT, LEGEND_INSET, LegendPlace, corner_box, legend_place, strip_height,
};
use super::range::{clip_polyline, data_range};
use super::style::register_font;
use plotters::coord::Shift;
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

/// Size of a plot's title \[px\], and the smallest it is shrunk to so that it fits.
const TITLE_PX: u32 = 20;
const TITLE_MIN_PX: u32 = 11;
/// Size of the axes' tick labels \[px\].
pub(super) const TICK_FONT_PX: u32 = 13;
/// How many ticks with labels the horizontal axis has at most (plotters' default).
const X_TICKS: usize = 11;

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
pub(super) struct Layout {
    pub(super) x: (f64, f64),
    pub(super) y: (f64, f64),
    pub(super) legend: LegendPlace,
    /// Each legend entry.
    pub(super) entries: Vec<Entry>,
    /// Width of each entry's text \[px\].
    pub(super) text_w: Vec<i32>,
    /// Height of the strip below the plot \[px\] (0 unless the legend is below).
    pub(super) strip: u32,
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

    /// The chart of this plot on `area` with the ranges `x` and `y`: its title (shrunk to fit
    /// the width), margins and label areas.
    pub(super) fn chart<'a, DB: DrawingBackend>(
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
            .margin_right(self.right_margin(area))
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(x.0..x.1, ya..yb)
            .map_err(|e| e.to_string())
    }

    /// The margin right of the plot area \[px\]: 12, or more so that the label of the last
    /// tick of the horizontal axis, centred on it (at most on the plot area's right edge),
    /// is drawn whole. Measured on the ranges before a map widens them ([`Plot::ranges`]), so
    /// the plot area is the same size when the ranges are decided and when they are drawn;
    /// 4 px spare for the label of a widened range.
    fn right_margin<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> u32 {
        let (x0, x1) = self.ranges().0;
        let axis = RangedCoordf64::from(x0..x1);
        let font: TextStyle = ("sans-serif", TICK_FONT_PX).into_font().into();
        let half = axis
            .key_points(X_TICKS)
            .last()
            .map(<RangedCoordf64 as ValueFormatter<f64>>::format)
            .and_then(|l| area.estimate_text_size(&l, &font).ok())
            .map_or(0, |(w, _)| w.div_ceil(2) + 4);
        half.max(12)
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
    pub(super) fn layout(&self) -> Result<Layout, String> {
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
}
