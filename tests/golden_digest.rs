//! Golden digest (as rapier's `snapshot_portability`): a hash of every vehicle's state after a
//! fixed run must not change silently, and must be the same on 1 and 2 threads.
//!
//! If you changed the physics, controllers, sensors or RNG use on purpose, this test fails:
//! check that the change is intended, then replace `GOLDEN` with the printed value and say so
//! in the commit message.

use shoal::sim::bench::swarm;
use shoal::sim::prelude::*;

/// Digest of the 300-vehicle benchmark swarm (seed 5) after 400 steps.
const GOLDEN: u64 = 0x2ce6_75fe_463a_5b3b;

#[test]
fn digest_is_golden_on_one_and_two_threads() {
    let desc = swarm(300, 5);
    let digests: Vec<u64> = [1, 2]
        .into_iter()
        .map(|threads| {
            let mut sim = Sim::new(
                &desc,
                SimOptions {
                    threads,
                    record: false,
                },
            );
            sim.run(400);
            sim.digest()
        })
        .collect();
    assert_eq!(digests[0], digests[1], "1 vs 2 threads");
    assert_eq!(
        digests[0], GOLDEN,
        "state digest changed: {:#018x}",
        digests[0]
    );
}
