//! What `shoal bench` measures of one swarm ([`Cell`]): built on a thread count, warmed up,
//! stepped for a wall time, its medium's counters read before and after ([`Marks`]) and its
//! phases timed on a continuation.

use crate::alloc::live_bytes;
use shoal_sim::phases::Phase;
use shoal_sim::prelude::*;
use shoal_world::desc::WorldDesc;
use std::time::Instant;

/// What one swarm measured.
pub(crate) struct Cell {
    /// Steps measured.
    pub(crate) steps: u64,
    /// Their wall time \[s\].
    pub(crate) wall_s: f64,
    /// Vehicles times steps per wall-clock second \[1/s\].
    pub(crate) vehicle_steps_per_s: f64,
    /// Simulated time per wall-clock time \[1\].
    pub(crate) real_time: f64,
    /// Heap the swarm took when built, per vehicle \[bytes\].
    pub(crate) bytes_per_vehicle: f64,
    /// Frames started per simulated second \[1/s\].
    pub(crate) frames_per_s: f64,
    /// Frames delivered per simulated second \[1/s\].
    pub(crate) deliveries_per_s: f64,
    /// Loops split over the thread pool during the measured steps.
    pub(crate) parallel_dispatches: u64,
    /// Share of each phase of the step (order of [`Phase::ALL`]), from a timed continuation
    /// of the measured run.
    pub(crate) phase_shares: [f64; 6],
    /// Reception attempts per step and the delivery phase's wall time per attempt \[ns\] in
    /// that continuation (`None` without attempts).
    pub(crate) attempts: Option<(f64, f64)>,
}

/// What a swarm had done when its measured steps began.
pub(crate) struct Marks {
    /// Frames started and delivered so far.
    sent: u64,
    delivered: u64,
    /// Loops split over the pool so far.
    split: u64,
    /// Simulated time \[s\].
    t: f64,
}

impl Marks {
    /// Of `sim` now.
    pub(crate) fn of(sim: &Sim) -> Self {
        Self {
            sent: sim.medium().started.0,
            delivered: sim.medium().delivered,
            split: sim.parallel_dispatches().total(),
            t: sim.time(),
        }
    }
}

/// The swarm of `desc` on `threads` threads, stepped `warmup` steps, and the heap it took
/// when built per vehicle \[bytes\].
pub(crate) fn prepared(desc: &WorldDesc, threads: usize, warmup: u64) -> (Sim, f64) {
    let before = live_bytes();
    let mut sim = Sim::new(
        desc,
        SimOptions {
            threads,
            record: false,
        },
    );
    let bytes = live_bytes().saturating_sub(before) as f64 / desc.vehicles.len() as f64;
    sim.run(warmup);
    (sim, bytes)
}

/// `desc` on `threads` threads, stepped `warmup` steps, then measured for at least `seconds`
/// \[s\] of wall time (and 10 steps).
pub(crate) fn measure(desc: &WorldDesc, threads: usize, seconds: f64, warmup: u64) -> Cell {
    let (mut sim, bytes) = prepared(desc, threads, warmup);
    let marks = Marks::of(&sim);
    let start = Instant::now();
    let mut steps = 0u64;
    let mut batch = 1u64;
    while start.elapsed().as_secs_f64() < seconds || steps < 10 {
        sim.run(batch);
        steps += batch;
        batch = (batch * 2).min(1000);
    }
    let wall = start.elapsed().as_secs_f64();
    cell(&mut sim, (steps, wall), bytes, &marks)
}

/// The cell of `sim`, which stepped `steps` in `wall` \[s\] of measured time since `marks`
/// (built taking `bytes` per vehicle); its phases are timed on a continuation of a quarter of
/// the measured steps, so that the clock reads cannot slow the measured rate (they matter in
/// the smallest worlds).
pub(crate) fn cell(sim: &mut Sim, (steps, wall): (u64, f64), bytes: f64, marks: &Marks) -> Cell {
    let n = sim.len();
    let sim_s = sim.time() - marks.t;
    let (sent, delivered) = (
        sim.medium().started.0 - marks.sent,
        sim.medium().delivered - marks.delivered,
    );
    let parallel_dispatches = sim.parallel_dispatches().total() - marks.split;
    sim.time_phases();
    let (attempts0, timed) = (sim.medium().attempts(), (steps / 4).max(10));
    sim.run(timed);
    let attempts = sim.medium().attempts() - attempts0;
    let delivery = sim.phase_times().of(Phase::MediumDelivery);
    Cell {
        steps,
        wall_s: wall,
        vehicle_steps_per_s: (steps * n as u64) as f64 / wall,
        real_time: sim_s / wall,
        bytes_per_vehicle: bytes,
        frames_per_s: sent as f64 / sim_s,
        deliveries_per_s: delivered as f64 / sim_s,
        parallel_dispatches,
        phase_shares: sim.phase_times().shares(),
        attempts: (attempts > 0).then(|| {
            (
                attempts as f64 / timed as f64,
                1e9 * delivery / attempts as f64,
            )
        }),
    }
}
