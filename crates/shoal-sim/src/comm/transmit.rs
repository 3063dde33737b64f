//! The transmit phase's walk through a step ([`Walk`]): the vehicles' turns in time order —
//! a vehicle's turn at `t` handles each of its ports whose head-of-queue frame is due then
//! (`max(ready, busy_until, step start)`), in modem order: the medium access decides
//! ([`super::mac`]), and a frame that is sent starts its transmission and wakes the vehicles
//! counting back-off slots near it ([`Countdowns`]). One event per vehicle, not per port:
//! the copies of a frame on a ring of modems decide once and go out together. Ties in time go
//! by vehicle id, so the walk's order never depends on threads.

use super::air::{Air, AirStore, FastMap, OnAir, OnRecord};
use super::countdown::{Countdowns, Wake};
use super::frames::{CommRng, Kind, Modems};
use super::grid::Cells;
use super::mac::{Ctx, Decision, Link};
use super::medium::{Medium, Transmission};
use super::sensing::{idle_since, reaches, sensed_power};
use super::started::{Started, led_use};
use super::stats::CommStats;
use rand::RngExt;
use shoal_model::math::Vec3;
use shoal_model::optics::ModemPose;
use std::cell::{Cell, OnceCell};
use std::collections::BinaryHeap;

/// A vehicle's turn.
#[derive(PartialEq)]
struct Turn {
    /// When \[s\].
    t: f64,
    vehicle: u32,
    /// How often the vehicle's wait had been cut short when the turn was made: a turn made
    /// before its latest wake-up ([`Countdowns`]) is stale.
    epoch: u32,
}

impl Eq for Turn {}
impl PartialOrd for Turn {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Turn {
    // Earliest first in a max-heap; ties by vehicle.
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        o.t.total_cmp(&self.t).then(o.vehicle.cmp(&self.vehicle))
    }
}

/// What a vehicle's turn reads and writes of it.
pub(super) struct Vehicle<'a> {
    pub(super) modems: &'a mut Modems,
    pub(super) rng: &'a mut CommRng,
    pub(super) stats: &'a mut CommStats,
    pub(super) link: &'a mut Link,
}

/// The walk through one step.
struct Walk {
    turns: BinaryHeap<Turn>,
    /// Wake-ups so far, by vehicle.
    epochs: FastMap<u32, u32>,
    /// What carrier sensing looks at, built when a protocol first listens and then kept
    /// beside the medium's transmissions as frames start.
    air: OnceCell<Air>,
    /// The storage `air` is made in (lent by the transmit phase).
    store: Cell<Option<AirStore>>,
    /// The vehicles counting idle slots down, asked again only when a frame starts near them.
    countdowns: Countdowns,
    /// Vehicles woken by the frames of the current turn.
    woken: Vec<Wake>,
    /// The decisions of the current turn, by frame (reused).
    decided: Vec<(u32, Decision)>,
    /// The copies the current turn sent: where they started \[m\], and what carrier sensing
    /// keeps of them (if it has begun) (reused).
    sent: (Vec<Vec3>, Vec<Option<OnAir>>),
    /// The sensing reach: cut-off range plus the farthest modem's offset \[m\].
    reach: f64,
    /// The step's start and end \[s\].
    t0: f64,
    t_end: f64,
    /// What the walk started: the medium takes it over when the walk is done.
    started: Started,
}

/// When the frame at the head of a port's queue is due, if any: when it was handed over,
/// when the port is free, not before the step's start `t0` \[s\].
fn due(port: &super::frames::ModemPort, t0: f64) -> Option<f64> {
    free_for_head(port).map(|at| at.max(t0))
}

/// When the frame at the head of `port`'s queue, if any, could start: when it was handed over
/// and the port is free \[s\].
fn free_for_head(port: &super::frames::ModemPort) -> Option<f64> {
    port.head().map(|h| h.ready.max(port.busy_until))
}

/// When the first of the frames queued at `modems` is due at the earliest (when handed over,
/// when its port is free) \[s\]; +∞ if none is queued. A step ending at `t_end` has a turn for
/// the vehicle only if this is earlier ([`Walk::schedule`]).
pub(super) fn earliest(modems: &Modems) -> f64 {
    modems
        .ports
        .iter()
        .filter_map(free_for_head)
        .fold(f64::INFINITY, f64::min)
}

/// When the first of the frames queued at `modems` is due in the step `t0 … t_end` \[s\]
/// (not before `t0`; `None` if none is before `t_end`): the vehicle's next turn.
pub(super) fn first_turn(modems: &Modems, (t0, t_end): (f64, f64)) -> Option<f64> {
    if modems.queued == 0 {
        return None;
    }
    let next = modems
        .ports
        .iter()
        .filter(|p| p.busy_until < t_end)
        .filter_map(|p| due(p, t0))
        .fold(f64::INFINITY, f64::min);
    (next < t_end).then_some(next)
}

/// The carrier sensing a walk starts with: made when a protocol first listens, in the
/// storage kept from the last step, or made already (beside other work: [`sensing_ahead`]).
/// (Not `sensing::Sensing`, what a listen reads.)
pub(super) enum SensingStart {
    Later(AirStore),
    Made(Air),
}

/// The carrier sensing of a walk of medium `m` made now, before any turn, in `store`: the
/// transmissions on record by position (what [`walk`] would make when a protocol first
/// listens, had nothing started before).
pub(super) fn sensing_ahead(m: &Medium, store: AirStore) -> Air {
    let rec = OnRecord {
        medium: &m.txs,
        started: &[],
    };
    Air::new(m, rec, sensing_reach(m), store)
}

/// The sensing reach of medium `m`: cut-off range plus the farthest modem's offset \[m\].
fn sensing_reach(m: &Medium) -> f64 {
    m.r_cut + m.max_modem_offset
}

/// Walks the step `t0 … t_end` \[s\] of medium `m` for `vehicles` (ascending ids; every
/// vehicle that can hear one of their frames or start one they hear is among them — all the
/// vehicles with a turn in the step, or one of the independent parts of them:
/// [`super::parts`]): their turns in time order, the vehicles woken by frames near them asked
/// again, those still counting down at the end set where the count leaves them. Carrier
/// sensing starts from `sensing`; returns its storage for the next step, and what the walk
/// started.
pub(super) fn walk(
    (m, geo): (&Medium, &shoal_world::geometry::Geometry),
    (t0, t_end): (f64, f64),
    sensing: SensingStart,
    vehicles: &mut [(u32, Vehicle<'_>)],
) -> (AirStore, Started) {
    let ports = vehicles.iter().map(|(_, v)| v.modems.ports.len()).sum();
    let mut walk = Walk::new(m, (t0, t_end), sensing, ports);
    for (id, v) in vehicles.iter() {
        walk.schedule(*id, v.modems);
    }
    // Vehicles by id: found by halving (a few hundred, in cache).
    let at = |vehicles: &[(u32, Vehicle<'_>)], id: u32| match vehicles
        .binary_search_by_key(&id, |(v, _)| *v)
    {
        Ok(i) => i,
        Err(_) => unreachable!("vehicle {id} has a turn, so it is walked"),
    };
    let mut woken = Vec::new();
    while let Some(turn) = walk.next() {
        let i = at(vehicles, turn.vehicle);
        walk.turn((m, geo), &turn, &mut vehicles[i].1);
        walk.take_woken(&mut woken);
        for w in &woken {
            walk.wake(vehicles[at(vehicles, w.vehicle)].1.modems, w);
        }
    }
    for w in walk.end() {
        walk.wake(vehicles[at(vehicles, w.vehicle)].1.modems, &w);
    }
    walk.finish()
}

/// Whether the frame at the head of `port`'s queue is due at `t` ≥ `t0` \[s\] ([`due`]): the
/// port's own fields answer, without reading the queue's storage.
fn due_at(port: &super::frames::ModemPort, t: f64, t0: f64) -> bool {
    port.busy_until <= t && due(port, t0).is_some_and(|d| d.to_bits() == t.to_bits())
}

impl Walk {
    /// A walk through the step `t0 … t_end` \[s\] of medium `m`, its carrier sensing from
    /// `sensing` (its storage handed back by [`Walk::finish`]); `ports`: how many ports the
    /// walked vehicles have, so that the step's turns and transmissions fit without growing
    /// (one of each a port as a rule).
    fn new(m: &Medium, (t0, t_end): (f64, f64), sensing: SensingStart, ports: usize) -> Self {
        let (air, store) = match sensing {
            SensingStart::Later(store) => (OnceCell::new(), Some(store)),
            SensingStart::Made(air) => (OnceCell::from(air), None),
        };
        Self {
            turns: BinaryHeap::with_capacity(ports),
            epochs: FastMap::default(),
            air,
            store: Cell::new(store),
            countdowns: Countdowns::default(),
            woken: Vec::new(),
            decided: Vec::new(),
            sent: (Vec::new(), Vec::new()),
            reach: sensing_reach(m),
            t0,
            t_end,
            started: Started {
                txs: Vec::with_capacity(ports),
            },
        }
    }

    /// Gives `vehicle` a turn when its first frame is due, if within the step.
    fn schedule(&mut self, vehicle: u32, modems: &Modems) {
        if let Some(next) = first_turn(modems, (self.t0, self.t_end)) {
            let epoch = self.epochs.get(&vehicle).copied().unwrap_or(0);
            self.turns.push(Turn {
                t: next,
                vehicle,
                epoch,
            });
        }
    }

    /// After the walk: the storage of its carrier sensing, for the next step's, and what it
    /// started (for [`Started::apply`]).
    fn finish(self) -> (AirStore, Started) {
        let store = match self.air.into_inner() {
            Some(air) => air.store(),
            None => self.store.take().unwrap_or_default(),
        };
        (store, self.started)
    }

    /// The next turn that is not stale.
    fn next(&mut self) -> Option<Turn> {
        while let Some(turn) = self.turns.pop() {
            if self.epochs.is_empty()
                || self.epochs.get(&turn.vehicle).copied().unwrap_or(0) == turn.epoch
            {
                return Some(turn);
            }
        }
        None
    }

    /// The vehicles woken since this was last called, to be handed to [`Walk::wake`], into
    /// `into` (its former contents dropped; the storage of both lists kept).
    fn take_woken(&mut self, into: &mut Vec<Wake>) {
        into.clear();
        std::mem::swap(&mut self.woken, into);
    }

    /// Vehicle `w.vehicle` (its `modems`) is asked earlier than it said: each port that
    /// waits for the boundary said waits for `w.at` instead; its earlier turn is stale.
    fn wake(&mut self, modems: &mut Modems, w: &Wake) {
        modems.access.counter = Some(w.left);
        for port in &mut modems.ports {
            if port.head().is_some() && port.busy_until.to_bits() == w.target.to_bits() {
                port.busy_until = w.at;
            }
        }
        *self.epochs.entry(w.vehicle).or_default() += 1;
        self.schedule(w.vehicle, modems);
    }

    /// The step ends: the vehicles still counting down, to be handed to [`Walk::wake`] (set
    /// where the slot-by-slot count leaves them; the next step's poses may change what they
    /// hear).
    fn end(&mut self) -> Vec<Wake> {
        let mut woken = Vec::new();
        self.countdowns.step_ended(self.t_end, &mut woken);
        woken
    }

    /// `turn` of vehicle `v`: each of its ports whose frame is due now decides, in modem
    /// order; the copies of a frame share the first one's decision. Then its next turn.
    fn turn(
        &mut self,
        (m, geo): (&Medium, &shoal_world::geometry::Geometry),
        turn: &Turn,
        v: &mut Vehicle<'_>,
    ) {
        let (t, vehicle) = (turn.t, turn.vehicle);
        // A vehicle whose count ran out undisturbed hears what it heard when the count began.
        let mut resumed = self.countdowns.end(vehicle, t);
        // Decisions of this turn by frame; the back-off all deferring ports share.
        let mut decided = std::mem::take(&mut self.decided);
        decided.clear();
        let mut backoff: Option<f64> = None;
        for k in 0..v.modems.ports.len() {
            if !due_at(&v.modems.ports[k], t, self.t0) {
                continue;
            }
            let Some(head) = v.modems.ports[k].head() else {
                continue;
            };
            let seq = head.seq;
            // Acknowledgements leave as soon as the modem is free, unless the protocol is
            // slotted.
            let ack_now = head.ack && !m.access[vehicle as usize][k].access.acks_wait();
            let decision = match decided.iter().find(|(s, _)| *s == seq) {
                Some(&(_, d)) => d,
                None if ack_now => Decision::Send,
                None => {
                    let d = self.decide((m, geo), (t, vehicle, k), v, resumed.take());
                    decided.push((seq, d));
                    d
                }
            };
            let retry = match decision {
                Decision::Send => None,
                Decision::At(at) => Some(at),
                Decision::Count { .. } => unreachable!("counted down in decide"),
                // All modems of a vehicle that defer at the same moment share one back-off,
                // so that copies of a frame on several modems stay in sync.
                Decision::Backoff(max) => Some(*backoff.get_or_insert_with(|| {
                    v.stats.cs_deferrals += 1;
                    t + v.rng.0.random::<f64>() * max
                })),
            };
            match retry {
                Some(at) => v.modems.ports[k].busy_until = at,
                None => self.send(m, (t, vehicle, k), v),
            }
        }
        self.decided = decided;
        self.wake_near_sent((m, geo), t);
        self.schedule(vehicle, v.modems);
    }

    /// The medium access of port `k` of `vehicle` decides at `t` \[s\]; a count of idle
    /// slots becomes a countdown ([`count_down`]). `resumed`: what the vehicle hears, if its
    /// countdown ran out undisturbed.
    fn decide(
        &mut self,
        (m, geo): (&Medium, &shoal_world::geometry::Geometry),
        (t, vehicle, k): (f64, u32, usize),
        v: &mut Vehicle<'_>,
        resumed: Option<(f64, f64)>,
    ) -> Decision {
        let Walk {
            air,
            store,
            countdowns,
            reach,
            started,
            ..
        } = self;
        let reach = *reach;
        let rec = started.on_record(m);
        let kind = &m.kinds[vehicle as usize];
        let (pos, att) = m.poses[vehicle as usize];
        // Carrier sense listens with all of the vehicle's photodiodes.
        let mut busy = |threshold: f64| {
            kind.params.modems.iter().enumerate().any(|(j, rxm)| {
                sensed_power(
                    (m, geo, air_of(air, store, (m, rec), reach), rec),
                    vehicle,
                    (j, &ModemPose::of(rxm, &pos, &att)),
                    t,
                ) > threshold
            })
        };
        // What the protocol found idle, and since when (for a countdown).
        let heard: Cell<Option<(f64, f64)>> = Cell::new(None);
        let mut idle_since = |threshold: f64| {
            let r = match resumed {
                Some((th, since)) if th == threshold => Ok(since),
                _ => {
                    let air = air_of(air, store, (m, rec), reach);
                    idle_since((m, geo, air, rec), vehicle, t, threshold)
                }
            };
            if let Ok(since) = r {
                heard.set(Some((threshold, since)));
            }
            r
        };
        let mut ctx = Ctx {
            t,
            vehicle,
            clock_rate: m.clock_rate(vehicle),
            busy: &mut busy,
            idle_since: &mut idle_since,
            state: &mut v.modems.access,
            rng: &mut v.rng.0,
        };
        match m.access[vehicle as usize][k].access.decide(&mut ctx) {
            Decision::Count { from, slot, left } => count_down(
                t,
                (from, slot, left),
                v.modems,
                Counter {
                    countdowns: (!m.slot_by_slot).then_some(countdowns),
                    vehicle,
                    pos: &pos,
                    heard: heard.get(),
                },
                (reach, || Air::cells(air_of(air, store, (m, rec), reach))),
            ),
            d => d,
        }
    }

    /// Port `k` of `vehicle` starts the frame at the head of its queue at `t` \[s\]: its
    /// transmission goes on record, its LED time and energy are counted (to its flow too), an
    /// acknowledged unicast's wait starts; the vehicles counting down near it are woken when
    /// the turn is over ([`Walk::wake_near_sent`]).
    fn send(&mut self, m: &Medium, (t, vehicle, k): (f64, u32, usize), v: &mut Vehicle<'_>) {
        let Some(frame) = v.modems.ports[k].pop() else {
            return;
        };
        v.modems.queued -= 1;
        let params = &m.kinds[vehicle as usize].params.modems[k];
        let (pos, att) = m.poses[vehicle as usize];
        let pose = ModemPose::of(params, &pos, &att);
        let (airtime, energy) = led_use(params, frame.payload.len());
        let bits = params.frame_bits(frame.payload.len());
        let end = t + airtime;
        v.modems.ports[k].busy_until = end;
        v.stats.led_on_s += airtime;
        v.stats.led_energy_j += energy;
        if let Kind::Unicast { ack: true, .. } = frame.kind
            && let Some(p) = &mut v.link.state().pending
            && p.seq == frame.seq
        {
            // The wait for the acknowledgement starts when the last copy has ended.
            let wait = end + m.access[vehicle as usize][k].ack_timeout;
            p.deadline = if p.deadline.is_finite() {
                p.deadline.max(wait)
            } else {
                wait
            };
        }
        let started = &mut self.started;
        let index = started.next_index(m);
        started.txs.push(Transmission {
            // Numbered when the walk is done (`Started::apply`).
            id: 0,
            tx: vehicle,
            modem: k,
            start: t,
            end,
            seq: frame.seq,
            sent: frame.ready,
            bits,
            payload: frame.payload,
            pose,
            kind: frame.kind,
        });
        let on = self
            .air
            .get_mut()
            .map(|air| air.push(index, &started.txs[started.txs.len() - 1]));
        self.countdowns.started(&pose.position, t);
        self.sent.0.push(pose.position);
        self.sent.1.push(on);
    }

    /// After a turn at `t` \[s\]: the vehicles counting down near the copies it sent that
    /// one of them reaches are asked again at their next boundary.
    fn wake_near_sent(&mut self, (m, geo): (&Medium, &shoal_world::geometry::Geometry), t: f64) {
        let (at, on) = &self.sent;
        if at.is_empty() {
            return;
        }
        let rec = self.started.on_record(m);
        let reaches = |k: usize, w| match (self.air.get(), &on[k]) {
            (Some(air), Some(on)) => reaches((m, geo, air, rec), w, on),
            _ => true,
        };
        self.countdowns
            .frames_started((at, t), self.reach, reaches, &mut self.woken);
        self.sent.0.clear();
        self.sent.1.clear();
    }
}

/// The walk's carrier sensing, made in `store` when first asked for.
fn air_of<'a>(
    air: &'a OnceCell<Air>,
    store: &Cell<Option<AirStore>>,
    (m, rec): (&Medium, OnRecord<'_>),
    reach: f64,
) -> &'a Air {
    air.get_or_init(|| Air::new(m, rec, reach, store.take().unwrap_or_default()))
}

/// Who counts down, for [`count_down`].
struct Counter<'a> {
    /// The step's countdowns (`None`: slot by slot).
    countdowns: Option<&'a mut Countdowns>,
    vehicle: u32,
    /// Its position \[m\].
    pos: &'a Vec3,
    /// The busy threshold the protocol listened with and since when the channel was idle
    /// \[W, s\], if it listened.
    heard: Option<(f64, f64)>,
}

/// A protocol's [`Decision::Count`] at `t` \[s\] of a vehicle's frame, as the decision to
/// act on: with the step's countdowns (unless [`Medium::slot_by_slot`]), the vehicle counts
/// down at once — if none of its ports is on the air and its queued ports all hold copies of
/// one frame (which decide together; otherwise the count would be shared by frames deciding
/// at different times), and no frame started nearby at this very instant: it is asked again
/// at the last boundary with the counter at 0, and hears there what it `heard` now (the
/// threshold and since when the channel was idle \[W, s\]) unless woken first. Else slot by
/// slot: asked at the next boundary.
fn count_down(
    t: f64,
    (from, slot, left): (f64, f64, u32),
    modems: &mut Modems,
    who: Counter<'_>,
    (reach, cells): (f64, impl FnOnce() -> Cells),
) -> Decision {
    let quiet = modems.ports.iter().all(|p| p.busy_until <= t);
    let mut fronts = modems.ports.iter().filter_map(|p| p.head());
    let together = fronts
        .next()
        .is_some_and(|f| fronts.all(|g| g.seq == f.seq));
    let target = match (who.countdowns, who.heard) {
        (Some(c), Some(heard)) if quiet && together => c.start(
            (who.vehicle, who.pos),
            (t, heard),
            (from, slot, left),
            (reach, cells),
        ),
        _ => None,
    };
    match target {
        Some(target) => {
            modems.access.counter = Some(0);
            Decision::At(target)
        }
        None if from > t => {
            modems.access.counter = Some(left);
            Decision::At(from)
        }
        None => {
            modems.access.counter = Some(left - 1);
            Decision::At(t + slot)
        }
    }
}
