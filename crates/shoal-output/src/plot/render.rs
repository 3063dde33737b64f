//! Drawing a laid-out plot (lines, dots, outlines, legend) onto a plotters backend, and
//! writing it as `<stem>.png` and `<stem>.svg`, each drawn in memory and written whole
//! ([`Plot::write`], [`Plot::write_until`]).

use super::description::Plot;
use super::layout::{Layout, TICK_FONT_PX};
use super::legend::LegendPlace;
use super::legend_draw::{draw_legend_below, draw_legend_corner};
use super::range::clip_polyline;
use super::style::register_font;
use crate::files::{FileError, write_whole};
use image::ColorType;
use image::ImageEncoder;
use image::codecs::png::PngEncoder;
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

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

/// Dots of at least this radius \[px\] are markers, drawn with a white ring.
const MARKER_RING_FROM: u32 = 3;

/// A plot's chart, in data units on both axes.
type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

impl Plot {
    /// Draws the plot, laid out as `lay`, on `root`; gives up between series once `stop` says
    /// so.
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
            .label_style(("sans-serif", TICK_FONT_PX))
            .draw()
            .map_err(|e| e.to_string())?;
        self.draw_outlines(&mut chart, x, y)?;
        self.draw_series(&mut chart, x, y, stop)?;
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

    /// Draws the outlines under everything else: filled grey when wholly inside the ranges,
    /// else their pieces inside as black lines.
    fn draw_outlines<DB: DrawingBackend>(
        &self,
        chart: &mut Chart<'_, DB>,
        x: (f64, f64),
        y: (f64, f64),
    ) -> Result<(), String> {
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
        Ok(())
    }

    /// Draws the series, lines before dots; gives up before a series once `stop` says so.
    fn draw_series<DB: DrawingBackend>(
        &self,
        chart: &mut Chart<'_, DB>,
        x: (f64, f64),
        y: (f64, f64),
        stop: &dyn Fn() -> bool,
    ) -> Result<(), DrawFail> {
        let inside = |p: &(f64, f64)| p.0 >= x.0 && p.0 <= x.1 && p.1 >= y.0 && p.1 <= y.1;
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
        Ok(())
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
    use crate::plot::description::Series;
    use crate::plot::style::rgb;

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

    /// The last tick label of the horizontal axis (centred on the plot area's right edge)
    /// is drawn whole inside the image, not cut off at its right edge.
    #[test]
    fn the_last_x_tick_label_lies_inside_the_image() {
        let dir = std::env::temp_dir().join(format!("shoal_plot_ticks_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // Ticks every 100 up to 1000: the last label, "1000.0", is centred on the right edge.
        let plot = Plot {
            title: "ticks".into(),
            series: vec![Series {
                points: vec![(0.0, 0.0), (1000.0, 1.0)],
                ..Default::default()
            }],
            x_range: Some((0.0, 1000.0)),
            size: (600, 300),
            ..Default::default()
        };
        plot.write(&dir.join("ticks")).unwrap();
        let img = image::open(dir.join("ticks.png")).unwrap().to_rgb8();
        let at = plot.ranges_drawn().unwrap();
        let right = at.origin.0 + at.area.0;
        let bottom = (at.origin.1 + at.area.1) as u32;
        // The tick labels' band: below the axis, above the axis title.
        let dark = |x: u32, y: u32| img.get_pixel(x, y).0.iter().all(|&c| c < 128);
        let band = || (bottom + 6..bottom + 22).flat_map(|y| (0..600).map(move |x| (x, y)));
        let inked: Vec<u32> = band()
            .filter(|&(x, y)| dark(x, y))
            .map(|(x, _)| x)
            .collect();
        let last = inked.iter().copied().max().unwrap_or(0);
        // "1000.0" in 13 px letters is about 33 px wide: centred on the axis' right end, its
        // ink reaches more than 12 px past it, and stops short of the image's edge.
        assert!(
            f64::from(last) > right + 12.0 && last < 600 - 3,
            "the last tick label's ink ends at x = {last} (the axis ends at {right:.0}, the \
             image at 600): it is cut off"
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
