//! Criterion benchmarks of the hot path: one vehicle's physics step (RK4 and semi-implicit
//! Euler), and one world step of the benchmark swarm at several sizes on 1 and 2 threads.
//! Run with `cargo bench --bench step`; compare ratios within one run.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use shoal::model::prelude::*;
use shoal::sim::bench::swarm;
use shoal::sim::prelude::*;
use std::hint::black_box;

fn vehicle_step(c: &mut Criterion) {
    let model = VehicleModel::new(presets::uauv2(), 1000.0);
    let env = Environment::default();
    let cmd = ActuatorCommands {
        thrusters: vec![20.0, 40.0, 35.0],
        tilts: vec![0.0, -0.6],
        pump: Pump::Off,
    };
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

criterion_group!(benches, vehicle_step, world_step);
criterion_main!(benches);
