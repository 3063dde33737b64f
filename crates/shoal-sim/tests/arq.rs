//! Unicast frames, acknowledgements and stop-and-wait retransmission: delivery after retries
//! follows 1 − (1 − p)^(k+1) for independent losses of probability 1 − p per try; a
//! destination hands a frame to its behaviour once however many copies arrive; frames for
//! another vehicle reach no behaviour; acknowledgements are frames on the air.

mod support;

use shoal_sim::behaviour::{Behave, Behaviour, BehaviourIo};
use shoal_sim::comm::{FrameEvent, FrameOutcome, Received};
use shoal_sim::components::VehicleId;
use shoal_sim::prelude::*;
use std::collections::BTreeSet;
use std::sync::{Arc, Mutex};
use support::world::world;

/// What a test behaviour saw: frames received, outcomes of its own frames.
#[derive(Default)]
struct Seen {
    inbox: Vec<Received>,
    outcomes: Vec<FrameEvent>,
}

/// Sends a numbered unicast to `to` every `period` seconds (with acknowledgement if `ack`),
/// and records what it receives and what became of its frames.
struct Unicaster {
    to: Option<u32>,
    period: f64,
    ack: bool,
    next: f64,
    n: u32,
    seen: Arc<Mutex<Seen>>,
}

impl Behaviour for Unicaster {
    fn tick(&mut self, io: &mut BehaviourIo<'_>) {
        let mut s = self.seen.lock().unwrap();
        s.inbox.extend(io.inbox.iter().cloned());
        s.outcomes.extend(io.outcomes.iter().cloned());
        if let Some(to) = self.to
            && io.t >= self.next
        {
            // A 32-byte frame: the number and padding.
            let mut payload = [0u8; 26];
            payload[..4].copy_from_slice(&self.n.to_le_bytes());
            io.send_to(to, None, &payload, 0.0, self.ack);
            self.n += 1;
            self.next += self.period;
        }
    }
}

/// Gives vehicle `id` a [`Unicaster`] sending to `to` (none: it only listens).
fn attach(sim: &mut Sim, id: usize, to: Option<u32>, period: f64, ack: bool) -> Arc<Mutex<Seen>> {
    let seen = Arc::new(Mutex::new(Seen::default()));
    let e = sim.vehicle_entity(id);
    let rng = shoal_sim::sim::vehicle_rng(0, id as u32, 9);
    let every = sim.fleet().get(VehicleId(id as u32)).control.every;
    let b = Unicaster {
        to,
        period,
        ack,
        next: 0.1,
        n: 0,
        seen: seen.clone(),
    };
    sim.world_mut()
        .entity_mut(e)
        .insert(Behave::new(Box::new(b), rng, every));
    seen
}

/// `pairs` pairs 20 m apart, each a sender facing its receiver `d` m away (modems 0.125 m
/// ahead of the hulls' centres) with `retries` retransmissions; a third vehicle `extra` m
/// beside each receiver's line of sight, when given.
fn pairs(pairs: usize, d: f64, retries: u32, extra: Option<f64>) -> String {
    let mut t = format!(
        "seed = 4\nduration = 1000\n[pool]\nsize = [{}, 12.0, 3.0]\n",
        20.0 * pairs as f64 + 10.0
    );
    let modem = format!("[[vehicles.model.modems]]\narq_retries = {retries}\n");
    for i in 0..pairs {
        let x0 = 5.0 + 20.0 * i as f64;
        t.push_str(&format!(
            "[[vehicles]]\nname = \"tx{i}\"\nposition = [{x0}, 6.0, 1.5]\n{modem}\
             [[vehicles]]\nname = \"rx{i}\"\nposition = [{}, 6.0, 1.5]\nheading_deg = 180\n{modem}",
            x0 + d + 0.25
        ));
        if let Some(e) = extra {
            t.push_str(&format!(
                "[[vehicles]]\nname = \"by{i}\"\nposition = [{}, {}, 1.5]\nheading_deg = 200\n{modem}",
                x0 + d + 0.25,
                6.0 + e
            ));
        }
    }
    t
}

/// Stop-and-wait over a link that loses half its frames (2.5 m in pool water): with k
/// retransmissions a frame reaches its destination with probability 1 − (1 − p)^(k+1), p the
/// per-try delivery measured on the same links — within 2 percentage points for k = 0, 1, 3.
#[test]
fn stop_and_wait_delivers_one_minus_the_loss_to_the_power_of_the_tries() {
    for k in [0u32, 1, 3] {
        let n_pairs = 6;
        let mut sim = world(&pairs(n_pairs, 2.5, k, None));
        let mut seen = Vec::new();
        for i in 0..n_pairs {
            let tx = attach(&mut sim, 2 * i, Some(2 * i as u32 + 1), 0.4, true);
            let rx = attach(&mut sim, 2 * i + 1, None, 0.4, true);
            seen.push((tx, rx));
        }
        sim.run(30_000); // 300 s: 750 frames per pair
        let (mut sent, mut got, mut tries, mut tries_ok) = (0usize, 0usize, 0u64, 0u64);
        for (i, (tx, rx)) in seen.iter().enumerate() {
            let (tx, rx) = (tx.lock().unwrap(), rx.lock().unwrap());
            // Each frame ended once: acknowledged or given up, after at most k + 1 tries.
            sent += tx.outcomes.len();
            assert!(
                tx.outcomes
                    .iter()
                    .all(|e| e.transmissions >= 1 && e.transmissions <= k + 1)
            );
            let gave_up = tx
                .outcomes
                .iter()
                .filter(|e| e.outcome == FrameOutcome::GaveUp);
            assert!(gave_up.clone().all(|e| e.transmissions == k + 1));
            // Unique frames at the destination, all from its sender, each once.
            let numbers: BTreeSet<&[u8]> = rx.inbox.iter().map(|r| &*r.payload).collect();
            assert_eq!(numbers.len(), rx.inbox.len(), "a frame delivered twice");
            assert!(rx.inbox.iter().all(|r| r.from == 2 * i as u32 && r.unicast));
            got += rx.inbox.len();
            // Every try at the receiver: attempts of the data link (acknowledgements go the
            // other way).
            let link = sim.vehicle(2 * i + 1).comm.rx;
            tries += link.attempts;
            tries_ok += link.delivered;
            assert_eq!(sim.vehicle(2 * i + 1).comm.acks_sent, link.delivered);
        }
        assert!(sent > 4000, "{sent} frames");
        let p = tries_ok as f64 / tries as f64;
        assert!((0.4..0.6).contains(&p), "per-try delivery {p}");
        let law = 1.0 - (1.0 - p).powi(k as i32 + 1);
        let measured = got as f64 / sent as f64;
        assert!(
            (measured - law).abs() < 0.02,
            "k = {k}: {got} of {sent} delivered ({measured:.4}), the law {law:.4} at p = {p:.4}"
        );
    }
}

/// A unicast for another vehicle is decoded by a bystander (its link statistics count it) but
/// reaches neither its inbox nor makes it acknowledge; broadcasts still reach it.
#[test]
fn frames_for_another_vehicle_reach_no_behaviour() {
    let mut sim = world(&pairs(1, 1.5, 3, Some(0.6)));
    let _tx = attach(&mut sim, 0, Some(1), 0.5, true);
    let rx = attach(&mut sim, 1, None, 0.5, true);
    let by = attach(&mut sim, 2, None, 0.5, true);
    sim.run(2000);
    let by_stats = sim.vehicle(2).comm;
    assert!(
        by_stats.rx.delivered > 10,
        "the bystander decodes: {by_stats:?}"
    );
    assert!(by.lock().unwrap().inbox.is_empty());
    assert_eq!(by_stats.acks_sent, 0);
    assert!(rx.lock().unwrap().inbox.len() > 30);
}

/// Acknowledgements are frames: they go on the air (the medium counts them), take a header's
/// airtime and are decoded by the sender like any frame; every one the destination sent for
/// a frame the sender then saw acknowledged.
#[test]
fn acknowledgements_are_frames_on_the_air() {
    let mut sim = world(&pairs(1, 1.5, 3, None));
    let tx = attach(&mut sim, 0, Some(1), 0.5, true);
    let _rx = attach(&mut sim, 1, None, 0.5, true);
    sim.run(2000); // 20 s: 40 frames on a link that loses none
    let tx = tx.lock().unwrap();
    let acked = tx
        .outcomes
        .iter()
        .filter(|e| e.outcome == FrameOutcome::Acknowledged && e.transmissions == 1)
        .count();
    assert!(acked >= 38, "{:?}", tx.outcomes);
    let acks = sim.vehicle(1).comm.acks_sent;
    assert_eq!(acks as usize, acked + usize::from(tx.outcomes.len() < 40));
    // The sender decoded every acknowledgement: its reception attempts are theirs.
    assert_eq!(sim.vehicle(0).comm.rx.delivered, acks);
    // Data frames and acknowledgements both started on the medium.
    assert_eq!(sim.medium().started.0, sim.vehicle(0).comm.sent + acks);
    // Latency of an acknowledged frame: its airtime (32 bytes: 16.7 ms) and the
    // acknowledgement's (a 6-byte header: 3.1 ms), each starting within a 10-ms step.
    for e in tx.outcomes.iter() {
        let l = e.t - e.sent;
        let both = 0.0167 + 0.0031;
        assert!((both - 1e-9..both + 0.02).contains(&l), "{e:?}");
    }
}

/// The value vehicle `i`'s behaviour reports under `key`.
fn report(sim: &Sim, i: usize, key: &str) -> f64 {
    let b = sim.vehicle(i).behaviour;
    b.iter().find(|(name, _)| *name == key).map_or_else(
        || panic!("vehicle {i} reports no {key}: {b:?}"),
        |(_, v)| *v,
    )
}

/// `worlds/reliable_gossip.toml`: a value flooded by acknowledged unicasts reaches all 65
/// vehicles, each learning it once from a neighbour one hop further from the origin; every
/// vehicle but the origin was served by an acknowledged unicast or passed the value on, and
/// the senders' acknowledged frames are the link layer's.
#[test]
fn reliable_gossip_reaches_everyone_by_acknowledged_unicasts() {
    let (desc, sim) = support::world::run_world_file("reliable_gossip");
    let n = desc.vehicles.len();
    assert_eq!(n, 65);
    let report = |i: usize, k: &str| report(&sim, i, k);
    let start = 2.0;
    for i in 0..n {
        let t = report(i, "learned_at");
        assert!(
            t >= start && t < desc.duration,
            "vehicle {i} learned at {t}"
        );
        let hops = report(i, "hops");
        assert_eq!(hops == 0.0, i == 0, "vehicle {i}: {hops} hops");
    }
    let acked: f64 = (0..n).map(|i| report(i, "acknowledged")).sum();
    let unicasts: f64 = (0..n).map(|i| report(i, "unicasts")).sum();
    assert!(acked >= (n - 1) as f64 / 2.0, "{acked} acknowledged");
    assert!(unicasts >= acked);
    // Every acknowledgement the behaviours saw is one the medium counted.
    let counted: u64 = sim.medium().ack_latency_histogram().iter().sum();
    assert_eq!(counted as f64, acked);
}

/// `worlds/formation.toml`: a leader orders three followers by acknowledged unicasts every
/// second; they steer for the same heading, depth and surge, so the diamond keeps its shape —
/// each follower ends within 0.6 m of its starting offset from the leader, heading as the
/// leader does — and nearly every order is acknowledged.
#[test]
fn followers_ordered_by_unicast_keep_the_formation() {
    let (desc, sim) = support::world::run_world_file("formation");
    let report = |i: usize, k: &str| report(&sim, i, k);
    let pos = |i: usize| sim.vehicle(i).state.rigid.position;
    let leader_moved = (pos(0) - desc.vehicles[0].position).norm();
    assert!(leader_moved > 1.0, "the leader travelled {leader_moved} m");
    let yaw = |i: usize| shoal_model::math::euler_rpy(&sim.vehicle(i).state.rigid.attitude).2;
    for i in 1..4 {
        let start = desc.vehicles[i].position - desc.vehicles[0].position;
        let end = pos(i) - pos(0);
        assert!(
            (end - start).norm() < 0.6,
            "follower {i}: {start:?} → {end:?}"
        );
        let dyaw = shoal_model::math::wrap_pi(yaw(i) - yaw(0)).abs();
        assert!(dyaw < 0.1, "follower {i} heads {dyaw} rad off the leader");
        assert!(report(i, "orders") >= 30.0, "follower {i}");
    }
    let acked = report(0, "acknowledged");
    let orders = report(0, "orders");
    assert!(
        acked >= 0.9 * orders,
        "{acked} of {orders} orders acknowledged"
    );
}
