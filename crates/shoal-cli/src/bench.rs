//! `shoal bench`: the scaling table. Every figure comes from one process in one run, so the
//! ratios between rows (thread speed-up, cost of the optical medium, memory per vehicle) are
//! comparable even on a noisy machine; absolute numbers are not.

use crate::alloc::live_bytes;
use shoal_sim::bench::{SPACING, TRAFFIC_SPACING, swarm_spaced};
use shoal_sim::prelude::*;
use shoal_world::desc::WorldDesc;
use std::time::Instant;

/// Arguments of `shoal bench`.
#[derive(clap::Args, Debug)]
pub struct BenchArgs {
    /// Vehicle counts.
    #[arg(long, value_delimiter = ',', default_values_t = [1usize, 10, 100, 1000, 10000])]
    pub vehicles: Vec<usize>,
    /// Thread counts.
    #[arg(long, value_delimiter = ',', default_values_t = [1usize, 2])]
    pub threads: Vec<usize>,
    /// Least wall time measured per cell [s].
    #[arg(long, default_value_t = 1.0)]
    pub seconds: f64,
    /// Skip the second table (optical traffic).
    #[arg(long)]
    pub no_comm: bool,
    /// Print the tables as JSON as well.
    #[arg(long)]
    pub json: bool,
}

struct Cell {
    steps: u64,
    wall_s: f64,
    vehicle_steps_per_s: f64,
    real_time: f64,
    bytes_per_vehicle: f64,
    frames_per_s: f64,
    deliveries_per_s: f64,
}

fn measure(desc: &WorldDesc, threads: usize, seconds: f64, warmup: u64) -> Cell {
    let n = desc.vehicles.len();
    let before = live_bytes();
    let mut sim = Sim::new(
        desc,
        SimOptions {
            threads,
            record: false,
        },
    );
    let bytes = live_bytes().saturating_sub(before) as f64 / n as f64;
    sim.run(warmup);
    let (sent0, got0) = (sim.medium().started.0, sim.medium().delivered);
    let start = Instant::now();
    let mut steps = 0u64;
    let mut batch = 1u64;
    while start.elapsed().as_secs_f64() < seconds || steps < 10 {
        sim.run(batch);
        steps += batch;
        batch = (batch * 2).min(1000);
    }
    let wall = start.elapsed().as_secs_f64();
    let sim_s = steps as f64 * desc.dt;
    Cell {
        steps,
        wall_s: wall,
        vehicle_steps_per_s: (steps * n as u64) as f64 / wall,
        real_time: sim_s / wall,
        bytes_per_vehicle: bytes,
        frames_per_s: (sim.medium().started.0 - sent0) as f64 / sim_s,
        deliveries_per_s: (sim.medium().delivered - got0) as f64 / sim_s,
    }
}

/// Runs the tables.
pub fn bench(a: &BenchArgs) -> anyhow::Result<()> {
    anyhow::ensure!(
        a.seconds > 0.0 && a.seconds.is_finite(),
        "--seconds must be > 0"
    );
    anyhow::ensure!(
        a.vehicles.iter().all(|n| (1..=1_000_000).contains(n)),
        "--vehicles: each 1 … 1000000"
    );
    anyhow::ensure!(
        a.threads.iter().all(|t| (1..=256).contains(t)),
        "--threads: each 1 … 256"
    );
    if cfg!(debug_assertions) {
        eprintln!(
            "warning: this is a debug build; benchmark a release build (cargo run --release -- bench)"
        );
    }
    let mut json = Vec::new();
    println!(
        "shoal bench — μAUV² swarm on a 0.6 m grid in auto mode, dt = 0.01 s, RK4, recording off"
    );
    println!(
        "{:>8} {:>7} {:>7} {:>9} {:>16} {:>12} {:>9} {:>14}",
        "vehicles",
        "threads",
        "steps",
        "wall s",
        "vehicle-steps/s",
        "real-time ×",
        "speed-up",
        "bytes/vehicle"
    );
    for &n in &a.vehicles {
        let desc = swarm_spaced(n, 1, SPACING, false);
        let mut base: Option<f64> = None;
        for &t in &a.threads {
            let c = measure(&desc, t, a.seconds, 20);
            let speedup = base.map_or(1.0, |b| c.vehicle_steps_per_s / b);
            base.get_or_insert(c.vehicle_steps_per_s);
            println!(
                "{:>8} {:>7} {:>7} {:>9.3} {:>16.0} {:>12.2} {:>9.2} {:>14.0}",
                n,
                t,
                c.steps,
                c.wall_s,
                c.vehicle_steps_per_s,
                c.real_time,
                speedup,
                c.bytes_per_vehicle
            );
            json.push(serde_json::json!({
                "table": "quiet", "vehicles": n, "threads": t, "steps": c.steps, "wall_s": c.wall_s,
                "vehicle_steps_per_s": c.vehicle_steps_per_s, "real_time_factor": c.real_time,
                "speed_up": speedup, "bytes_per_vehicle": c.bytes_per_vehicle
            }));
        }
    }
    if !a.no_comm {
        println!(
            "\nwith optical traffic — a {TRAFFIC_SPACING} m grid, every vehicle with 4 modems beaconing a 32-byte frame once a second;\nmedium share = 1 − rate with traffic / rate of the same swarm without"
        );
        println!(
            "{:>8} {:>7} {:>7} {:>9} {:>16} {:>12} {:>10} {:>12} {:>14}",
            "vehicles",
            "threads",
            "steps",
            "wall s",
            "vehicle-steps/s",
            "real-time ×",
            "frames/s",
            "delivered/s",
            "medium share"
        );
        for &n in &a.vehicles {
            let desc = swarm_spaced(n, 1, TRAFFIC_SPACING, true);
            let silent = swarm_spaced(n, 1, TRAFFIC_SPACING, false);
            for &t in &a.threads {
                // 1.5 s of warm-up: every beacon has started.
                let c = measure(&desc, t, a.seconds, 150);
                let q = measure(&silent, t, a.seconds, 150).vehicle_steps_per_s;
                // Share of a step's time spent on the medium: 1 − (rate with traffic / quiet rate).
                let share = 1.0 - c.vehicle_steps_per_s / q;
                println!(
                    "{:>8} {:>7} {:>7} {:>9.3} {:>16.0} {:>12.2} {:>10.0} {:>12.0} {:>13.0}%",
                    n,
                    t,
                    c.steps,
                    c.wall_s,
                    c.vehicle_steps_per_s,
                    c.real_time,
                    c.frames_per_s,
                    c.deliveries_per_s,
                    100.0 * share
                );
                json.push(serde_json::json!({
                    "table": "traffic", "vehicles": n, "threads": t, "steps": c.steps, "wall_s": c.wall_s,
                    "vehicle_steps_per_s": c.vehicle_steps_per_s, "real_time_factor": c.real_time,
                    "frames_per_s": c.frames_per_s, "deliveries_per_s": c.deliveries_per_s, "medium_share": share,
                    "bytes_per_vehicle": c.bytes_per_vehicle
                }));
            }
        }
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&json)?);
    }
    Ok(())
}
