//! The fixed colours of a GIF and its one palette (group, link-outcome, map colours and a grey
//! ramp) with the lookup table that maps a drawn pixel to its nearest entry. The link-outcome
//! colours and labels are [`crate::link_key`]'s.

use crate::replay::Outcome;
use plotters::prelude::*;

pub(super) const BG: RGBColor = RGBColor(255, 255, 255);
pub(super) const TEXT: RGBColor = RGBColor(0, 0, 0);
pub(super) const TEXT_GREY: RGBColor = RGBColor(88, 88, 88);
/// Beyond the pool's walls and below its floor.
pub(super) const OUTSIDE: RGBColor = RGBColor(224, 224, 224);
pub(super) const WATER: RGBColor = RGBColor(234, 243, 251);
pub(super) const GRID: RGBColor = RGBColor(206, 219, 232);
pub(super) const OBSTACLE: RGBColor = RGBColor(150, 150, 150);
pub(super) const OBSTACLE_EDGE: RGBColor = RGBColor(96, 96, 96);
pub(super) const WALL: RGBColor = RGBColor(40, 40, 40);
pub(super) const SURFACE: RGBColor = RGBColor(70, 130, 200);
pub(super) const FRAME: RGBColor = RGBColor(128, 128, 128);

/// The colour of a link outcome: the one key of [`crate::link_key`].
pub(super) fn outcome_color(o: Outcome) -> RGBColor {
    let (r, g, b) = crate::link_key::style(o).rgb;
    RGBColor(r, g, b)
}

/// Outcomes in drawing order (deliveries first, losses over them), as the key lists them.
pub(super) const OUTCOMES: [Outcome; 5] = Outcome::ALL;

/// `#rrggbb` as a colour.
pub(super) fn parse_hex(s: &str) -> Option<RGBColor> {
    let h = s.strip_prefix('#')?;
    if h.len() != 6 || !h.is_ascii() {
        return None;
    }
    let c = |i: usize| u8::from_str_radix(&h[i..i + 2], 16).ok();
    Some(RGBColor(c(0)?, c(2)?, c(4)?))
}

/// `a` moved the fraction `f` towards `b`.
pub(super) fn mix(a: RGBColor, b: RGBColor, f: f64) -> RGBColor {
    let m = |x: u8, y: u8| (f64::from(x) + f * (f64::from(y) - f64::from(x))).round() as u8;
    RGBColor(m(a.0, b.0), m(a.1, b.1), m(a.2, b.2))
}

/// The palette index kept free for "unchanged" pixels of a partial frame.
pub(super) const TRANSPARENT_INDEX: u8 = 255;

/// The GIF's one palette and the map from any RGB colour to its nearest entry.
pub(super) struct GifPalette {
    /// 256 entries, r, g, b each; entries from `len` on are unused.
    pub(super) rgb: Vec<u8>,
    /// Entries in use (at most 255: the last is [`TRANSPARENT_INDEX`]).
    #[cfg_attr(not(test), expect(dead_code, reason = "read by the tests"))]
    pub(super) len: usize,
    /// Nearest entry of each colour with 5 bits per channel.
    pub(super) lut: Vec<u8>,
}

impl GifPalette {
    #[inline]
    pub(super) fn key(r: u8, g: u8, b: u8) -> usize {
        (usize::from(r >> 3) << 10) | (usize::from(g >> 3) << 5) | usize::from(b >> 3)
    }

    /// The palette of `colors` in order of importance: a colour whose 5-bit cell already
    /// holds an earlier one is left out (it is within 8 levels per channel of it); beyond
    /// 255 colours the rest are left out.
    pub(super) fn new(colors: &[RGBColor]) -> Self {
        let mut taken = vec![false; 1 << 15];
        let mut rgb = Vec::with_capacity(256 * 3);
        let mut len = 0;
        for c in colors {
            let k = Self::key(c.0, c.1, c.2);
            if taken[k] || len == usize::from(TRANSPARENT_INDEX) {
                continue;
            }
            taken[k] = true;
            rgb.extend_from_slice(&[c.0, c.1, c.2]);
            len += 1;
        }
        rgb.resize(256 * 3, 0);
        let dist = |i: usize, r: i32, g: i32, b: i32| {
            let d = |k: usize, v: i32| i32::from(rgb[3 * i + k]) - v;
            // Weighted for the eye's sensitivity (green most, blue least).
            2 * d(0, r).pow(2) + 4 * d(1, g).pow(2) + 3 * d(2, b).pow(2)
        };
        let mut lut = vec![0u8; 1 << 15];
        for (k, slot) in lut.iter_mut().enumerate() {
            // The cell's centre.
            let (r, g, b) = (
                ((k >> 10) as i32) * 8 + 4,
                (((k >> 5) & 31) as i32) * 8 + 4,
                ((k & 31) as i32) * 8 + 4,
            );
            *slot = (0..len).min_by_key(|&i| dist(i, r, g, b)).unwrap_or(0) as u8;
        }
        // Every palette colour maps to itself.
        for i in 0..len {
            lut[Self::key(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2])] = i as u8;
        }
        Self { rgb, len, lut }
    }

    /// The entry of the colour `c`.
    #[inline]
    pub(super) fn index(&self, c: [u8; 3]) -> u8 {
        self.lut[Self::key(c[0], c[1], c[2])]
    }

    /// Maps the RGB image `rgb` to palette indices in `out` (one per pixel).
    pub(super) fn map(&self, rgb: &[u8], out: &mut [u8]) {
        for (px, o) in rgb.chunks_exact(3).zip(out.iter_mut()) {
            *o = self.index([px[0], px[1], px[2]]);
        }
    }
}
