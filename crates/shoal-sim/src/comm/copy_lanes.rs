//! A frame's copies in lanes ([`CopyLanes`]): the LEDs that send one logical frame, their
//! positions and axes as structure of arrays, so that the geometry of the best-case bound of
//! [`Medium::may_decode`](super::Medium) — a distance, a dot product, a division and three
//! roots per copy — is computed for four copies per instruction with AVX (two without), once
//! per reception attempt, instead of copy after copy.
//!
//! Every lane does the bound's scalar operations in their order (dot products and squared
//! norms summed from zero in x, y, z order, as nalgebra sums them; roots and divisions are
//! IEEE operations in any width), so each copy's geometry, and with it every decision of the
//! bound, is bit-identical to the scalar computation.

use super::lanes::{Lane, PoseLanes, avx_dispatch};
use shoal_model::math::Vec3;
use shoal_model::optics::ModemPose;

use super::lanes::W;

/// Up to [`W`] copies of a frame: LED positions \[m\] and unit axes; padded lanes repeat the
/// last copy (their results are never read).
pub(super) type CopyChunk = PoseLanes;

/// The geometry of the bound for one chunk of copies and one receiver: the distance from each
/// LED to the receiver's centre \[m\] and the cosine of the most favourable emission angle
/// towards its hull \[1\].
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct BoundGeometry {
    pub(super) dist: Lane,
    pub(super) cos_best: Lane,
}

/// The chunks of every frame's copies, frame after frame (see [`CopyLanes::push_frame`]): a
/// frame of `n` copies takes `n.div_ceil(W)` chunks.
#[derive(Debug, Default)]
pub(super) struct CopyLanes {
    chunks: Vec<CopyChunk>,
}

impl CopyLanes {
    /// Appends the chunks of one frame's copies, sent from `poses` (in copy order); padded
    /// lanes repeat the last copy.
    pub(super) fn push_frame<'p>(&mut self, poses: impl IntoIterator<Item = &'p ModemPose>) {
        let (mut c, mut lane, mut last) = (CopyChunk::default(), 0, None);
        for p in poses {
            set_lane(&mut c, lane, p);
            (lane, last) = (lane + 1, Some(p));
            if lane == W {
                self.chunks.push(c);
                lane = 0;
            }
        }
        if let (true, Some(p)) = (lane > 0, last) {
            for l in lane..W {
                set_lane(&mut c, l, p);
            }
            self.chunks.push(c);
        }
    }

    /// Every frame's chunks.
    pub(super) fn chunks(&self) -> &[CopyChunk] {
        &self.chunks
    }
}

/// Puts `p` into lane `l` of chunk `c`.
fn set_lane(c: &mut CopyChunk, l: usize, p: &ModemPose) {
    let (q, a) = (&p.position, &p.axis);
    (c.px[l], c.py[l], c.pz[l]) = (q.x, q.y, q.z);
    (c.ax[l], c.ay[l], c.az[l]) = (a.x, a.y, a.z);
}

avx_dispatch!(
    /// The bound's geometry of chunk `c` for a receiver at `pos` \[m\] whose hull has the
    /// bounding radius `r` \[m\], with the widest vectors this CPU has.
    pub(super) fn bound_geometry(c: &CopyChunk, pos: &Vec3, r: f64) -> BoundGeometry => bound_lanes
);

/// The lanes of [`bound_geometry`]: for each copy, the distance to the receiver's centre and
/// cos(φ − δ) — φ the angle between the LED axis and the centre, δ the half-angle the hull's
/// bounding sphere subtends — or 1 when that cone contains the axis. A lane at or inside the
/// sphere (`dist ≤ r`) has a meaningless cosine: the caller bounds it by ∞ first.
#[inline(always)]
fn bound_lanes(c: &CopyChunk, pos: &Vec3, r: f64) -> BoundGeometry {
    let mut g = BoundGeometry::default();
    for l in 0..W {
        let (dx, dy, dz) = (pos.x - c.px[l], pos.y - c.py[l], pos.z - c.pz[l]);
        let dist = (0.0 + dx * dx + dy * dy + dz * dz).sqrt();
        let along = 0.0 + c.ax[l] * dx + c.ay[l] * dy + c.az[l] * dz;
        let cos_phi = (along / dist).clamp(-1.0, 1.0);
        let sin_delta = r / dist;
        let cos_delta = (1.0 - sin_delta * sin_delta).sqrt();
        let sin_phi = (1.0 - cos_phi * cos_phi).sqrt();
        let tilted = cos_phi * cos_delta + sin_phi * sin_delta;
        g.dist[l] = dist;
        g.cos_best[l] = if cos_phi >= cos_delta { 1.0 } else { tilted };
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bound's geometry as the scalar code computes it for one copy (nalgebra's norm and
    /// dot product): the reference every lane must match bit for bit.
    fn scalar(led: &ModemPose, pos: &Vec3, r: f64) -> (f64, f64) {
        let d = pos - led.position;
        let dist = d.norm();
        let cos_phi = (led.axis.dot(&d) / dist).clamp(-1.0, 1.0);
        let sin_delta = r / dist;
        let cos_delta = (1.0 - sin_delta * sin_delta).sqrt();
        let sin_phi = (1.0 - cos_phi * cos_phi).sqrt();
        let cos_best = if cos_phi >= cos_delta {
            1.0
        } else {
            cos_phi * cos_delta + sin_phi * sin_delta
        };
        (dist, cos_best)
    }

    /// Every lane's distance and best cosine are bit for bit the scalar ones, for frames of
    /// one to six copies (padded chunks, a second chunk) around receivers in front of, beside,
    /// behind and inside the cone of each LED (seen failing with the dot product summed in
    /// another order: the last bits differ).
    #[test]
    fn lanes_give_the_scalar_bound_geometry_bit_for_bit() {
        let mut checked = 0;
        let mut within = 0;
        for n in 1..=6usize {
            let copies: Vec<ModemPose> = (0..n)
                .map(|k| {
                    let a = k as f64 * 1.1 + n as f64 * 0.3;
                    ModemPose {
                        position: Vec3::new(0.12 * a.cos(), 0.08 * a.sin(), 0.01 * k as f64),
                        axis: Vec3::new(a.cos(), a.sin(), 0.1 * a.sin()).normalize(),
                    }
                })
                .collect();
            let mut lanes = CopyLanes::default();
            lanes.push_frame(&copies);
            assert_eq!(lanes.chunks().len(), n.div_ceil(W));
            for i in 0..300 {
                let t = i as f64 * 0.41;
                let rho = 0.05 + (i % 30) as f64 * 0.2;
                let pos = Vec3::new(rho * t.cos(), rho * t.sin(), 0.2 * (0.7 * t).sin());
                let r = 0.15;
                for (part, chunk) in copies.chunks(W).zip(lanes.chunks()) {
                    let g = bound_geometry(chunk, &pos, r);
                    for (l, c) in part.iter().enumerate() {
                        let (dist, cos_best) = scalar(c, &pos, r);
                        assert_eq!(
                            g.dist[l].to_bits(),
                            dist.to_bits(),
                            "n {n}, receiver {i}, copy {l}"
                        );
                        if dist > r {
                            assert_eq!(
                                g.cos_best[l].to_bits(),
                                cos_best.to_bits(),
                                "n {n}, receiver {i}, copy {l}"
                            );
                            within += usize::from(cos_best == 1.0);
                        }
                        checked += 1;
                    }
                }
            }
        }
        // Both branches of the best cosine are exercised.
        assert!(
            checked > 5000 && within > 30 && within < checked / 2,
            "{checked} {within}"
        );
    }
}
