//! A world whose numbers are each within range but together blow up (a 1-g body with full
//! thrust and enormous quadratic drag: explicit integration overflows in a step) stops at the
//! step where a state became non-finite: exit code 4, a message naming the vehicle, the time
//! and the last finite state, and the outputs up to then written, with summary.json marked
//! `failed`. Before, such runs wrote NaN trajectories and exited 0.

mod common;

use std::process::Command;

const WORLD: &str = r#"duration = 5.0
[pool]
size = [10.0, 10.0, 3.0]
[[vehicles]]
name = "blowup"
position = [5.0, 5.0, 1.5]
mission = [{ t = 0.0, mode = "raw", thrusters = { top = 100.0, port = 100.0, stbd = 100.0 } }]
[vehicles.model.body]
mass = 0.001
volume = 1e-6
inertia = [1e-9, 1e-9, 1e-9]
added_mass = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
damping_quadratic = [1e5, 1e5, 1e5, 1e5, 1e5, 1e5]
[[vehicles]]
name = "calm"
position = [2.0, 2.0, 1.0]
"#;

#[test]
fn a_run_whose_state_becomes_non_finite_stops_with_exit_4_and_marked_outputs() {
    let dir = common::tmp("nonfinite", "run");
    let world = dir.join("w.toml");
    std::fs::write(&world, WORLD).unwrap();
    let out = dir.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_shoal"))
        .args(["run", "--quiet", "--no-plots"])
        .arg(&world)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(4), "{stderr}");
    assert!(
        stderr.contains("the state of vehicle `blowup` (id 0) became non-finite at t = 0.02 s")
            && stderr.contains("last finite state: position (5.0000, 5.0000, 1.5000) m"),
        "{stderr}"
    );
    let s = common::summary(&out);
    let failed = s["failed"].as_str().expect("summary.json has `failed`");
    assert!(failed.contains("`blowup`"), "{failed}");
    assert!(s["simulated_s"].as_f64().unwrap() <= 0.02 + 1e-9, "{s}");
    // Every trajectory value written is finite.
    let csv = std::fs::read_to_string(out.join("trajectories.csv")).unwrap();
    let mut rows = 0;
    for line in csv.lines().skip(1) {
        for field in line.split(',') {
            if let Ok(x) = field.parse::<f64>() {
                assert!(x.is_finite(), "{line}");
            }
        }
        rows += 1;
    }
    assert!(rows >= 2, "{csv}");
    std::fs::remove_dir_all(&dir).ok();
}
