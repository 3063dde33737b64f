//! Golden digests (as rapier's `snapshot_portability`): a hash of every vehicle's state after a
//! fixed run must not change silently, and must be the same on 1 and 2 threads with the
//! parallel path taken (the world's dispatch count says it was). Three worlds: the quiet
//! benchmark swarm (every system of a step), the default world as `shoal run` runs it (its
//! digest is the one README.md's sample output shows) and the flock of worlds/flock.toml
//! (behaviours steering by the frames the medium delivers).
//!
//! If you changed the physics, controllers, sensors, the medium or RNG use on purpose, a
//! test here fails with the old and the new value: check that the change is intended, then
//! replace the constant (for the default world, also regenerate README.md's sample output with
//! scripts/readme-figures.sh) and say in the commit message why the digest changed.

use shoal::sim::bench::swarm;
use shoal::sim::parallel::{Dispatches, MIN_PARALLEL};
use shoal::sim::prelude::*;
use shoal::world::desc::WorldDesc;
use shoal::world::load::{default_world, load_file};
use std::path::Path;

/// Digest of the 300-vehicle benchmark swarm (seed 5) after 400 steps.
const GOLDEN_SWARM: u64 = 0x2ce6_75fe_463a_5b3b;
/// Digest of the default world (worlds/default.toml, embedded in `shoal run`) with its own
/// seed (42) and duration (100 s): what `cargo run --release -- run` prints.
const GOLDEN_DEFAULT: u64 = 0x2480_3a80_3cf6_f214;
/// Digest of worlds/flock.toml with its own seed (8) after 20 s.
const GOLDEN_FLOCK: u64 = 0x1b8d_fe27_1911_8c0e;

/// Runs `desc` for `steps` steps on 1 and 2 threads, loops of at least `min_parallel`
/// vehicles split over the pool; checks that both give `golden` and returns the 2-thread
/// run's dispatch count (the 1-thread run must split nothing).
fn digest_on_one_and_two_threads(
    what: &str,
    desc: &WorldDesc,
    steps: u64,
    min_parallel: usize,
    golden: u64,
) -> Dispatches {
    let runs: Vec<(u64, Dispatches)> = [1, 2]
        .into_iter()
        .map(|threads| {
            let mut sim = Sim::new(
                desc,
                SimOptions {
                    threads,
                    record: false,
                },
            );
            sim.set_min_parallel(min_parallel);
            sim.run(steps);
            (sim.digest(), sim.parallel_dispatches())
        })
        .collect();
    let [(one, split_one), (two, split_two)] = runs[..] else {
        unreachable!("two runs")
    };
    assert_eq!(
        split_one,
        Dispatches::default(),
        "{what}: split on 1 thread"
    );
    assert_eq!(
        one, two,
        "{what}: 1 vs 2 threads: {one:#018x} vs {two:#018x}"
    );
    assert_eq!(
        one, golden,
        "{what}: the state digest changed from {golden:#018x} to {one:#018x}. If the change is \
         intended, replace the constant in tests/golden_digest.rs and say in the commit message \
         why the digest changed"
    );
    split_two
}

#[test]
fn benchmark_swarm_digest_is_golden_on_one_and_two_threads() {
    let split =
        digest_on_one_and_two_threads("swarm", &swarm(300, 5), 400, MIN_PARALLEL, GOLDEN_SWARM);
    // 300 vehicles are above the threshold: every step's vehicle pass ran on the pool.
    assert_eq!(split.vehicles, 400, "{split:?}");
}

#[test]
fn default_world_digest_is_golden_on_one_and_two_threads() {
    let desc = default_world().unwrap_or_else(|e| panic!("{e}"));
    let steps = (desc.duration / desc.dt).round() as u64;
    assert_eq!(
        (desc.seed, steps),
        (42, 10_000),
        "the run `shoal run` makes"
    );
    // Twelve vehicles: every loop is split over the pool however small.
    let split = digest_on_one_and_two_threads("default world", &desc, steps, 1, GOLDEN_DEFAULT);
    // Every step's vehicle pass and every control tick's behaviours (0.05 s), and the
    // deliveries of the steps in which frames ended.
    assert_eq!(
        (split.vehicles, split.behaviour),
        (10_000, 2_000),
        "{split:?}"
    );
    assert!(split.delivery > 100, "{split:?}");
}

#[test]
fn flock_digest_is_golden_on_one_and_two_threads() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("worlds/flock.toml");
    let desc = load_file(&path).unwrap_or_else(|e| panic!("{e}"));
    let split = digest_on_one_and_two_threads("flock", &desc, 2_000, 1, GOLDEN_FLOCK);
    assert_eq!((split.vehicles, split.behaviour), (2_000, 400), "{split:?}");
    assert!(split.delivery > 100, "{split:?}");
}

#[test]
fn readme_sample_output_shows_the_golden_digest_of_the_default_world() {
    let readme =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    let sample = readme
        .split("<!-- sample-output:start -->")
        .nth(1)
        .and_then(|s| s.split("<!-- sample-output:end -->").next())
        .expect("README.md has a sample output block");
    // The sample is the default world with its own seed and duration, as the golden run.
    assert!(
        sample.contains("\n$ cargo run --release -- run\n"),
        "the sample is not a plain `run`:\n{sample}"
    );
    let digest = sample
        .lines()
        .find_map(|l| l.strip_prefix("digest "))
        .and_then(|l| l.split_whitespace().next())
        .expect("the sample prints a digest");
    assert_eq!(
        digest,
        format!("{GOLDEN_DEFAULT:016x}"),
        "README.md's sample output is not what this build prints: regenerate it with \
         scripts/readme-figures.sh"
    );
}
