//! Back-off slots counted down at once (`comm/countdown.rs`) against the reference, asking the
//! protocol at every slot boundary (`Medium::slot_by_slot`): in the reliable-gossip world
//! (65 vehicles with a ring of four modems, hellos and acknowledged unicasts, so that frames
//! collide, acknowledgements go astray, windows grow and counts freeze and run across steps),
//! CSMA/CA and p-persistent CSMA start the same frames at the same instants — every vehicle's
//! counters, every flow's latencies and the world's totals agree to the last bit, on one
//! thread and on two (the transmit walk split into independent parts walked on both). Seen
//! failing when a frame that started at the very boundary a vehicle began counting at did not
//! stop the count.

use shoal_sim::comm::Medium;
use shoal_sim::prelude::*;
use shoal_world::desc::WorldDesc;
use shoal_world::load::load_str;
use std::path::Path;

/// The reliable-gossip world with `access` on every modem, for `seconds`.
fn world(access: &str, seconds: f64) -> WorldDesc {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../worlds/reliable_gossip.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let text = text
        .replace("duration = 20.0", &format!("duration = {seconds}"))
        .replace(
            "[[vehicles.model.modems]]\n",
            &format!("[[vehicles.model.modems]]\naccess = {access}\n"),
        );
    load_str(&text, &path).unwrap()
}

/// Everything a run's frames decide, as text: the world's totals, every flow and every
/// vehicle's communication counters.
/// Also the frames started and the retransmissions.
/// On two threads every loop is split, however small: the transmit phase's walk goes in
/// independent parts (`comm/parts.rs`), and it is checked that it did.
fn outcome(desc: &WorldDesc, threads: usize, slot_by_slot: bool) -> (String, u64, u64) {
    let mut sim = Sim::new(
        desc,
        SimOptions {
            threads,
            record: false,
        },
    );
    sim.world_mut().resource_mut::<Medium>().slot_by_slot = slot_by_slot;
    if threads > 1 {
        sim.set_min_parallel(2);
    }
    let steps = (desc.duration / desc.dt).round() as u64;
    sim.run(steps);
    let walks = sim.parallel_dispatches().walk;
    assert_eq!(
        walks > 0,
        threads > 1,
        "{walks} walks split on {threads} thread(s)"
    );
    let m = sim.medium();
    let mut flows: Vec<_> = m.flows().iter().collect();
    flows.sort_by_key(|(k, _)| **k);
    let vehicles: Vec<_> = sim.vehicles().into_iter().map(|v| v.comm).collect();
    let text = format!(
        "started {:?} delivered {} ended {}\nflows {flows:?}\nvehicles {vehicles:?}",
        m.started, m.delivered, m.ended
    );
    let retransmissions = flows.iter().map(|(_, f)| f.retransmissions).sum();
    (text, m.started.0, retransmissions)
}

fn same_frames(access: &str) {
    let desc = world(access, 6.0);
    let (reference, started, retransmissions) = outcome(&desc, 1, true);
    // Enough traffic to mean something: hellos, and unicasts from t = 2 s on, some of them
    // sent again.
    assert!(started > 2_000, "{access}: {started} frames");
    assert!(retransmissions > 0, "{access}: no retransmission");
    for threads in [1, 2] {
        let (counted, _, _) = outcome(&desc, threads, false);
        assert!(
            counted == reference,
            "{access}, {threads} thread(s): counting down at once differs from slot by slot"
        );
    }
}

#[test]
fn csma_ca_counts_down_at_once_with_the_same_frames() {
    same_frames("\"csma_ca\"");
    // Short windows: counts of a few slots, frozen often.
    same_frames("{ kind = \"csma_ca\", cw_min = 4, cw_max = 64 }");
}

#[test]
fn p_persistent_counts_down_at_once_with_the_same_frames() {
    same_frames("{ kind = \"p_persistent\", p = 0.3 }");
}
