//! The link layer at a vehicle, above its medium access: on the sending side
//! ([`link_layer`], at the start of the transmit phase) the frames handed over enter the
//! modems' queues, acknowledgements owed go first, an outstanding acknowledged frame is
//! retransmitted or given up; on the receiving side ([`Mail`], in the delivery phase) a
//! decoded frame goes to the inbox if it is for this vehicle, is acknowledged if it asks to
//! be, and an acknowledgement ends the outstanding frame. The state is [`super::Link`]
//! (`mac/arq.rs`).

use super::flows::{FlowEvent, Flows};
use super::frames::{
    FrameEvent, FrameOutcome, Inbox, Kind, Modems, OutFrame, Outbox, Queued, Received,
};
use super::mac::{AckDue, Link, LinkState, ModemLink, Pending};
use super::medium::Transmission;
use super::stats::CommStats;
use shoal_model::optics::ModemParams;
use std::sync::Arc;

/// A sending vehicle's components the link layer works on.
pub(super) type Parts<'a> = (
    &'a mut Outbox,
    &'a mut Modems,
    &'a mut CommStats,
    &'a mut Link,
    &'a mut Inbox,
);

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
        if port.queued() >= params[k].queue_frames {
            stats.queue_overflow += 1;
            continue;
        }
        let q = Queued {
            payload: payload.clone(),
            ready: f.ready,
            seq,
            kind,
        };
        port.push(q, front);
        modems.queued += 1;
        queued_any = true;
    }
    queued_any
}

/// Queues a broadcast, or a unicast without acknowledgement, behind what waits (counted as
/// sent if it went into some queue).
fn queue_plain(params: &[ModemParams], modems: &mut Modems, stats: &mut CommStats, f: &OutFrame) {
    let seq = next_seq(modems);
    let kind =
        f.to.map_or(Kind::Broadcast, |to| Kind::Unicast { to, ack: false });
    if enqueue(
        params,
        modems,
        stats,
        f,
        f.payload.clone().into(),
        (seq, kind, false),
    ) {
        stats.sent += 1;
    }
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
/// (acknowledged unicasts behind the outstanding one, in order). The vehicle's flows (`me`'s
/// in `flows`) count the unicasts handed over, retransmitted and given up. Returns how many
/// frames it gave up (their outcomes are in the inbox).
pub(super) fn link_layer(
    t: f64,
    params: &[ModemParams],
    links: &[ModemLink],
    (outbox, modems, stats, link, inbox): Parts<'_>,
    (me, flows): (u32, &mut Flows),
) -> u64 {
    for f in &outbox.0 {
        if let Some(to) = f.to {
            let flow = flows.get(me, to);
            flow.offered += 1;
            flow.offered_bytes += f.payload.len() as u64;
        }
    }
    let gave_up = inbox.outcomes.len();
    link_layer_of(
        t,
        params,
        links,
        (outbox, modems, stats, link, inbox),
        flows,
        me,
    );
    for e in &inbox.outcomes[gave_up..] {
        flows.get(me, e.to).gave_up += 1;
    }
    (inbox.outcomes.len() - gave_up) as u64
}

/// [`link_layer`] once the flows counted what was handed over (the outcomes it adds are all
/// given up: acknowledgements end frames in the delivery phase).
fn link_layer_of(
    t: f64,
    params: &[ModemParams],
    links: &[ModemLink],
    (outbox, modems, stats, link, inbox): Parts<'_>,
    flows: &mut Flows,
    me: u32,
) {
    if !link.busy() && !outbox.0.iter().any(reliable) {
        // The common case: broadcasts and unicasts without acknowledgement only.
        for f in outbox.0.drain(..) {
            queue_plain(params, modems, stats, &f);
        }
        return;
    }
    let handed: Vec<OutFrame> = outbox.0.drain(..).collect();
    let s = link.state();
    send_acks(s, params, modems, stats);
    let retransmissions = stats.retransmissions;
    time_out(t, s, (params, links), modems, stats, inbox);
    if let Some(p) = &s.pending {
        flows.get(me, p.to).retransmissions += stats.retransmissions - retransmissions;
    }
    // Frames wait behind the outstanding one up to the first modem's queue length.
    let room = params.first().map_or(0, |p| p.queue_frames);
    for f in handed {
        if !reliable(&f) {
            queue_plain(params, modems, stats, &f);
        } else if s.waiting.len() < room {
            s.waiting.push_back(f);
        } else {
            stats.queue_overflow += 1;
            inbox.outcomes.push(refused(t, 0, &f));
        }
    }
    // The medium access learns what became of the outstanding frames (acknowledged in the
    // delivery phase, timed out above) before it decides on the next one.
    for (modem, acked) in s.feedback.drain(..) {
        if let Some(l) = links.get(modem.unwrap_or(0)) {
            l.access.feedback(&mut modems.access, acked);
        }
    }
    promote(t, s, params, modems, stats, inbox);
}

/// Whether `f` goes under stop-and-wait ARQ (a unicast asking for acknowledgement).
fn reliable(f: &OutFrame) -> bool {
    f.ack && f.to.is_some()
}

/// The outcome of reliable frame `f` (sequence number `seq`) refused at `t` \[s\]: a full
/// queue or a payload too long (counted); it never went on the air.
fn refused(t: f64, seq: u32, f: &OutFrame) -> FrameEvent {
    FrameEvent {
        t,
        to: f.to.unwrap_or(u32::MAX),
        seq,
        tag: f.tag,
        payload: f.payload.clone().into(),
        sent: f.ready,
        transmissions: 0,
        outcome: FrameOutcome::GaveUp,
    }
}

/// The acknowledgements `s` owes go to the front of the queues, on every modem, like the
/// copies of a broadcast: everyone around hears that the channel is taken (802.11's
/// acknowledgements are omnidirectional too).
fn send_acks(
    s: &mut LinkState,
    params: &[ModemParams],
    modems: &mut Modems,
    stats: &mut CommStats,
) {
    for a in std::mem::take(&mut s.acks) {
        let ack = OutFrame {
            modem: None,
            payload: Vec::new(),
            ready: a.ready,
            to: Some(a.to),
            ack: false,
            tag: 0,
        };
        let seq = next_seq(modems);
        let kind = Kind::Ack {
            to: a.to,
            seq: a.seq,
        };
        let empty = Arc::from(&[][..]);
        if enqueue(params, modems, stats, &ack, empty, (seq, kind, true)) {
            stats.acks_sent += 1;
        }
    }
}

/// The outstanding frame of `s` whose wait ran out by `t` \[s\]: retransmitted at the front
/// of its queues while it has retries left (those of its first modem), else given up.
fn time_out(
    t: f64,
    s: &mut LinkState,
    (params, links): (&[ModemParams], &[ModemLink]),
    modems: &mut Modems,
    stats: &mut CommStats,
    inbox: &mut Inbox,
) {
    let Some(p) = &mut s.pending else {
        return;
    };
    if p.deadline > t {
        return;
    }
    let first = p.modem.unwrap_or(0).min(links.len().saturating_sub(1));
    let retries = links.get(first).map_or(0, |l| l.retries);
    s.feedback.push((p.modem, false));
    if p.transmissions > retries {
        stats.gave_up += 1;
        inbox.outcomes.push(p.event(t, FrameOutcome::GaveUp));
        s.pending = None;
        return;
    }
    p.transmissions += 1;
    p.deadline = f64::INFINITY;
    stats.retransmissions += 1;
    // `enqueue` checks the length of `again.payload`: the frame's own length passed.
    let again = OutFrame {
        modem: p.modem,
        payload: Vec::new(),
        ready: t,
        to: Some(p.to),
        ack: true,
        tag: p.tag,
    };
    let kind = Kind::Unicast {
        to: p.to,
        ack: true,
    };
    if !enqueue(
        params,
        modems,
        stats,
        &again,
        p.payload.clone(),
        (p.seq, kind, true),
    ) {
        // Its queues are full: the wait starts over (it was counted as an overflow).
        p.deadline = t;
    }
}

/// While `s` has no outstanding frame, the next waiting one goes into the queues and becomes
/// it (one refused by its queues ends at once, given up).
fn promote(
    t: f64,
    s: &mut LinkState,
    params: &[ModemParams],
    modems: &mut Modems,
    stats: &mut CommStats,
    inbox: &mut Inbox,
) {
    while s.pending.is_none()
        && let Some(f) = s.waiting.pop_front()
    {
        let Some(to) = f.to else {
            continue;
        };
        let seq = next_seq(modems);
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
            inbox.outcomes.push(refused(t, seq, &f));
            continue;
        }
        stats.sent += 1;
        s.pending = Some(Pending {
            seq,
            to,
            tag: f.tag,
            modem: f.modem,
            payload,
            sent: f.ready,
            transmissions: 1,
            deadline: f64::INFINITY,
        });
    }
}

/// Where a receiver's decoded frames go: its inbox (frames for it) and its link layer
/// (acknowledgements to send and received).
pub(super) struct Mail<'a> {
    /// The receiver's inbox.
    pub(super) inbox: &'a mut Inbox,
    /// Its link-layer state.
    pub(super) link: &'a mut Link,
    /// What its receptions tell the flows (folded in after the delivery phase).
    pub(super) flows: &'a mut Vec<FlowEvent>,
}

impl Mail<'_> {
    /// Frame `f` decoded at receiver `me` by `modem`: a broadcast, or a unicast for `me`
    /// that is not a retransmission already received, goes to the inbox; a unicast for `me`
    /// asking for acknowledgement is acknowledged (every copy); an acknowledgement for `me`
    /// ends its outstanding frame; others' unicasts and acknowledgements are dropped. Returns
    /// the latency of the frame an acknowledgement ended (hand-over to acknowledgement) \[s\].
    pub(super) fn decoded(
        &mut self,
        me: u32,
        f: &Transmission,
        (modem, power, snr): (usize, f64, f64),
    ) -> Option<f64> {
        let mut acked = None;
        let new = match f.kind {
            Kind::Broadcast => true,
            Kind::Unicast { to, ack } if to == me => {
                let new = !ack || {
                    let s = self.link.state();
                    s.acks.push(AckDue {
                        to: f.tx,
                        seq: f.seq,
                        ready: f.end,
                    });
                    s.first_delivery(f.tx, f.seq)
                };
                if new {
                    self.flows.push(FlowEvent::Delivered {
                        from: f.tx,
                        to: me,
                        bytes: f.payload.len() as u64,
                    });
                }
                new
            }
            Kind::Ack { to, seq } if to == me => {
                if let Some(e) = self.link.state().acknowledged(f.tx, seq, f.end) {
                    let latency = e.t - e.sent;
                    acked = Some(latency);
                    self.flows.push(FlowEvent::Acknowledged {
                        from: me,
                        to: f.tx,
                        latency,
                    });
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
