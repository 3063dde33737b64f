//! Times the benchmark swarm with optical traffic against variants, for profiling the medium:
//! `cargo run --release --example profile_comm -- N [beacons [THREADS]]` (with `beacons`, only
//! the swarm with traffic, stepped for longer on THREADS threads, default 1: a run to record
//! with `perf`).

use shoal::sim::bench::{TRAFFIC_SPACING, swarm_text};
use shoal::sim::prelude::*;
use shoal::world::load::load_str;
use std::path::Path;
use std::time::Instant;

fn time(label: &str, text: &str, steps: u64, threads: usize) {
    let desc = load_str(text, Path::new("p.toml")).unwrap();
    let mut sim = Sim::new(
        &desc,
        SimOptions {
            threads,
            record: false,
        },
    );
    sim.run(150);
    let t = Instant::now();
    sim.run(steps);
    println!(
        "{label:<40} {:>8.3} ms/step  delivered {}",
        t.elapsed().as_secs_f64() * 1e3 / steps as f64,
        sim.medium().delivered
    );
}

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1000);
    let traffic = swarm_text(n, 1, TRAFFIC_SPACING, true);
    if std::env::args().nth(2).as_deref() == Some("beacons") {
        let threads = std::env::args()
            .nth(3)
            .and_then(|s| s.parse().ok())
            .unwrap_or(1);
        time("beacons at 1 Hz", &traffic, 1000, threads);
        return;
    }
    let quiet = swarm_text(n, 1, TRAFFIC_SPACING, false);
    time("quiet", &quiet, 200, 1);
    time(
        "modems + beacon behaviour, no frames",
        &traffic.replace("period = 1.0", "period = 100000.0"),
        200,
        1,
    );
    time("beacons at 1 Hz", &traffic, 200, 1);
}
