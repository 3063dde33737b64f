//! The legend of a plot: where it goes (a corner that nothing drawn passes through, else a
//! strip below the plot) and its size; `legend_draw` draws it.

use super::range::clip_polyline;
use plotters::prelude::RGBColor;

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
pub(super) const LEGEND_FONT: u32 = 13;
pub(super) const LEGEND_ROW: i32 = 18;
pub(super) const LEGEND_SAMPLE: i32 = 24;
pub(super) const LEGEND_PAD: i32 = 6;
/// Gap between the plot area's edge and a corner legend \[px\].
pub(super) const LEGEND_INSET: i32 = 8;

/// A legend entry: label, colour, dashed, dots, line width or dot radius \[px\] (0: default).
pub(super) type Entry = (String, RGBColor, bool, bool, u32);

/// Size of a corner legend with entries of text widths `text_w` \[px\].
pub(super) fn corner_box(text_w: &[i32]) -> (i32, i32) {
    let w = LEGEND_SAMPLE + LEGEND_PAD + text_w.iter().copied().max().unwrap_or(0) + 2 * LEGEND_PAD;
    let h = text_w.len() as i32 * LEGEND_ROW + LEGEND_PAD;
    (w, h)
}

/// Height of the strip below a plot `width` px wide for a legend with entries of text widths
/// `text_w` \[px\].
pub(super) fn strip_height(text_w: &[i32], width: i32) -> u32 {
    let rows = below_rows(text_w, width).len() as i32;
    (rows * LEGEND_ROW + 2 * LEGEND_PAD) as u32
}

/// The entries of each row of a legend below the plot, filling rows of `width` \[px\].
pub(super) fn below_rows(text_w: &[i32], width: i32) -> Vec<Vec<usize>> {
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
