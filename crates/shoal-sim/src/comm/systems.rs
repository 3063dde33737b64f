//! The three step systems of the medium: [`comm_snapshot_system`] (poses, grid, pruning),
//! [`comm_transmit_system`] (queues, access, carrier sense) and [`comm_deliver_system`] (every
//! reception decided at its receiver).

use super::ending::{ByVehicle, Ended, candidates, own_transmissions};
use super::frames::{
    CommRng, FrameOutcome, Inbox, Kind, Modems, OutFrame, Outbox, Queued, Received,
};
use super::ledger::Ledger;
use super::links::Outcome;
use super::mac::{AckDue, Ctx, Decision, Link, ModemLink, Pending};
use super::medium::{Logical, Medium, Transmission, received_power};
use super::modem_lanes::ModemLanes;
use super::stats::{CommStats, DIST_BIN, DIST_BINS, Tally, latency_bin};
use crate::components::{StaticGeometry, VehicleEntities, VehicleId};
use crate::parallel::{Loop, Parallel};
use crate::rng::VehicleRng;
use bevy_ecs::prelude::*;
use rand::RngExt;
use shoal_model::math::Vec3;
use shoal_model::optics::{
    LinkGeometry, ModemParams, ModemPose, background_current, ber_ook, frame_error_rate,
    noise_variance,
};
use shoal_model::vehicle::VehicleModel;
use std::collections::{BinaryHeap, HashMap};
use std::sync::Arc;

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

/// Received optical power at a modem from every transmission active at time `t` except
/// those of vehicle `me` [W] (for carrier sense).
fn sensed_power(
    medium: &Medium,
    geo: &shoal_world::geometry::Geometry,
    me: u32,
    k: usize,
    pose: &ModemPose,
    t: f64,
) -> f64 {
    medium
        .txs
        .iter()
        .filter(|x| x.tx != me && x.start <= t && x.end > t)
        .map(|x| sensed_one(medium, geo, x, me, k, pose))
        .sum()
}

/// The optical power transmission `x` delivers to modem `k` of vehicle `me` at `pose` \[W\]:
/// the link budget, zero beyond the cut-off range or when walls, obstacles or hulls block it.
fn sensed_one(
    medium: &Medium,
    geo: &shoal_world::geometry::Geometry,
    x: &Transmission,
    me: u32,
    k: usize,
    pose: &ModemPose,
) -> f64 {
    let rx = &medium.consts[me as usize][k];
    let g = LinkGeometry::between(&x.pose, pose);
    if g.distance > medium.r_cut {
        return 0.0;
    }
    let p = received_power(
        &medium.consts[x.tx as usize][x.modem],
        rx,
        &g,
        medium.attenuation,
    );
    if p > 0.0
        && geo.line_of_sight(&x.pose.position, &pose.position)
        && medium.vehicles_clear(x.tx, me)
    {
        p
    } else {
        0.0
    }
}

/// For carrier sensing by vehicle `v` at `pos`, `att` with threshold `threshold` \[W\] at time
/// `t` \[s\]: `None` if the power its photodiodes receive from other vehicles' frames on the
/// air exceeds the threshold at one of them, else the end of the last frame that alone did
/// (or the vehicle's own last frame, if later; −∞ if none) \[s\].
#[allow(clippy::too_many_arguments)]
fn idle_since(
    m: &Medium,
    geo: &shoal_world::geometry::Geometry,
    v: u32,
    pos: &Vec3,
    att: &shoal_model::math::Quat,
    t: f64,
    threshold: f64,
) -> Option<f64> {
    let modems = &m.kinds[v as usize].params.modems;
    let poses: Vec<ModemPose> = modems.iter().map(|p| ModemPose::of(p, pos, att)).collect();
    let mut now = vec![0.0; modems.len()];
    let mut since = f64::NEG_INFINITY;
    // A frame that starts at this very instant is not heard yet (sensing takes time): two
    // stations whose back-offs end together both send, and collide.
    for x in m.txs.iter().filter(|x| x.start < t) {
        if x.tx == v {
            since = since.max(x.end.min(t));
            continue;
        }
        for (k, pose) in poses.iter().enumerate() {
            let p = sensed_one(m, geo, x, v, k, pose);
            if x.end > t {
                now[k] += p;
            } else if p > threshold {
                since = since.max(x.end);
            }
        }
    }
    if now.iter().any(|&p| p > threshold) {
        None
    } else {
        Some(since)
    }
}

#[derive(PartialEq)]
struct StartEvent {
    t: f64,
    vehicle: u32,
    modem: usize,
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

/// Puts frame `f` (sequence number `seq`) into the queues of its modem(s) — at the front for
/// `front` (acknowledgements, retransmissions) — unless a queue is full (counted) or the
/// payload too long for one of them (counted, and then nowhere). Returns whether it went into
/// some queue.
fn enqueue(
    params: &[ModemParams],
    modems: &mut Modems,
    stats: &mut CommStats,
    f: &OutFrame,
    payload: Arc<[u8]>,
    (seq, kind, front): (u32, Kind, bool),
) -> bool {
    let targets = match f.modem {
        Some(k) if k < params.len() => k..k + 1,
        Some(_) => return false,
        None => 0..params.len(),
    };
    if targets
        .clone()
        .any(|k| f.payload.len() > params[k].max_payload)
    {
        stats.oversize += 1;
        return false;
    }
    let mut queued_any = false;
    for k in targets {
        let port = &mut modems.ports[k];
        if port.queue.len() >= params[k].queue_frames {
            stats.queue_overflow += 1;
            continue;
        }
        let q = Queued {
            payload: payload.clone(),
            ready: f.ready,
            seq,
            kind,
        };
        if front {
            port.queue.push_front(q);
        } else {
            port.queue.push_back(q);
        }
        modems.queued += 1;
        queued_any = true;
    }
    queued_any
}

/// The next sequence number of a vehicle.
fn next_seq(modems: &mut Modems) -> u32 {
    let seq = modems.next_seq;
    modems.next_seq = modems.next_seq.wrapping_add(1);
    seq
}

/// The link layer of one sending vehicle at the start of its transmit phase at `t` \[s\]:
/// acknowledgements it owes go to the front of their modems' queues; an outstanding frame
/// whose wait ran out is retransmitted or given up (`retries` of its first modem); the next
/// waiting frame becomes outstanding when none is; then the frames handed over join the queues
/// (acknowledged unicasts behind the outstanding one, in order).
fn link_layer(
    t: f64,
    params: &[ModemParams],
    links: &[ModemLink],
    (outbox, modems, stats, link, inbox): (
        &mut Outbox,
        &mut Modems,
        &mut CommStats,
        &mut Link,
        &mut Inbox,
    ),
) {
    let reliable = |f: &OutFrame| f.ack && f.to.is_some();
    if !link.busy() && !outbox.0.iter().any(reliable) {
        // The common case: broadcasts and unicasts without acknowledgement only.
        for f in outbox.0.drain(..) {
            let seq = next_seq(modems);
            let kind =
                f.to.map_or(Kind::Broadcast, |to| Kind::Unicast { to, ack: false });
            if enqueue(
                params,
                modems,
                stats,
                &f,
                f.payload.clone().into(),
                (seq, kind, false),
            ) {
                stats.sent += 1;
            }
        }
        return;
    }
    let handed: Vec<OutFrame> = outbox.0.drain(..).collect();
    let s = link.state();
    for a in std::mem::take(&mut s.acks) {
        // On every modem, like the copies of a broadcast: everyone around hears that the
        // channel is taken (802.11's acknowledgements are omnidirectional too).
        let ack = OutFrame {
            modem: None,
            payload: Vec::new(),
            ready: a.ready,
            to: Some(a.to),
            ack: false,
        };
        let seq = next_seq(modems);
        let kind = Kind::Ack {
            to: a.to,
            seq: a.seq,
        };
        if enqueue(
            params,
            modems,
            stats,
            &ack,
            Arc::from(&[][..]),
            (seq, kind, true),
        ) {
            stats.acks_sent += 1;
        }
    }
    if let Some(p) = &mut s.pending
        && p.deadline <= t
    {
        let first = p.modem.unwrap_or(0).min(links.len().saturating_sub(1));
        let retries = links.get(first).map_or(0, |l| l.retries);
        s.feedback.push((p.modem, false));
        if p.transmissions <= retries {
            p.transmissions += 1;
            p.deadline = f64::INFINITY;
            stats.retransmissions += 1;
            let again = OutFrame {
                modem: p.modem,
                payload: Vec::new(),
                ready: t,
                to: Some(p.to),
                ack: true,
            };
            let kind = Kind::Unicast {
                to: p.to,
                ack: true,
            };
            let payload = p.payload.clone();
            // `enqueue` checks the length of `again.payload`: the frame's own length passed.
            if !enqueue(params, modems, stats, &again, payload, (p.seq, kind, true)) {
                // Its queues are full: the wait starts over (it was counted as an overflow).
                p.deadline = t;
            }
        } else {
            stats.gave_up += 1;
            let p = s.pending.take().expect("checked");
            inbox.outcomes.push(p.event(t, FrameOutcome::GaveUp));
        }
    }
    // Frames wait behind the outstanding one up to the first modem's queue length.
    let room = params.first().map_or(0, |p| p.queue_frames);
    for f in handed {
        if reliable(&f) {
            if s.waiting.len() < room {
                s.waiting.push_back(f);
            } else {
                stats.queue_overflow += 1;
                let refused = Pending {
                    seq: 0,
                    to: f.to.unwrap_or(u32::MAX),
                    modem: f.modem,
                    payload: f.payload.into(),
                    sent: f.ready,
                    transmissions: 0,
                    deadline: t,
                };
                inbox.outcomes.push(refused.event(t, FrameOutcome::GaveUp));
            }
            continue;
        }
        let seq = next_seq(modems);
        let kind =
            f.to.map_or(Kind::Broadcast, |to| Kind::Unicast { to, ack: false });
        if enqueue(
            params,
            modems,
            stats,
            &f,
            f.payload.clone().into(),
            (seq, kind, false),
        ) {
            stats.sent += 1;
        }
    }
    // The medium access learns what became of the outstanding frames (acknowledged in the
    // delivery phase, timed out above) before it decides on the next one.
    for (modem, acked) in s.feedback.drain(..) {
        if let Some(l) = links.get(modem.unwrap_or(0)) {
            l.access.feedback(&mut modems.access, acked);
        }
    }
    while s.pending.is_none()
        && let Some(f) = s.waiting.pop_front()
    {
        let seq = next_seq(modems);
        let to = f.to.expect("reliable frames have a destination");
        let payload: Arc<[u8]> = f.payload.clone().into();
        let kind = Kind::Unicast { to, ack: true };
        if !enqueue(
            params,
            modems,
            stats,
            &f,
            payload.clone(),
            (seq, kind, false),
        ) {
            // Refused (a full queue or too long, counted): it never went on the air.
            let refused = Pending {
                seq,
                to,
                modem: f.modem,
                payload,
                sent: f.ready,
                transmissions: 0,
                deadline: t,
            };
            inbox.outcomes.push(refused.event(t, FrameOutcome::GaveUp));
        } else {
            stats.sent += 1;
            s.pending = Some(Pending {
                seq,
                to,
                modem: f.modem,
                payload,
                sent: f.ready,
                transmissions: 1,
                deadline: f64::INFINITY,
            });
        }
    }
}

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
    let kinds = &medium.kinds;
    for (id, outbox, modems, _, stats, link, inbox) in &mut items {
        let params = &kinds[id.0 as usize].params.modems;
        let links = &medium.access[id.0 as usize];
        let modems = &mut **modems;
        link_layer(
            clock.t(),
            params,
            links,
            (outbox, modems, stats, link, inbox),
        );
        for (k, port) in modems.ports.iter().enumerate() {
            if let Some(front) = port.queue.front() {
                let start = front.ready.max(port.busy_until).max(clock.t());
                if start < t_end {
                    heap.push(StartEvent {
                        t: start,
                        vehicle: id.0,
                        modem: k,
                    });
                }
            }
        }
    }
    let index: HashMap<u32, usize> = items
        .iter()
        .enumerate()
        .map(|(i, it)| (it.0.0, i))
        .collect();
    let m = &mut *medium;
    let mut backoffs: HashMap<(u32, u64), f64> = HashMap::new();
    let mut decided: HashMap<(u32, u32, u64), Decision> = HashMap::new();
    while let Some(ev) = heap.pop() {
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
                    ev.vehicle,
                    k,
                    &ModemPose::of(rxm, &pos, &att),
                    ev.t,
                ) > threshold
            })
        };
        let mut idle_since =
            |threshold: f64| idle_since(m, &geo.0, ev.vehicle, &pos, &att, ev.t, threshold);
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
                let d = link_params.access.decide(&mut ctx);
                decided.insert(key, d);
                d
            }
        };
        let retry = match decision {
            Decision::Send => None,
            Decision::At(t) => Some(t),
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
                });
            }
        }
    }
    ids.retain(|&v| {
        let it = &items[index[&v]];
        it.2.queued > 0 || it.5.busy()
    });
    m.waiting = ids;
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
        || (Tally::new(), Scratch::default(), Vec::new(), Vec::new()),
        |(tally, scratch, events, linked), (id, inbox, rng, link)| {
            let mut rx = Listener::new(m, id.0, scratch);
            let mut mail = Mail { inbox, link };
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
    for (t, _, events, l) in &states {
        total.add(t);
        ledger.append(events, m.log_links);
        linked.extend_from_slice(l);
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

/// Buffers of the delivery phase, one set per chunk of receivers, reused from receiver to
/// receiver.
#[derive(Default)]
struct Scratch {
    /// The interferers of the current reception near its receiver (positions in the frame's
    /// [`Logical::overlap`]).
    interferers: Vec<u32>,
    /// Hull occlusion between the current receiver and other vehicles (other vehicle, clear),
    /// computed once per step: it depends on the vehicles' positions only.
    hulls: Vec<(u32, bool)>,
    /// The current receiver's modems (empty until a reception needs them).
    modems: ModemLanes,
    /// The power of each copy of the current frame at each modem, copy after copy \[W\].
    signal: Vec<f64>,
}

/// One receiver of the frames ending in a step, with what it needs for every reception.
struct Listener<'s> {
    /// Its id.
    me: u32,
    /// Its model.
    kind: &'s VehicleModel,
    /// Body position \[m\] and attitude.
    pos: Vec3,
    att: shoal_model::math::Quat,
    /// Largest photodiode area of its modems \[m²\].
    area: f64,
    /// Buffers, reset for this receiver.
    scratch: &'s mut Scratch,
}

impl<'s> Listener<'s> {
    /// Receiver `me`, its buffers `scratch` emptied for it.
    fn new(m: &'s Medium, me: u32, scratch: &'s mut Scratch) -> Self {
        let kind = &*m.kinds[me as usize];
        let (pos, att) = m.poses[me as usize];
        let area = m.consts[me as usize]
            .iter()
            .map(|c| c.area)
            .fold(0.0, f64::max);
        scratch.hulls.clear();
        scratch.modems.clear();
        Self {
            me,
            kind,
            pos,
            att,
            area,
            scratch,
        }
    }

    /// Hull occlusion between `other` and this receiver (see [`Medium::vehicles_clear`]),
    /// computed once per step.
    fn clear_of_hulls(hulls: &mut Vec<(u32, bool)>, m: &Medium, other: u32, me: u32) -> bool {
        if let Some(&(_, c)) = hulls.iter().find(|h| h.0 == other) {
            return c;
        }
        let c = m.vehicles_clear(other, me);
        hulls.push((other, c));
        c
    }
}

/// Where a receiver's decoded frames go: its inbox (frames for it) and its link layer
/// (acknowledgements to send and received).
struct Mail<'a> {
    inbox: &'a mut Inbox,
    link: &'a mut Link,
}

impl Mail<'_> {
    /// Frame `f` decoded at receiver `me` by `modem`: a broadcast, or a unicast for `me`
    /// that is not a retransmission already received, goes to the inbox; a unicast for `me`
    /// asking for acknowledgement is acknowledged (every copy); an acknowledgement for `me`
    /// ends its outstanding frame; others' unicasts and acknowledgements are dropped. Returns
    /// the latency of the frame an acknowledgement ended (hand-over to acknowledgement) \[s\].
    fn decoded(
        &mut self,
        me: u32,
        f: &Transmission,
        (modem, power, snr): (usize, f64, f64),
    ) -> Option<f64> {
        let mut acked = None;
        let new = match f.kind {
            Kind::Broadcast => true,
            Kind::Unicast { to, ack } if to == me => {
                !ack || {
                    let s = self.link.state();
                    s.acks.push(AckDue {
                        to: f.tx,
                        seq: f.seq,
                        ready: f.end,
                    });
                    s.first_delivery(f.tx, f.seq)
                }
            }
            Kind::Ack { to, seq } if to == me => {
                if let Some(e) = self.link.state().acknowledged(f.tx, seq, f.end) {
                    acked = Some(e.t - e.sent);
                    self.inbox.outcomes.push(e);
                }
                false
            }
            Kind::Unicast { .. } | Kind::Ack { .. } => false,
        };
        if new {
            self.inbox.frames.push(Received {
                t: f.end,
                from: f.tx,
                seq: f.seq,
                modem,
                power,
                snr,
                sent: f.sent,
                payload: f.payload.clone(),
                unicast: f.kind != Kind::Broadcast,
            });
        }
        acked
    }
}

/// Decides one logical frame at one receiver; returns the outcome.
#[allow(clippy::too_many_arguments)]
fn receive(
    m: &Medium,
    geo: &shoal_world::geometry::Geometry,
    rx: &mut Listener<'_>,
    own: &ByVehicle,
    l: &Logical<'_>,
    rng: &mut VehicleRng,
    mail: &mut Mail<'_>,
    tally: &mut Tally,
) -> Outcome {
    let f = l.first();
    let latency = f.end - f.sent;
    let distance = (m.poses[f.tx as usize].0 - rx.pos).norm();
    let bin = ((distance / DIST_BIN) as usize).min(DIST_BINS - 1);
    tally.by_distance[bin].0 += 1;
    if !m.may_decode(l, rx.me, rx.area) {
        // Undecodable even in the best case (P(delivery) < 1e-12): lost to range.
        return Outcome::OutOfBudget;
    }
    let consts = &m.consts[rx.me as usize];
    if rx.scratch.modems.is_empty() {
        let modems = &rx.kind.params.modems;
        rx.scratch.modems.fill(modems, consts, &rx.pos, &rx.att);
    }
    // Every copy's power at every modem, the modems' geometry in lanes.
    let n = consts.len();
    if n == 0 {
        // A hull without modems hears nothing (it is a candidate only by its position).
        return Outcome::OutOfBudget;
    }
    rx.scratch.signal.resize(l.copies.len() * n, 0.0);
    for (c, out) in l.copies.iter().zip(rx.scratch.signal.chunks_exact_mut(n)) {
        rx.scratch.modems.powers(m, c, consts, out);
    }
    // Interferers within range of this receiver, once a modem hears the signal.
    rx.scratch.interferers.clear();
    let mut interferers_found = false;
    let mut best = Outcome::OutOfBudget;
    let mut got: Option<(usize, f64, f64)> = None;
    for k in 0..n {
        let at = AtModem {
            m,
            geo,
            me: rx.me,
            k,
            pose: rx.scratch.modems.poses[k],
        };
        let hulls = &mut rx.scratch.hulls;
        let powers = rx.scratch.signal.iter().skip(k).step_by(n).copied();
        let p_sig = match at.signal(l, powers, hulls) {
            Ok(p) => p,
            Err(o) => {
                best = best.better(o);
                continue;
            }
        };
        if own_transmitting(m, own, rx.me, k, f.start, f.end) {
            best = best.better(Outcome::HalfDuplex);
            continue;
        }
        if !interferers_found {
            interferers_found = true;
            near_interferers(m, l, rx.me, &rx.pos, &mut rx.scratch.interferers);
        }
        let rxm = &rx.kind.params.modems[k];
        let p = at.interference(l, &rx.scratch.interferers, &mut rx.scratch.hulls);
        match decode(m, rxm, &at.pose, f.bits, p_sig, p, rng) {
            Ok(snr) => {
                best = Outcome::Delivered;
                if got.is_none_or(|g| p_sig > g.1) {
                    got = Some((k, p_sig, snr));
                }
            }
            Err(o) => best = best.better(o),
        }
    }
    if let Some(got) = got {
        tally.by_distance[bin].1 += 1;
        tally.latency[latency_bin(latency)] += 1;
        if let Some(l) = mail.decoded(rx.me, f, got) {
            tally.acknowledged[latency_bin(l)] += 1;
        }
    }
    best
}

/// Whether modem `modem` of vehicle `v` was transmitting at some time in (start, end) \[s\].
fn own_transmitting(
    m: &Medium,
    own: &ByVehicle,
    v: u32,
    modem: usize,
    start: f64,
    end: f64,
) -> bool {
    own.of(v)
        .iter()
        .map(|&k| &m.txs[k as usize])
        .any(|x| x.modem == modem && x.start < end && x.end > start)
}

/// Fills `out` with the positions in `l.overlap` of the transmissions of other vehicles
/// within range (r_cut plus a hull) of receiver `me` at `pos` \[m\], in order.
fn near_interferers(m: &Medium, l: &Logical<'_>, me: u32, pos: &Vec3, out: &mut Vec<u32>) {
    let reach = m.r_cut + m.max_hull_radius;
    out.extend(
        l.overlap
            .iter()
            .enumerate()
            .filter(|(_, x)| x.tx != me && (x.pose.position - pos).norm_squared() <= reach * reach)
            .map(|(i, _)| i as u32),
    );
}

/// One receiving modem of one reception.
struct AtModem<'a> {
    /// The medium.
    m: &'a Medium,
    /// Walls and obstacles.
    geo: &'a shoal_world::geometry::Geometry,
    /// The receiver.
    me: u32,
    /// The modem's index.
    k: usize,
    /// Its pose.
    pose: ModemPose,
}

impl AtModem<'_> {
    /// Whether the ray from `a` to this modem is clear of the water surface, walls and
    /// obstacles.
    fn path_clear(&self, a: &ModemPose) -> bool {
        let b = &self.pose;
        a.position.z > 0.0 && b.position.z > 0.0 && self.geo.line_of_sight(&a.position, &b.position)
    }

    /// The received power of the copies of `l` this modem can see \[W\], or why it has none:
    /// [`Outcome::Occluded`] if some copy would reach it but was blocked, else
    /// [`Outcome::OutOfBudget`]. `powers`: each copy's power at this modem, unoccluded
    /// ([`Medium::power_between`]).
    fn signal(
        &self,
        l: &Logical<'_>,
        powers: impl Iterator<Item = f64>,
        hulls: &mut Vec<(u32, bool)>,
    ) -> Result<f64, Outcome> {
        let mut p_sig = 0.0;
        let mut outcome = Outcome::OutOfBudget;
        for (c, p) in l.copies.iter().zip(powers) {
            if p <= 0.0 {
                continue;
            }
            if self.path_clear(&c.pose) && Listener::clear_of_hulls(hulls, self.m, c.tx, self.me) {
                p_sig += p;
            } else {
                outcome = outcome.better(Outcome::Occluded);
            }
        }
        if p_sig <= 0.0 {
            Err(outcome)
        } else {
            Ok(p_sig)
        }
    }

    /// Total and largest power of the interferers of `l` at `picked` positions of its overlap
    /// list that reach this modem \[W\], in order.
    fn interference(
        &self,
        l: &Logical<'_>,
        picked: &[u32],
        hulls: &mut Vec<(u32, bool)>,
    ) -> (f64, f64) {
        let my = &self.m.consts[self.me as usize][self.k];
        let (mut p_int, mut p_max) = (0.0f64, 0.0f64);
        for &i in picked {
            let x = l.overlap[i as usize];
            let p = self.m.power_between(x, &self.pose, my);
            if p <= 0.0
                || !self.path_clear(&x.pose)
                || !Listener::clear_of_hulls(hulls, self.m, x.tx, self.me)
            {
                continue;
            }
            p_int += p;
            p_max = p_max.max(p);
        }
        (p_int, p_max)
    }
}

/// Decodes a frame of `bits` line bits with signal `p_sig` and interference `(total,
/// largest)` \[W\] at modem `rxm` at `pose`: the SNR if delivered, else the outcome
/// ([`Outcome::Collided`] when the largest interferer is not weak enough to capture over,
/// [`Outcome::OutOfBudget`] for bit errors). Draws one number from `rng` unless it collided.
fn decode(
    m: &Medium,
    rxm: &ModemParams,
    pose: &ModemPose,
    bits: u64,
    p_sig: f64,
    (p_int, p_max): (f64, f64),
    rng: &mut VehicleRng,
) -> Result<f64, Outcome> {
    if p_max * rxm.capture_ratio > p_sig {
        return Err(Outcome::Collided);
    }
    // Delivered when a uniform draw is at least the frame error rate. The Chernoff bound
    // FER ≤ n·BER ≤ n·½·e^(−SNR/2) settles most draws without the error function; the
    // decision is exactly the one the full rate gives.
    let i_s = rxm.rx.responsivity * p_sig;
    let i_bg = background_current(&rxm.rx, &m.ambient, pose.position.z);
    let snr = i_s * i_s / noise_variance(&rxm.rx, i_s, i_bg, p_int);
    let u = rng.random::<f64>();
    let bound = bits as f64 * 0.5 * (-0.5 * snr).exp();
    if u < bound && u < frame_error_rate(ber_ook(snr), bits) {
        return Err(Outcome::OutOfBudget);
    }
    Ok(snr)
}
