//! Idle slots counted down at once ([`Countdowns`]): a protocol that counts back-off slots
//! (CSMA/CA, p-persistent CSMA) would otherwise be asked at every slot boundary whether the
//! channel is still idle. Within a step nothing changes what a vehicle hears except a frame
//! that starts (every pose stands still, a frame heard below the threshold stays so, and the
//! frames that end only lower the power), so a vehicle that finds the channel idle, with
//! `left` idle boundaries to count from the next one on, is asked again only at the last of
//! them — unless a frame starts within its reach first: then it is asked at the first boundary
//! after that start (a frame is not heard at the instant it starts), with the boundaries
//! passed counted off. At the end of the step
//! every vehicle still counting is set where the slot-by-slot count would have left it (the
//! poses change with the next step). The boundaries are the slot-by-slot ones to the last bit:
//! each the one before plus a slot.
//!
//! The vehicles counting down are kept in lists per cell of the same grid as the transmissions
//! on record ([`super::air::Air`], cells at least the sensing reach), so that a frame that
//! starts looks only at the cells around its sender.

use super::air::FastMap;
use super::grid::{CellLists, Cells};
use shoal_model::math::Vec3;

/// A vehicle counting idle slots down.
#[derive(Clone, Copy, Debug)]
struct Countdown {
    vehicle: u32,
    /// The vehicle's position \[m\].
    position: Vec3,
    /// The first boundary it counts \[s\] (now, or the next one).
    from: f64,
    /// Slot \[s\].
    slot: f64,
    /// Boundaries to count from `from` (`from` included) before the one it is asked at again.
    left: u32,
    /// That boundary (`left` slots after `from`) \[s\].
    target: f64,
    /// The busy threshold the protocol listened with \[W\], and since when the channel was
    /// idle \[s\]: what it hears at `target` if nothing starts nearby before (`None` once
    /// something has: it listens again there).
    heard: Option<(f64, f64)>,
}

/// Where a vehicle counting down is to be asked again, earlier than it said.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Wake {
    /// The vehicle.
    pub(super) vehicle: u32,
    /// The boundary to ask at \[s\].
    pub(super) at: f64,
    /// The count still to go there (the protocol's `AccessState::counter`).
    pub(super) left: u32,
    /// The boundary it had said \[s\] (what its ports wait for).
    pub(super) target: f64,
}

/// The vehicles counting idle slots down in this step.
#[derive(Default)]
pub(super) struct Countdowns {
    /// Every countdown of the step by position, once one has begun.
    entries: Option<CellLists<Countdown>>,
    /// Each counting vehicle's current entry (older entries of a vehicle are passed over).
    live: FastMap<u32, u32>,
    /// The latest time a frame started \[s\], and where the frames that started then did \[m\].
    latest: (f64, Vec<Vec3>),
}

/// The `j`-th boundary from `from` in steps of `slot` (`from` itself the 0-th; each the one
/// before plus a slot, as the slot-by-slot count computes them), for the first `j` in
/// `0..=left` where `stop` holds; `None` if it holds for none.
fn first_boundary(
    from: f64,
    slot: f64,
    left: u32,
    stop: impl Fn(f64) -> bool,
) -> Option<(f64, u32)> {
    let mut t = from;
    for j in 0..=left {
        if stop(t) {
            return Some((t, j));
        }
        t += slot;
    }
    None
}

impl Countdowns {
    /// `vehicle` at `position` \[m\] found the channel idle at `now` \[s\], with `left` idle
    /// boundaries of `slot` \[s\] to count from the boundary `from` ≥ `now` on (`from`
    /// included; `from` = `now` if it is one): returns the boundary it is to be asked at again
    /// if no frame starts within `reach` \[m\] of it — `None` if one started at `now` itself
    /// (not heard yet, but at the next boundary: the vehicle is asked there as usual).
    /// `cells` gives the grid to keep it in (at least `reach` wide).
    pub(super) fn start(
        &mut self,
        (vehicle, position): (u32, &Vec3),
        (now, heard): (f64, (f64, f64)),
        (from, slot, left): (f64, f64, u32),
        (reach, cells): (f64, impl FnOnce() -> Cells),
    ) -> Option<f64> {
        if self.latest.0 == now
            && self
                .latest
                .1
                .iter()
                .any(|p| (p - position).norm_squared() <= reach * reach)
        {
            return None;
        }
        let target = (0..left).fold(from, |t, _| t + slot);
        let entries = self.entries.get_or_insert_with(|| CellLists::new(cells()));
        let e = entries.push(
            position,
            Countdown {
                vehicle,
                position: *position,
                from,
                slot,
                left,
                target,
                heard: Some(heard),
            },
        );
        self.live.insert(vehicle, e);
        Some(target)
    }

    /// `vehicle` is asked again at `t` \[s\]: if that is the boundary its countdown said, it no
    /// longer counts down (a countdown it started at `t` itself goes on), and what it heard
    /// when the countdown began is returned — what it hears now, since nothing started near
    /// it in between (the threshold \[W\] and since when the channel has been idle \[s\]).
    pub(super) fn end(&mut self, vehicle: u32, t: f64) -> Option<(f64, f64)> {
        let &e = self.live.get(&vehicle)?;
        let d = self.entries.as_ref()?.get(e);
        if d.target > t {
            return None;
        }
        self.live.remove(&vehicle);
        if d.target == t { d.heard } else { None }
    }

    /// A frame started at `t` \[s\] from `position` \[m\]: a vehicle within reach of it that
    /// finds the channel idle at `t` itself does not count down at once ([`Countdowns::start`]:
    /// it hears the frame only at its next boundary).
    pub(super) fn started(&mut self, position: &Vec3, t: f64) {
        if self.latest.0 != t {
            self.latest.0 = t;
            self.latest.1.clear();
        }
        self.latest.1.push(*position);
    }

    /// Frames started at `t` \[s\] from `positions` \[m\] (the copies of a vehicle's turn, each
    /// noted by [`Countdowns::started`]): the vehicles counting down within `reach` \[m\] of
    /// one of them that it `reaches` (copy, vehicle: one that receives no power from it hears
    /// nothing new, and counts on) whose last boundary is later than the first one after `t`
    /// are to be asked at that one instead (added to `woken`); they no longer count down.
    /// Those whose last boundary is that one will listen there again. The copies share one
    /// look at the cells around them (each cell once, however many copies are in it).
    pub(super) fn frames_started(
        &mut self,
        (positions, t): (&[Vec3], f64),
        reach: f64,
        mut reaches: impl FnMut(usize, u32) -> bool,
        woken: &mut Vec<Wake>,
    ) {
        let (Some(entries), live) = (&mut self.entries, &mut self.live) else {
            return;
        };
        if live.is_empty() {
            return;
        }
        let cells = entries.cells();
        for (i, p) in positions.iter().enumerate() {
            let c = cells.index(p);
            if positions[..i].iter().any(|q| cells.index(q) == c) {
                continue;
            }
            entries.each_around(p, |e, d| {
                // Within reach of a copy first (no lookup), then still counting.
                let near = |q: &Vec3| (d.position - q).norm_squared() <= reach * reach;
                if positions.iter().any(near)
                    && live.get(&d.vehicle) == Some(&e)
                    && let Some((at, j)) = first_boundary(d.from, d.slot, d.left, |b| b > t)
                    && positions
                        .iter()
                        .enumerate()
                        .any(|(k, q)| near(q) && reaches(k, d.vehicle))
                {
                    if j < d.left {
                        live.remove(&d.vehicle);
                        woken.push(Wake {
                            vehicle: d.vehicle,
                            at,
                            left: d.left - j,
                            target: d.target,
                        });
                    } else {
                        // Asked at its last boundary anyway, where it hears this frame.
                        d.heard = None;
                    }
                }
            });
        }
    }

    /// The step ends at `t_end` \[s\]: every vehicle still counting down is to be asked at its
    /// first boundary at or after `t_end` (added to `woken`, in the order of the vehicles).
    pub(super) fn step_ended(&mut self, t_end: f64, woken: &mut Vec<Wake>) {
        let first = woken.len();
        let Some(entries) = &self.entries else {
            return;
        };
        for (&vehicle, &e) in &self.live {
            let d = entries.get(e);
            let (at, j) = first_boundary(d.from, d.slot, d.left, |b| b >= t_end)
                .unwrap_or((d.target, d.left));
            woken.push(Wake {
                vehicle,
                at,
                left: d.left - j,
                target: d.target,
            });
        }
        woken[first..].sort_unstable_by_key(|w| w.vehicle);
        self.live.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    impl Countdowns {
        /// One frame started at `t` from `p`: [`Countdowns::started`], then
        /// [`Countdowns::frames_started`] with it alone.
        fn frame_started(
            &mut self,
            (p, t): (&Vec3, f64),
            reach: f64,
            mut reaches: impl FnMut(u32) -> bool,
            woken: &mut Vec<Wake>,
        ) {
            self.started(p, t);
            self.frames_started(
                (std::slice::from_ref(p), t),
                reach,
                |_, v| reaches(v),
                woken,
            );
        }
    }

    fn cells() -> Cells {
        Cells::over(Vec3::zeros(), Vec3::new(20.0, 20.0, 5.0), 3.0)
    }

    /// The boundary said is the slot-by-slot one to the last bit (each the one before plus a
    /// slot), not `from + left · slot`.
    #[test]
    fn the_last_boundary_is_the_slot_by_slot_one() {
        let mut c = Countdowns::default();
        let (from, slot) = (0.123_456_789, 0.001);
        let target = c
            .start(
                (7, &Vec3::zeros()),
                (from, (1e-9, 0.0)),
                (from, slot, 300),
                (2.5, cells),
            )
            .unwrap();
        let mut t = from;
        for _ in 0..300 {
            t += slot;
        }
        assert_eq!(target.to_bits(), t.to_bits());
        assert_ne!(
            target.to_bits(),
            (from + 300.0 * slot).to_bits(),
            "pick a case where the two differ"
        );
    }

    /// A frame that starts within reach wakes a counting vehicle at the first boundary after
    /// its start, with the boundaries passed counted off; a frame beyond reach, or one whose
    /// first boundary after is the last one anyway, wakes nobody; a vehicle woken once is not
    /// woken again.
    #[test]
    fn a_frame_within_reach_wakes_at_the_next_boundary() {
        let mut c = Countdowns::default();
        let p = Vec3::new(1.0, 1.0, 1.0);
        let target = c
            .start((3, &p), (1.0, (1e-9, 0.0)), (1.0, 0.01, 10), (2.5, cells))
            .unwrap();
        let mut woken = Vec::new();
        // Beyond reach: nothing.
        c.frame_started(
            (&Vec3::new(5.0, 1.0, 1.0), 1.023),
            2.5,
            |_| true,
            &mut woken,
        );
        assert!(woken.is_empty());
        // At 1.023 within reach: boundaries 1.00 … 1.02 passed (3 of 10), asked at 1.03 with 7.
        c.frame_started(
            (&Vec3::new(2.0, 1.0, 1.0), 1.023),
            2.5,
            |_| true,
            &mut woken,
        );
        assert_eq!(woken.len(), 1);
        let w = woken[0];
        assert_eq!(
            (w.vehicle, w.left, w.target.to_bits()),
            (3, 7, target.to_bits())
        );
        assert!((w.at - 1.03).abs() < 1e-12, "{}", w.at);
        // Woken: no longer counting.
        c.frame_started((&Vec3::new(2.0, 1.0, 1.0), 1.05), 2.5, |_| true, &mut woken);
        assert_eq!(woken.len(), 1);
        // A start on a boundary is not heard there: the next one is the boundary to ask at.
        let mut c = Countdowns::default();
        c.start((4, &p), (1.0, (1e-9, 0.0)), (1.0, 0.25, 4), (2.5, cells))
            .unwrap();
        let mut woken = Vec::new();
        c.frame_started((&p, 1.5), 2.5, |_| true, &mut woken);
        assert_eq!((woken[0].at, woken[0].left), (1.75, 1));
        // Counting from a later boundary: a frame before it wakes the vehicle there, with the
        // whole count still to go.
        let mut c = Countdowns::default();
        c.start((6, &p), (1.1, (1e-9, 0.0)), (1.25, 0.25, 4), (2.5, cells))
            .unwrap();
        let mut woken = Vec::new();
        c.frame_started((&p, 1.2), 2.5, |_| true, &mut woken);
        assert_eq!((woken[0].at, woken[0].left), (1.25, 4));
        // Whose first boundary after is the last: asked there anyway, not woken.
        let mut c = Countdowns::default();
        c.start((5, &p), (1.0, (1e-9, 0.0)), (1.0, 0.25, 4), (2.5, cells))
            .unwrap();
        let mut woken = Vec::new();
        c.frame_started((&p, 1.8), 2.5, |_| true, &mut woken);
        assert!(woken.is_empty());
    }

    /// A frame within reach that reaches none of a counting vehicle's modems changes nothing
    /// it hears: it neither wakes the vehicle nor makes it listen again at its last boundary.
    #[test]
    fn a_frame_that_reaches_no_modem_wakes_nobody() {
        let mut c = Countdowns::default();
        let p = Vec3::new(1.0, 1.0, 1.0);
        let target = c
            .start((3, &p), (1.0, (1e-9, 0.5)), (1.0, 0.25, 4), (2.5, cells))
            .unwrap();
        let mut woken = Vec::new();
        let mut asked = Vec::new();
        c.frame_started(
            (&p, 1.1),
            2.5,
            |v| {
                asked.push(v);
                false
            },
            &mut woken,
        );
        assert_eq!(asked, [3], "the vehicle within reach is asked about");
        assert!(woken.is_empty());
        // Just before the last boundary, a frame that does not reach it leaves what it heard.
        c.frame_started((&p, 1.7), 2.5, |_| false, &mut woken);
        assert_eq!(c.end(3, target), Some((1e-9, 0.5)));
        // One that reaches it wakes it.
        c.start((4, &p), (2.0, (1e-9, 0.5)), (2.0, 0.25, 4), (2.5, cells))
            .unwrap();
        c.frame_started((&p, 2.1), 2.5, |_| true, &mut woken);
        assert_eq!(woken.len(), 1);
    }

    /// The copies of a turn wake, together, every counting vehicle one of them reaches (and
    /// only once): also one that the first copy does not reach, and one in a cell next to a
    /// later copy's but not the first's.
    #[test]
    fn the_copies_of_a_turn_wake_whom_any_of_them_reaches() {
        let mut c = Countdowns::default();
        let start = |c: &mut Countdowns, v: u32, p: Vec3| {
            c.start((v, &p), (1.0, (1e-9, 0.0)), (1.0, 0.25, 4), (3.0, cells))
                .unwrap()
        };
        // Cells 3 m wide: the copies at x = 0.5 and 3.5 lie in cells 0 and 1; vehicle 8 at
        // x = 6.4 in cell 2, next to the second copy's cell only, 2.9 m from that copy.
        start(&mut c, 7, Vec3::new(1.0, 1.0, 1.0));
        start(&mut c, 8, Vec3::new(6.4, 1.0, 1.0));
        start(&mut c, 9, Vec3::new(2.0, 1.0, 1.0));
        let copies = [Vec3::new(0.5, 1.0, 1.0), Vec3::new(3.5, 1.0, 1.0)];
        for p in &copies {
            c.started(p, 1.1);
        }
        let mut woken = Vec::new();
        // Vehicle 7 hears only the second copy, 9 neither.
        c.frames_started(
            (&copies, 1.1),
            3.0,
            |k, v| v != 9 && (v != 7 || k == 1),
            &mut woken,
        );
        // Boundary 1.0 passed: asked at 1.25 with 3 of 4 to go.
        let mut got: Vec<_> = woken.iter().map(|w| (w.vehicle, w.left)).collect();
        got.sort_unstable();
        assert_eq!(got, [(7, 3), (8, 3)]);
    }

    /// A frame that started at the very boundary a vehicle finds the channel idle at is not
    /// heard there but at the next one: that vehicle does not count down at once. A frame
    /// that started there beyond its reach, or earlier, does not stop it.
    #[test]
    fn a_frame_starting_at_the_boundary_itself_stops_the_count() {
        let mut c = Countdowns::default();
        let p = Vec3::new(1.0, 1.0, 1.0);
        let mut woken = Vec::new();
        c.frame_started((&Vec3::new(9.0, 1.0, 1.0), 2.0), 2.5, |_| true, &mut woken);
        assert!(
            c.start((1, &p), (2.0, (1e-9, 0.0)), (2.0, 0.01, 5), (2.5, cells))
                .is_some()
        );
        c.frame_started((&Vec3::new(2.0, 1.0, 1.0), 2.0), 2.5, |_| true, &mut woken);
        assert_eq!(woken.len(), 1, "the first is woken at 2.01");
        assert_eq!(
            c.start((2, &p), (2.0, (1e-9, 0.0)), (2.0, 0.01, 5), (2.5, cells)),
            None
        );
        c.frame_started(
            (&Vec3::new(2.0, 1.0, 1.0), 2.005),
            2.5,
            |_| true,
            &mut woken,
        );
        assert!(
            c.start((3, &p), (2.01, (1e-9, 0.0)), (2.01, 0.01, 5), (2.5, cells))
                .is_some()
        );
    }

    /// A vehicle whose count runs out undisturbed is told, at its last boundary, what it heard
    /// when the count began; asked earlier, it goes on counting; woken, it is told nothing.
    #[test]
    fn an_undisturbed_count_hears_at_its_end_what_it_heard_at_its_start() {
        let mut c = Countdowns::default();
        let p = Vec3::zeros();
        let target = c
            .start((1, &p), (1.0, (2e-9, 0.7)), (1.0, 0.25, 4), (2.5, cells))
            .unwrap();
        assert_eq!(c.end(1, 1.5), None);
        assert_eq!(c.end(1, target), Some((2e-9, 0.7)));
        assert_eq!(c.end(1, target), None);
        c.start((2, &p), (1.0, (2e-9, 0.7)), (1.0, 0.25, 4), (2.5, cells))
            .unwrap();
        let mut woken = Vec::new();
        c.frame_started((&p, 1.1), 2.5, |_| true, &mut woken);
        assert_eq!(c.end(2, woken[0].at), None);
        // A frame just before the last boundary: not woken, but it listens there.
        let target = c
            .start((3, &p), (1.0, (2e-9, 0.7)), (1.0, 0.25, 4), (2.5, cells))
            .unwrap();
        c.frame_started((&p, 1.9), 2.5, |_| true, &mut woken);
        assert_eq!(woken.len(), 1);
        assert_eq!(c.end(3, target), None);
    }

    /// At the end of a step each vehicle still counting is set at its first boundary at or
    /// after the step's end, with the boundaries before it counted off.
    #[test]
    fn the_step_end_sets_each_count_where_the_slots_leave_it() {
        let mut c = Countdowns::default();
        c.start(
            (9, &Vec3::zeros()),
            (0.0, (1e-9, 0.0)),
            (0.0, 0.25, 8),
            (2.5, cells),
        )
        .unwrap();
        c.start(
            (2, &Vec3::zeros()),
            (0.5, (1e-9, 0.0)),
            (0.5, 0.25, 2),
            (2.5, cells),
        )
        .unwrap();
        let mut woken = Vec::new();
        c.step_ended(1.0, &mut woken);
        let got: Vec<_> = woken.iter().map(|w| (w.vehicle, w.at, w.left)).collect();
        assert_eq!(got, [(2, 1.0, 0), (9, 1.0, 4)]);
        // Nobody is left counting.
        let mut again = Vec::new();
        c.frame_started((&Vec3::zeros(), 0.6), 2.5, |_| true, &mut again);
        assert!(again.is_empty());
    }
}
