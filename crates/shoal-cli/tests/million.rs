//! A million vehicles run within 4 GB: the process's peak resident memory, as `shoal run`
//! reports it in summary.json, stays under 4 GB for a 10⁶-vehicle μAUV² swarm (before:
//! 11–12 GB, from per-vehicle trajectory buffers, plot points kept for every vehicle, a copy of
//! every vehicle at the end and a 300-byte random generator per vehicle and purpose).

mod common;

use std::process::Command;

#[test]
fn a_million_vehicles_run_within_four_gigabytes() {
    let dir = common::tmp("million", "run");
    let world = dir.join("w.toml");
    // 10⁶ vehicles, 0.6 m apart on a 1000 × 1000 grid, in auto mode: two steps (the first
    // trajectory row of every vehicle is written, the end-of-run tables hold every vehicle).
    std::fs::write(
        &world,
        "name = \"million\"\nduration = 0.02\ndt = 0.01\n\
         [pool]\nsize = [602.0, 602.0, 3.0]\n[output]\nplots = false\nrecord_hz = 1\n\
         [[vehicles]]\nname = \"b\"\ncount = 1000000\n\
         grid = { origin = [1.0, 1.0, 1.0], spacing = [0.6, 0.6], columns = 1000 }\n\
         mission = [{ t = 0, mode = \"auto\", depth = 1.3, yaw_deg = 45 }]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_shoal"))
        .args(["run", "--quiet", "--threads", "2"])
        .arg(&world)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = common::summary(&out);
    assert_eq!(s["vehicles"], 1_000_000);
    assert_eq!(s["steps"], 2);
    let peak = s["peak_memory_bytes"]
        .as_u64()
        .expect("Linux reports the peak");
    assert!(
        peak < 4_000_000_000,
        "a million vehicles peaked at {:.2} GB",
        peak as f64 / 1e9
    );
    // The per-vehicle table is whole: a header and a row per vehicle.
    let rows = std::fs::read_to_string(out.join("vehicles.csv"))
        .unwrap()
        .lines()
        .count();
    assert_eq!(rows, 1_000_001);
    std::fs::remove_dir_all(&dir).ok();
}
