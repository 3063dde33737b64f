//! The root examples run as a person runs them, and what they write is read back and held to
//! what it should show: `link_budget_curves` draws the link budget of each water type,
//! `paper_section5` draws and tabulates the paper's runs (the same worlds run here through
//! `record_run`), `hidden_effect` writes two whole measured runs `shoal validate` reads, and
//! `profile_comm` times a swarm whose beacons are delivered. Plots are checked by
//! `crates/shoal-record/tests/support/plots.rs`: SVG lines against the numbers, PNGs decoded
//! with their series' colours in the plot area.
//!
//! The examples are built with cargo like the test itself (`cargo test --workspace` has
//! built them already) and run from `target/<profile>/examples`.

#[path = "../crates/shoal-record/tests/support/cargo_example.rs"]
mod cargo_example;
#[path = "../crates/shoal-record/tests/support/plots.rs"]
mod plots;

use plots::{assert_png_colours, assert_svg_lines};
use shoal::model::optics::{Ambient, LinkGeometry, budget};
use shoal::model::presets::uauv2_modem;
use shoal::output::plot::rgb;
use shoal::record::analysis::{point_depth, record_run};
use shoal::sim::recorder::col;
use shoal::sysid::log::run::MeasuredRun;
use shoal::world::load::load_file;
use shoal::world::spec::WATER_TYPES;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The repository root.
fn repo() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Builds the root example `name` (same profile as this test) and returns its path.
fn example(name: &str) -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    // target/<profile>/deps/<this test> → target/<profile>
    let profile_dir = exe.parent().unwrap().parent().unwrap();
    cargo_example::build_example(repo(), profile_dir, name)
}

/// Runs `exe` with `args` in `dir`; returns its standard output.
fn run_in(dir: &Path, exe: &Path, args: &[&str]) -> String {
    let o = Command::new(exe)
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "{} failed: {}",
        exe.display(),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// A fresh temporary folder.
fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("shoal-examples-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `link_budget_curves`: one line per water type (palette colours 0 …), each the delivery
/// probability 1 − FER of a 32-byte frame on axis at 1 m depth under indoor light, from 1 cm
/// to 4 m; and the daylight curve (grey, dashed) in the PNG.
#[test]
fn link_budget_curves_draws_the_budget_of_every_water_type() {
    let dir = tmp("link_budget");
    let said = run_in(&dir, &example("link_budget_curves"), &["link_budget"]);
    assert!(
        said.contains("link_budget.png") && said.contains("link_budget.svg"),
        "{said}"
    );
    let m = uauv2_modem();
    let indoor = Ambient {
        surface_irradiance: 0.5,
        diffuse_attenuation: 0.1,
    };
    let delivered = |c: f64, d: f64| {
        1.0 - budget(
            &m.led,
            &m.rx,
            &LinkGeometry::on_axis(d),
            c,
            &indoor,
            1.0,
            0.0,
            320,
        )
        .fer
    };
    let series: Vec<_> = WATER_TYPES
        .iter()
        .enumerate()
        .map(|(i, (_, c))| {
            let pts = (1..=400)
                .map(|k| k as f64 * 0.01)
                .map(|d| (d, delivered(*c, d)));
            (rgb(i), pts.collect::<Vec<_>>())
        })
        .collect();
    assert_svg_lines(&dir.join("link_budget.svg"), &series);
    let mut colours: Vec<_> = series.iter().map(|s| s.0).collect();
    colours.push(rgb(7));
    assert_png_colours(&dir.join("link_budget.png"), &colours, 150);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Each vehicle's recorded rows of the world file `file` (as the example runs it).
fn rows(file: &str) -> (Vec<Vec<Vec<f64>>>, Vec<f64>) {
    let desc = load_file(&repo().join("worlds").join(file)).unwrap();
    let pz = desc
        .vehicles
        .iter()
        .map(|v| v.model.params.pressure.position.z)
        .collect();
    (record_run(&desc), pz)
}

/// Time and sensor depth of vehicle `v` of `file`.
fn sensor_depth(file: &str, v: usize) -> Vec<(f64, f64)> {
    let (rows, pz) = rows(file);
    rows[v]
        .iter()
        .map(|r| (r[col::T], point_depth(r, pz[v])))
        .collect()
}

/// `paper_section5`: `diving` draws the diving and auto runs' sensor depth, `buoyancy` the
/// buoyancy run's (and its dead zone), `turning` three headings of as many samples as the
/// runs have, and `metrics.md` has both step tables and the buoyancy run's depth at 16 s.
#[test]
fn paper_section5_draws_and_tabulates_the_paper_runs() {
    let dir = tmp("paper");
    run_in(&dir, &example("paper_section5"), &["paper"]);
    let out = dir.join("paper");
    let diving = [
        (rgb(0), sensor_depth("paper_diving.toml", 0)),
        (rgb(1), sensor_depth("paper_auto.toml", 0)),
    ];
    assert_svg_lines(&out.join("diving.svg"), &diving);
    assert_png_colours(&out.join("diving.png"), &[rgb(0), rgb(1), rgb(7)], 300);
    let buoyancy = sensor_depth("paper_buoyancy.toml", 0);
    assert_svg_lines(&out.join("buoyancy.svg"), &[(rgb(0), buoyancy.clone())]);
    assert_png_colours(&out.join("buoyancy.png"), &[rgb(0), rgb(3), rgb(7)], 300);
    // Headings: one line per run, a point per recorded row.
    let svg = std::fs::read_to_string(out.join("turning.svg")).unwrap();
    for (c, file, v) in [
        (0, "paper_turning.toml", 0),
        (2, "paper_turning_zeta1.toml", 0),
        (1, "paper_auto.toml", 1),
    ] {
        let n = rows(file).0[v].len();
        assert!(
            plots::lines(&svg)
                .iter()
                .any(|l| l.stroke == rgb(c) && l.width == 2 && l.points.len() == n),
            "turning.svg: no line of colour {c} with {n} points ({file})"
        );
    }
    assert_png_colours(&out.join("turning.png"), &[rgb(0), rgb(1), rgb(2)], 300);
    let md = std::fs::read_to_string(out.join("metrics.md")).unwrap();
    let rows_starting = |p: &str| md.lines().filter(|l| l.starts_with(p)).count();
    assert_eq!(
        rows_starting("| diving |") + rows_starting("| auto (heave) |"),
        6
    );
    assert_eq!(
        rows_starting("| turning, ") + rows_starting("| auto (yaw) |"),
        12
    );
    let at16 = buoyancy.iter().find(|p| p.0 >= 16.0 - 1e-9).unwrap().1;
    assert!(
        md.contains(&format!("buoyancy: depth at 16 s {at16:.3} m")),
        "{at16:.3} m at 16 s, not in:\n{md}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `hidden_effect`: two measured runs of 120 s at 50 Hz with the μAUV²'s inputs, depth and
/// yaw, each read whole by `shoal validate`'s reader.
#[test]
fn hidden_effect_writes_two_whole_measured_runs() {
    let dir = tmp("hidden");
    run_in(&dir, &example("hidden_effect"), &[]);
    for name in ["dive_a", "dive_b"] {
        let path = dir.join(format!("out/hidden/{name}.csv"));
        let run = MeasuredRun::read(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(run.t.len(), 6001, "{name}");
        assert!((run.t[6000] - 120.0).abs() < 1e-9, "{name}");
        let inputs: Vec<&str> = run.inputs.iter().map(|i| i.name.as_str()).collect();
        for i in ["top", "port", "stbd", "alpha", "beta", "pump"] {
            assert!(inputs.contains(&i), "{name}: no u.{i} in {inputs:?}");
        }
        let channels: Vec<String> = run.channels.iter().map(|c| c.label()).collect();
        assert!(
            channels.contains(&"y.depth".to_string()),
            "{name}: {channels:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `profile_comm 30`: three timings, the quiet swarm and the one without frames deliver
/// nothing, the beaconing one delivers frames.
#[test]
fn profile_comm_times_a_swarm_whose_beacons_are_delivered() {
    let dir = tmp("profile");
    let said = run_in(&dir, &example("profile_comm"), &["30"]);
    let delivered: Vec<u64> = said
        .lines()
        .filter(|l| l.contains(" ms/step  delivered "))
        .map(|l| l.rsplit(' ').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(delivered.len(), 3, "{said}");
    assert_eq!(delivered[..2], [0, 0], "{said}");
    assert!(delivered[2] > 0, "{said}");
    let _ = std::fs::remove_dir_all(&dir);
}
