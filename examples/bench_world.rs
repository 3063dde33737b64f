//! Prints the world file of `shoal bench`'s swarm, so that a whole `shoal run` of it can be
//! timed beside the benchmark's loop (scripts/run-vs-bench.sh):
//! `cargo run --release --example bench_world -- N [quiet|beaconing]`.

use shoal::sim::bench::{standard_spacing, swarm_text};

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(10_000);
    let traffic = match args.next().as_deref() {
        None | Some("quiet") => false,
        Some("beaconing") => true,
        Some(other) => {
            eprintln!("bench_world: the world is `quiet` or `beaconing`, not `{other}`");
            std::process::exit(2);
        }
    };
    print!("{}", swarm_text(n, 1, standard_spacing(traffic), traffic));
}
