//! What a plot shows: its lines and dots ([`Series`]), the outlines under them ([`Outline`]),
//! titles, axis labels, ranges and size ([`Plot`]). PNG and SVG are both drawn from this one
//! description.

use super::style::rgb;
use plotters::prelude::RGBColor;

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
    /// from `shoal_record::link_key`.
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

impl Series {
    /// The colour it is drawn in: its own, or the palette's.
    pub fn drawn_rgb(&self) -> (u8, u8, u8) {
        self.rgb.unwrap_or_else(|| rgb(self.color))
    }

    pub(super) fn drawn_color(&self) -> RGBColor {
        let (r, g, b) = self.drawn_rgb();
        RGBColor(r, g, b)
    }
}

impl Plot {
    /// The image size \[px\]: the field `size`, or 900 × 600 when that is (0, 0).
    pub(super) fn size(&self) -> (u32, u32) {
        if self.size == (0, 0) {
            (900, 600)
        } else {
            self.size
        }
    }
}
