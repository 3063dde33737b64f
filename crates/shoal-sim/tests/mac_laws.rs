//! Medium access against the textbook: throughput of unslotted and slotted ALOHA in shoal's
//! optical medium, in the geometry the laws assume (`shoal_sim::mac_laws`), within 2
//! percentage points of S = G·e^(−2G) and S = G·e^(−G); TDMA free of collisions at full load;
//! CSMA/CA with binary exponential back-off within 2 points of Bianchi's saturation model.
//! The full curves (nine loads, 240 s each) are `examples/mac_laws.rs`, drawn in docs/mac.md.

use shoal_sim::mac_laws::{Law, SLOT, measure, measure_csma, measure_p_persistent, world_text};
use shoal_sim::sim::{Sim, SimOptions};
use shoal_world::load::load_str;
use std::path::Path;

/// 78 senders (six layers of 13), 60 simulated seconds per load: about 3,500 frames at G = 1,
/// a standard error of ≈ 0.8 pp on S there.
const SENDERS: usize = 78;
const SECONDS: f64 = 60.0;

/// Measures `law` at loads `loads` and checks each point within 2 pp of the law, and that the
/// receiver lost nothing to anything but collisions (the geometry is what the law assumes).
fn follows(law: Law, loads: &[f64]) {
    for (k, &g) in loads.iter().enumerate() {
        let p = measure(law, &world_text(law, SENDERS, g, SECONDS, 7 + k as u64)).unwrap();
        assert!(
            (p.g - g).abs() < 0.1 * g + 0.02,
            "{law:?}: offered {g}, measured G = {}",
            p.g
        );
        assert_eq!(p.other_losses, 0, "{law:?} at G = {g}: {p:?}");
        let want = law.throughput(p.g);
        assert!(
            (p.s - want).abs() < 0.02,
            "{law:?} at G = {:.3}: S = {:.4}, the law {want:.4} ({p:?})",
            p.g,
            p.s
        );
    }
}

#[test]
fn unslotted_aloha_follows_g_e_minus_2g() {
    follows(Law::PureAloha, &[0.1, 0.5, 1.0, 2.0]);
}

#[test]
fn slotted_aloha_follows_g_e_minus_g() {
    follows(Law::SlottedAloha, &[0.1, 0.5, 1.0, 2.0]);
}

/// The two laws differ by more than the tolerance where it matters: at G = 0.5 slotted ALOHA
/// carries 0.30 frames per slot, unslotted 0.18 per frame time — a medium that ignored the
/// slots would fail the slotted law.
#[test]
fn slots_double_the_peak_throughput() {
    let g = 0.5;
    let pure = measure(
        Law::PureAloha,
        &world_text(Law::PureAloha, SENDERS, g, SECONDS, 3),
    )
    .unwrap();
    let slotted = measure(
        Law::SlottedAloha,
        &world_text(Law::SlottedAloha, SENDERS, g, SECONDS, 3),
    )
    .unwrap();
    assert!(slotted.s > pure.s + 0.08, "{slotted:?} against {pure:?}");
}

/// TDMA at full load: ten senders, each with a frame ready at every moment (a queue kept full
/// by Poisson traffic far above its share), one slot each in a cycle of ten. Every slot
/// carries a frame and no frame collides: the receiver gets one frame per slot.
#[test]
fn tdma_is_collision_free_at_full_load() {
    let mut text = world_text(Law::SlottedAloha, 10, 30.0, 20.0, 5);
    text = text.replace("kind = \"slotted_aloha\"", "kind = \"tdma\", slots = 10");
    let desc = load_str(&text, Path::new("tdma.toml")).unwrap();
    let mut sim = Sim::new(
        &desc,
        SimOptions {
            threads: 1,
            record: false,
        },
    );
    sim.run(2000);
    let rx = sim.vehicle(0).comm.rx;
    let slots = 20.0 / SLOT;
    assert_eq!(rx.lost_collision, 0, "{rx:?}");
    assert_eq!(rx.lost_range + rx.lost_occlusion, 0, "{rx:?}");
    // Every slot used (less the first cycle, before the queues filled, and the last frames
    // still on the air at the end).
    assert!(
        rx.delivered as f64 > slots - 20.0 && rx.delivered as f64 <= slots + 1.0,
        "{} frames in {slots:.0} slots",
        rx.delivered
    );
    // The senders are saturated: their queues overflowed.
    let overflow: u64 = (1..=10).map(|i| sim.vehicle(i).comm.queue_overflow).sum();
    assert!(overflow > 0);
}

/// Clocks that drift let the vehicles' slots slide against each other: with every clock off
/// by up to 2 % (a slot's length every 0.9 s), frames overlap partly again and slotted
/// ALOHA's throughput at G = 0.5 falls from the law's 0.30 towards unslotted ALOHA's 0.18.
#[test]
fn drifting_clocks_lose_the_gain_of_slots() {
    let text = world_text(Law::SlottedAloha, SENDERS, 0.5, SECONDS, 3).replace(
        "kind = \"slotted_aloha\"",
        "kind = \"slotted_aloha\", clock_drift_ppm = 20000",
    );
    let p = measure(Law::SlottedAloha, &text).unwrap();
    assert!(
        p.s < Law::SlottedAloha.throughput(p.g) - 0.05,
        "{p:?}: the slots should no longer line up"
    );
    assert!(p.s > Law::PureAloha.throughput(p.g) - 0.03, "{p:?}");
}

/// CSMA/CA with binary exponential back-off, saturated stations that all hear each other and
/// one access point (`shoal_sim::mac_laws::csma_world_text`): the throughput within 2
/// percentage points of Bianchi's model for 2, 10 and 20 stations (20 simulated seconds each,
/// ≈ 600 frames).
#[test]
fn csma_ca_follows_bianchis_saturation_model() {
    for n in [2, 10, 20] {
        let r = measure_csma(n, 20.0, 11).unwrap();
        assert!(r.delivered > 400, "{r:?}");
        assert!((r.s - r.model).abs() < 0.02, "{r:?}");
        // Collisions happen and are resolved by retransmission.
        assert!(r.retransmissions > 0, "{r:?}");
    }
}

/// Slotted p-persistent CSMA (the protocol added last, `comm/mac/p_persistent.rs`) with
/// saturated stations that all hear each other: the access point's throughput within 2
/// percentage points of the law n·p·(1 − p)^(n−1)·T / ((1 − p)^n·σ + (1 − (1 − p)^n)·(T + σ))
/// for 2, 10 and 20 stations at p = 0.1, and 10 stations at p = 0.3, where collisions
/// dominate (60 simulated seconds each, 390 … 2,600 frames decoded: the counting noise is
/// about ±1 pp, ±2 pp at 20 s). Seen failing when stations that had not looked since the
/// channel fell idle kept slots of their own (+15 pp at 10 stations).
#[test]
fn p_persistent_csma_follows_its_saturation_law() {
    for (n, p) in [(2, 0.1), (10, 0.1), (20, 0.1), (10, 0.3)] {
        let r = measure_p_persistent(n, p, 60.0, 13).unwrap();
        assert!(r.delivered > 300, "{r:?}");
        assert!((r.s - r.model).abs() < 0.02, "{r:?}");
        if n > 2 {
            assert!(r.collisions > 0, "{r:?}");
        }
    }
}
