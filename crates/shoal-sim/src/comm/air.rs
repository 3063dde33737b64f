//! The transmissions on record by position, for carrier sensing ([`Air`]): a compact copy of
//! each (times, sender, the sending modem's position: [`OnAir`]) in a uniform grid whose cells
//! are at least the sensing reach, each cell a linked list, so that a decision of the transmit
//! phase looks only at the cells around the deciding vehicle, and a frame that starts during
//! the phase joins its cell at once. The transmissions found are handed over in the order of
//! the medium's list, so that powers add up in one order whatever the grid.
//!
//! Within a step every pose stands still, so the power a transmission delivers to a vehicle's
//! modems does not change however often the vehicle listens (a back-off counts several slots
//! a step): [`Air::powers`] remembers it for the phase.

use super::grid::{cell_of, flat_index};
use super::medium::{Medium, Transmission};
use shoal_model::math::Vec3;
use std::cell::RefCell;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// Most modems of a vehicle whose received powers [`Air::powers`] remembers.
pub(super) const MODEMS_REMEMBERED: usize = 8;

/// A multiply-rotate hash for the small integer keys of the transmit phase's maps
/// (vehicle ids, times' bits): a few instructions where the standard hash takes a hundred.
#[derive(Default)]
pub(super) struct KeyHasher(u64);

/// A hash map with [`KeyHasher`].
pub(super) type FastMap<K, V> = HashMap<K, V, BuildHasherDefault<KeyHasher>>;

impl Hasher for KeyHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.write_u64(u64::from(*b));
        }
    }
    fn write_u64(&mut self, i: u64) {
        self.0 = (self.0.rotate_left(5) ^ i).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_u32(&mut self, i: u32) {
        self.write_u64(u64::from(i));
    }
    fn write_usize(&mut self, i: usize) {
        self.write_u64(i as u64);
    }
}

/// What carrier sensing reads of a transmission on record first.
#[derive(Clone, Copy, Debug)]
pub(super) struct OnAir {
    /// Start \[s\].
    pub(super) start: f64,
    /// End \[s\].
    pub(super) end: f64,
    /// The sending modem's position \[m\].
    pub(super) position: Vec3,
    /// Sending vehicle.
    pub(super) tx: u32,
    /// Index in the medium's list of transmissions.
    pub(super) index: u32,
}

/// No entry (end of a cell's list).
const NONE: u32 = u32::MAX;

/// The transmissions on record, by grid cell.
pub(super) struct Air {
    entries: Vec<OnAir>,
    /// Next entry in the same cell.
    next: Vec<u32>,
    /// First entry of each cell.
    head: Vec<u32>,
    origin: Vec3,
    cell: f64,
    dims: [usize; 3],
    /// Indices found by a query (reused).
    found: RefCell<Vec<u32>>,
    /// Powers at a vehicle's modems from a transmission, by (vehicle, entry) \[W\].
    powers: RefCell<FastMap<u64, [f64; MODEMS_REMEMBERED]>>,
}

impl Air {
    /// The transmissions of `m` on record, in cells at least `reach` \[m\] wide over the
    /// vehicles' positions (the senders of every frame of the phase).
    pub(super) fn new(m: &Medium, reach: f64) -> Self {
        let (mut lo, mut hi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
        for (p, _) in &m.poses {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        if lo.x > hi.x {
            (lo, hi) = (Vec3::zeros(), Vec3::zeros());
        }
        // At most 2^16 cells: wider cells for a spread-out swarm (a query only looks further).
        let span = hi - lo;
        let mut cell = reach.max(1e-3);
        let dims = loop {
            let d = span.map(|s| (s / cell).floor() as usize + 1);
            if d.x.saturating_mul(d.y).saturating_mul(d.z) <= 1 << 16 {
                break [d.x, d.y, d.z];
            }
            cell *= 2.0;
        };
        let mut air = Self {
            entries: Vec::with_capacity(m.txs.len()),
            next: Vec::with_capacity(m.txs.len()),
            head: vec![NONE; dims[0] * dims[1] * dims[2]],
            origin: lo,
            cell,
            dims,
            found: RefCell::new(Vec::new()),
            powers: RefCell::new(HashMap::default()),
        };
        for (i, x) in m.txs.iter().enumerate() {
            air.push(i, x);
        }
        air
    }

    /// The cell of `p`, clamped to the grid (a position outside it falls into a border cell,
    /// and a query still finds everything within a cell of it: [`cell_of`]).
    fn coord(&self, p: &Vec3) -> [usize; 3] {
        cell_of(p, &self.origin, self.cell, self.dims)
    }

    fn flat(&self, c: [usize; 3]) -> usize {
        flat_index(c, self.dims)
    }

    /// Adds transmission `x`, at `index` in the medium's list.
    pub(super) fn push(&mut self, index: usize, x: &Transmission) {
        let e = OnAir {
            start: x.start,
            end: x.end,
            position: x.pose.position,
            tx: x.tx,
            index: index as u32,
        };
        let k = self.flat(self.coord(&e.position));
        self.next.push(self.head[k]);
        self.head[k] = self.entries.len() as u32;
        self.entries.push(e);
    }

    /// Calls `f` with every transmission whose sending modem lies in the cells around `pos`
    /// (all within `reach` of it among them), in the order of the medium's list.
    pub(super) fn near(&self, pos: &Vec3, mut f: impl FnMut(&OnAir)) {
        let c = self.coord(pos);
        let mut found = self.found.borrow_mut();
        found.clear();
        let range = |c: usize, n: usize| c.saturating_sub(1)..(c + 2).min(n);
        for i in range(c[0], self.dims[0]) {
            for j in range(c[1], self.dims[1]) {
                for k in range(c[2], self.dims[2]) {
                    let mut e = self.head[self.flat([i, j, k])];
                    while e != NONE {
                        found.push(e);
                        e = self.next[e as usize];
                    }
                }
            }
        }
        // Entries were numbered in the order of the list.
        found.sort_unstable();
        for &e in found.iter() {
            f(&self.entries[e as usize]);
        }
    }

    /// The powers transmission `x` (its [`OnAir::index`]) delivers to the modems of vehicle
    /// `v` \[W\], as `compute` gives them the first time in this phase (vehicles with at most
    /// [`MODEMS_REMEMBERED`] modems).
    pub(super) fn powers(
        &self,
        v: u32,
        x: &OnAir,
        compute: impl FnOnce() -> [f64; MODEMS_REMEMBERED],
    ) -> [f64; MODEMS_REMEMBERED] {
        let key = (u64::from(v) << 32) | u64::from(x.index);
        if let Some(p) = self.powers.borrow().get(&key) {
            return *p;
        }
        let p = compute();
        self.powers.borrow_mut().insert(key, p);
        p
    }
}
