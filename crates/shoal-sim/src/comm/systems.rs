//! The three step systems of the medium: [`comm_snapshot_system`] (poses, grid, pruning),
//! [`comm_transmit_system`] (queues, access, carrier sense) and [`comm_deliver_system`] (every
//! reception decided at its receiver).

use super::air::{Air, FastMap};
use super::countdown::{Countdowns, Wake};
use super::ending::{Ended, candidates, own_transmissions};
use super::frames::{CommRng, Inbox, Kind, Modems, Outbox};
use super::grid::Cells;
use super::ledger::Ledger;
use super::link_layer::{Mail, link_layer};
use super::links::Outcome;
use super::mac::{Ctx, Decision, Link};
use super::medium::{Medium, Transmission};
use super::reception::{Listener, Scratch, receive};
use super::sensing::{idle_since, sensed_power};
use super::stats::{CommStats, Tally};
use crate::components::{StaticGeometry, VehicleEntities, VehicleId};
use crate::parallel::{Loop, Parallel};
use bevy_ecs::prelude::*;
use rand::RngExt;
use shoal_model::optics::ModemPose;
use std::cell::{Cell, OnceCell};
use std::collections::BinaryHeap;

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

#[derive(PartialEq)]
struct StartEvent {
    t: f64,
    vehicle: u32,
    modem: usize,
    /// How often the port's wait had been cut short when the event was made: an event made
    /// before its latest wake-up ([`Countdowns`]) is stale.
    epoch: u32,
}

impl Eq for StartEvent {}
impl PartialOrd for StartEvent {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for StartEvent {
    // Earliest first in a max-heap; ties by vehicle, then modem.
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        o.t.total_cmp(&self.t)
            .then(o.vehicle.cmp(&self.vehicle))
            .then(o.modem.cmp(&self.modem))
    }
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

/// The vehicles whose outbox changed since the transmit phase last ran.
type HandedOver<'w, 's> = Query<'w, 's, (&'static VehicleId, &'static Outbox), Changed<Outbox>>;

/// Step phase 2: queue handed-over frames and start transmissions in time order.
pub fn comm_transmit_system(
    clock: Res<crate::components::Clock>,
    geo: Res<StaticGeometry>,
    mut medium: ResMut<Medium>,
    entities: Res<VehicleEntities>,
    mut qs: ParamSet<(HandedOver, Query<Sender>)>,
) {
    if !medium.active() {
        return;
    }
    // The vehicles with something to send: frames handed over since the last step (their
    // outbox changed), still queued at a modem, or with link-layer work.
    let mut ids = std::mem::take(&mut medium.waiting);
    ids.extend(
        qs.p0()
            .iter()
            .filter(|(_, out)| !out.0.is_empty())
            .map(|(id, _)| id.0),
    );
    if ids.is_empty() {
        return;
    }
    ids.sort_unstable();
    ids.dedup();
    let mut q = qs.p1();
    let t_end = clock.t() + clock.dt;
    let mut items: Vec<_> = q
        .iter_many_unique_mut(entities.set_of(&ids))
        .matched()
        .collect();
    items.sort_unstable_by_key(|it| it.0.0);
    let mut heap = BinaryHeap::new();
    let med = &mut *medium;
    let (kinds, access, flows) = (&med.kinds, &med.access, &mut med.flows);
    let mut ended = 0;
    for (id, outbox, modems, _, stats, link, inbox) in &mut items {
        let params = &kinds[id.0 as usize].params.modems;
        let links = &access[id.0 as usize];
        let modems = &mut **modems;
        ended += link_layer(
            clock.t(),
            params,
            links,
            (outbox, modems, stats, link, inbox),
            (id.0, flows),
        );
        for (k, port) in modems.ports.iter().enumerate() {
            if let Some(front) = port.queue.front() {
                let start = front.ready.max(port.busy_until).max(clock.t());
                if start < t_end {
                    heap.push(StartEvent {
                        t: start,
                        vehicle: id.0,
                        modem: k,
                        epoch: 0,
                    });
                }
            }
        }
    }
    let index: FastMap<u32, usize> = items
        .iter()
        .enumerate()
        .map(|(i, it)| (it.0.0, i))
        .collect();
    medium.ended += ended;
    let m = &mut *medium;
    let mut backoffs: FastMap<(u32, u64), f64> = FastMap::default();
    let mut decided: FastMap<(u32, u32, u64), Decision> = FastMap::default();
    // What carrier sensing looks at, built when a protocol first listens and then kept beside
    // `m.txs` as frames start.
    let mut air: OnceCell<Air> = OnceCell::new();
    let reach = m.r_cut + m.max_modem_offset;
    // The vehicles counting idle slots down, asked again only when a frame starts near them.
    let mut countdowns = Countdowns::default();
    let mut epochs: FastMap<(u32, usize), u32> = FastMap::default();
    let mut woken: Vec<Wake> = Vec::new();
    while let Some(ev) = heap.pop() {
        if !epochs.is_empty()
            && epochs.get(&(ev.vehicle, ev.modem)).copied().unwrap_or(0) != ev.epoch
        {
            continue;
        }
        // A vehicle whose count ran out undisturbed hears what it heard when the count began.
        let resumed = countdowns.end(ev.vehicle, ev.t);
        let (_, _, modems, rng, stats, link, _) = &mut items[index[&ev.vehicle]];
        let kind = &m.kinds[ev.vehicle as usize];
        let params = &kind.params.modems[ev.modem];
        let (pos, att) = m.poses[ev.vehicle as usize];
        let pose = ModemPose::of(params, &pos, &att);
        // Carrier sense listens with all of the vehicle's photodiodes.
        let mut busy = |threshold: f64| {
            kind.params.modems.iter().enumerate().any(|(k, rxm)| {
                sensed_power(
                    m,
                    &geo.0,
                    air.get_or_init(|| Air::new(m, reach)),
                    ev.vehicle,
                    (k, &ModemPose::of(rxm, &pos, &att)),
                    ev.t,
                ) > threshold
            })
        };
        // What the protocol found idle, and since when (for a countdown).
        let heard: Cell<Option<(f64, f64)>> = Cell::new(None);
        let mut idle_since = |threshold: f64| {
            let r = match resumed {
                Some((th, since)) if th == threshold => Ok(since),
                _ => {
                    let air = air.get_or_init(|| Air::new(m, reach));
                    idle_since(m, &geo.0, air, ev.vehicle, &pos, &att, ev.t, threshold)
                }
            };
            if let Ok(since) = r {
                heard.set(Some((threshold, since)));
            }
            r
        };
        let link_params = &m.access[ev.vehicle as usize][ev.modem];
        let Some(front) = modems.ports[ev.modem]
            .queue
            .front()
            .map(|q| (q.seq, q.kind))
        else {
            continue;
        };
        // Acknowledgements leave as soon as the modem is free, unless the protocol is slotted.
        let ack_now = matches!(front.1, Kind::Ack { .. }) && !link_params.access.acks_wait();
        // The copies of a frame on several modems, deciding at the same moment, share the
        // first one's decision: they go out together.
        let key = (ev.vehicle, front.0, ev.t.to_bits());
        let decision = match decided.get(&key) {
            Some(&d) => d,
            None if ack_now => Decision::Send,
            None => {
                let mut ctx = Ctx {
                    t: ev.t,
                    vehicle: ev.vehicle,
                    clock_rate: m.clock_rate(ev.vehicle),
                    busy: &mut busy,
                    idle_since: &mut idle_since,
                    state: &mut modems.access,
                    rng: &mut rng.0,
                };
                let d = match link_params.access.decide(&mut ctx) {
                    Decision::Count { from, slot, left } => count_down(
                        ev.t,
                        (from, slot, left),
                        modems,
                        (
                            (!m.slot_by_slot).then_some(&mut countdowns),
                            (ev.vehicle, &pos),
                            heard.get(),
                        ),
                        (reach, || Air::cells(air.get_or_init(|| Air::new(m, reach)))),
                    ),
                    d => d,
                };
                decided.insert(key, d);
                d
            }
        };
        let retry = match decision {
            Decision::Send => None,
            Decision::At(t) => Some(t),
            Decision::Count { .. } => unreachable!("counted down above"),
            // All modems of a vehicle that defer at the same moment share one back-off, so
            // that copies of a frame on several modems stay in sync.
            Decision::Backoff(max) => Some(
                *backoffs
                    .entry((ev.vehicle, ev.t.to_bits()))
                    .or_insert_with(|| {
                        stats.cs_deferrals += 1;
                        ev.t + rng.0.random::<f64>() * max
                    }),
            ),
        };
        if let Some(retry) = retry {
            modems.ports[ev.modem].busy_until = retry;
            if retry < t_end {
                heap.push(StartEvent { t: retry, ..ev });
            }
            continue;
        }
        let Some(frame) = modems.ports[ev.modem].queue.pop_front() else {
            continue;
        };
        modems.queued -= 1;
        let port = &mut modems.ports[ev.modem];
        let airtime = params.airtime(frame.payload.len());
        let end = ev.t + airtime;
        port.busy_until = end;
        stats.led_on_s += airtime;
        stats.led_energy_j += params.led.power * airtime;
        // A unicast's copies, and the acknowledgements of one, are its flow's LED time.
        let flow = match frame.kind {
            Kind::Unicast { to, .. } => Some((ev.vehicle, to)),
            Kind::Ack { to, .. } => Some((to, ev.vehicle)),
            Kind::Broadcast => None,
        };
        if let Some((from, to)) = flow {
            let f = m.flows.get(from, to);
            f.led_on_s += airtime;
            f.led_energy_j += params.led.power * airtime;
        }
        if let Kind::Unicast { ack: true, .. } = frame.kind
            && let Some(p) = &mut link.state().pending
            && p.seq == frame.seq
        {
            // The wait for the acknowledgement starts when the last copy has ended.
            let wait = end + link_params.ack_timeout;
            p.deadline = if p.deadline.is_finite() {
                p.deadline.max(wait)
            } else {
                wait
            };
        }
        m.txs.push(Transmission {
            id: m.next_id,
            tx: ev.vehicle,
            modem: ev.modem,
            start: ev.t,
            end,
            seq: frame.seq,
            sent: frame.ready,
            bits: params.frame_bits(frame.payload.len()),
            payload: frame.payload,
            pose,
            kind: frame.kind,
        });
        if let Some(air) = air.get_mut() {
            air.push(m.txs.len() - 1, &m.txs[m.txs.len() - 1]);
        }
        m.next_id += 1;
        m.started.0 += 1;
        m.started.1 += m.txs.last().map_or(0, |t| t.bits);
        if let Some(next) = port.queue.front() {
            let start = next.ready.max(end);
            if start < t_end {
                heap.push(StartEvent {
                    t: start,
                    vehicle: ev.vehicle,
                    modem: ev.modem,
                    epoch: epochs.get(&(ev.vehicle, ev.modem)).copied().unwrap_or(0),
                });
            }
        }
        // The vehicles counting down near it are asked again at their next boundary.
        {
            countdowns.frame_started(&pose.position, ev.t, reach, &mut woken);
            for w in woken.drain(..) {
                wake(
                    &mut items[index[&w.vehicle]].2,
                    &w,
                    (&mut epochs, &mut heap, t_end),
                );
            }
        }
    }
    // Those still counting at the end of the step are set where the slot-by-slot count leaves
    // them (the next step's poses may change what they hear).
    {
        countdowns.step_ended(t_end, &mut woken);
        for w in woken.drain(..) {
            wake(
                &mut items[index[&w.vehicle]].2,
                &w,
                (&mut epochs, &mut heap, t_end),
            );
        }
    }
    ids.retain(|&v| {
        let it = &items[index[&v]];
        it.2.queued > 0 || it.5.busy()
    });
    m.waiting = ids;
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
    (countdowns, (vehicle, pos), heard): (
        Option<&mut Countdowns>,
        (u32, &shoal_model::math::Vec3),
        Option<(f64, f64)>,
    ),
    (reach, cells): (f64, impl FnOnce() -> Cells),
) -> Decision {
    let quiet = modems.ports.iter().all(|p| p.busy_until <= t);
    let mut fronts = modems.ports.iter().filter_map(|p| p.queue.front());
    let together = fronts
        .next()
        .is_some_and(|f| fronts.all(|g| g.seq == f.seq));
    let target = match (countdowns, heard) {
        (Some(c), Some(heard)) if quiet && together => c.start(
            (vehicle, pos),
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

/// Vehicle's `modems` are asked earlier than they said (`w`): each port that waits for the
/// boundary said waits for `w.at` instead, its earlier event made stale.
fn wake(
    modems: &mut Modems,
    w: &Wake,
    (epochs, heap, t_end): (
        &mut FastMap<(u32, usize), u32>,
        &mut BinaryHeap<StartEvent>,
        f64,
    ),
) {
    modems.access.counter = Some(w.left);
    for (k, port) in modems.ports.iter_mut().enumerate() {
        if port.queue.is_empty() || port.busy_until.to_bits() != w.target.to_bits() {
            continue;
        }
        port.busy_until = w.at;
        let epoch = epochs.entry((w.vehicle, k)).or_default();
        *epoch += 1;
        if w.at < t_end {
            heap.push(StartEvent {
                t: w.at,
                vehicle: w.vehicle,
                modem: k,
                epoch: *epoch,
            });
        }
    }
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
    let frame0 = ledger.frames(logical.iter().map(|l| {
        let f = l.first();
        let bytes = u32::try_from(f.payload.len()).unwrap_or(u32::MAX);
        (f.tx, f.sent, f.end, bytes)
    }));
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
    medium.waiting.extend(linked);
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
