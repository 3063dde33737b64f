//! Simple, dependable plots (PNG and SVG from one description) with plotters and an embedded
//! DejaVu Sans font, so plots render on machines without system fonts.

use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Once;

static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

fn register_font() {
    REGISTER.call_once(|| {
        // The embedded font is known to be valid; a failure would only lose text in plots.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// A plotting failure.
#[derive(Debug, thiserror::Error)]
#[error("cannot draw {path}: {message}")]
pub struct PlotError {
    /// The file being drawn.
    pub path: PathBuf,
    /// What went wrong.
    pub message: String,
}

/// One line of a plot.
#[derive(Clone, Debug, Default)]
pub struct Series {
    /// Legend label (none: not in the legend).
    pub label: Option<String>,
    /// Points (x, y) in data units.
    pub points: Vec<(f64, f64)>,
    /// Palette index of the colour.
    pub color: usize,
    /// Dashed (for setpoints and references).
    pub dashed: bool,
    /// Mark the first point with a dot.
    pub mark_start: bool,
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
    /// Image size \[px\].
    pub size: (u32, u32),
}

fn color(i: usize) -> RGBColor {
    const C: [RGBColor; 10] = [
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(127, 127, 127),
        RGBColor(188, 189, 34),
        RGBColor(23, 190, 207),
    ];
    C[i % C.len()]
}

impl Plot {
    fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let mut xs = (f64::INFINITY, f64::NEG_INFINITY);
        let mut ys = (f64::INFINITY, f64::NEG_INFINITY);
        let pts = self
            .series
            .iter()
            .flat_map(|s| s.points.iter())
            .chain(self.outlines.iter().flat_map(|o| o.points.iter()));
        for &(x, y) in pts {
            if x.is_finite() && y.is_finite() {
                xs = (xs.0.min(x), xs.1.max(x));
                ys = (ys.0.min(y), ys.1.max(y));
            }
        }
        let pad = |r: (f64, f64)| {
            if !r.0.is_finite() {
                (0.0, 1.0)
            } else {
                let span = (r.1 - r.0).max(1e-9);
                (r.0 - 0.05 * span, r.1 + 0.05 * span)
            }
        };
        (
            self.x_range.unwrap_or_else(|| pad(xs)),
            self.y_range.unwrap_or_else(|| pad(ys)),
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        register_font();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let ((x0, x1), (y0, y1)) = self.ranges();
        let (ya, yb) = if self.y_down { (y1, y0) } else { (y0, y1) };
        let mut chart = ChartBuilder::on(&root)
            .caption(&self.title, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(x0..x1, ya..yb)
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(|e| e.to_string())?;
        for o in &self.outlines {
            let mut pts = o.points.clone();
            if let Some(first) = pts.first().copied() {
                pts.push(first);
            }
            if o.filled {
                chart
                    .draw_series(std::iter::once(Polygon::new(
                        pts,
                        RGBColor(170, 170, 170).filled(),
                    )))
                    .map_err(|e| e.to_string())?;
            } else {
                chart
                    .draw_series(LineSeries::new(pts, BLACK.stroke_width(2)))
                    .map_err(|e| e.to_string())?;
            }
        }
        let mut any_label = false;
        for s in &self.series {
            let c = color(s.color);
            let style = c.stroke_width(2);
            let ann = if s.dashed {
                chart.draw_series(DashedLineSeries::new(
                    s.points.iter().copied(),
                    6,
                    4,
                    c.stroke_width(1),
                ))
            } else {
                chart.draw_series(LineSeries::new(s.points.iter().copied(), style))
            }
            .map_err(|e| e.to_string())?;
            if let Some(l) = &s.label {
                any_label = true;
                ann.label(l.as_str()).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2))
                });
            }
            if s.mark_start
                && let Some(p) = s.points.first()
            {
                chart
                    .draw_series(std::iter::once(Circle::new(*p, 3, c.filled())))
                    .map_err(|e| e.to_string())?;
            }
        }
        if any_label {
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 13))
                .draw()
                .map_err(|e| e.to_string())?;
        }
        root.present().map_err(|e| e.to_string())
    }

    /// Writes `<stem>.png` and `<stem>.svg`; returns both paths.
    pub fn write(&self, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
        let size = if self.size == (0, 0) {
            (900, 600)
        } else {
            self.size
        };
        let png = stem.with_extension("png");
        let svg = stem.with_extension("svg");
        let err = |p: &Path, message: String| PlotError {
            path: p.to_path_buf(),
            message,
        };
        self.draw(BitMapBackend::new(&png, size).into_drawing_area())
            .map_err(|m| err(&png, m))?;
        self.draw(SVGBackend::new(&svg, size).into_drawing_area())
            .map_err(|m| err(&svg, m))?;
        Ok(vec![png, svg])
    }
}
