//! The optical medium through the whole simulator: calibration of delivery against distance,
//! field of view, airtime, half-duplex, collisions and capture, occlusion by obstacles and
//! hulls, water type, carrier sense, and identical statistics on 1 and 2 threads.

mod support;
use shoal_model::optics::{Ambient, LinkGeometry, budget};
use shoal_model::presets::uauv2_modem;
use shoal_sim::behaviour::{Behave, Behaviour, BehaviourIo};
use shoal_sim::comm::{CommStats, OutFrame, Outbox, Received};
use shoal_sim::prelude::*;
use shoal_world::geometry::Geometry;
use shoal_world::load::load_str;
use std::path::Path;
use std::sync::{Arc, Mutex};
use support::world::world;

fn stats(sim: &Sim, id: usize) -> CommStats {
    sim.vehicle(id).comm
}

/// Records every frame its vehicle receives.
struct Sink(Arc<Mutex<Vec<Received>>>);
impl Behaviour for Sink {
    fn tick(&mut self, io: &mut BehaviourIo<'_>) {
        self.0.lock().unwrap().extend(io.inbox.iter().cloned());
    }
}

fn sink(sim: &mut Sim, id: usize) -> Arc<Mutex<Vec<Received>>> {
    let log = Arc::new(Mutex::new(Vec::new()));
    let e = sim.vehicle_entity(id);
    let rng = shoal_sim::sim::vehicle_rng(0, id as u32, 9);
    let every = sim.fleet().get(VehicleId(id as u32)).control.every;
    sim.world_mut()
        .entity_mut(e)
        .insert(Behave::new(Box::new(Sink(log.clone())), rng, every));
    log
}

fn send(sim: &mut Sim, id: usize, payload: usize, ready: f64) {
    let e = sim.vehicle_entity(id);
    sim.world_mut()
        .get_mut::<Outbox>(e)
        .unwrap()
        .0
        .push(OutFrame::broadcast(None, vec![7; payload], ready));
}

/// Pairs of vehicles facing each other with their modems `d` apart, far from other pairs;
/// the first of each pair beacons 32-byte frames (26 payload + 6 header) every `period`.
fn pairs_text(distances: &[f64], period: f64, water: &str) -> String {
    let mut t = format!(
        "seed = 4\nduration = 400\n[pool]\nsize = [{}, 12.0, 3.0]\n[water]\nattenuation = {water}\n",
        20.0 * distances.len() as f64 + 10.0
    );
    for (i, d) in distances.iter().enumerate() {
        let x0 = 5.0 + 20.0 * i as f64;
        // Modems sit 0.125 m ahead of each hull's centre.
        t.push_str(&format!(
            "[[vehicles]]\nname = \"tx{i}\"\nposition = [{x0}, 6.0, 1.5]\nbehaviour = {{ kind = \"beacon\", period = {period}, payload_bytes = 26, jitter = 0.01 }}\n\
             [[vehicles]]\nname = \"rx{i}\"\nposition = [{}, 6.0, 1.5]\nheading_deg = 180\n",
            x0 + d + 0.25
        ));
    }
    t
}

fn ratio(s: &CommStats) -> f64 {
    s.rx.delivered as f64 / s.rx.attempts as f64
}

#[test]
fn delivery_ratio_against_distance_matches_the_calibration() {
    let mut sim = world(&pairs_text(&[2.0, 2.5, 3.0], 0.1, "\"pool\""));
    sim.run(20_000); // 200 s: ≈2000 frames per pair
    let r: Vec<f64> = (0..3).map(|i| ratio(&stats(&sim, 2 * i + 1))).collect();
    let n = stats(&sim, 3).rx.attempts as f64;
    assert!(n > 1900.0);
    // Expected from the link budget (test link_budget.rs): 0.99937, 0.5, 1.2e-4.
    // Binomial standard error at p = 0.5 with n ≈ 2000: 0.011; allow 4σ.
    assert!(r[0] > 0.995, "2.0 m: {}", r[0]);
    assert!(
        (r[1] - 0.5).abs() < 4.0 * (0.25 / n).sqrt(),
        "2.5 m: {}",
        r[1]
    );
    assert!(r[2] < 0.003, "3.0 m: {}", r[2]);
    // Nothing else can have happened on an isolated link.
    for i in 0..3 {
        let s = stats(&sim, 2 * i + 1);
        assert_eq!(s.rx.delivered + s.rx.lost_range, s.rx.attempts);
    }
}

/// Between folds the reception attempts wait in the ledger; every way of reading the
/// statistics counts them: a snapshot of one vehicle, of all, and the folded components.
#[test]
fn statistics_read_between_folds_count_the_attempts_the_ledger_holds() {
    let mut sim = world(&pairs_text(&[2.0, 2.5], 0.1, "\"pool\""));
    // 3.5 s: the last fold was the connectivity sample at 3 s, half a second ago.
    sim.run(350);
    let pending = sim.world().resource::<shoal_sim::comm::Ledger>().len();
    // Two senders at 10 Hz, each heard by its own receiver only: ≈ 5 attempts each.
    assert!(
        (8..=12).contains(&pending),
        "the ledger holds the last half second: {pending}"
    );
    let all = sim.vehicles();
    let one: Vec<CommStats> = (0..4).map(|i| stats(&sim, i)).collect();
    for (i, v) in all.iter().enumerate() {
        assert_eq!(v.comm.rx, one[i].rx, "vehicle {i}");
        assert_eq!(v.comm.links(), one[i].links(), "vehicle {i}");
    }
    // 35 frames per sender (10 Hz for 3.5 s, the first within the jitter of t = 0).
    for i in [1, 3] {
        assert!((34..=35).contains(&one[i].rx.attempts), "{:?}", one[i].rx);
        assert_eq!(one[i].links()[&(i as u32 - 1)].attempts, one[i].rx.attempts);
    }
    sim.fold_comm();
    assert!(sim.world().resource::<shoal_sim::comm::Ledger>().is_empty());
    let e = sim.vehicle_entity(3);
    let folded = sim.world().get::<CommStats>(e).unwrap().clone();
    assert_eq!(folded.rx, one[3].rx);
    assert_eq!(folded.links(), one[3].links());
}

/// A receiver looking −x and a beaconing sender 1 m from the receiver's modem, `angle` off the
/// receiver's axis, facing the receiver's modem (so it is on the sender's LED axis).
fn fov_world(angle_deg: f64) -> String {
    let (rx, ry) = (6.0, 5.0);
    let (mx, my) = (rx - 0.125, ry); // the receiver's modem
    let a = angle_deg.to_radians();
    let (tx_m, ty_m) = (mx - a.cos(), my + a.sin()); // sender's modem
    let h = (my - ty_m).atan2(mx - tx_m);
    format!(
        "seed = 1\nduration = 30\n[pool]\nsize = [10.0, 10.0, 3.0]\n\
         [[vehicles]]\nname = \"tx\"\nposition = [{}, {}, 1.5]\nheading_deg = {}\n\
         behaviour = {{ kind = \"beacon\", period = 0.1, payload_bytes = 26 }}\n\
         [[vehicles]]\nname = \"rx\"\nposition = [{rx}, {ry}, 1.5]\nheading_deg = 180\n",
        tx_m - 0.125 * h.cos(),
        ty_m - 0.125 * h.sin(),
        h.to_degrees()
    )
}

#[test]
fn nothing_is_received_outside_the_field_of_view() {
    // The receiver's field of view is 60° (half-angle): at 59° off its axis a sender 1 m away
    // gets through; at 61° and 90° nothing arrives, however close.
    let run = |a: f64| {
        let mut sim = world(&fov_world(a));
        sim.run(2000);
        stats(&sim, 1).rx
    };
    let inside = run(59.0);
    assert!(
        inside.attempts > 150 && inside.delivered as f64 > 0.99 * inside.attempts as f64,
        "{inside:?}"
    );
    for a in [61.0, 90.0] {
        let s = run(a);
        assert!(s.attempts > 150);
        assert_eq!(s.delivered, 0, "{a}°: {s:?}");
        assert_eq!(s.lost_range, s.attempts, "counted as out of range/angle");
    }
}

#[test]
fn frames_take_their_airtime_back_to_back_and_queues_overflow_visibly() {
    let text = "duration = 10\n[pool]\nsize = [10.0, 6.0, 3.0]\n\
        [[vehicles]]\nname = \"a\"\nposition = [4.0, 3.0, 1.5]\n\
        [[vehicles]]\nname = \"b\"\nposition = [5.25, 3.0, 1.5]\nheading_deg = 180\n";
    let mut sim = world(text);
    let log = sink(&mut sim, 1);
    // 12 frames of 58 payload + 6 header = 64 bytes, all handed over at t = 0.1 s; the queue
    // holds 8, so 4 are dropped and counted.
    for _ in 0..12 {
        send(&mut sim, 0, 58, 0.1);
    }
    sim.run(300);
    let got = log.lock().unwrap().clone();
    let a = stats(&sim, 0);
    assert_eq!(a.queue_overflow, 4);
    assert_eq!(a.sent, 8);
    assert_eq!(got.len(), 8, "1.25 m: all delivered");
    let airtime = 64.0 * 10.0 / 19_200.0;
    for (k, r) in got.iter().enumerate() {
        // N frames of L bytes end N·L·10/19200 s after the first started.
        assert!(
            (r.t - (0.1 + (k + 1) as f64 * airtime)).abs() < 1e-9,
            "frame {k} at {}",
            r.t
        );
        assert!(
            (r.t - r.sent - (k + 1) as f64 * airtime).abs() < 1e-9,
            "latency includes queueing"
        );
    }
}

#[test]
fn a_transmitting_modem_receives_nothing() {
    let text = "duration = 10\n[pool]\nsize = [10.0, 6.0, 3.0]\n\
        [[vehicles]]\nname = \"a\"\nposition = [4.0, 3.0, 1.5]\n\
        [[vehicles]]\nname = \"b\"\nposition = [5.25, 3.0, 1.5]\nheading_deg = 180\n";
    let mut sim = world(text);
    // Both send at the same moment: each is transmitting while the other's frame arrives.
    send(&mut sim, 0, 26, 0.1);
    send(&mut sim, 1, 26, 0.105);
    sim.run(100);
    for id in 0..2 {
        let s = stats(&sim, id);
        assert_eq!(
            (s.rx.attempts, s.rx.delivered, s.rx.lost_half_duplex),
            (1, 0, 1),
            "vehicle {id}"
        );
    }
    // One after the other: both arrive.
    let mut sim = world(text);
    send(&mut sim, 0, 26, 0.1);
    send(&mut sim, 1, 26, 0.2);
    sim.run(100);
    assert_eq!(stats(&sim, 0).rx.delivered + stats(&sim, 1).rx.delivered, 2);
}

/// A receiver at the origin side looking +x; two senders 20° left and right of its axis,
/// both facing it, at distances `da` and `db` from its modem.
fn collision_world(da: f64, db: f64) -> String {
    let (s, c) = (20f64.to_radians().sin(), 20f64.to_radians().cos());
    let rx = [3.0, 5.0, 1.5];
    let m = [rx[0] + 0.125, rx[1]];
    let place = |d: f64, sign: f64| {
        let (x, y) = (m[0] + d * c, m[1] + sign * d * s);
        // Back the hull off so that its modem (0.125 m ahead) is at (x, y), facing the rx.
        let heading = (m[1] - y).atan2(m[0] - x);
        (
            x - 0.125 * heading.cos(),
            y - 0.125 * heading.sin(),
            heading.to_degrees(),
        )
    };
    let (ax, ay, ah) = place(da, 1.0);
    let (bx, by, bh) = place(db, -1.0);
    format!(
        "duration = 10\n[pool]\nsize = [10.0, 10.0, 3.0]\n\
         [[vehicles]]\nname = \"rx\"\nposition = [{}, {}, 1.5]\n\
         [[vehicles]]\nname = \"a\"\nposition = [{ax}, {ay}, 1.5]\nheading_deg = {ah}\n\
         [[vehicles]]\nname = \"b\"\nposition = [{bx}, {by}, 1.5]\nheading_deg = {bh}\n",
        rx[0], rx[1]
    )
}

#[test]
fn equal_overlapping_frames_collide_and_a_much_stronger_one_is_captured() {
    // Equal distance, equal power: both frames lost to collision.
    let mut sim = world(&collision_world(1.5, 1.5));
    send(&mut sim, 1, 26, 0.1);
    send(&mut sim, 2, 26, 0.105);
    sim.run(100);
    let s = stats(&sim, 0);
    assert_eq!(
        (s.rx.attempts, s.rx.delivered, s.rx.lost_collision),
        (2, 0, 2),
        "{:?}",
        s.rx
    );
    // Sender a at 0.8 m: (1.5/0.8)² · e^(0.07·0.7) ≈ 3.7 times stronger than b, above the
    // capture ratio 2: a's frame survives, b's is lost.
    let mut sim = world(&collision_world(0.8, 1.5));
    send(&mut sim, 1, 26, 0.1);
    send(&mut sim, 2, 26, 0.105);
    sim.run(100);
    let s = stats(&sim, 0);
    assert_eq!((s.rx.delivered, s.rx.lost_collision), (1, 1), "{:?}", s.rx);
    assert_eq!(s.links()[&1].delivered, 1);
    assert_eq!(s.links()[&2].lost_collision, 1);
    // Not overlapping in time: both arrive.
    let mut sim = world(&collision_world(1.5, 1.5));
    send(&mut sim, 1, 26, 0.1);
    send(&mut sim, 2, 26, 0.2);
    sim.run(100);
    assert_eq!(stats(&sim, 0).rx.delivered, 2);
}

#[test]
fn an_obstacle_blocks_the_link_and_moving_it_away_restores_it() {
    let text = format!(
        "{}[[obstacles]]\nname = \"post\"\nshape = \"cylinder\"\nradius = 0.1\nheight = 3.0\nposition = [6.0, 6.0, 1.5]\n",
        pairs_text(&[1.5], 0.1, "\"pool\"")
    );
    let mut sim = world(&text);
    sim.run(1000);
    let s = stats(&sim, 1);
    assert!(s.rx.attempts > 80);
    assert_eq!(s.rx.delivered, 0);
    assert_eq!(s.rx.lost_occlusion, s.rx.attempts);
    // Move the post 1 m to the side.
    {
        let mut geo = sim.world_mut().resource_mut::<StaticGeometry>();
        let ob = &geo.0.obstacles[0];
        let moved = Geometry::obstacle(
            &ob.name,
            ob.shape.clone(),
            &nalgebra::Vector3::new(6.0, 7.0, 1.5),
            &nalgebra::UnitQuaternion::from_axis_angle(
                &nalgebra::Vector3::x_axis(),
                std::f64::consts::FRAC_PI_2,
            ),
        );
        geo.0.obstacles[0] = moved;
    }
    let before = stats(&sim, 1).rx;
    sim.run(1000);
    let after = stats(&sim, 1).rx;
    assert!(
        after.delivered - before.delivered > 80,
        "restored: {after:?}"
    );
    assert_eq!(after.lost_occlusion, before.lost_occlusion);
}

#[test]
fn another_hull_in_between_blocks_the_link() {
    let mut text = pairs_text(&[2.0], 0.1, "\"pool\"");
    text.push_str(
        "[[vehicles]]\nname = \"blocker\"\nposition = [6.2, 6.0, 1.5]\nheading_deg = 90\n",
    );
    let mut sim = world(&text);
    sim.run(1000);
    let s = stats(&sim, 1);
    assert!(s.rx.attempts > 80);
    assert_eq!(s.rx.lost_occlusion, s.rx.attempts, "{:?}", s.rx);
}

#[test]
fn water_type_moves_the_range_by_the_beer_lambert_amount() {
    // At the distance where the link budget puts FER = 0.5 for each water type, the medium
    // must deliver half the frames, whatever the water.
    let m = uauv2_modem();
    let ambient = Ambient {
        surface_irradiance: 0.5,
        diffuse_attenuation: 0.1,
    };
    let d50 = |c: f64| {
        let (mut lo, mut hi) = (0.1, 10.0);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if budget(
                &m.led,
                &m.rx,
                &LinkGeometry::on_axis(mid),
                c,
                &ambient,
                1.5,
                0.0,
                320,
            )
            .fer < 0.5
            {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    };
    let waters = [
        ("\"clear_ocean\"", 0.151),
        ("\"coastal\"", 0.398),
        ("\"turbid_harbour\"", 2.19),
    ];
    let mut last = f64::INFINITY;
    for (name, c) in waters {
        let d = d50(c);
        assert!(d < last, "murkier water, shorter range");
        last = d;
        let mut sim = world(&pairs_text(&[d], 0.1, name));
        sim.run(15_000);
        let s = stats(&sim, 1);
        let n = s.rx.attempts as f64;
        assert!(
            (ratio(&s) - 0.5).abs() < 4.0 * (0.25 / n).sqrt(),
            "{name} at {d:.3} m: {}",
            ratio(&s)
        );
        // And in clearer pool water at that distance, clearly better than half.
        let mut pool = world(&pairs_text(&[d], 0.1, "\"pool\""));
        pool.run(3000);
        let s = stats(&pool, 1);
        assert!(
            ratio(&s) > 0.5 + 4.0 * (0.25 / s.rx.attempts as f64).sqrt(),
            "pool water at {d:.3} m: {}",
            ratio(&s)
        );
    }
}

/// Five beaconing vehicles 1 m around a point, each with four modems (front, right, back,
/// left) so that every vehicle hears every other one (no hidden terminals). Offered load:
/// 5 vehicles × 5 frames/s × 16.7 ms = 42 % of the channel.
fn crowd(access: &str) -> String {
    let mut t = String::from("seed = 9\nduration = 60\n[pool]\nsize = [10.0, 10.0, 3.0]\n");
    for i in 0..5 {
        let a = i as f64 * std::f64::consts::TAU / 5.0;
        let (x, y) = (5.0 + 0.5 * a.cos(), 5.0 + 0.5 * a.sin());
        t.push_str(&format!(
            "[[vehicles]]\nname = \"v{i}\"\nposition = [{x}, {y}, 1.5]\n\
             behaviour = {{ kind = \"beacon\", period = 0.2, payload_bytes = 26, jitter = 0.2 }}\n"
        ));
        for (name, p, d) in [
            ("front", "[0.125, 0.0, 0.0]", "[1.0, 0.0, 0.0]"),
            ("right", "[0.0, 0.07, 0.0]", "[0.0, 1.0, 0.0]"),
            ("back", "[-0.125, 0.0, 0.0]", "[-1.0, 0.0, 0.0]"),
            ("left", "[0.0, -0.07, 0.0]", "[0.0, -1.0, 0.0]"),
        ] {
            t.push_str(&format!(
                "[[vehicles.model.modems]]\nname = \"{name}\"\nposition = {p}\ndirection = {d}\naccess = \"{access}\"\n"
            ));
        }
    }
    t
}

#[test]
fn carrier_sense_avoids_collisions_that_aloha_suffers() {
    let run = |access: &str| {
        let mut sim = world(&crowd(access));
        sim.run(3000);
        (0..5)
            .map(|i| stats(&sim, i))
            .fold((0u64, 0u64, 0u64), |acc, s| {
                (
                    acc.0 + s.rx.lost_collision + s.rx.lost_half_duplex,
                    acc.1 + s.rx.delivered,
                    acc.2 + s.cs_deferrals,
                )
            })
    };
    let (lost_aloha, got_aloha, defer_aloha) = run("aloha");
    let (lost_cs, got_cs, defer_cs) = run("carrier_sense");
    assert_eq!(defer_aloha, 0);
    assert!(defer_cs > 0);
    assert!(
        lost_aloha > 100,
        "five beacons at 5 Hz on one channel collide: {lost_aloha}"
    );
    // Everyone hears everyone, so listening first removes (almost) every collision.
    assert!(
        lost_cs * 20 < lost_aloha,
        "carrier sense: {lost_cs} vs ALOHA {lost_aloha}"
    );
    assert!(got_cs > got_aloha, "{got_cs} vs {got_aloha}");
}

#[test]
fn medium_statistics_are_identical_on_one_and_two_threads() {
    // 300 beaconing vehicles: above the parallel threshold, and dense enough that more than
    // that many may hear the frames ending in some steps, so delivery runs on the pool.
    // Random headings: in a grid facing one way every LED would point at the back of the
    // vehicle ahead, whose photodiode looks away.
    let t = "seed = 2\nduration = 30\n[pool]\nsize = [14.0, 14.0, 3.0]\n\
        [[vehicles]]\ncount = 300\nrandom = { min = [0.5, 0.5, 1.0], max = [13.5, 13.5, 2.0], random_heading = true }\n\
        behaviour = { kind = \"beacon\", period = 0.5, payload_bytes = 26, jitter = 0.2 }\n";
    let desc = load_str(t, Path::new("t.toml")).unwrap();
    let mut out = Vec::new();
    for threads in [1, 2] {
        let mut sim = Sim::new(
            &desc,
            SimOptions {
                threads,
                record: false,
            },
        );
        sim.run(500);
        // The parallel path ran on 2 threads: every step's vehicle pass, every control tick's
        // behaviours (0.05 s) and the medium's deliveries in some steps; on 1 thread none.
        let split = sim.parallel_dispatches();
        if threads == 1 {
            assert_eq!(split.total(), 0, "{split:?}");
        } else {
            assert_eq!((split.vehicles, split.behaviour), (500, 100), "{split:?}");
            assert!(split.delivery > 0, "delivery never on the pool: {split:?}");
            // The communication graph, sampled every second, folds the links on the pool.
            assert_eq!(split.links, 5, "{split:?}");
        }
        let s: Vec<_> = (0..300)
            .map(|i| {
                let c = stats(&sim, i);
                (c.sent, c.rx, {
                    let mut l: Vec<_> = c
                        .links()
                        .iter()
                        .map(|(k, v)| (*k, v.delivered, v.lost_collision))
                        .collect();
                    l.sort_unstable();
                    l
                })
            })
            .collect();
        let delivered: u64 = s.iter().map(|x| x.1.delivered).sum();
        assert!(delivered > 1000, "a busy medium: {delivered}");
        // The world-wide tallies (summed over the chunks of receivers the pool ran) count
        // every receiver's attempts and deliveries once.
        let attempts: u64 = s.iter().map(|x| x.1.attempts).sum();
        let m = sim.medium();
        let by_distance = m.delivery_by_distance();
        let latency = m.latency_histogram();
        assert_eq!(by_distance.iter().map(|b| b.0).sum::<u64>(), attempts);
        assert_eq!(by_distance.iter().map(|b| b.1).sum::<u64>(), delivered);
        assert_eq!(latency.iter().sum::<u64>(), delivered);
        assert_eq!(m.delivered, delivered);
        let per_second: u64 = m.per_second.iter().flatten().sum();
        assert_eq!(per_second, attempts);
        let conn = sim.connectivity();
        assert!(
            conn.samples.iter().any(|c| c.edges > 0),
            "{:?}",
            conn.samples
        );
        let world = format!(
            "{by_distance:?} {latency:?} {:?} {:?} {:?}",
            m.per_second, conn.samples, conn.last_edges
        );
        out.push((sim.digest(), format!("{s:?} {world}")));
    }
    assert_eq!(out[0].0, out[1].0);
    assert!(
        out[0].1 == out[1].1,
        "medium statistics differ between 1 and 2 threads"
    );
}

#[test]
fn the_flock_keeps_optical_contact_while_it_travels() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../worlds/flock.toml");
    let mut desc = shoal_world::load::load_file(&path).unwrap();
    desc.duration = 90.0;
    let mut sim = Sim::new(
        &desc,
        SimOptions {
            threads: 1,
            record: false,
        },
    );
    let start: Vec<_> = sim
        .vehicles()
        .iter()
        .map(|v| v.state.rigid.position)
        .collect();
    sim.run(desc.steps());
    let conn = sim.connectivity();
    let n = desc.vehicles.len();
    // After the first seconds of sorting out, the largest group in contact holds nearly all.
    let late: Vec<usize> = conn
        .samples
        .iter()
        .filter(|s| s.t >= 30.0)
        .map(|s| s.largest)
        .collect();
    assert!(!late.is_empty());
    let mean = late.iter().sum::<usize>() as f64 / late.len() as f64;
    assert!(mean >= 0.9 * n as f64, "mean largest group {mean} of {n}");
    // And it moved as a group: everyone travelled, and the spread stayed bounded.
    let end: Vec<_> = sim
        .vehicles()
        .iter()
        .map(|v| v.state.rigid.position)
        .collect();
    let moved = start
        .iter()
        .zip(&end)
        .map(|(a, b)| (b - a).xy().norm())
        .fold(f64::INFINITY, f64::min);
    assert!(moved > 2.0, "least distance travelled {moved} m");
    let centre = end.iter().fold(nalgebra::Vector3::zeros(), |a, p| a + p) / n as f64;
    let spread = end
        .iter()
        .map(|p| (p - centre).xy().norm())
        .fold(0.0, f64::max);
    assert!(spread < 5.0, "group radius {spread} m");
}

/// Outcome counts per second of the 900-vehicle beaconing benchmark swarm (seed 3) in its
/// first 250 steps, in the order of [`GOLDEN_ORDER`], and an FNV-1a digest of every delivery.
const GOLDEN_BEACON_OUTCOMES: [[u64; 5]; 3] = [
    [19719, 6058, 390, 725, 6115],
    [20616, 6457, 406, 1157, 6541],
    [10543, 3312, 230, 612, 3337],
];
/// The outcomes of a row of [`GOLDEN_BEACON_OUTCOMES`] (as pinned when the medium's own list
/// had this order).
const GOLDEN_ORDER: [shoal_sim::comm::Outcome; 5] = {
    use shoal_sim::comm::Outcome::*;
    [OutOfBudget, Occluded, HalfDuplex, Collided, Delivered]
};
/// See [`GOLDEN_BEACON_OUTCOMES`].
const GOLDEN_BEACON_DELIVERIES: u64 = 0x6f99_3915_1876_fc8d;

/// Every reception of a beaconing swarm is pinned — each outcome, and the receiver, sender,
/// sequence number, modem, power and SNR of every delivery — and the same on 1 and 2 threads
/// (delivery split over the pool). A change to the medium's decisions, the order of its
/// random draws or its sums shows up here; a speed-up of the medium must leave it alone.
#[test]
fn beaconing_swarm_receptions_are_pinned_on_one_and_two_threads() {
    use shoal_sim::comm::Inbox;
    use shoal_sim::components::VehicleId;
    let desc = shoal_sim::bench::swarm_with(900, 3, true);
    let mut runs = Vec::new();
    for threads in [1, 2] {
        let mut sim = Sim::new(
            &desc,
            SimOptions {
                threads,
                record: false,
            },
        );
        sim.set_min_parallel(64);
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for _ in 0..250 {
            sim.step();
            // An inbox holds the frames delivered in the last step.
            let w = sim.world_mut();
            let mut got: Vec<_> = w
                .query::<(&VehicleId, &Inbox)>()
                .iter(w)
                .flat_map(|(id, inbox)| inbox.frames.iter().map(move |r| (id.0, r)))
                .map(|(id, r)| {
                    let modem = r.modem as u64;
                    (id, r.from, r.seq, modem, r.power.to_bits(), r.snr.to_bits())
                })
                .collect();
            got.sort_unstable();
            for (id, from, seq, modem, power, snr) in got {
                for x in [
                    u64::from(id),
                    u64::from(from),
                    u64::from(seq),
                    modem,
                    power,
                    snr,
                ] {
                    h = (h ^ x).wrapping_mul(0x0000_0100_0000_01b3);
                }
            }
        }
        if threads == 2 {
            assert!(sim.parallel_dispatches().delivery > 0);
        }
        let m = sim.medium();
        let tallies = (m.delivery_by_distance(), m.latency_histogram());
        let per_second: Vec<[u64; 5]> = m
            .per_second
            .iter()
            .map(|c| GOLDEN_ORDER.map(|o| c[o.index()]))
            .collect();
        runs.push((per_second, h, tallies));
    }
    assert!(
        runs[0] == runs[1],
        "receptions differ between 1 and 2 threads"
    );
    assert_eq!(
        (runs[0].0.as_slice(), runs[0].1),
        (&GOLDEN_BEACON_OUTCOMES[..], GOLDEN_BEACON_DELIVERIES)
    );
}

/// A vehicle without modems hears nothing, even right in front of a beaconing LED where the
/// cheap bound cannot rule a frame out (its centre within its own hull radius of the LED): it
/// stays a candidate by its position, every attempt ends out of budget, and the run goes on
/// (seen failing — a panic on a zero-length chunk of modems — before the delivery returned
/// early for it).
#[test]
fn a_vehicle_without_modems_in_front_of_an_led_hears_nothing() {
    let text = "seed = 4\nduration = 10\n[pool]\nsize = [10.0, 10.0, 3.0]\n\
        [[vehicles]]\nname = \"tx\"\nposition = [5.0, 5.0, 1.5]\n\
        behaviour = { kind = \"beacon\", period = 0.1, payload_bytes = 26, jitter = 0.01 }\n\
        [[vehicles]]\nname = \"deaf\"\nposition = [5.28, 5.0, 1.5]\nmodel = { modems = [] }\n";
    let mut sim = world(text);
    sim.run(200);
    let s = stats(&sim, 1);
    assert!(s.rx.attempts > 10, "{:?}", s.rx);
    assert_eq!(s.rx.delivered, 0, "{:?}", s.rx);
    assert_eq!(s.rx.lost_range, s.rx.attempts, "{:?}", s.rx);
}
