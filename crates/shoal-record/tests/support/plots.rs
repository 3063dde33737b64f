//! Checks that a plot shows what it should, for the tests of shoal-sim, shoal-cli and the
//! root crate (the others include this file by path). Its SVG's solid lines must be the data
//! ([`assert_svg_lines`]: in each series' colour, one line per series with a pixel per data
//! point, and one affine map per axis that takes every data point to its pixel within a
//! pixel), and its PNG must decode, have the SVG's size and have pixels of every series'
//! colour drawn inside the plot area ([`assert_png_colours`]) — more than a legend's sample
//! line holds.

#![allow(dead_code)]

use std::path::Path;

/// A colour (red, green, blue).
pub type Rgb = (u8, u8, u8);

/// A `<polyline>` of an SVG drawn by plotters.
#[derive(Clone, Debug)]
pub struct Line {
    /// Stroke colour.
    pub stroke: Rgb,
    /// Stroke width [px].
    pub width: u32,
    /// Points [px].
    pub points: Vec<(f64, f64)>,
}

/// The value of the attribute `name` in the tag `tag`.
fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let k = format!(" {name}=\"");
    let i = tag.find(&k)? + k.len();
    Some(&tag[i..i + tag[i..].find('"')?])
}

/// `#RRGGBB` as a colour.
fn hex(s: &str) -> Option<Rgb> {
    let s = s.strip_prefix('#')?;
    let c = |k: usize| u8::from_str_radix(s.get(k..k + 2)?, 16).ok();
    Some((c(0)?, c(2)?, c(4)?))
}

/// The tags `<name …>` of `svg`, in order.
fn tags<'a>(svg: &'a str, name: &str) -> Vec<&'a str> {
    let open = format!("<{name} ");
    svg.match_indices(&open)
        .map(|(i, _)| &svg[i..i + svg[i..].find('>').unwrap_or(svg.len() - i)])
        .collect()
}

/// Every polyline of `svg`, in document order.
pub fn lines(svg: &str) -> Vec<Line> {
    tags(svg, "polyline")
        .into_iter()
        .filter_map(|t| {
            let points = attr(t, "points")?
                .split_whitespace()
                .filter_map(|p| {
                    let (x, y) = p.split_once(',')?;
                    Some((x.parse().ok()?, y.parse().ok()?))
                })
                .collect();
            Some(Line {
                stroke: hex(attr(t, "stroke")?)?,
                width: attr(t, "stroke-width")?.parse().ok()?,
                points,
            })
        })
        .collect()
}

/// The plot area of a plotters SVG [px]: the box of its grid lines (x0, y0, x1, y1).
pub fn plot_area(svg: &str) -> (f64, f64, f64, f64) {
    let mut b = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    for t in tags(svg, "line")
        .into_iter()
        .filter(|t| attr(t, "opacity") == Some("0.1"))
    {
        for (x, y) in [("x1", "y1"), ("x2", "y2")] {
            let x: f64 = attr(t, x).and_then(|v| v.parse().ok()).unwrap();
            let y: f64 = attr(t, y).and_then(|v| v.parse().ok()).unwrap();
            b = (b.0.min(x), b.1.min(y), b.2.max(x), b.3.max(y));
        }
    }
    assert!(b.0 < b.2 && b.1 < b.3, "no grid lines in the SVG");
    b
}

/// Whether `l` is a legend's sample line: two points, level, 24 px long.
fn legend_sample(l: &Line) -> bool {
    l.points.len() == 2
        && l.points[0].1 == l.points[1].1
        && (l.points[1].0 - l.points[0].0).abs() == 24.0
}

/// Least-squares `px ≈ a + b·u` over `pairs`; returns the largest miss [px].
fn affine_miss(pairs: &[(f64, f64)]) -> f64 {
    let n = pairs.len() as f64;
    let (mu, mp) = pairs
        .iter()
        .fold((0.0, 0.0), |(a, b), (u, p)| (a + u / n, b + p / n));
    let (suu, sup) = pairs.iter().fold((0.0, 0.0), |(a, b), (u, p)| {
        (a + (u - mu) * (u - mu), b + (u - mu) * (p - mp))
    });
    let slope = if suu > 0.0 { sup / suu } else { 0.0 };
    pairs
        .iter()
        .map(|(u, p)| (p - (mp + slope * (u - mu))).abs())
        .fold(0.0, f64::max)
}

/// Asserts that the solid lines (2 px, the default) of the SVG `path` in the colours of
/// `series` are
/// `series`: per colour, in order, one line per series with one point per data point, and
/// one affine map per axis that takes every data point (data units) to its pixel within
/// 1 px (pixels are whole numbers). Other lines (dashed, outlines, legend samples) are left
/// alone. `series` are (colour, points), every point inside the plot's ranges.
pub fn assert_svg_lines(path: &Path, series: &[(Rgb, Vec<(f64, f64)>)]) {
    assert_svg_series(path, 2, series);
}

/// [`assert_svg_lines`] for lines `width` px wide.
pub fn assert_svg_series(path: &Path, width: u32, series: &[(Rgb, Vec<(f64, f64)>)]) {
    let svg = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(
        svg.trim_end().ends_with("</svg>"),
        "{} is not a whole SVG",
        path.display()
    );
    let drawn: Vec<Line> = lines(&svg)
        .into_iter()
        .filter(|l| {
            l.width == width && !legend_sample(l) && series.iter().any(|(c, _)| *c == l.stroke)
        })
        .collect();
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    let mut used = vec![false; drawn.len()];
    for (k, (colour, points)) in series.iter().enumerate() {
        let i = (0..drawn.len())
            .find(|&i| !used[i] && drawn[i].stroke == *colour)
            .unwrap_or_else(|| panic!("{}: no line for series {k} ({colour:?})", path.display()));
        used[i] = true;
        assert_eq!(
            drawn[i].points.len(),
            points.len(),
            "{}: series {k} ({colour:?}) has {} points, its line {}",
            path.display(),
            points.len(),
            drawn[i].points.len()
        );
        for (d, p) in points.iter().zip(&drawn[i].points) {
            xs.push((d.0, p.0));
            ys.push((d.1, p.1));
        }
    }
    let extra = used.iter().filter(|u| !**u).count();
    assert_eq!(
        extra,
        0,
        "{}: {extra} lines in the series' colours left over",
        path.display()
    );
    let (mx, my) = (affine_miss(&xs), affine_miss(&ys));
    assert!(
        mx <= 1.0 && my <= 1.0,
        "{}: the lines are not the data: off by up to {mx:.2} px across, {my:.2} px up",
        path.display()
    );
}

/// Decodes the PNG `path`, checks that it has the size of the SVG beside it, and that each
/// of `colours` has at least `min` pixels (within 20 of it, summed over the channels) inside
/// the SVG's plot area; returns the counts.
pub fn assert_png_colours(path: &Path, colours: &[Rgb], min: usize) -> Vec<usize> {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{} does not decode: {e}", path.display()))
        .to_rgb8();
    let svg = std::fs::read_to_string(path.with_extension("svg")).unwrap();
    let size = tags(&svg, "svg")[0];
    let w: u32 = attr(size, "width").and_then(|v| v.parse().ok()).unwrap();
    let h: u32 = attr(size, "height").and_then(|v| v.parse().ok()).unwrap();
    assert_eq!(
        img.dimensions(),
        (w, h),
        "{}: the PNG's size against the SVG's",
        path.display()
    );
    let (x0, y0, x1, y1) = plot_area(&svg);
    let counts: Vec<usize> = colours
        .iter()
        .map(|&(r, g, b)| {
            img.enumerate_pixels()
                .filter(|(x, y, _)| {
                    (x0..=x1).contains(&f64::from(*x)) && (y0..=y1).contains(&f64::from(*y))
                })
                .filter(|(_, _, p)| {
                    let d = |a: u8, b: u8| u32::from(a.abs_diff(b));
                    d(p.0[0], r) + d(p.0[1], g) + d(p.0[2], b) <= 20
                })
                .count()
        })
        .collect();
    for (c, n) in colours.iter().zip(&counts) {
        assert!(
            *n >= min,
            "{}: {n} pixels of {c:?} in the plot area, fewer than {min}",
            path.display()
        );
    }
    counts
}

/// The filled circles of `svg` inside its plot area: (fill colour, centre [px]).
pub fn dots(svg: &str) -> Vec<(Rgb, (f64, f64))> {
    let (x0, y0, x1, y1) = plot_area(svg);
    tags(svg, "circle")
        .into_iter()
        .filter_map(|t| {
            let x: f64 = attr(t, "cx")?.parse().ok()?;
            let y: f64 = attr(t, "cy")?.parse().ok()?;
            let inside = (x0..=x1).contains(&x) && (y0..=y1).contains(&y);
            inside.then_some((hex(attr(t, "fill")?)?, (x, y)))
        })
        .collect()
}

/// Asserts that the figure of means with 95 % intervals `path` (an SVG of
/// `shoal_record::ci_plot`) draws `groups`: per colour, a dot per (mean, half-width) in
/// category order (left to right) and a vertical bar from mean − half to mean + half where
/// the half-width is not 0, with one affine map of the vertical axis that takes every mean
/// and every bar end to its pixel within 1 px.
pub fn assert_ci_svg(path: &Path, groups: &[(Rgb, Vec<(f64, f64)>)]) {
    let svg = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let all_dots = dots(&svg);
    let all_lines = lines(&svg);
    let mut ys = Vec::new();
    for (colour, points) in groups {
        let mut at: Vec<(f64, f64)> = all_dots
            .iter()
            .filter(|d| d.0 == *colour)
            .map(|d| d.1)
            .collect();
        at.sort_by(|a, b| a.0.total_cmp(&b.0));
        assert_eq!(
            at.len(),
            points.len(),
            "{}: dots of {colour:?}",
            path.display()
        );
        let mut bars: Vec<(f64, f64, f64)> = all_lines
            .iter()
            .filter(|l| l.stroke == *colour && l.points.len() == 2)
            .filter(|l| l.points[0].0 == l.points[1].0 && l.points[0].1 != l.points[1].1)
            .map(|l| {
                let (a, b) = (l.points[0].1, l.points[1].1);
                (l.points[0].0, a.min(b), a.max(b))
            })
            .collect();
        bars.sort_by(|a, b| a.0.total_cmp(&b.0));
        let with_bars: Vec<usize> = (0..points.len()).filter(|&i| points[i].1 > 0.0).collect();
        assert_eq!(
            bars.len(),
            with_bars.len(),
            "{}: bars of {colour:?}",
            path.display()
        );
        for ((mean, _), dot) in points.iter().zip(&at) {
            ys.push((*mean, dot.1));
        }
        for (&i, bar) in with_bars.iter().zip(&bars) {
            let (mean, half) = points[i];
            assert!(
                (bar.0 - at[i].0).abs() <= 1.0,
                "{}: a bar off its dot",
                path.display()
            );
            // Pixels grow downwards: the top of the bar is the upper end.
            ys.push((mean + half, bar.1));
            ys.push((mean - half, bar.2));
        }
    }
    let miss = affine_miss(&ys);
    assert!(
        miss <= 1.0,
        "{}: the dots and bars are not the means and intervals: off by up to {miss:.2} px",
        path.display()
    );
}
