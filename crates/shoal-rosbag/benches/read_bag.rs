//! Reading a 10-minute rosbag2 with six topics (`tests/common/bagkit.rs`: IMU 100 Hz,
//! pressure 40 Hz, thrusters and tilts 20 Hz, pump 1 Hz, an unmapped 64-value topic 30 Hz;
//! 126 600 messages) into a measured run through its mapping: file read, every
//! message of a mapped topic decoded by its schema, the time base built. Issue 34's aim:
//! ≤ 2 s on 2 cores. `cargo bench -p shoal-rosbag --bench read_bag`.

#[path = "../tests/common/mod.rs"]
mod common;

use common::bagkit;
use criterion::{Criterion, criterion_group, criterion_main};
use shoal_rosbag::{Mapping, read_bag};
use std::path::Path;

fn read_ten_minutes(c: &mut Criterion) {
    let dir = std::env::temp_dir().join(format!("shoal-bench-bag-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let path = dir.join("ten_minutes.mcap");
    std::fs::write(&path, bagkit::bag(600)).expect("the bag written");
    let mapping =
        Mapping::parse(bagkit::MAPPING, Path::new("kit.toml")).expect("the kit's mapping");
    let mut g = c.benchmark_group("rosbag2");
    g.sample_size(10);
    g.bench_function("read 10 min, 6 topics", |b| {
        b.iter(|| {
            let run = read_bag(&path, &mapping).expect("the kit's bag reads");
            assert!(run.t.len() > 60_000);
            run
        })
    });
    g.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, read_ten_minutes);
criterion_main!(benches);
