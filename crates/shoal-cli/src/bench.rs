//! `shoal bench`: the scaling table. Every figure comes from one process in one run, so the
//! ratios between rows (thread speed-up, cost per vehicle) are comparable even on a noisy
//! machine; absolute numbers are not.

use crate::alloc::live_bytes;
use shoal_sim::bench::swarm;
use shoal_sim::prelude::*;
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
    /// Print the table as JSON as well.
    #[arg(long)]
    pub json: bool,
}

struct Row {
    vehicles: usize,
    threads: usize,
    steps: u64,
    wall_s: f64,
    vehicle_steps_per_s: f64,
    real_time: f64,
    bytes_per_vehicle: f64,
}

/// Runs the table.
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
    println!("shoal bench — μAUV² swarm in auto mode, dt = 0.01 s, RK4, recording off");
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
    let mut rows: Vec<Row> = Vec::new();
    for &n in &a.vehicles {
        let desc = swarm(n, 1);
        let mut base: Option<f64> = None;
        for &t in &a.threads {
            let before = live_bytes();
            let mut sim = Sim::new(
                &desc,
                SimOptions {
                    threads: t,
                    record: false,
                },
            );
            let bytes = live_bytes().saturating_sub(before) as f64 / n as f64;
            sim.run(20); // warm-up: caches, pools, first control ticks
            let start = Instant::now();
            let mut steps = 0u64;
            let mut batch = 1u64;
            while start.elapsed().as_secs_f64() < a.seconds || steps < 10 {
                sim.run(batch);
                steps += batch;
                batch = (batch * 2).min(1000);
            }
            let wall = start.elapsed().as_secs_f64();
            let vsps = (steps * n as u64) as f64 / wall;
            let rt = steps as f64 * desc.dt / wall;
            let speedup = base.map_or(1.0, |b| vsps / b);
            base.get_or_insert(vsps);
            println!(
                "{:>8} {:>7} {:>7} {:>9.3} {:>16.0} {:>12.2} {:>9.2} {:>14.0}",
                n, t, steps, wall, vsps, rt, speedup, bytes
            );
            rows.push(Row {
                vehicles: n,
                threads: t,
                steps,
                wall_s: wall,
                vehicle_steps_per_s: vsps,
                real_time: rt,
                bytes_per_vehicle: bytes,
            });
        }
    }
    if a.json {
        let v: Vec<serde_json::Value> = rows
            .iter()
            .map(|r| {
                serde_json::json!({
                    "vehicles": r.vehicles, "threads": r.threads, "steps": r.steps, "wall_s": r.wall_s,
                    "vehicle_steps_per_s": r.vehicle_steps_per_s, "real_time_factor": r.real_time,
                    "bytes_per_vehicle": r.bytes_per_vehicle
                })
            })
            .collect();
        println!("{}", serde_json::to_string_pretty(&v)?);
    }
    Ok(())
}
