//! Workloads for benchmarks: a swarm of N μAUV² on a grid in a pool sized to fit, every vehicle
//! in auto mode (heave, yaw and surge control, tilt drives moving), so that every system of a
//! step does real work. Shared by `shoal bench` and the criterion benches.

use shoal_world::desc::WorldDesc;
use shoal_world::load::load_str;
use std::path::Path;

/// Grid spacing of the benchmark swarm [m].
pub const SPACING: f64 = 0.6;

/// The world-file text of an `n`-vehicle benchmark swarm.
pub fn swarm_text(n: usize, seed: u64) -> String {
    let columns = (n as f64).sqrt().ceil().max(1.0) as usize;
    let rows = n.div_ceil(columns);
    let (lx, ly) = (columns as f64 * SPACING + 2.0, rows as f64 * SPACING + 2.0);
    format!(
        "name = \"bench swarm of {n}\"\nseed = {seed}\nduration = 3600\ndt = 0.01\n\
         [pool]\nsize = [{lx}, {ly}, 3.0]\n\
         [[vehicles]]\nname = \"b\"\ncount = {n}\n\
         grid = {{ origin = [1.0, 1.0, 1.0], spacing = [{SPACING}, {SPACING}], columns = {columns} }}\n\
         mission = [{{ t = 0, mode = \"auto\", depth = 1.3, yaw_deg = 45 }}, {{ t = 2, surge = 0.02, yaw_deg = -60 }}]\n\
         [output]\nplots = false\n"
    )
}

/// The validated `n`-vehicle benchmark swarm.
pub fn swarm(n: usize, seed: u64) -> WorldDesc {
    match load_str(&swarm_text(n, seed), Path::new("<bench swarm>")) {
        Ok(w) => w,
        Err(e) => unreachable!("the generated bench world is valid: {e}"),
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn swarm_sizes_load() {
        for n in [1, 10, 100, 1000] {
            assert_eq!(super::swarm(n, 1).vehicles.len(), n);
        }
    }
}
