//! The replay gathered while a world runs holds what the run did: one pose per vehicle and
//! frame (quantised within the pool, matching the final state), the panel once a second (less
//! often for large swarms),
//! every reception attempt (under the budget) and a timeline that adds up to the medium's
//! totals.

use shoal_sim::prelude::*;
use shoal_sim::replay::{Outcome, PANEL, ReplayData, capture::frame_dt};
use std::path::Path;

/// `desc` run for `steps` steps on two threads with the replay gathered: the simulation and
/// its replay.
fn run_with_replay(desc: &shoal_world::desc::WorldDesc, steps: u64) -> (Sim, ReplayData) {
    let mut sim = Sim::new(
        desc,
        SimOptions {
            threads: 2,
            record: false,
        },
    );
    sim.enable_replay(desc);
    sim.run(steps);
    let r = sim.take_replay().expect("enabled");
    (sim, r)
}

#[test]
fn the_replay_of_the_default_world_matches_the_run() {
    let mut desc = shoal_world::load::load_file(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../worlds/default.toml"),
    )
    .unwrap();
    desc.duration = 10.0;
    let (sim, r) = run_with_replay(&desc, desc.steps());
    let m = &r.meta;
    let n = desc.vehicles.len();
    assert_eq!(m.vehicles, n);
    // 12 vehicles are far below the pose budget: the full frame rate, 20 per second.
    assert!((m.frame_dt - 0.05).abs() < 1e-12, "{}", m.frame_dt);
    assert_eq!(m.frame_dt, frame_dt(n, 10.0, 0.01));
    assert_eq!(
        m.frames, 201,
        "frames at t = dt, 0.05, 0.10, …, 10.0 s (the first is t ≈ 0)"
    );
    assert_eq!(r.pos.len(), m.frames * n * 3);
    assert_eq!(r.att.len(), r.pos.len());
    // The colour key is the page writer's (shoal-record), not the capture's.
    assert!(m.outcomes.is_empty());
    // Panel rows at t ≈ 0, 1, …, 10 s.
    assert_eq!(r.panel.len(), 11 * n * PANEL.len());
    // The last frame is the final state, within the quantisation (pool / 65535 ≈ 0.1 mm).
    for i in 0..n {
        let v = sim.vehicle(i);
        let p = v.state.rigid.position;
        let k = ((m.frames - 1) * n + i) * 3;
        for (a, span) in m.pool.iter().enumerate() {
            let x = f64::from(r.pos[k + a]) / 65535.0 * span;
            assert!(
                (x - p[a]).abs() <= 0.5 * span / 65535.0 + 1e-9,
                "{i} axis {a}"
            );
        }
        let yaw = f64::from(r.att[k + 2]) * std::f64::consts::PI / 32767.0;
        let true_yaw = v.state.rigid.attitude.euler_angles().2;
        assert!(shoal_model::math::wrap_pi(yaw - true_yaw).abs() < 1e-4);
        // The panel's last row: the depth reading and the frames sent.
        let row = &r.panel[(10 * n + i) * PANEL.len()..(10 * n + i + 1) * PANEL.len()];
        assert_eq!(row[0], v.sensors.depth as f32);
        assert_eq!(row[4], v.comm.sent as f32);
    }
    // Every reception attempt is there (far below the budget), and the per-second timeline
    // adds up to the medium's totals.
    let rx = sim
        .vehicles()
        .iter()
        .fold(0u64, |a, v| a + v.comm.rx.attempts);
    assert!(rx > 1000, "the default world talks: {rx}");
    assert_eq!(m.links_total, rx);
    assert_eq!(r.links.len() as u64, rx);
    assert_eq!(m.timeline.attempted.iter().sum::<u64>(), rx);
    let delivered = r
        .links
        .iter()
        .filter(|e| e.outcome == Outcome::Delivered)
        .count() as u64;
    assert_eq!(m.timeline.delivered.iter().sum::<u64>(), delivered);
    assert!(r.links.iter().any(|e| e.outcome == Outcome::Occluded));
    assert!(r.links.windows(2).all(|w| w[0].t <= w[1].t));
    assert!(
        r.links
            .iter()
            .all(|e| (e.from as usize) < n && (e.to as usize) < n && e.from != e.to)
    );
    assert_eq!(m.timeline.largest_fraction.len(), 10);
    // The pillar is described for the viewer.
    assert_eq!(m.obstacles.len(), 1);
    assert_eq!(m.obstacles[0].kind, "cylinder");
    assert_eq!(m.obstacles[0].radius, Some(0.25));
    assert_eq!(m.obstacles[0].height, Some(2.0));
}

#[test]
fn a_large_swarm_lowers_the_frame_rate_to_the_budget() {
    // 12 bytes per vehicle and frame within the pose budget: 1,000 vehicles × 100 s keep 10 frames/s
    // (0.1 s), 10,000 vehicles 1 frame/s.
    assert!((frame_dt(1000, 100.0, 0.01) - 0.1).abs() < 1e-12);
    assert!((frame_dt(10_000, 100.0, 0.01) - 1.0).abs() < 1e-12);
    assert!((frame_dt(1, 100.0, 0.01) - 0.05).abs() < 1e-12);
}

#[test]
fn a_large_swarm_samples_its_panel_less_often() {
    // 3,000 vehicles planned for 1,000 s: a panel row is 84 kB, so the 6 MiB panel budget
    // allows 74 rows, and the finest interval that fits is 20 s (51 rows). The capture takes
    // rows at t ≈ 0 and every 20 s: after 20 s, two.
    let text = "name = \"big\"\nduration = 1000.0\n[pool]\nsize = [70.0, 70.0, 3.0]\n\
                [[vehicles]]\nname = \"g\"\ncount = 3000\n\
                grid = { origin = [1.0, 1.0, 1.5], spacing = [1.2, 1.2], columns = 55 }\n\
                mission = [{ t = 0, mode = \"auto\", depth = 1.5, yaw_deg = 0 }]\n";
    let desc = shoal_world::load::load_str(text, Path::new("big.toml")).unwrap();
    let (sim, r) = run_with_replay(&desc, 2000);
    assert_eq!(r.meta.panel_dt, 20.0);
    assert_eq!(r.meta.panel_dt, shoal_sim::replay::panel_dt(3000, 1000.0));
    assert_eq!(r.panel_rows(), 2);
    // The second row is the state at t = 20 s: the depth readings of the vehicles.
    let w = PANEL.len();
    for i in [0, 1234, 2999] {
        let depth = r.panel[(3000 + i) * w];
        assert_eq!(depth, sim.vehicle(i).sensors.depth as f32, "vehicle {i}");
    }
    r.check().unwrap();
}

/// `a` sends acknowledged unicasts to `b` 1.25 m ahead of it, facing it; `b` beacons to
/// everyone besides (shared with `shoal-record`'s run.mcap tests).
const ACKED: &str = include_str!("support/acked_pair.toml");

/// The replay tells acknowledgement frames from the others: every event flagged as one goes
/// from the destination `b` back to the sender `a` — one for each acknowledgement `b` put on
/// the air (but one still on the air at the end), those delivered the frames `a` saw
/// acknowledged —, and every data frame (`a` → `b`) and beacon (`b` → `a`) is not flagged.
#[test]
fn acknowledgements_are_flagged_and_go_back_to_the_sender() {
    let desc = shoal_world::load::load_str(ACKED, Path::new("acked.toml")).unwrap();
    let (mut sim, r) = run_with_replay(&desc, desc.steps());
    sim.fold_comm();
    r.check().unwrap();
    let (a, b) = (0, 1);
    let acks: Vec<_> = r.links.iter().filter(|e| e.ack).collect();
    let others: Vec<_> = r.links.iter().filter(|e| !e.ack).collect();
    assert!(
        acks.iter().all(|e| (e.from, e.to) == (b, a)),
        "an acknowledgement not from b to a"
    );
    let data = others.iter().filter(|e| (e.from, e.to) == (a, b)).count() as u64;
    let beacons = others.iter().filter(|e| (e.from, e.to) == (b, a)).count() as u64;
    assert_eq!(data + beacons, others.len() as u64);
    assert_eq!(r.links.len() as u64, r.meta.links_total, "nothing thinned");
    // Every frame of a's reached b as an attempt, every frame of b's reached a.
    let (va, vb) = (sim.vehicle(0).comm, sim.vehicle(1).comm);
    assert_eq!(data, vb.rx.attempts);
    assert_eq!(acks.len() as u64 + beacons, va.rx.attempts);
    assert!(
        data > 60 && beacons > 20,
        "{data} data frames, {beacons} beacons"
    );
    // One attempt at a for each acknowledgement b sent (the last may not have ended).
    let sent = vb.acks_sent;
    let flagged = acks.len() as u64;
    assert!(
        flagged <= sent && flagged + 1 >= sent,
        "{flagged} acknowledgements in the replay, {sent} sent"
    );
    // Those delivered completed a's frames.
    let acked = sim
        .medium()
        .flows()
        .iter()
        .find(|(k, _)| **k == (a, b))
        .map(|(_, f)| f.acknowledged)
        .unwrap();
    let delivered = acks
        .iter()
        .filter(|e| e.outcome == Outcome::Delivered)
        .count() as u64;
    assert_eq!(delivered, acked);
}
