//! The transmissions on record by position, for carrier sensing ([`Air`]): a compact copy of
//! each (times, sender, the sending modem's position: [`OnAir`]) in a uniform grid whose cells
//! are at least the sensing reach, each cell a linked list, so that a decision of the transmit
//! phase looks only at the cells around the deciding vehicle, and a frame that starts during
//! the phase joins its cell at once. The transmissions are found in no particular order: the
//! callers put the few that add to a sum in the order of the medium's list
//! ([`Air::in_list_order`]), so that powers add up in one order whatever the grid.
//!
//! Within a step every pose stands still: [`Air::vehicles_clear`] remembers for the phase
//! whether other hulls block the line between two vehicles (asked by every copy of a frame),
//! and [`Air::with_modem_poses`] where a listening vehicle's modems are. The powers a frame
//! delivers are not remembered: the same vehicle seldom listens twice to the same frame in a
//! step (2 % of the asks on the 10k CSMA/CA swarm), and keeping them cost more than it saved.

use super::grid::{CellLists, Cells};
use super::medium::{Medium, Transmission};
use shoal_model::math::Vec3;
use shoal_model::optics::ModemPose;
use std::cell::RefCell;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

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

impl OnAir {
    /// Of transmission `x`, at `index` in the medium's list.
    fn of(index: usize, x: &Transmission) -> Self {
        Self {
            start: x.start,
            end: x.end,
            position: x.pose.position,
            tx: x.tx,
            index: index as u32,
        }
    }
}

/// What a listen (`sensing.rs`) keeps while it looks, reused from one listen to the next.
#[derive(Default)]
pub(super) struct Scratch {
    /// The frames that ended near the listening vehicle, put aside.
    pub(super) ended: Vec<OnAir>,
    /// The frames on the air within its reach.
    pub(super) on: Vec<OnAir>,
    /// The powers of one of them at its modems \[W\].
    pub(super) powers: Vec<f64>,
}

/// The transmissions on record in the transmit phase: the medium's list, then the
/// transmissions started in the phase so far (kept by the walk until it ends), one index
/// across both ([`OnAir::index`]).
#[derive(Clone, Copy)]
pub(super) struct OnRecord<'a> {
    /// The medium's list.
    pub(super) medium: &'a [Transmission],
    /// Started in this phase.
    pub(super) started: &'a [Transmission],
}

impl<'a> OnRecord<'a> {
    /// The transmission at `index`.
    pub(super) fn get(&self, index: u32) -> &'a Transmission {
        let i = index as usize;
        match self.medium.get(i) {
            Some(x) => x,
            None => &self.started[i - self.medium.len()],
        }
    }

    /// All of them, in list order.
    fn iter(&self) -> impl Iterator<Item = &'a Transmission> {
        self.medium.iter().chain(self.started)
    }
}

/// The transmissions on record, by grid cell.
pub(super) struct Air {
    entries: CellLists<OnAir>,
    /// The transmissions a query keeps, put in list order (reused).
    kept: RefCell<Vec<OnAir>>,
    /// What a listen keeps while it looks (reused; `sensing.rs`).
    pub(super) listening: RefCell<Scratch>,
    /// Whether other hulls leave the line between two vehicles clear, by (sender, receiver).
    clear: RefCell<FastMap<u64, bool>>,
    /// Where the poses of a listening vehicle's modems start in `modem_poses`, by vehicle.
    poses_at: RefCell<FastMap<u32, u32>>,
    /// The poses of the listening vehicles' modems, each vehicle's in modem order.
    modem_poses: RefCell<Vec<ModemPose>>,
}

/// The storage of an [`Air`], kept by the transmit phase from one step to the next (its
/// lists and maps keep their capacity).
#[derive(Default)]
pub struct AirStore {
    entries: Option<CellLists<OnAir>>,
    kept: Vec<OnAir>,
    listening: Scratch,
    clear: FastMap<u64, bool>,
    poses_at: FastMap<u32, u32>,
    modem_poses: Vec<ModemPose>,
}

impl Air {
    /// The transmissions on record `rec`, in cells at least `reach` \[m\] wide over the
    /// vehicles' positions in `m` (the senders of every frame of the phase), in `store`.
    pub(super) fn new(m: &Medium, rec: OnRecord<'_>, reach: f64, store: AirStore) -> Self {
        // The vehicles' box at the grid's last rebuild (they have moved a little since).
        let (lo, hi) = m.grid.bounds();
        let cells = Cells::over(lo, hi, reach);
        let AirStore {
            entries,
            mut kept,
            listening,
            mut clear,
            mut poses_at,
            mut modem_poses,
        } = store;
        let mut entries = entries.unwrap_or_else(|| CellLists::new(cells));
        entries.reset(cells);
        for (i, x) in rec.iter().enumerate() {
            let a = OnAir::of(i, x);
            entries.push(&a.position, a);
        }
        kept.clear();
        clear.clear();
        poses_at.clear();
        modem_poses.clear();
        Self {
            entries,
            kept: RefCell::new(kept),
            listening: RefCell::new(listening),
            clear: RefCell::new(clear),
            poses_at: RefCell::new(poses_at),
            modem_poses: RefCell::new(modem_poses),
        }
    }

    /// Its storage, for the next phase.
    pub(super) fn store(self) -> AirStore {
        AirStore {
            entries: Some(self.entries),
            kept: self.kept.into_inner(),
            listening: self.listening.into_inner(),
            clear: self.clear.into_inner(),
            poses_at: self.poses_at.into_inner(),
            modem_poses: self.modem_poses.into_inner(),
        }
    }

    /// Its cells (at least the sensing reach wide).
    pub(super) fn cells(&self) -> Cells {
        self.entries.cells()
    }

    /// Adds transmission `x`, started now, at `index` in the medium's list; returns what
    /// it keeps of it.
    pub(super) fn push(&mut self, index: usize, x: &Transmission) -> OnAir {
        let e = OnAir::of(index, x);
        self.entries.push(&e.position, e);
        e
    }

    /// Calls `f` with every transmission whose sending modem lies in the cells around `pos`
    /// (all within the reach of it among them), in no particular order.
    pub(super) fn each_near(&self, pos: &Vec3, f: impl FnMut(&OnAir)) {
        self.entries.each_near(pos, f);
    }

    /// Calls `keep` with every transmission whose sending modem lies in the cells around `pos`
    /// (all within the reach of it among them), in no particular order, then `f` with those
    /// it kept (returned `true` for) in the order of the medium's list — the order in which
    /// powers are added up.
    pub(super) fn in_list_order(
        &self,
        pos: &Vec3,
        mut keep: impl FnMut(&OnAir) -> bool,
        mut f: impl FnMut(&OnAir),
    ) {
        let mut kept = self.kept.borrow_mut();
        kept.clear();
        self.entries.each_near(pos, |a| {
            if keep(a) {
                kept.push(*a);
            }
        });
        kept.sort_unstable_by_key(|a| a.index);
        for a in kept.iter() {
            f(a);
        }
    }

    /// Calls `f` with the poses of vehicle `v`'s modems in `m`, in modem order (worked out
    /// once in the phase: the poses stand still within a step).
    pub(super) fn with_modem_poses<R>(
        &self,
        m: &Medium,
        v: u32,
        f: impl FnOnce(&[ModemPose]) -> R,
    ) -> R {
        let modems = &m.kinds[v as usize].params.modems;
        let start = *self.poses_at.borrow_mut().entry(v).or_insert_with(|| {
            let mut arena = self.modem_poses.borrow_mut();
            let start = arena.len() as u32;
            let (pos, att) = &m.poses[v as usize];
            arena.extend(modems.iter().map(|p| ModemPose::of(p, pos, att)));
            start
        }) as usize;
        f(&self.modem_poses.borrow()[start..start + modems.len()])
    }

    /// [`Medium::vehicles_clear`] of `from` and `to` in `m`, remembered for the phase (the
    /// copies of a frame and the modems of a receiver ask it of the same two vehicles).
    pub(super) fn vehicles_clear(&self, m: &Medium, from: u32, to: u32) -> bool {
        let key = (u64::from(from) << 32) | u64::from(to);
        if let Some(&c) = self.clear.borrow().get(&key) {
            return c;
        }
        let c = m.vehicles_clear(from, to);
        self.clear.borrow_mut().insert(key, c);
        c
    }
}
