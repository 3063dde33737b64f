//! Criterion benchmarks of the hot path: one vehicle's physics step (RK4 and semi-implicit
//! Euler); its parts per vehicle (actuation, the RK4 integration of a chunk of 256
//! vehicles); one world step of the benchmark swarm at several sizes on 1 and 2 threads; and
//! the optical medium: a world step of the beaconing swarm against the same swarm without
//! traffic (the difference is the medium's cost per vehicle). Run with
//! `cargo bench --bench step`; compare ratios within one run.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use shoal::model::lanes::{DynConsts, LANES, Lanes, rk4_group};
use shoal::model::prelude::*;
use shoal::sim::bench::{TRAFFIC_SPACING, swarm, swarm_spaced};
use shoal::sim::prelude::*;
use std::hint::black_box;

/// The μAUV² preset, still water and a command that runs all three thrusters and tilts one
/// drive.
fn uauv2_setup() -> (VehicleModel, Environment, ActuatorCommands) {
    let cmd = ActuatorCommands {
        thrusters: vec![20.0, 40.0, 35.0].into(),
        tilts: vec![0.0, -0.6].into(),
        pump: Pump::Off,
    };
    (
        VehicleModel::new(presets::uauv2(), 1000.0),
        Environment::default(),
        cmd,
    )
}

fn vehicle_step(c: &mut Criterion) {
    let (model, env, cmd) = uauv2_setup();
    let mut g = c.benchmark_group("vehicle_step");
    for (name, integ) in [
        ("rk4", Integrator::Rk4),
        ("semi_implicit_euler", Integrator::SemiImplicitEuler),
    ] {
        let mut st = VehicleState::new(
            &model,
            RigidState::at_rest(Vec3::new(1.0, 1.0, 1.0), Quat::identity()),
            &env,
        );
        g.bench_function(name, |b| {
            b.iter(|| {
                step(&model, &mut st, black_box(&cmd), &env, integ, 0.01);
            })
        });
    }
    g.finish();
}

fn world_step(c: &mut Criterion) {
    let mut g = c.benchmark_group("world_step");
    g.sample_size(20);
    for n in [100usize, 1000] {
        let desc = swarm(n, 1);
        g.throughput(Throughput::Elements(n as u64));
        for threads in [1usize, 2] {
            let mut sim = Sim::new(
                &desc,
                SimOptions {
                    threads,
                    record: false,
                },
            );
            sim.run(10);
            g.bench_with_input(
                BenchmarkId::new(format!("{threads}_threads"), n),
                &n,
                |b, _| b.iter(|| sim.step()),
            );
        }
    }
    g.finish();
}

/// Actuation of one vehicle, and RK4 integration of a chunk of 256 vehicles one by one and
/// four lanes at a time (throughput: vehicles).
fn parts(c: &mut Criterion) {
    let (model, env, cmd) = uauv2_setup();
    let state = |i: usize| {
        VehicleState::new(
            &model,
            RigidState::at_rest(Vec3::new(1.0 + 0.01 * i as f64, 1.0, 1.0), Quat::identity()),
            &env,
        )
    };
    let mut g = c.benchmark_group("vehicle_parts");
    g.throughput(Throughput::Elements(1));
    let mut st = state(0);
    g.bench_function("actuate", |b| {
        b.iter(|| actuate_vehicle(&model, &mut st, black_box(&cmd), &env, 0.01))
    });
    const CHUNK: usize = 256;
    let mut chunk: Vec<VehicleState> = (0..CHUNK).map(state).collect();
    for st in &mut chunk {
        actuate_vehicle(&model, st, &cmd, &env, 0.01);
    }
    g.throughput(Throughput::Elements(CHUNK as u64));
    g.bench_function("integrate_rk4_chunk_256", |b| {
        b.iter(|| {
            for st in chunk.iter_mut() {
                integrate_vehicle(&model, st, &env, Integrator::Rk4, 0.01);
            }
        })
    });
    // The same chunk as the world integrates it: groups of four lanes sharing one set of
    // constants (the state is loaded into and stored from the lanes, as the world does).
    let consts = DynConsts::new(&model.params.body, &chunk[0].mass, &env);
    g.bench_function("integrate_rk4_lanes_chunk_256", |b| {
        b.iter(|| {
            for group in chunk.chunks_mut(LANES) {
                let mut x = Lanes::<LANES>::default();
                for (l, st) in group.iter().enumerate() {
                    x.load(l, &st.rigid, &st.tau);
                }
                rk4_group(black_box(&consts), &mut x, 0.01);
                for (l, st) in group.iter_mut().enumerate() {
                    x.store(l, &mut st.rigid);
                }
            }
        })
    });
    g.finish();
}

/// A world step of the beaconing benchmark swarm (four modems each, a frame a second) and of
/// the same swarm without traffic, on one thread.
fn medium(c: &mut Criterion) {
    let mut g = c.benchmark_group("medium");
    g.sample_size(20);
    for n in [100usize, 1000] {
        g.throughput(Throughput::Elements(n as u64));
        for (name, traffic) in [("quiet", false), ("beaconing", true)] {
            let desc = swarm_spaced(n, 1, TRAFFIC_SPACING, traffic);
            let mut sim = Sim::new(
                &desc,
                SimOptions {
                    threads: 1,
                    record: false,
                },
            );
            // 1.5 s: every beacon has started.
            sim.run(150);
            g.bench_with_input(BenchmarkId::new(name, n), &n, |b, _| b.iter(|| sim.step()));
        }
    }
    g.finish();
}

criterion_group!(benches, vehicle_step, parts, world_step, medium);
criterion_main!(benches);
