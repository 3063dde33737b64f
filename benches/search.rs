//! Criterion benchmarks of `shoal validate`'s work: one open-loop replay of a 120 s, 50 Hz
//! measured run (the unit every fit repeats thousands of times), and the whole catalogue
//! search on that run with one hidden effect, on 1 and 2 threads. Run with
//! `cargo bench --bench search`; compare ratios within one run.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use shoal::model::effects::{EffectInstance, Effects, by_name};
use shoal::model::presets;
use shoal::model::rigid_body::Environment;
use shoal::model::vehicle::VehicleModel;
use shoal::sysid::evaluate::dataset::{DataOptions, Dataset};
use shoal::sysid::log::run::MeasuredRun;
use shoal::sysid::search::{SearchOptions, search};
use shoal_testkit::design;
use shoal_testkit::synth::synthesize;
use std::hint::black_box;

/// A μAUV² diving run (120 s, 50 Hz) with a 0.4 s thruster lag hidden in it, as the tool
/// would read it from a file; the dataset uses the default 10 ms replay step.
fn dataset() -> Dataset {
    let truth = VehicleModel::with_effects(
        presets::uauv2(),
        Effects::new(vec![EffectInstance {
            effect: by_name("thruster_lag").unwrap(),
            params: vec![0.4],
        }]),
        1000.0,
    );
    let exp = design::uauv2_heave(1, 120.0);
    let run = synthesize(&truth, &Environment::default(), &exp, 0.005, 7);
    let run = MeasuredRun::parse(&run.to_csv(), std::path::Path::new("heave.csv")).unwrap();
    Dataset::new(
        &presets::uauv2(),
        Environment::default(),
        vec![run],
        vec![],
        &DataOptions::default(),
    )
    .unwrap()
}

fn replay(c: &mut Criterion) {
    let ds = dataset();
    let model = VehicleModel::new(presets::uauv2(), 1000.0);
    c.bench_function("replay_120s_dt10ms", |b| {
        b.iter(|| black_box(ds.evaluate(black_box(&model))))
    });
}

fn catalogue_search(c: &mut Criterion) {
    let ds = dataset();
    let base = presets::uauv2();
    let mut g = c.benchmark_group("catalogue_search_120s");
    g.sample_size(10);
    for threads in [1, 2] {
        let opts = SearchOptions {
            threads,
            ..Default::default()
        };
        g.bench_with_input(BenchmarkId::new("threads", threads), &opts, |b, opts| {
            b.iter(|| {
                let out = search(&ds, &base, opts, &|_| {});
                assert_eq!(out.chosen.names(), vec!["thruster_lag"]);
                out
            })
        });
    }
    g.finish();
}

criterion_group!(benches, replay, catalogue_search);
criterion_main!(benches);
