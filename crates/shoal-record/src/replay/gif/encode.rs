//! Encoding: each frame mapped to the palette and stored as the rectangle that changed, transparent where unchanged.

use super::palette::TRANSPARENT_INDEX;
use std::borrow::Cow;
use std::io::Write;

/// Writes frames into the GIF: the first whole, later ones as the rectangle that changed with
/// unchanged pixels transparent.
pub(super) struct Frames {
    pub(super) prev: Vec<u8>,
    pub(super) sub: Vec<u8>,
    pub(super) width: usize,
    pub(super) height: usize,
    pub(super) first: bool,
}

impl Frames {
    pub(super) fn write<W: Write>(
        &mut self,
        enc: &mut ::gif::Encoder<W>,
        cur: &[u8],
        delay: u16,
    ) -> Result<(), ::gif::EncodingError> {
        let (w, h) = (self.width, self.height);
        let mut frame = ::gif::Frame {
            delay,
            dispose: ::gif::DisposalMethod::Keep,
            ..::gif::Frame::default()
        };
        if self.first {
            self.first = false;
            frame.width = w as u16;
            frame.height = h as u16;
            frame.buffer = Cow::Borrowed(cur);
            enc.write_frame(&frame)?;
            self.prev.copy_from_slice(cur);
            return Ok(());
        }
        // The rectangle that changed.
        let (mut x0, mut y0, mut x1, mut y1) = (w, h, 0, 0);
        for (y, (a, b)) in cur
            .chunks_exact(w)
            .zip(self.prev.chunks_exact(w))
            .enumerate()
        {
            if a == b {
                continue;
            }
            let first = a.iter().zip(b).position(|(p, q)| p != q).unwrap_or(0);
            let last = w - a
                .iter()
                .rev()
                .zip(b.iter().rev())
                .position(|(p, q)| p != q)
                .unwrap_or(0);
            x0 = x0.min(first);
            x1 = x1.max(last);
            y0 = y0.min(y);
            y1 = y1.max(y + 1);
        }
        self.sub.clear();
        frame.transparent = Some(TRANSPARENT_INDEX);
        if x1 <= x0 {
            // Nothing changed: one transparent pixel.
            self.sub.push(TRANSPARENT_INDEX);
            frame.width = 1;
            frame.height = 1;
        } else {
            for y in y0..y1 {
                let row = y * w;
                self.sub.extend(
                    cur[row + x0..row + x1]
                        .iter()
                        .zip(&self.prev[row + x0..row + x1])
                        .map(|(&c, &p)| if c == p { TRANSPARENT_INDEX } else { c }),
                );
            }
            frame.left = x0 as u16;
            frame.top = y0 as u16;
            frame.width = (x1 - x0) as u16;
            frame.height = (y1 - y0) as u16;
        }
        frame.buffer = Cow::Borrowed(&self.sub);
        enc.write_frame(&frame)?;
        self.prev.copy_from_slice(cur);
        Ok(())
    }
}
