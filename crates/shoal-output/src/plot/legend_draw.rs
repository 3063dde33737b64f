//! Drawing a plot's legend where its layout put it: in a corner of the plot area, in a white
//! box, or in rows in the strip below the plot.

use super::layout::Layout;
use super::legend::{
    Entry, LEGEND_FONT, LEGEND_INSET, LEGEND_PAD, LEGEND_ROW, LEGEND_SAMPLE, LegendPlace,
    below_rows, corner_box,
};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

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

pub(super) fn draw_legend_corner<DB: DrawingBackend>(
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

pub(super) fn draw_legend_below<DB: DrawingBackend>(
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
