//! The three step systems of the medium: [`comm_snapshot_system`] (poses, grid, pruning),
//! [`comm_transmit_system`] (queues, access, carrier sense) and [`comm_deliver_system`] (every
//! reception decided at its receiver).

use super::air::{Air, AirStore};
use super::ending::{Ended, candidates, own_transmissions};
use super::flows::Flows;
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
use crate::parallel::{Handout, Loop, Parallel};
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
    let mut q = qs.p1();
    let mut items = Vec::with_capacity(ids.len());
    let m = &*medium;
    let threads = par.parts(walk_work(m, &ids));
    let (started, flows, ended) = {
        let (items, q) = (&mut items, &mut q);
        let (ids, linked) = (&ids, &linked);
        let grouping = Grouping {
            m,
            ids,
            threads,
            parts: Mutex::new(None),
        };
        let walk = (m, &geo.0, &*par);
        let make = move |grouping: &Grouping<'_>, handout: &Handout<'_, _>| {
            let (items, q) = (items, q);
            items.extend(q.iter_many_unique_mut(entities.set_of(ids)).matched());
            items.sort_unstable_by_key(|it| it.0.0);
            // The workers' parts are handed out at once: each thread runs its vehicles' link
            // layers, then walks them.
            let mut parts = by_part(items, &grouping.take()).into_iter();
            let first = parts.next();
            for part in parts {
                handout.give(part);
            }
            first.into_iter().collect()
        };
        walk_in_parts(walk, (t0, t_end), &grouping, (&mut sensing, linked), make)
    };
    medium.flows.absorb(flows);
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

/// A part of the walk: its vehicles with their ids, ascending.
type Part<'a> = Vec<(u32, Vehicle<'a>)>;

/// The link layer of each of the `items` (ascending ids) in `linked` (ascending) at the
/// start `t0` of the step `t0 … t_end` \[s\] of medium `m` (the link layer of a vehicle with
/// neither frames handed over nor work of its own does nothing: only its queued frames are
/// walked), counting to `flows`; returns the items with a turn in the step, as a part of the
/// walk, and how many frames ended there (acknowledged or given up).
fn link_layers<'a>(
    m: &Medium,
    (t0, t_end): (f64, f64),
    linked: &[u32],
    items: Vec<&'a mut SenderItem<'_>>,
    flows: &mut Flows,
) -> (Part<'a>, u64) {
    let mut ended = 0;
    let mut with_link = linked.iter().copied().peekable();
    let mut walked = Vec::new();
    for (id, outbox, modems, rng, stats, link, inbox) in items {
        // Linked vehicles of other parts are passed over on the way.
        while with_link.next_if(|&v| v < id.0).is_some() {}
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
            walked.push((
                id.0,
                Vehicle {
                    modems,
                    rng,
                    stats,
                    link,
                },
            ));
        }
    }
    (walked, ended)
}

/// The `items` (ascending ids) in the independent `parts` of the vehicles looked at (their
/// ids, [`Grouping`]), each part's ascending.
fn by_part<'a, 'w>(
    items: &'a mut [SenderItem<'w>],
    parts: &[Vec<u32>],
) -> Vec<Vec<&'a mut SenderItem<'w>>> {
    let mut part_of: Vec<(u32, usize)> = parts
        .iter()
        .enumerate()
        .flat_map(|(k, p)| p.iter().map(move |&v| (v, k)))
        .collect();
    part_of.sort_unstable();
    let mut out: Vec<Vec<&'a mut SenderItem<'w>>> = parts.iter().map(|_| Vec::new()).collect();
    for item in items.iter_mut() {
        let id = item.0.0;
        match part_of.binary_search_by_key(&id, |&(v, _)| v) {
            Ok(j) => out[part_of[j].1].push(item),
            Err(_) => unreachable!("vehicle {id} was looked at, so it is in a part"),
        }
    }
    out
}

/// The vehicles looked at in a step (`ids`) in at most `threads` independent parts ([`split`]:
/// those with a turn are among them, and a coarser grouping is as independent), made by the
/// first worker while the calling thread fetches the vehicles — or by the calling thread, if
/// it asks first.
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

/// The items of a part of the walk's vehicles, before their link layers have run.
type Items<'a, 'w> = Vec<&'a mut SenderItem<'w>>;

/// Runs the link layers of the vehicles `make` returns and walks the step `t0 … t_end` \[s\]
/// of medium `m` for those with a turn, in the independent parts `make` returns them in (of
/// `grouping`, which it is handed), on `grouping.threads` threads of `par` (one part each:
/// the link layers of its vehicles in `linked`, then its walk), each with carrier sensing made
/// in its storage of `stores`. Returns what they started, in the order one walk of them all
/// starts it, what the link layers counted to the flows, and how many frames ended there. On
/// several threads the first worker makes the grouping and every thread's carrier sensing
/// while the calling thread fetches the vehicles (`make`), which hands the workers their
/// parts at once.
fn walk_in_parts<'a, 'w: 'a>(
    (m, geo, par): (&Medium, &shoal_world::geometry::Geometry, &Parallel),
    step: (f64, f64),
    grouping: &Grouping<'_>,
    (stores, linked): (&mut Vec<AirStore>, &[u32]),
    make: impl FnOnce(&Grouping<'_>, &Handout<'_, Items<'a, 'w>>) -> Vec<Items<'a, 'w>>,
) -> (Started, Flows, u64) {
    let threads = grouping.threads;
    stores.resize_with(stores.len().max(threads), Default::default);
    // A thread's part: its link layers, then its walk.
    let link_and_walk = |items: Option<Items<'a, 'w>>, sensing: SensingStart| {
        let mut flows = Flows::default();
        let (mut walked, ended) = match items {
            Some(items) => link_layers(m, step, linked, items, &mut flows),
            None => (Vec::new(), 0),
        };
        let (store, started) = walk((m, geo), step, sensing, &mut walked);
        (store, started, flows, ended)
    };
    if threads == 1 {
        // One part (the grouping's on one thread).
        let handout = Handout::none();
        let mut parts = make(grouping, &handout);
        parts.extend(handout.into_extra());
        // The grouping on one thread is one part, in order.
        let all: Items<'a, 'w> = parts.into_iter().flatten().collect();
        let sensing = SensingStart::Later(take(&mut stores[0]));
        let (store, started, flows, ended) = link_and_walk(Some(all), sensing);
        stores[0] = store;
        return (started, flows, ended);
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
        |handout| make(grouping, handout),
        ready,
        |part, air| link_and_walk(part, SensingStart::Made(air)),
    );
    let mut started = Vec::with_capacity(walked.len());
    let (mut flows, mut ended) = (Flows::default(), 0);
    for (store, s, f, n) in walked {
        stores.push(store);
        started.push(s);
        flows.absorb(f);
        ended += n;
    }
    (Started::merge(started), flows, ended)
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
