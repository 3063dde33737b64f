//! One receiver's modems in lanes ([`ModemLanes`]): their poses and link-budget constants as
//! structure of arrays, so that the received power of a transmission at every modem
//! ([`ModemLanes::powers`]) is computed with the geometry of all modems at once — the
//! differences, dot products, root and divisions of four modems per instruction with AVX, two
//! without — and the link budget itself only at the modems the LED reaches.
//!
//! Every lane does the operations of [`Medium::power_between`] in its order (the dot products
//! summed from zero in x, y, z order as nalgebra sums them, the root and divisions as IEEE
//! operations in any vector width), and the budget is [`received_power`] itself, so each power
//! is bit-identical to `power_between`'s.

use super::lanes::{Lane, PoseLanes, W, avx_dispatch};
use super::medium::{Medium, Transmission, received_power};
use shoal_model::math::{Quat, Vec3};
use shoal_model::optics::{LinkGeometry, ModemConsts, ModemParams, ModemPose};

/// The geometry of one chunk of modems: positions, axes and the cosines of their fields of
/// view; padded lanes have a field of view no cosine reaches (∞).
#[derive(Clone, Copy, Debug, Default)]
struct Chunk {
    pose: PoseLanes,
    cos_fov: Lane,
}

/// What the budget needs of one lane: the distance \[m\] and the two cosines, and whether the
/// LED reaches the modem at all.
#[derive(Clone, Copy, Debug, Default)]
struct Geometry {
    dist: Lane,
    cos_tx: Lane,
    cos_rx: Lane,
    reach: [bool; W],
}

/// A receiver's modems, as lanes.
#[derive(Debug, Default)]
pub(super) struct ModemLanes {
    chunks: Vec<Chunk>,
    /// The poses, modem by modem.
    pub(super) poses: Vec<ModemPose>,
}

impl ModemLanes {
    /// Whether the lanes hold no receiver's modems (not filled since [`ModemLanes::clear`]).
    pub(super) fn is_empty(&self) -> bool {
        self.poses.is_empty()
    }

    /// Forgets the receiver.
    pub(super) fn clear(&mut self) {
        self.chunks.clear();
        self.poses.clear();
    }

    /// The modems `params` (constants `consts`) of a hull at `pos` \[m\] with attitude `att`.
    pub(super) fn fill(
        &mut self,
        params: &[ModemParams],
        consts: &[ModemConsts],
        pos: &Vec3,
        att: &Quat,
    ) {
        self.clear();
        self.poses
            .extend(params.iter().map(|p| ModemPose::of(p, pos, att)));
        for (poses, consts) in self.poses.chunks(W).zip(consts.chunks(W)) {
            let mut c = Chunk {
                cos_fov: [f64::INFINITY; W],
                ..Chunk::default()
            };
            for (l, (p, k)) in poses.iter().zip(consts).enumerate() {
                (c.pose.px[l], c.pose.py[l], c.pose.pz[l]) =
                    (p.position.x, p.position.y, p.position.z);
                (c.pose.ax[l], c.pose.ay[l], c.pose.az[l]) = (p.axis.x, p.axis.y, p.axis.z);
                c.cos_fov[l] = k.cos_fov;
            }
            self.chunks.push(c);
        }
    }

    /// The optical power \[W\] transmission `x` delivers to each modem (constants `consts`, the
    /// receiver's), into `out` (one per modem): [`Medium::power_between`] of each, with no
    /// occlusion test.
    pub(super) fn powers(
        &self,
        m: &Medium,
        x: &Transmission,
        consts: &[ModemConsts],
        out: &mut [f64],
    ) {
        let tx = &m.consts[x.tx as usize][x.modem];
        let r_cut2 = m.r_cut * m.r_cut;
        for ((c, out), consts) in self
            .chunks
            .iter()
            .zip(out.chunks_mut(W))
            .zip(consts.chunks(W))
        {
            let g = geometry(c, &x.pose, r_cut2);
            for (l, (o, rx)) in out.iter_mut().zip(consts).enumerate() {
                *o = if g.reach[l] {
                    let g = LinkGeometry {
                        distance: g.dist[l],
                        cos_tx: g.cos_tx[l],
                        cos_rx: g.cos_rx[l],
                    };
                    received_power(tx, rx, &g, m.attenuation)
                } else {
                    0.0
                };
            }
        }
    }
}

avx_dispatch!(
    /// The geometry of the LED at `led` and the modems of chunk `c`, with the widest vectors
    /// this CPU has (the same operations in every width, so the same bits).
    fn geometry(c: &Chunk, led: &ModemPose, r_cut2: f64) -> Geometry => geometry_lanes
);

/// The lanes of [`geometry`]: for each modem, the steps of [`Medium::power_between`] up to the
/// budget — behind the LED, beyond the cut-off range or outside the field of view, no reach.
#[inline(always)]
fn geometry_lanes(c: &Chunk, led: &ModemPose, r_cut2: f64) -> Geometry {
    let (o, a) = (&led.position, &led.axis);
    let mut g = Geometry::default();
    for l in 0..W {
        let (dx, dy, dz) = (c.pose.px[l] - o.x, c.pose.py[l] - o.y, c.pose.pz[l] - o.z);
        // As nalgebra's dot products and norms of 3-vectors: summed from zero, x, y, z.
        let along = 0.0 + a.x * dx + a.y * dy + a.z * dz;
        let d2 = 0.0 + dx * dx + dy * dy + dz * dz;
        let facing = 0.0 + c.pose.ax[l] * dx + c.pose.ay[l] * dy + c.pose.az[l] * dz;
        let dist = d2.sqrt();
        let cos_rx = -facing / dist;
        g.dist[l] = dist;
        g.cos_tx[l] = along / dist;
        g.cos_rx[l] = cos_rx;
        // The tests `power_between` returns 0 on, so that a NaN reaches the budget there as
        // here.
        let unreached = along <= 0.0 || d2 > r_cut2 || d2 <= 0.0 || cos_rx < c.cos_fov[l];
        g.reach[l] = !unreached;
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;
    use shoal_model::presets;
    use shoal_model::vehicle::VehicleModel;
    use std::sync::Arc;

    /// Every lane's power is bit for bit `power_between`'s, for LEDs all around a receiver
    /// with five modems (a padded second chunk): in front, behind, beyond the range, off axis,
    /// at the receiver itself (seen failing with the dot products summed in another order:
    /// the last bits differ).
    #[test]
    fn lanes_give_power_between_bit_for_bit() {
        let mut params = presets::uauv2();
        let ring = params.modems[0].clone();
        params.modems = (0..5)
            .map(|i| {
                let mut m = ring.clone();
                let a = i as f64 * 1.3;
                m.position = Vec3::new(0.1 * a.cos(), 0.07 * a.sin(), 0.01 * i as f64);
                m.direction = nalgebra::Unit::new_normalize(Vec3::new(a.cos(), a.sin(), 0.2));
                m
            })
            .collect();
        let kind = Arc::new(VehicleModel::new(params, 1000.0));
        let m = Medium::in_the_dark(vec![kind.clone(); 2]);
        let consts = m.consts[1].clone();
        let (pos, att) = (
            Vec3::new(1.0, 2.0, 1.5),
            Quat::from_euler_angles(0.1, -0.2, 0.7),
        );
        let mut lanes = ModemLanes::default();
        lanes.fill(&kind.params.modems, &consts, &pos, &att);
        let mut out = vec![0.0; 5];
        let mut reached = 0;
        for i in 0..400 {
            let t = i as f64 * 0.37;
            let r = 0.05 + (i % 40) as f64 * 0.15;
            let pose = ModemPose {
                position: pos + Vec3::new(r * t.cos(), r * t.sin(), 0.3 * (0.5 * t).sin()),
                axis: Vec3::new((t + 2.0).cos(), (t + 2.0).sin(), 0.1 * t.cos()).normalize(),
            };
            let x = Transmission::sent_from(i, i as usize % 5, pose);
            lanes.powers(&m, &x, &consts, &mut out);
            for k in 0..5 {
                let want = m.power_between(&x, &lanes.poses[k], &consts[k]);
                assert_eq!(
                    out[k].to_bits(),
                    want.to_bits(),
                    "transmission {i}, modem {k}"
                );
                reached += usize::from(want > 0.0);
            }
        }
        // Both outcomes are exercised.
        assert!(reached > 100 && reached < 1800, "{reached}");
    }
}
