//! The three step systems of the medium: [`comm_snapshot_system`] (poses, grid, pruning),
//! [`comm_transmit_system`] (queues, access, carrier sense) and [`comm_deliver_system`] (every
//! reception decided at its receiver).

use super::frames::{CommRng, Inbox, Modems, Outbox, Queued, Received};
use super::grid::Grid;
use super::medium::{Logical, Medium, Transmission, received_power};
use super::stats::{CommStats, DIST_BIN, DIST_BINS, Outcome, Tally, latency_bin};
use crate::components::{Kind, StaticGeometry, VehicleId};
use crate::fleet::Fleet;
use crate::parallel::{Loop, Parallel};
use crate::rng::VehicleRng;
use bevy_ecs::prelude::*;
use rand::RngExt;
use shoal_model::math::Vec3;
use shoal_model::optics::{
    Access, LinkGeometry, ModemPose, background_current, ber_ook, frame_error_rate, noise_variance,
};
use shoal_model::vehicle::VehicleModel;
use std::collections::{BinaryHeap, HashMap};
use std::sync::Arc;

/// Step phase 1: snapshot poses, rebuild the grid, prune old transmissions.
pub fn comm_snapshot_system(
    clock: Res<crate::components::Clock>,
    mut medium: ResMut<Medium>,
    fleet: Res<Fleet>,
    q: Query<(&Modems, &Outbox)>,
) {
    if !medium.active() {
        return;
    }
    // Nothing on the air and nothing waiting to go: the medium has no work this step.
    let idle = medium.txs.is_empty()
        && q.iter()
            .all(|(modems, out)| out.0.is_empty() && modems.queued == 0);
    if idle {
        return;
    }
    let m = &mut *medium;
    for (pose, v) in m.poses.iter_mut().zip(fleet.as_slice()) {
        let r = &v.physics.state.rigid;
        *pose = (r.position, r.attitude);
    }
    m.update_grid();
    // A frame ending in the coming steps started at most `max_airtime` before its end; what
    // ended before that can no longer overlap it.
    let horizon = clock.t() - m.max_airtime - clock.dt;
    m.txs.retain(|t| t.end > horizon);
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
    let rx = &medium.consts[me as usize][k];
    medium
        .txs
        .iter()
        .filter(|x| x.tx != me && x.start <= t && x.end > t)
        .map(|x| {
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
        })
        .sum()
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

/// Step phase 2: queue handed-over frames and start transmissions in time order.
pub fn comm_transmit_system(
    clock: Res<crate::components::Clock>,
    geo: Res<StaticGeometry>,
    mut medium: ResMut<Medium>,
    mut q: Query<(
        &VehicleId,
        &Kind,
        &mut Outbox,
        &mut Modems,
        &mut CommRng,
        &mut CommStats,
    )>,
) {
    if !medium.active() {
        return;
    }
    let pending = |out: &Outbox, modems: &Modems| !out.0.is_empty() || modems.queued > 0;
    if !q
        .iter()
        .any(|(_, _, out, modems, _, _)| pending(out, modems))
    {
        return;
    }
    let t_end = clock.t() + clock.dt;
    let mut items: Vec<_> = q.iter_mut().filter(|it| pending(&it.2, &it.3)).collect();
    items.sort_by_key(|it| it.0.0);
    let mut heap = BinaryHeap::new();
    for (id, kind, outbox, modems, _, stats) in &mut items {
        let params = &kind.0.params.modems;
        let modems = &mut **modems;
        for f in outbox.0.drain(..) {
            let targets: Vec<usize> = match f.modem {
                Some(k) if k < params.len() => vec![k],
                Some(_) => continue,
                None => (0..params.len()).collect(),
            };
            if targets
                .iter()
                .any(|&k| f.payload.len() > params[k].max_payload)
            {
                stats.oversize += 1;
                continue;
            }
            let seq = modems.next_seq;
            modems.next_seq = modems.next_seq.wrapping_add(1);
            let payload: Arc<[u8]> = f.payload.into();
            let mut queued_any = false;
            for k in targets {
                let port = &mut modems.ports[k];
                if port.queue.len() >= params[k].queue_frames {
                    stats.queue_overflow += 1;
                } else {
                    port.queue.push_back(Queued {
                        payload: payload.clone(),
                        ready: f.ready,
                        seq,
                    });
                    modems.queued += 1;
                    queued_any = true;
                }
            }
            if queued_any {
                stats.sent += 1;
            }
        }
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
    while let Some(ev) = heap.pop() {
        let (_, kind, _, modems, rng, stats) = &mut items[index[&ev.vehicle]];
        let params = &kind.0.params.modems[ev.modem];
        let (pos, att) = m.poses[ev.vehicle as usize];
        let pose = ModemPose::of(params, &pos, &att);
        // Carrier sense listens with all of the vehicle's photodiodes, and all modems of a
        // vehicle that defer at the same moment share one back-off, so that copies of a frame
        // on several modems stay in sync.
        if let Access::CarrierSense {
            threshold,
            backoff_max,
        } = params.access
            && kind.0.params.modems.iter().enumerate().any(|(k, rxm)| {
                sensed_power(
                    m,
                    &geo.0,
                    ev.vehicle,
                    k,
                    &ModemPose::of(rxm, &pos, &att),
                    ev.t,
                ) > threshold
            })
        {
            let retry = *backoffs
                .entry((ev.vehicle, ev.t.to_bits()))
                .or_insert_with(|| {
                    stats.cs_deferrals += 1;
                    ev.t + rng.0.random::<f64>() * backoff_max
                });
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
        let end = ev.t + params.airtime(frame.payload.len());
        port.busy_until = end;
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
}

/// Step phase 3: decide every reception of frames that ended in this step.
pub fn comm_deliver_system(
    clock: Res<crate::components::Clock>,
    par: Res<Parallel>,
    geo: Res<StaticGeometry>,
    mut medium: ResMut<Medium>,
    mut q: Query<(&VehicleId, &Kind, &mut Inbox, &mut CommRng, &mut CommStats)>,
) {
    if !medium.active() {
        return;
    }
    let (t0, t_end) = (clock.t(), clock.t() + clock.dt);
    let m = &*medium;
    // Frames ending in (t0, t_end], grouped into logical frames, in (end, id) order.
    let mut ended: Vec<&Transmission> = m
        .txs
        .iter()
        .filter(|x| x.end > t0 && x.end <= t_end)
        .collect();
    ended.sort_by(|a, b| a.end.total_cmp(&b.end).then(a.id.cmp(&b.id)));
    let mut logical: Vec<Logical<'_>> = Vec::new();
    let mut by_key: HashMap<(u32, u32, u64), usize> = HashMap::new();
    for t in ended {
        let key = (t.tx, t.seq, t.start.to_bits());
        match by_key.get(&key) {
            Some(&i) => logical[i].copies.push(t),
            None => {
                by_key.insert(key, logical.len());
                logical.push(Logical {
                    copies: vec![t],
                    overlap: Vec::new(),
                    p_dead: 0.0,
                });
            }
        }
    }
    if logical.is_empty() {
        return;
    }
    for l in &mut logical {
        l.p_dead = m.dead_power(l.first().bits);
    }
    // Possible interferers of each frame: overlapping in time, and close enough to the sender
    // to reach a receiver that could hear the sender (within 2 r_cut). Transmissions are
    // indexed by position for this.
    let near = 2.0 * (m.r_cut + m.max_hull_radius);
    let tx_points: Vec<Vec3> = m.txs.iter().map(|x| x.pose.position).collect();
    let mut tx_grid = Grid::default();
    tx_grid.rebuild(near / 2.0, &tx_points);
    for l in &mut logical {
        let f = l.copies[0];
        let p = m.poses[f.tx as usize].0;
        let mut overlap = Vec::new();
        tx_grid.each_in_box(&(p - Vec3::repeat(near)), &(p + Vec3::repeat(near)), |k| {
            let x = &m.txs[k as usize];
            if x.start < f.end
                && x.end > f.start
                && !(x.tx == f.tx && x.seq == f.seq)
                && (x.pose.position - p).norm_squared() <= near * near
            {
                overlap.push(x);
            }
            true
        });
        // Grid order is spatial; keep the medium's order so results do not depend on it.
        overlap.sort_unstable_by_key(|x| x.id);
        l.overlap = overlap;
    }
    // Candidate receivers of each logical frame (vehicles within the cut-off range), as
    // (receiver, frame) pairs counting-sorted by receiver.
    let n = m.poses.len();
    let reach = m.r_cut + m.max_hull_radius;
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for (i, l) in logical.iter().enumerate() {
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
    let mut start = vec![0u32; n + 1];
    for &(r, _) in &pairs {
        start[r as usize + 1] += 1;
    }
    for k in 0..n {
        start[k + 1] += start[k];
    }
    let mut frames_of = vec![0u32; pairs.len()];
    let mut fill = start.clone();
    // `pairs` is in frame order, so each receiver's frames stay in (end, id) order.
    for &(r, i) in &pairs {
        frames_of[fill[r as usize] as usize] = i;
        fill[r as usize] += 1;
    }
    // The medium's transmissions by sender, for the half-duplex test (a receiver's own
    // frames overlapping the one it would receive): everything that can overlap a frame
    // ending now is still in `txs`.
    let mut own: Vec<(u32, u32)> = (0..m.txs.len() as u32)
        .map(|k| (m.txs[k as usize].tx, k))
        .collect();
    own.sort_unstable();
    let own = Own { m, by_sender: own };
    let mut items: Vec<_> = q
        .iter_mut()
        .filter(|it| start[it.0.0 as usize + 1] > start[it.0.0 as usize])
        .collect();
    let geo = &geo.0;
    // Outcomes by second (a step reaches into the next second at most) and kind, and the
    // distance and latency histograms: tallied per chunk of receivers, summed afterwards.
    let second0 = t0.floor();
    let tallies = par.for_each_with(
        Loop::Delivery,
        &mut items,
        Tally::new,
        |tally, (id, kind, inbox, rng, stats)| {
            let frames =
                &frames_of[start[id.0 as usize] as usize..start[id.0 as usize + 1] as usize];
            let mut scratch = Scratch::default();
            for &i in frames {
                let l = &logical[i as usize];
                let o = receive(
                    m,
                    geo,
                    id.0,
                    &kind.0,
                    &own,
                    l,
                    &mut rng.0,
                    stats,
                    inbox,
                    &mut scratch,
                    tally,
                );
                let s = usize::from(l.first().end.floor() > second0);
                tally.outcomes[s][o.index()] += 1;
            }
        },
    );
    let mut total = Tally::new();
    for t in &tallies {
        total.add(t);
    }
    let medium = &mut *medium;
    for ((a, d), (ta, td)) in medium.by_distance.iter_mut().zip(&total.by_distance) {
        *a += ta;
        *d += td;
    }
    for (h, t) in medium.latency_hist.iter_mut().zip(&total.latency) {
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

/// The medium's transmissions sorted by sender.
struct Own<'a> {
    m: &'a Medium,
    /// (sender, index into `m.txs`), sorted.
    by_sender: Vec<(u32, u32)>,
}

impl Own<'_> {
    /// Whether modem `modem` of vehicle `v` was transmitting at some time in (start, end).
    fn transmitting_during(&self, v: u32, modem: usize, start: f64, end: f64) -> bool {
        let from = self.by_sender.partition_point(|&(s, _)| s < v);
        self.by_sender[from..]
            .iter()
            .take_while(|&&(s, _)| s == v)
            .map(|&(_, k)| &self.m.txs[k as usize])
            .any(|x| x.modem == modem && x.start < end && x.end > start)
    }
}

/// Buffers reused across the receptions of one receiver.
#[derive(Default)]
struct Scratch<'a> {
    interferers: Vec<&'a Transmission>,
    hulls: Vec<(u32, bool)>,
}

/// Decides one logical frame at one receiver; returns whether it was delivered.
#[allow(clippy::too_many_arguments)]
fn receive<'a>(
    m: &Medium,
    geo: &shoal_world::geometry::Geometry,
    me: u32,
    kind: &VehicleModel,
    own: &Own<'_>,
    l: &Logical<'a>,
    rng: &mut VehicleRng,
    stats: &mut CommStats,
    inbox: &mut Inbox,
    scratch: &mut Scratch<'a>,
    tally: &mut Tally,
) -> Outcome {
    let f = l.first();
    let (pos, att) = m.poses[me as usize];
    let latency = f.end - f.sent;
    let distance = (m.poses[f.tx as usize].0 - pos).norm();
    let area = m.consts[me as usize]
        .iter()
        .map(|c| c.area)
        .fold(0.0, f64::max);
    if m.power_bound(l, me, area) < l.p_dead {
        // Undecodable even in the best case (P(delivery) < 1e-12): lost to range.
        stats.record(f.tx, Outcome::Range, latency, f.end, m.log_links);
        let bin = ((distance / DIST_BIN) as usize).min(DIST_BINS - 1);
        tally.by_distance[bin].0 += 1;
        return Outcome::Range;
    }
    let my = &m.consts[me as usize];
    let mut best = Outcome::Range;
    let mut got: Option<(usize, f64, f64)> = None;
    // Hull occlusion per other vehicle, computed once for this reception.
    let hulls = &mut scratch.hulls;
    hulls.clear();
    let mut clear_of_hulls = |other: u32| -> bool {
        if let Some(&(_, c)) = hulls.iter().find(|h| h.0 == other) {
            return c;
        }
        let c = m.vehicles_clear(other, me);
        hulls.push((other, c));
        c
    };
    let path_clear = |a: &ModemPose, b: &ModemPose| {
        a.position.z > 0.0 && b.position.z > 0.0 && geo.line_of_sight(&a.position, &b.position)
    };
    // Interferers within range of this receiver.
    let reach = m.r_cut + m.max_hull_radius;
    let interferers = &mut scratch.interferers;
    interferers.clear();
    interferers.extend(
        l.overlap
            .iter()
            .copied()
            .filter(|x| x.tx != me && (x.pose.position - pos).norm_squared() <= reach * reach),
    );
    for (k, rxm) in kind.params.modems.iter().enumerate() {
        let pose = ModemPose::of(rxm, &pos, &att);
        // Signal: the sum of the copies this modem can see.
        let mut p_sig = 0.0;
        let mut outcome = Outcome::Range;
        for c in &l.copies {
            let p = m.power_between(c, &pose, &my[k]);
            if p <= 0.0 {
                continue;
            }
            if path_clear(&c.pose, &pose) && clear_of_hulls(c.tx) {
                p_sig += p;
            } else {
                outcome = outcome.max(Outcome::Occluded);
            }
        }
        if p_sig <= 0.0 {
            best = best.max(outcome);
            continue;
        }
        if own.transmitting_during(me, k, f.start, f.end) {
            best = best.max(Outcome::HalfDuplex);
            continue;
        }
        // Interference: other transmissions overlapping this frame in time.
        let (mut p_int, mut p_max) = (0.0f64, 0.0f64);
        for x in interferers.iter() {
            let p = m.power_between(x, &pose, &my[k]);
            if p <= 0.0 || !path_clear(&x.pose, &pose) || !clear_of_hulls(x.tx) {
                continue;
            }
            p_int += p;
            p_max = p_max.max(p);
        }
        if p_max * rxm.capture_ratio > p_sig {
            best = best.max(Outcome::Collision);
            continue;
        }
        // Delivered when a uniform draw is at least the frame error rate. The Chernoff bound
        // FER ≤ n·BER ≤ n·½·e^(−SNR/2) settles most draws without the error function; the
        // decision is exactly the one the full rate gives.
        let i_s = rxm.rx.responsivity * p_sig;
        let i_bg = background_current(&rxm.rx, &m.ambient, pose.position.z);
        let snr = i_s * i_s / noise_variance(&rxm.rx, i_s, i_bg, p_int);
        let u = rng.random::<f64>();
        let bound = f.bits as f64 * 0.5 * (-0.5 * snr).exp();
        if u < bound && u < frame_error_rate(ber_ook(snr), f.bits) {
            best = best.max(Outcome::Range);
            continue;
        }
        best = Outcome::Delivered;
        if got.is_none_or(|g| p_sig > g.1) {
            got = Some((k, p_sig, snr));
        }
    }
    stats.record(f.tx, best, latency, f.end, m.log_links);
    let bin = ((distance / DIST_BIN) as usize).min(DIST_BINS - 1);
    tally.by_distance[bin].0 += 1;
    if let Some((modem, power, snr)) = got {
        tally.by_distance[bin].1 += 1;
        tally.latency[latency_bin(latency)] += 1;
        inbox.0.push(Received {
            t: f.end,
            from: f.tx,
            seq: f.seq,
            modem,
            power,
            snr,
            sent: f.sent,
            payload: f.payload.clone(),
        });
    }
    best
}
