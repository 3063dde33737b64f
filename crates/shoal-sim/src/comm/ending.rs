//! The frames ending in a step as the delivery phase sees them ([`Ended`]): their copies
//! grouped into logical frames, each frame's possible interferers, and the lists by vehicle
//! ([`ByVehicle`]) of the frames each receiver may hear and of each vehicle's own
//! transmissions. Everything lives in a few flat buffers, so a step allocates a handful of
//! vectors however many frames end in it.

use super::copy_lanes::CopyLanes;
use super::grid::Grid;
use super::lanes::W;
use super::medium::{Logical, Medium, Transmission};
use shoal_model::math::Vec3;

/// Values grouped by vehicle id (compressed rows), each vehicle's values in the order they
/// were given (a stable counting sort).
pub(super) struct ByVehicle<T = u32> {
    /// Vehicle `v`'s values are `values[start[v]..start[v + 1]]`.
    start: Vec<u32>,
    values: Vec<T>,
}

impl<T: Copy> ByVehicle<T> {
    /// Groups the `(vehicle, value)` pairs of `pairs` (vehicle ids below `n`).
    pub(super) fn new<I>(n: usize, pairs: I) -> Self
    where
        I: Iterator<Item = (u32, T)> + Clone,
    {
        let mut by = Self {
            start: Vec::new(),
            values: Vec::new(),
        };
        by.regroup(n, pairs);
        by
    }

    /// [`ByVehicle::new`] into this one's buffers (no allocation once they are large enough).
    pub(super) fn regroup<I>(&mut self, n: usize, pairs: I)
    where
        I: Iterator<Item = (u32, T)> + Clone,
    {
        let start = &mut self.start;
        start.clear();
        start.resize(n + 1, 0);
        for (v, _) in pairs.clone() {
            start[v as usize + 1] += 1;
        }
        for k in 0..n {
            start[k + 1] += start[k];
        }
        self.values.clear();
        let Some((_, filler)) = pairs.clone().next() else {
            return;
        };
        self.values.resize(start[n] as usize, filler);
        // Each vehicle's next free place, kept in `start[v]` (which ends up as `start[v + 1]`
        // was) and restored by a shift afterwards.
        for (v, x) in pairs {
            let at = &mut start[v as usize];
            self.values[*at as usize] = x;
            *at += 1;
        }
        start.copy_within(0..n, 1);
        start[0] = 0;
    }

    /// How many vehicles have values.
    pub(super) fn vehicles(&self) -> usize {
        self.start.windows(2).filter(|w| w[1] > w[0]).count()
    }

    /// The values of vehicle `v`, in the order given.
    pub(super) fn of(&self, v: u32) -> &[T] {
        &self.values[self.start[v as usize] as usize..self.start[v as usize + 1] as usize]
    }
}

/// The frames that ended in a step, in flat buffers: the copies of every logical frame and
/// its possible interferers (see [`Ended::frames`]).
pub(super) struct Ended<'a> {
    /// The copies of every logical frame, frame after frame, each frame's in (end, id) order.
    copies: Vec<&'a Transmission>,
    /// Frame `i`'s copies end at `copies[copies_end[i]]` (exclusive).
    copies_end: Vec<u32>,
    /// Every frame's possible interferers, frame after frame, each frame's in id order.
    overlap: Vec<&'a Transmission>,
    /// Frame `i`'s interferers end at `overlap[overlap_end[i]]` (exclusive).
    overlap_end: Vec<u32>,
    /// Every frame's dead power (see [`Logical::p_dead`]) \[W\].
    p_dead: Vec<f64>,
    /// Every frame's copies in lanes, frame after frame (⌈copies / W⌉ chunks each).
    lanes: CopyLanes,
}

impl<'a> Ended<'a> {
    /// The transmissions of `m` ending in `(t0, t_end]` \[s\], grouped into logical frames in
    /// (end, id) order of their first copy, with their possible interferers.
    pub(super) fn gather(m: &'a Medium, t0: f64, t_end: f64) -> Self {
        let mut ended: Vec<&Transmission> = m
            .txs
            .iter()
            .filter(|x| x.end > t0 && x.end <= t_end)
            .collect();
        ended.sort_by(|a, b| a.end.total_cmp(&b.end).then(a.id.cmp(&b.id)));
        // Copies of one logical frame share sender, sequence number and start: runs of equal
        // keys, each run in (end, id) order, the runs in order of their first copy.
        let key = |i: u32| {
            let t = ended[i as usize];
            (t.tx, t.seq, t.start.to_bits())
        };
        let mut order: Vec<u32> = (0..ended.len() as u32).collect();
        order.sort_unstable_by_key(|&i| (key(i), i));
        let mut runs: Vec<&[u32]> = order.chunk_by(|&i, &j| key(i) == key(j)).collect();
        runs.sort_unstable_by_key(|r| r[0]);
        let copies: Vec<&Transmission> = runs
            .iter()
            .flat_map(|r| r.iter().map(|&i| ended[i as usize]))
            .collect();
        let copies_end = runs
            .iter()
            .scan(0u32, |end, r| {
                *end += r.len() as u32;
                Some(*end)
            })
            .collect();
        let mut lanes = CopyLanes::default();
        let mut from = 0;
        for r in &runs {
            lanes.push_frame(copies[from..from + r.len()].iter().map(|c| &c.pose));
            from += r.len();
        }
        let mut e = Self {
            copies,
            copies_end,
            overlap: Vec::new(),
            overlap_end: Vec::with_capacity(runs.len()),
            p_dead: Vec::with_capacity(runs.len()),
            lanes,
        };
        e.find_interferers(m);
        e
    }

    /// Fills the possible interferers of every frame: overlapping it in time, and close
    /// enough to the sender to reach a receiver that could hear the sender (within
    /// 2 (r_cut + hull radius)), found through a grid of the transmissions' positions; and
    /// every frame's dead power.
    fn find_interferers(&mut self, m: &'a Medium) {
        let near = 2.0 * (m.r_cut + m.max_hull_radius);
        // Only what was on the air after the earliest start of these frames can overlap one.
        let earliest = self
            .copies
            .iter()
            .map(|c| c.start)
            .fold(f64::INFINITY, f64::min);
        let live: Vec<&Transmission> = m.txs.iter().filter(|x| x.end > earliest).collect();
        let tx_points: Vec<Vec3> = live.iter().map(|x| x.pose.position).collect();
        let mut tx_grid = Grid::default();
        tx_grid.rebuild(near / 2.0, &tx_points);
        let mut from = 0;
        for &end in &self.copies_end {
            let f = self.copies[from as usize];
            from = end;
            let p = m.poses[f.tx as usize].0;
            let first = self.overlap.len();
            tx_grid.each_in_box(&(p - Vec3::repeat(near)), &(p + Vec3::repeat(near)), |k| {
                let x = live[k as usize];
                if x.start < f.end
                    && x.end > f.start
                    && !(x.tx == f.tx && x.seq == f.seq)
                    && (x.pose.position - p).norm_squared() <= near * near
                {
                    self.overlap.push(x);
                }
                true
            });
            // Grid order is spatial; keep the medium's order so results do not depend on it.
            self.overlap[first..].sort_unstable_by_key(|x| x.id);
            self.overlap_end.push(self.overlap.len() as u32);
            self.p_dead.push(m.dead_power(f.bits));
        }
    }

    /// The logical frames, in (end, id) order of their first copy.
    pub(super) fn frames(&self) -> Vec<Logical<'_>> {
        let (mut c0, mut o0, mut k0) = (0, 0, 0);
        (0..self.copies_end.len())
            .map(|i| {
                let (c1, o1) = (self.copies_end[i] as usize, self.overlap_end[i] as usize);
                let k1 = k0 + (c1 - c0).div_ceil(W);
                let l = Logical {
                    copies: &self.copies[c0..c1],
                    lanes: &self.lanes.chunks()[k0..k1],
                    overlap: &self.overlap[o0..o1],
                    p_dead: self.p_dead[i],
                };
                (c0, o0, k0) = (c1, o1, k1);
                l
            })
            .collect()
    }
}

/// The frames each vehicle may hear: those whose sender is within the cut-off range (plus a
/// hull), by receiver, each receiver's in frame order.
pub(super) fn candidates(m: &Medium, frames: &[Logical<'_>]) -> ByVehicle {
    let reach = m.r_cut + m.max_hull_radius;
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for (i, l) in frames.iter().enumerate() {
        let f = l.first();
        let p = m.poses[f.tx as usize].0;
        m.each_near(
            &(p - Vec3::repeat(reach)),
            &(p + Vec3::repeat(reach)),
            |id| {
                if id != f.tx && (m.poses[id as usize].0 - p).norm_squared() <= reach * reach {
                    pairs.push((id, i as u32));
                }
                true
            },
        );
    }
    ByVehicle::new(m.poses.len(), pairs.iter().copied())
}

/// The medium's transmissions (indices into [`Medium::txs`]) by sender, for the half-duplex
/// test: everything that can overlap a frame ending now is still in `txs`.
pub(super) fn own_transmissions(m: &Medium) -> ByVehicle {
    ByVehicle::new(
        m.poses.len(),
        m.txs.iter().enumerate().map(|(k, x)| (x.tx, k as u32)),
    )
}
