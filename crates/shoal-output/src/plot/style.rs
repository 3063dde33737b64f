//! The look shared by every plot: the embedded DejaVu Sans font (plots render on machines
//! without system fonts) and the palette of line and group colours.

use plotters::prelude::*;
use std::sync::Once;

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
