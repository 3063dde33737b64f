//! `shoal bench --access`: the traffic table once per medium-access protocol, each row with
//! its step's cost against unslotted ALOHA's on the same swarm. The two swarms are built and
//! warmed up once, then stepped in turns — slices of ALOHA, the protocol, the protocol,
//! ALOHA — so that a drift of the machine's speed that is steady over a round falls on both
//! alike; the figure is the median round's ratio, printed with the range of the rounds'
//! ratios (how far the machine's speed drifted within a round).

use crate::bench_measure::{Cell, Marks, cell, prepared};
use shoal_sim::bench::TRAFFIC_SPACING;
use shoal_sim::phases::ByPhase;
use shoal_sim::prelude::*;
use shoal_world::desc::WorldDesc;
use std::time::Instant;

/// Rounds of [`paired_cost`] (odd: the median is a round's). Fifteen short rounds rather than a
/// few long ones: the guest's speed drifts within a second, and a short round sees less of it.
const ROUNDS: usize = 15;

/// Steps of warm-up: 1.5 s at the bench's 0.01 s, so that every beacon has started.
const WARMUP: u64 = 150;

/// The traffic table once per medium-access protocol in `access`, for each of `vehicles` and
/// `threads`, each row with its step's cost against unslotted ALOHA's ([`paired_cost`],
/// `seconds` \[s\] of wall time in all).
pub(crate) fn access_table(
    (vehicles, threads): (&[usize], &[usize]),
    access: &[String],
    seconds: f64,
    json: &mut Vec<serde_json::Value>,
) -> anyhow::Result<()> {
    println!(
        "\nwith optical traffic — a {TRAFFIC_SPACING} m grid, every vehicle with 4 modems beaconing a 32-byte frame once a second, its modems getting the medium by each protocol;\ncost × ALOHA = wall time of a step / that of the same swarm under unslotted ALOHA (the two stepped in turns, ALOHA–protocol–protocol–ALOHA; the median of {ROUNDS} rounds, and their range)"
    );
    println!(
        "{:>8} {:>7} {:>14} {:>16} {:>10} {:>12} {:>14} {:>14}",
        "vehicles",
        "threads",
        "access",
        "vehicle-steps/s",
        "frames/s",
        "delivered/s",
        "cost × ALOHA",
        "rounds"
    );
    for &n in vehicles {
        let aloha = shoal_sim::bench::traffic_swarm_with_access(n, 1, "\"aloha\"")
            .map_err(anyhow::Error::msg)?;
        for &t in threads {
            for name in access {
                let desc = shoal_sim::bench::traffic_swarm_with_access(n, 1, &format!("{name:?}"))
                    .map_err(|e| anyhow::anyhow!("--access {name}: {e}"))?;
                let ((cost, (lo, hi)), c) = paired_cost(&aloha, &desc, t, seconds);
                println!(
                    "{:>8} {:>7} {:>14} {:>16.0} {:>10.0} {:>12.0} {:>14.3} {:>14}",
                    n,
                    t,
                    name,
                    c.vehicle_steps_per_s,
                    c.frames_per_s,
                    c.deliveries_per_s,
                    cost,
                    format!("{lo:.3}–{hi:.3}")
                );
                json.push(serde_json::json!({
                    "table": "access", "vehicles": n, "threads": t, "access": name,
                    "steps": c.steps, "wall_s": c.wall_s,
                    "vehicle_steps_per_s": c.vehicle_steps_per_s, "frames_per_s": c.frames_per_s,
                    "deliveries_per_s": c.deliveries_per_s, "cost_vs_aloha": cost,
                    "cost_rounds": [lo, hi],
                    "phase_shares": ByPhase(c.phase_shares),
                }));
            }
        }
    }
    Ok(())
}

/// The wall time of a step of `desc` against one of `aloha` on `threads` threads: both swarms
/// built and warmed up, then [`ROUNDS`] rounds of four slices of the same number of steps —
/// ALOHA, `desc`, `desc`, ALOHA — `seconds` \[s\] in all; the median round's ratio with the
/// lowest and the highest, and the cell of `desc` over all its slices.
fn paired_cost(
    aloha: &WorldDesc,
    desc: &WorldDesc,
    threads: usize,
    seconds: f64,
) -> ((f64, (f64, f64)), Cell) {
    let (mut a, _) = prepared(aloha, threads, WARMUP);
    let (mut b, bytes) = prepared(desc, threads, WARMUP);
    let time = |sim: &mut Sim, steps: u64| {
        let start = Instant::now();
        sim.run(steps);
        start.elapsed().as_secs_f64()
    };
    // Steps per slice, from a first look at the slower of the two.
    let probe = 10;
    let step = time(&mut a, probe).max(time(&mut b, probe)) / probe as f64;
    let per_slice = seconds / (4 * ROUNDS) as f64;
    let k = ((per_slice / step.max(1e-9)).ceil() as u64).max(1);
    let marks = Marks::of(&b);
    let mut wall_b = 0.0;
    let mut ratios: Vec<f64> = (0..ROUNDS)
        .map(|_| {
            let first = time(&mut a, k);
            let mine = time(&mut b, k) + time(&mut b, k);
            let last = time(&mut a, k);
            wall_b += mine;
            mine / (first + last)
        })
        .collect();
    ratios.sort_by(f64::total_cmp);
    let c = cell(&mut b, (2 * k * ROUNDS as u64, wall_b), bytes, &marks);
    let range = (ratios[0], ratios[ROUNDS - 1]);
    ((ratios[ROUNDS / 2], range), c)
}
