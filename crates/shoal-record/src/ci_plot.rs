//! Means with confidence intervals against a discrete parameter: the figure of a parameter
//! study (a sweep). The horizontal axis has one equally spaced position per value of the
//! parameter, labelled with the value as written (so 10, 100 and 1000 vehicles, or water
//! types by name, sit side by side); each group (a combination of the other parameters) is a
//! line of mean markers with vertical error bars, shifted a little sideways so bars of
//! different groups at the same value do not hide each other. PNG and SVG from one
//! description, with the embedded font of [`shoal_output::plot`], written whole through
//! [`shoal_output::files`]; the legend sits in a strip below the plot, so it never covers data.

use image::ColorType;
use image::ImageEncoder;
use image::codecs::png::PngEncoder;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use shoal_output::files::write_whole;
use shoal_output::plot::{PlotError, color, data_range, register_font};
use std::path::{Path, PathBuf};

/// One mean with its interval, in the metric's unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CiPoint {
    /// Mean.
    pub mean: f64,
    /// Lower end of the interval (equal to the mean when there is none, e.g. one sample).
    pub low: f64,
    /// Upper end of the interval.
    pub high: f64,
}

/// One line of the plot: a mean (or nothing) at each category.
#[derive(Clone, Debug, Default)]
pub struct CiGroup {
    /// Legend label (none: not in the legend).
    pub label: Option<String>,
    /// One entry per category of the plot, in order; `None` where the group has no data.
    pub points: Vec<Option<CiPoint>>,
}

/// Means with intervals against the values of one parameter.
#[derive(Clone, Debug, Default)]
pub struct CiPlot {
    /// Title.
    pub title: String,
    /// Horizontal axis label (the parameter, with its unit where it has one).
    pub x_label: String,
    /// Vertical axis label (the metric, with its unit where it has one).
    pub y_label: String,
    /// The parameter's values as text, in axis order.
    pub categories: Vec<String>,
    /// The lines.
    pub groups: Vec<CiGroup>,
    /// Image size without the legend strip \[px\] ((0, 0): 900 × 600).
    pub size: (u32, u32),
}

/// Legend geometry \[px\].
const LEGEND_ROW: i32 = 20;
const LEGEND_FONT: u32 = 14;
/// Width of half an error bar's cap, as a share of one category's width.
const CAP: f64 = 0.04;

impl CiPlot {
    fn size(&self) -> (u32, u32) {
        if self.size == (0, 0) {
            (900, 600)
        } else {
            self.size
        }
    }

    fn labelled(&self) -> Vec<(usize, &str)> {
        self.groups
            .iter()
            .enumerate()
            .filter_map(|(i, g)| g.label.as_deref().map(|l| (i, l)))
            .collect()
    }

    /// Horizontal shift of group `g` from its category's centre (in categories).
    fn dodge(&self, g: usize) -> f64 {
        let n = self.groups.len();
        if n < 2 {
            return 0.0;
        }
        let step = (0.5 / n as f64).min(0.08);
        (g as f64 - 0.5 * (n - 1) as f64) * step
    }

    /// The vertical range: every interval end, with a margin.
    pub fn y_range(&self) -> (f64, f64) {
        data_range(
            self.groups
                .iter()
                .flat_map(|g| g.points.iter().flatten())
                .flat_map(|p| [p.low, p.high, p.mean]),
            0.0,
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        register_font();
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(e)?;
        let (_, h) = self.size();
        let labelled = self.labelled();
        let (area, strip) = if labelled.is_empty() {
            (root.clone(), None)
        } else {
            let (a, b) = root.split_vertically(h);
            (a, Some(b))
        };
        let n = self.categories.len().max(1) as f64;
        let x = (-0.5, n - 0.5);
        let y = self.y_range();
        let mut chart = ChartBuilder::on(&area)
            .caption(&self.title, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(48)
            .y_label_area_size(70)
            .build_cartesian_2d(x.0..x.1, y.0..y.1)
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(0)
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(|e| e.to_string())?;
        // The categories under the axis, at their positions.
        let tick = ("sans-serif", 13)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Top));
        for (i, c) in self.categories.iter().enumerate() {
            let (px, py) = chart.backend_coord(&(i as f64, y.0));
            area.draw(&PathElement::new(vec![(px, py), (px, py + 5)], BLACK))
                .map_err(e)?;
            area.draw(&Text::new(c.clone(), (px, py + 8), tick.clone()))
                .map_err(e)?;
        }
        for (g, group) in self.groups.iter().enumerate() {
            let c = color(g);
            let dx = self.dodge(g);
            let mut line: Vec<(f64, f64)> = Vec::new();
            for (i, p) in group.points.iter().enumerate() {
                let Some(p) = p else {
                    // A missing point breaks the line.
                    if line.len() > 1 {
                        chart
                            .draw_series(LineSeries::new(line.clone(), c.stroke_width(2)))
                            .map_err(|e| e.to_string())?;
                    }
                    line.clear();
                    continue;
                };
                let xc = i as f64 + dx;
                line.push((xc, p.mean));
                if p.high > p.low {
                    for seg in [
                        vec![(xc, p.low), (xc, p.high)],
                        vec![(xc - CAP, p.low), (xc + CAP, p.low)],
                        vec![(xc - CAP, p.high), (xc + CAP, p.high)],
                    ] {
                        chart
                            .draw_series(LineSeries::new(seg, c.stroke_width(2)))
                            .map_err(|e| e.to_string())?;
                    }
                }
                chart
                    .draw_series(std::iter::once(Circle::new((xc, p.mean), 4, c.filled())))
                    .map_err(|e| e.to_string())?;
            }
            if line.len() > 1 {
                chart
                    .draw_series(LineSeries::new(line, c.stroke_width(2)))
                    .map_err(|e| e.to_string())?;
            }
        }
        if let Some(strip) = strip {
            let font = ("sans-serif", LEGEND_FONT)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Left, VPos::Center));
            for (row, (g, label)) in labelled.iter().enumerate() {
                let y = LEGEND_ROW / 2 + 4 + row as i32 * LEGEND_ROW;
                let x0 = 82;
                let c = color(*g);
                strip
                    .draw(&PathElement::new(
                        vec![(x0, y), (x0 + 24, y)],
                        c.stroke_width(2),
                    ))
                    .map_err(e)?;
                strip
                    .draw(&Circle::new((x0 + 12, y), 4, c.filled()))
                    .map_err(e)?;
                strip
                    .draw(&Text::new(label.to_string(), (x0 + 32, y), font.clone()))
                    .map_err(e)?;
            }
        }
        root.present().map_err(e)
    }

    /// Height of the legend strip below the plot \[px\].
    fn strip(&self) -> u32 {
        let n = self.labelled().len() as u32;
        if n == 0 { 0 } else { n * LEGEND_ROW as u32 + 8 }
    }

    /// Writes `<stem>.png` and `<stem>.svg` (drawn in memory, each written whole); returns
    /// both paths.
    pub fn write(&self, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
        let png = stem.with_extension("png");
        let svg = stem.with_extension("svg");
        let err = |p: &Path, message: String| PlotError::Draw {
            path: p.to_path_buf(),
            message,
        };
        let (w, h) = self.size();
        let size = (w, h + self.strip());
        let mut pixels = vec![0u8; size.0 as usize * size.1 as usize * 3];
        self.draw(BitMapBackend::with_buffer(&mut pixels, size).into_drawing_area())
            .map_err(|m| err(&png, m))?;
        let mut encoded = Vec::new();
        PngEncoder::new(&mut encoded)
            .write_image(&pixels, size.0, size.1, ColorType::Rgb8)
            .map_err(|e| err(&png, e.to_string()))?;
        let mut written = vec![write_whole(&png, &encoded)?];
        let mut text = String::new();
        self.draw(SVGBackend::with_string(&mut text, size).into_drawing_area())
            .map_err(|m| err(&svg, m))?;
        written.push(write_whole(&svg, text.as_bytes())?);
        Ok(written)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pt(mean: f64, half: f64) -> Option<CiPoint> {
        Some(CiPoint {
            mean,
            low: mean - half,
            high: mean + half,
        })
    }

    #[test]
    fn the_vertical_range_covers_every_interval() {
        let p = CiPlot {
            categories: vec!["10".into(), "100".into()],
            groups: vec![CiGroup {
                label: None,
                points: vec![pt(0.5, 0.2), pt(0.9, 0.3)],
            }],
            ..Default::default()
        };
        let (lo, hi) = p.y_range();
        assert!(lo < 0.3 && hi > 1.2, "{lo} {hi}");
    }

    #[test]
    fn groups_are_spread_around_each_category_and_the_figure_is_written() {
        let dir = std::env::temp_dir().join(format!("shoal_ci_plot_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = CiPlot {
            title: "delivery ratio".into(),
            x_label: "vehicles".into(),
            y_label: "delivery ratio".into(),
            categories: vec!["10".into(), "30".into(), "100".into()],
            groups: vec![
                CiGroup {
                    label: Some("pool".into()),
                    points: vec![pt(0.8, 0.05), None, pt(0.6, 0.02)],
                },
                CiGroup {
                    label: Some("coastal".into()),
                    points: vec![pt(0.5, 0.1), pt(0.4, 0.0), pt(0.3, 0.05)],
                },
            ],
            ..Default::default()
        };
        assert!(p.dodge(0) < 0.0 && p.dodge(1) > 0.0);
        assert_eq!(p.dodge(0), -p.dodge(1));
        let files = p.write(&dir.join("ci")).unwrap();
        assert_eq!(files.len(), 2);
        let img = image::open(&files[0]).unwrap();
        // The legend strip: two rows below the 600 px plot.
        assert_eq!(img.height(), 600 + 2 * LEGEND_ROW as u32 + 8);
        let svg = std::fs::read_to_string(&files[1]).unwrap();
        assert!(svg.contains("coastal") && svg.contains("100"));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
