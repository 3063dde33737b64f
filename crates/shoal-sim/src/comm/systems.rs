//! The three step systems of the medium: [`comm_snapshot_system`] (poses, grid, pruning),
//! [`comm_transmit_system`] (queues, access, carrier sense) and [`comm_deliver_system`] (every
//! reception decided at its receiver).

use super::air::{Air, AirStore};
use super::ending::{Ended, candidates, own_transmissions};
use super::frames::{CommRng, Inbox, Modems, Outbox};
use super::ledger::Ledger;
use super::link_layer::{Mail, link_layer};
use super::links::Outcome;
use super::mac::Link;
use super::medium::{Logical, Medium};
use super::parts::split;
use super::reception::{Listener, Scratch, receive};
use super::started::Started;
use super::stats::{CommStats, Tally};
use super::transmit::{SensingStart, Vehicle, earliest, first_turn, sensing_ahead, walk};
use crate::components::{StaticGeometry, VehicleEntities, VehicleId};
use crate::parallel::{Loop, Parallel};
use bevy_ecs::prelude::*;
use std::mem::take;
use std::sync::Mutex;

/// Step phase 1: bring the grid up to date with the poses (which the vehicle pass wrote),
/// prune old transmissions.
pub fn comm_snapshot_system(
    clock: Res<crate::components::Clock>,
    mut medium: ResMut<Medium>,
    fresh: Query<&Outbox, Changed<Outbox>>,
) {
    if !medium.active() {
        return;
    }
    // Nothing on the air and nothing waiting to go: the medium has no work this step.
    let idle = medium.txs.is_empty()
        && medium.waiting.is_empty()
        && medium.linked.is_empty()
        && fresh.iter().all(|out| out.0.is_empty());
    if idle {
        return;
    }
    let m = &mut *medium;
    m.update_grid();
    // Every frame still to end is on the air now or starts later, so it started no earlier
    // than the earliest start on the air now: what ended before that can no longer overlap
    // it (nor a frame starting later, nor carrier sense from now on) — unless a medium-access
    // protocol still looks back at it.
    let t = clock.t();
    let horizon = m
        .txs
        .iter()
        .filter(|x| x.end > t)
        .map(|x| x.start)
        .fold(t - m.memory, f64::min);
    m.txs.retain(|x| x.end > horizon);
}

/// What the transmit phase reads and writes of a sending vehicle.
type Sender = (
    &'static VehicleId,
    &'static mut Outbox,
    &'static mut Modems,
    &'static mut CommRng,
    &'static mut CommStats,
    &'static mut Link,
    &'static mut Inbox,
);

/// What a vehicle's turns in the transmit walk cost when its protocol listens to the channel,
/// in vehicle updates (the unit of [`Parallel::min_parallel`]): a few turns a step, each
/// computing link budgets around it, about 2 µs against a vehicle update's 0.3 µs (profiled on
/// the 10,000-vehicle CSMA/CA swarm). A turn that does not listen costs about one: ALOHA's
/// walk of that swarm (0.06 ms a step) took longer split in two (0.09 ms) than on one thread.
const LISTENING_TURN: usize = 8;

/// A sending vehicle's components, as the transmit phase's query hands them out.
type SenderItem<'w> = (
    &'w VehicleId,
    Mut<'w, Outbox>,
    Mut<'w, Modems>,
    Mut<'w, CommRng>,
    Mut<'w, CommStats>,
    Mut<'w, Link>,
    Mut<'w, Inbox>,
);

/// The vehicles whose outbox changed since the transmit phase last ran.
type HandedOver<'w, 's> = Query<'w, 's, (&'static VehicleId, &'static Outbox), Changed<Outbox>>;

/// Step phase 2: queue handed-over frames and start transmissions in time order.
pub fn comm_transmit_system(
    clock: Res<crate::components::Clock>,
    par: Res<Parallel>,
    geo: Res<StaticGeometry>,
    mut sensing: Local<Vec<AirStore>>,
    mut medium: ResMut<Medium>,
    entities: Res<VehicleEntities>,
    mut qs: ParamSet<(HandedOver, Query<Sender>)>,
) {
    if !medium.active() {
        return;
    }
    // The vehicles with something to send: frames still queued at a modem, or work for the
    // link layer — frames handed over since the last step (their outbox changed), or the
    // link layer's own.
    let mut linked = take(&mut medium.linked);
    linked.extend(
        qs.p0()
            .iter()
            .filter(|(_, out)| !out.0.is_empty())
            .map(|(id, _)| id.0),
    );
    linked.sort_unstable();
    linked.dedup();
    let (t0, t_end) = (clock.t(), clock.t() + clock.dt);
    // Those waiting whose first frame is due after this step are not even looked at.
    let (mut ids, later) = due_in_step(take(&mut medium.waiting), &linked, t_end);
    if ids.is_empty() {
        medium.waiting = later;
        return;
    }
    // The flows are the link layer's while the medium is read by the walk's threads.
    let mut flows = take(&mut medium.flows);
    let mut ended = 0;
    let mut q = qs.p1();
    let mut items = Vec::with_capacity(ids.len());
    let m = &*medium;
    let threads = par.parts(walk_work(m, &ids));
    let started = {
        let (items, q, flows, ended) = (&mut items, &mut q, &mut flows, &mut ended);
        let (ids, linked) = (&ids, &linked);
        let grouping = Grouping {
            m,
            ids,
            threads,
            parts: Mutex::new(None),
        };
        let make = move |grouping: &Grouping<'_>| {
            let (items, q, flows, ended) = (items, q, flows, ended);
            items.extend(q.iter_many_unique_mut(entities.set_of(ids)).matched());
            items.sort_unstable_by_key(|it| it.0.0);
            let (turning, n) = link_layers(m, (t0, t_end), linked, items, flows);
            *ended = n;
            in_parts(items, &turning, &grouping.take())
        };
        let walk = (m, &geo.0, &*par);
        walk_in_parts(walk, (t0, t_end), &grouping, &mut sensing, make)
    };
    medium.flows = flows;
    medium.ended += ended;
    started.apply(&mut medium);
    // Items by vehicle: sorted by id, found by halving their ids (a few hundred, in cache).
    let keys: Vec<u32> = items.iter().map(|it| it.0.0).collect();
    let at = |v: u32| match keys.binary_search(&v) {
        Ok(i) => i,
        Err(_) => unreachable!("vehicle {v} was looked at, so it has an item"),
    };
    let m = &mut *medium;
    // Only the link layer changes whether it has work in this phase.
    linked.retain(|&v| items[at(v)].5.busy());
    ids.retain(|&v| items[at(v)].2.queued > 0);
    let walked = ids.iter().map(|&v| (v, earliest(&items[at(v)].2)));
    m.waiting = merge_by_vehicle(later, walked);
    m.linked = linked;
}

/// What the walk of a step looking at vehicles `ids` of medium `m` is likely to cost, in
/// vehicle updates (the unit of [`Parallel::min_parallel`]), to choose its threads before the
/// link layer has run: [`LISTENING_TURN`] for a vehicle whose protocol listens, else one.
fn walk_work(m: &Medium, ids: &[u32]) -> usize {
    ids.iter()
        .map(
            |&v| match m.access[v as usize].iter().any(|l| l.access.listens()) {
                true => LISTENING_TURN,
                false => 1,
            },
        )
        .sum()
}

/// The link layer of each of the `items` (ascending ids) in `linked` (ascending) at the
/// start `t0` of the step `t0 … t_end` \[s\] of medium `m` (the link layer of a vehicle with
/// neither frames handed over nor work of its own does nothing: only its queued frames are
/// walked), counting to `flows`; returns the positions of the items with a turn in the step,
/// and how many frames ended there (acknowledged or given up).
fn link_layers(
    m: &Medium,
    (t0, t_end): (f64, f64),
    linked: &[u32],
    items: &mut [SenderItem<'_>],
    flows: &mut super::flows::Flows,
) -> (Vec<usize>, u64) {
    let mut ended = 0;
    let mut with_link = linked.iter().copied().peekable();
    let mut turning = Vec::new();
    for (i, (id, outbox, modems, _, stats, link, inbox)) in items.iter_mut().enumerate() {
        let modems = &mut **modems;
        if with_link.next_if_eq(&id.0).is_some() {
            let params = &m.kinds[id.0 as usize].params.modems;
            let links = &m.access[id.0 as usize];
            ended += link_layer(
                t0,
                params,
                links,
                (outbox, modems, stats, link, inbox),
                (id.0, flows),
            );
        }
        if first_turn(modems, (t0, t_end)).is_some() {
            turning.push(i);
        }
    }
    (turning, ended)
}

/// The `items` at positions `turning` (those with a turn in the step) in the independent
/// `parts` of the vehicles looked at (their ids, [`Grouping`]): each part's vehicles with their
/// ids, ascending; no empty part.
fn in_parts<'a>(
    items: &'a mut [SenderItem<'_>],
    turning: &[usize],
    parts: &[Vec<u32>],
) -> Vec<Vec<(u32, Vehicle<'a>)>> {
    let mut part_of: Vec<(u32, usize)> = parts
        .iter()
        .enumerate()
        .flat_map(|(k, p)| p.iter().map(move |&v| (v, k)))
        .collect();
    part_of.sort_unstable();
    let mut out: Vec<Vec<(u32, Vehicle<'a>)>> = parts.iter().map(|_| Vec::new()).collect();
    let mut next = turning.iter().peekable();
    for (i, (id, _, modems, rng, stats, link, _)) in items.iter_mut().enumerate() {
        if next.next_if_eq(&&i).is_none() {
            continue;
        }
        let k = match part_of.binary_search_by_key(&id.0, |&(v, _)| v) {
            Ok(j) => part_of[j].1,
            Err(_) => unreachable!("vehicle {} was looked at, so it is in a part", id.0),
        };
        out[k].push((
            id.0,
            Vehicle {
                modems,
                rng,
                stats,
                link,
            },
        ));
    }
    out.retain(|p| !p.is_empty());
    out
}

/// The vehicles looked at in a step (`ids`) in at most `threads` independent parts ([`split`]:
/// those with a turn are among them, and a coarser grouping is as independent), made by the
/// first worker while the calling thread runs the link layer — or by the calling thread, if it
/// asks first.
struct Grouping<'a> {
    m: &'a Medium,
    ids: &'a [u32],
    threads: usize,
    /// The parts (ids), once made; made under the lock, so that the calling thread asking for
    /// them meanwhile waits for them.
    parts: Mutex<Option<Vec<Vec<u32>>>>,
}

impl Grouping<'_> {
    /// Makes the parts unless they are made.
    fn make(&self) {
        let mut parts = self.parts.lock().unwrap_or_else(|e| e.into_inner());
        if parts.is_none() {
            let split = split(self.m, self.ids, self.threads);
            *parts = Some(
                split
                    .iter()
                    .map(|p| p.iter().map(|&k| self.ids[k]).collect())
                    .collect(),
            );
        }
    }

    /// The parts (made now if they are not yet).
    fn take(&self) -> Vec<Vec<u32>> {
        self.make();
        let mut parts = self.parts.lock().unwrap_or_else(|e| e.into_inner());
        parts.take().unwrap_or_else(|| vec![self.ids.to_vec()])
    }
}

/// The carrier sensing of a thread of a walk in parts ([`walk_in_parts`]).
enum Ready {
    /// Its storage, the sensing not made yet.
    Store(AirStore),
    /// Made.
    Made(Air),
    /// Taken by its thread.
    Taken,
}

/// Walks the step `t0 … t_end` \[s\] of medium `m` for the vehicles `make` returns, in the
/// independent parts it returns them in (of `grouping`, which it is handed), on
/// `grouping.threads` threads of `par` (one part each), each with carrier sensing made in its
/// storage of `stores`; returns what they started, in the order one walk of them all starts
/// it. On several threads the workers make the grouping and every thread's carrier sensing
/// while the calling thread runs `make` (the link layer: serial work the step has anyway).
fn walk_in_parts<'a>(
    (m, geo, par): (&Medium, &shoal_world::geometry::Geometry, &Parallel),
    step: (f64, f64),
    grouping: &Grouping<'_>,
    stores: &mut Vec<AirStore>,
    make: impl FnOnce(&Grouping<'_>) -> Vec<Vec<(u32, Vehicle<'a>)>>,
) -> Started {
    let threads = grouping.threads;
    stores.resize_with(stores.len().max(threads), Default::default);
    if threads == 1 {
        let mut all = make(grouping).pop().unwrap_or_default();
        let (store, started) = walk(
            (m, geo),
            step,
            SensingStart::Later(take(&mut stores[0])),
            &mut all,
        );
        stores[0] = store;
        return started;
    }
    let kept: Vec<Mutex<Ready>> = stores
        .drain(..)
        .map(|s| Mutex::new(Ready::Store(s)))
        .collect();
    // Made under the lock, so that a thread asking for it meanwhile waits for it.
    let made = |k: usize, take_it: bool| -> Option<Air> {
        let mut r = kept[k].lock().ok()?;
        let air = match std::mem::replace(&mut *r, Ready::Taken) {
            Ready::Store(store) => sensing_ahead(m, store),
            Ready::Made(air) => air,
            Ready::Taken => return None,
        };
        if take_it {
            return Some(air);
        }
        *r = Ready::Made(air);
        None
    };
    let ready = |k: usize| {
        // The first worker makes the grouping and the calling thread's carrier sensing too
        // (which runs `make` meanwhile).
        if k == 1 {
            grouping.make();
            made(0, false);
        }
        made(k, true).unwrap_or_else(|| sensing_ahead(m, AirStore::default()))
    };
    let walked = par.for_parts_made(
        Loop::Walk,
        || make(grouping),
        ready,
        |part, air| match part {
            Some(mut vs) => walk((m, geo), step, SensingStart::Made(air), &mut vs),
            None => (air.store(), Started::default()),
        },
    );
    let mut started = Vec::with_capacity(walked.len());
    for (store, s) in walked {
        stores.push(store);
        started.push(s);
    }
    Started::merge(started)
}

/// Of the vehicles `waiting` (ascending, each with when its first frame is due at the
/// earliest \[s\]) and those with work for the link layer (`linked`, ascending): the ones the
/// transmit phase of a step ending at `t_end` \[s\] looks at (ascending), and the others (still
/// waiting). A vehicle waiting changes only in the transmit phase: until then its frames are
/// due when they were.
fn due_in_step(
    waiting: Vec<(u32, f64)>,
    linked: &[u32],
    t_end: f64,
) -> (Vec<u32>, Vec<(u32, f64)>) {
    let (now, later): (Vec<_>, Vec<_>) = waiting
        .into_iter()
        .partition(|&(v, due)| due < t_end || linked.binary_search(&v).is_ok());
    let mut ids: Vec<u32> = now.into_iter().map(|(v, _)| v).collect();
    ids.extend_from_slice(linked);
    ids.sort_unstable();
    ids.dedup();
    (ids, later)
}

/// Two lists ascending by vehicle, with no vehicle in both, as one.
fn merge_by_vehicle(a: Vec<(u32, f64)>, b: impl Iterator<Item = (u32, f64)>) -> Vec<(u32, f64)> {
    let mut all = a;
    all.extend(b);
    all.sort_unstable_by_key(|&(v, _)| v);
    all
}

/// Step phase 3: decide every reception of frames that ended in this step.
pub fn comm_deliver_system(
    clock: Res<crate::components::Clock>,
    par: Res<Parallel>,
    geo: Res<StaticGeometry>,
    mut medium: ResMut<Medium>,
    mut ledger: ResMut<Ledger>,
    mut q: Query<(&VehicleId, &mut Inbox, &mut CommRng, &mut Link)>,
) {
    if !medium.active() {
        return;
    }
    let (t0, t_end) = (clock.t(), clock.t() + clock.dt);
    let m = &*medium;
    let ended = Ended::gather(m, t0, t_end);
    let logical = ended.frames();
    if logical.is_empty() {
        return;
    }
    let heard = candidates(m, &logical);
    let own = own_transmissions(m);
    let mut items = Vec::with_capacity(heard.vehicles());
    items.extend(q.iter_mut().filter(|it| !heard.of(it.0.0).is_empty()));
    let geo = &geo.0;
    // Outcomes by second (a step reaches into the next second at most) and kind, and the
    // distance and latency histograms: tallied per chunk of receivers, summed afterwards;
    // every attempt goes to the chunk's part of the ledger, in receiver order.
    let second0 = t0.floor();
    // A frame ending at `end` falls into the next second when ⌊end⌋ > second0, i.e.
    // end ≥ second0 + 1 (an integer).
    let second1 = second0 + 1.0;
    let frame0 = ledger.frames_of(logical.iter().map(Logical::first));
    let states = par.for_each_with(
        Loop::Delivery,
        &mut items,
        || {
            let flows = Vec::new();
            (
                Tally::new(),
                Scratch::default(),
                Vec::new(),
                Vec::new(),
                flows,
            )
        },
        |(tally, scratch, events, linked, flows), (id, inbox, rng, link)| {
            let mut rx = Listener::new(m, id.0, scratch);
            let mut mail = Mail { inbox, link, flows };
            for &i in heard.of(id.0) {
                let l = &logical[i as usize];
                let o = receive(m, geo, &mut rx, &own, l, &mut rng.0, &mut mail, tally);
                events.push(Ledger::attempt(id.0, frame0 + i, o));
                let s = usize::from(l.first().end >= second1);
                tally.outcomes[s][o.index()] += 1;
            }
            if mail.link.busy() {
                linked.push(id.0);
            }
        },
    );
    let mut total = Tally::new();
    let mut linked = Vec::new();
    let mut flow_events = Vec::new();
    for (t, _, events, l, f) in &states {
        total.add(t);
        ledger.append(events, m.log_links);
        linked.extend_from_slice(l);
        flow_events.extend_from_slice(f);
    }
    for e in &flow_events {
        medium.flows.apply(e);
    }
    add_tally(&mut medium, &total, second0);
    // Vehicles that owe an acknowledgement or got one: the transmit phase visits them next.
    medium.linked.extend(linked);
}

/// Adds the tallies of a step whose first second is `second0` \[s\] to the medium's.
fn add_tally(medium: &mut Medium, total: &Tally, second0: f64) {
    for ((a, d), (ta, td)) in medium.by_distance.iter_mut().zip(&total.by_distance) {
        *a += ta;
        *d += td;
    }
    for (h, t) in medium.latency_hist.iter_mut().zip(&total.latency) {
        *h += t;
    }
    for (h, t) in medium.ack_latency_hist.iter_mut().zip(&total.acknowledged) {
        *h += t;
        medium.ended += t;
    }
    for (s, c) in total.outcomes.iter().enumerate() {
        if c.iter().all(|k| *k == 0) {
            continue;
        }
        let second = second0 as usize + s;
        if medium.per_second.len() <= second {
            medium.per_second.resize(second + 1, [0; 5]);
        }
        for (a, k) in medium.per_second[second].iter_mut().zip(c) {
            *a += k;
        }
        medium.delivered += c[Outcome::Delivered.index()];
    }
}
