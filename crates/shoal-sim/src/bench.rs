//! Workloads for benchmarks: a swarm of N μAUV² on a grid in a pool sized to fit, every vehicle
//! in auto mode (heave, yaw and surge control, tilt drives moving), so that every system of a
//! step does real work. Shared by `shoal bench` and the criterion benches.

use shoal_world::desc::WorldDesc;
use shoal_world::load::load_str;
use std::path::Path;

/// Grid spacing of the quiet benchmark swarm \[m\]: a dense swarm, all dynamics.
pub const SPACING: f64 = 0.6;
/// Grid spacing of the benchmark swarm with optical traffic \[m\]: neighbours well inside the
/// reliable range (≈2 m), about 25 vehicles within the cut-off range of each.
pub const TRAFFIC_SPACING: f64 = 1.5;

/// The world-file text of an `n`-vehicle benchmark swarm on a grid of `spacing` \[m\]. With
/// `traffic`, every vehicle carries a ring of four modems and beacons a 26-byte payload (a
/// 32-byte frame) once a second. At [`TRAFFIC_SPACING`] the vehicles turn on the spot (with or
/// without traffic, so the two can be compared); otherwise they also drive forward.
pub fn swarm_text(n: usize, seed: u64, spacing: f64, traffic: bool) -> String {
    // With traffic the vehicles turn on the spot, so that the grid (and the load on the
    // medium) stays the same however long a cell runs; the quiet swarm also drives forward.
    let surge = if spacing == TRAFFIC_SPACING {
        0.0
    } else {
        0.02
    };
    let columns = (n as f64).sqrt().ceil().max(1.0) as usize;
    let rows = n.div_ceil(columns);
    let (lx, ly) = (columns as f64 * spacing + 2.0, rows as f64 * spacing + 2.0);
    let mut t = format!(
        "name = \"bench swarm of {n}\"\nseed = {seed}\nduration = 3600\ndt = 0.01\n\
         [pool]\nsize = [{lx}, {ly}, 3.0]\n\
         [[vehicles]]\nname = \"b\"\ncount = {n}\n\
         grid = {{ origin = [1.0, 1.0, 1.0], spacing = [{spacing}, {spacing}], columns = {columns} }}\n\
         mission = [{{ t = 0, mode = \"auto\", depth = 1.3, yaw_deg = 45 }}, {{ t = 2, surge = {surge}, yaw_deg = -60 }}]\n"
    );
    if traffic {
        t.push_str(
            "behaviour = { kind = \"beacon\", period = 1.0, payload_bytes = 26, jitter = 0.05 }\n",
        );
        for (name, pos, dir) in RING {
            t.push_str(&format!("[[vehicles.model.modems]]\nname = \"{name}\"\nposition = {pos}\ndirection = {dir}\n"));
        }
    }
    t.push_str("[output]\nplots = false\n");
    t
}

/// The world-file text of an `n`-vehicle swarm on a [`SPACING`] grid driven by one external
/// agent `pilot` in lock-step, with service prefix `prefix` (the agent latency benchmark).
pub fn agent_swarm_text(n: usize, prefix: &str) -> String {
    let columns = (n as f64).sqrt().ceil().max(1.0) as usize;
    let rows = n.div_ceil(columns);
    let (lx, ly) = (columns as f64 * SPACING + 2.0, rows as f64 * SPACING + 2.0);
    format!(
        "name = \"agent bench swarm of {n}\"\nseed = 1\nduration = 3600\ndt = 0.01\n\
         [pool]\nsize = [{lx}, {ly}, 3.0]\n\
         [agents]\nprefix = \"{prefix}\"\ntiming = \"lockstep\"\ntimeout = 5.0\nattach_timeout = 30.0\n\
         [[vehicles]]\nname = \"b\"\ncount = {n}\n\
         grid = {{ origin = [1.0, 1.0, 1.0], spacing = [{SPACING}, {SPACING}], columns = {columns} }}\n\
         agent = \"pilot\"\n[output]\nplots = false\n"
    )
}

/// The validated agent benchmark swarm (see [`agent_swarm_text`]).
pub fn agent_swarm(n: usize, prefix: &str) -> Result<WorldDesc, String> {
    load_str(
        &agent_swarm_text(n, prefix),
        Path::new("<agent bench swarm>"),
    )
    .map_err(|e| e.to_string())
}

/// A ring of four modems: front, right, back, left (name, position, direction).
pub const RING: [(&str, &str, &str); 4] = [
    ("front", "[0.125, 0.0, 0.0]", "[1.0, 0.0, 0.0]"),
    ("right", "[0.0, 0.078, 0.0]", "[0.0, 1.0, 0.0]"),
    ("back", "[-0.125, 0.0, 0.0]", "[-1.0, 0.0, 0.0]"),
    ("left", "[0.0, -0.078, 0.0]", "[0.0, -1.0, 0.0]"),
];

/// The validated `n`-vehicle benchmark swarm.
pub fn swarm(n: usize, seed: u64) -> WorldDesc {
    swarm_with(n, seed, false)
}

/// The benchmark swarm, with or without optical traffic, at its standard spacing
/// ([`SPACING`] quiet, [`TRAFFIC_SPACING`] with traffic).
pub fn swarm_with(n: usize, seed: u64, traffic: bool) -> WorldDesc {
    swarm_spaced(n, seed, standard_spacing(traffic), traffic)
}

/// The grid spacing of the benchmark swarm with or without optical traffic \[m\]: [`SPACING`]
/// quiet, [`TRAFFIC_SPACING`] with traffic.
pub fn standard_spacing(traffic: bool) -> f64 {
    if traffic { TRAFFIC_SPACING } else { SPACING }
}

/// The benchmark swarm with optical traffic at [`TRAFFIC_SPACING`], its modems getting the
/// medium by `access` (a world file's `access` value, e.g. `"csma_ca"`).
pub fn traffic_swarm_with_access(n: usize, seed: u64, access: &str) -> Result<WorldDesc, String> {
    let text = swarm_text(n, seed, TRAFFIC_SPACING, true).replace(
        "[[vehicles.model.modems]]\n",
        &format!("[[vehicles.model.modems]]\naccess = {access}\n"),
    );
    load_str(&text, Path::new("<bench swarm>")).map_err(|e| e.to_string())
}

/// The benchmark swarm at any grid spacing \[m\].
pub fn swarm_spaced(n: usize, seed: u64, spacing: f64, traffic: bool) -> WorldDesc {
    match load_str(
        &swarm_text(n, seed, spacing, traffic),
        Path::new("<bench swarm>"),
    ) {
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
            assert_eq!(
                super::swarm_with(n, 1, true).vehicles[0]
                    .model
                    .params
                    .modems
                    .len(),
                4
            );
        }
    }
}
