//! Reproduces the μAUV² paper's Section 5 experiments from `worlds/paper_*.toml` and writes the
//! figures and the metrics table used in `docs/paper-comparison.md`.
//!
//! ```text
//! cargo run --release --example paper_section5 -- [OUT_DIR]     # default: docs/paper
//! ```

use shoal::model::control::heading_error;
use shoal::model::math::wrap_pi;
use shoal::output::plot::{Plot, Series};
use shoal::record::analysis::{Segment, point_depth, record_run, segments};
use shoal::sim::recorder::col;
use shoal::world::load::load_file;
use std::path::{Path, PathBuf};

struct Run {
    rows: Vec<Vec<Vec<f64>>>,
    port_z: Vec<f64>,
}

fn run(file: &str) -> Run {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("worlds")
        .join(file);
    let desc = load_file(&path).unwrap_or_else(|e| panic!("{e}"));
    Run {
        rows: record_run(&desc),
        port_z: desc
            .vehicles
            .iter()
            .map(|v| v.model.params.pressure.position.z)
            .collect(),
    }
}

fn depth(r: &[f64], pz: f64) -> f64 {
    point_depth(r, pz)
}

fn depth_series(run: &Run, v: usize) -> Vec<(f64, f64, f64)> {
    run.rows[v]
        .iter()
        .map(|r| (r[col::T], depth(r, run.port_z[v]), r[col::DEPTH_SP]))
        .collect()
}

fn yaw_series(run: &Run, v: usize) -> Vec<(f64, f64, f64)> {
    run.rows[v]
        .iter()
        .map(|r| (r[col::T], r[col::YAW], r[col::YAW_SP]))
        .collect()
}

/// Unwrapped yaw [deg] and the setpoint on the branch nearest to it [deg].
type Points = Vec<(f64, f64)>;

fn yaw_deg(s: &[(f64, f64, f64)]) -> (Points, Points) {
    let mut prev: Option<f64> = None;
    let mut y = Vec::new();
    let mut sp = Vec::new();
    for &(t, v, p) in s {
        let u = prev.map_or(v, |q| q + wrap_pi(v - q));
        prev = Some(u);
        y.push((t, u.to_degrees()));
        sp.push((t, (u + heading_error(p, u)).to_degrees()));
    }
    (y, sp)
}

fn line(label: &str, pts: Vec<(f64, f64)>, color: usize, dashed: bool) -> Series {
    Series {
        label: (!label.is_empty()).then(|| label.to_string()),
        points: pts,
        color,
        dashed,
        mark_start: false,
        ..Default::default()
    }
}

fn table_depth(name: &str, segs: &[Segment]) -> String {
    let mut s = String::new();
    for g in segs.iter().skip(1) {
        s.push_str(&format!(
            "| {name} | {:.2} → {:.2} m | {:.1} mm | {} | {:+.1} mm | {} |\n",
            g.from,
            g.target,
            g.overshoot * 1e3,
            g.time_to_band
                .map_or("not reached".into(), |t| format!("{t:.1} s")),
            g.final_error * 1e3,
            g.rate_10_90
                .map_or("—".into(), |r| format!("{:.1} mm/s", r * 1e3)),
        ));
    }
    s
}

fn table_yaw(name: &str, segs: &[Segment]) -> String {
    let mut s = String::new();
    for g in segs.iter().skip(1) {
        s.push_str(&format!(
            "| {name} | {:.0}° → {:.0}° | {:.1}° | {} | {:+.1}° | {:.1}°/s | {} |\n",
            g.from.to_degrees(),
            g.target.to_degrees(),
            g.overshoot.to_degrees(),
            g.time_to_band
                .map_or("not reached".into(), |t| format!("{t:.1} s")),
            g.final_error.to_degrees(),
            g.peak_rate.to_degrees(),
            g.rate_10_90
                .map_or("—".into(), |r| format!("{:.1}°/s", r.to_degrees())),
        ));
    }
    s
}

fn main() {
    let out = std::env::args()
        .nth(1)
        .map_or_else(|| PathBuf::from("docs/paper"), PathBuf::from);
    std::fs::create_dir_all(&out).expect("create the output folder");
    let dive = run("paper_diving.toml");
    let buoy = run("paper_buoyancy.toml");
    let turn = run("paper_turning.toml");
    let turn1 = run("paper_turning_zeta1.toml");
    let auto = run("paper_auto.toml");

    let pts = |s: &[(f64, f64, f64)], k: usize| -> Vec<(f64, f64)> {
        s.iter()
            .map(|p| (p.0, if k == 1 { p.1 } else { p.2 }))
            .collect()
    };
    let ds = depth_series(&dive, 0);
    let au = depth_series(&auto, 0);
    Plot {
        title: "Diving (paper Fig. 11) and auto mode (Fig. 16): sensor depth".into(),
        x_label: "time [s]".into(),
        y_label: "depth [m]".into(),
        series: vec![
            line("diving mode", pts(&ds, 1), 0, false),
            line("auto mode", pts(&au, 1), 1, false),
            line("setpoint", pts(&ds, 2), 7, true),
        ],
        y_down: true,
        ..Default::default()
    }
    .write(&out.join("diving"))
    .expect("plot");
    let bs = depth_series(&buoy, 0);
    Plot {
        title: "Buoyancy calibration (paper Fig. 13): sensor depth".into(),
        x_label: "time [s]".into(),
        y_label: "depth [m]".into(),
        series: vec![
            line("buoyancy mode, +0.023 N at start", pts(&bs, 1), 0, false),
            line("setpoint", pts(&bs, 2), 7, true),
            line(
                "dead zone ±8 mm",
                bs.iter().map(|p| (p.0, p.2 + 0.008)).collect(),
                3,
                true,
            ),
            line("", bs.iter().map(|p| (p.0, p.2 - 0.008)).collect(), 3, true),
        ],
        y_down: true,
        ..Default::default()
    }
    .write(&out.join("buoyancy"))
    .expect("plot");
    let (y0, sp) = yaw_deg(&yaw_series(&turn, 0));
    let (y1, _) = yaw_deg(&yaw_series(&turn1, 0));
    let (ya, _) = yaw_deg(&yaw_series(&auto, 1));
    Plot {
        title: "Turning (paper Figs. 14, 15, 17): heading".into(),
        x_label: "time [s]".into(),
        y_label: "heading [deg]".into(),
        series: vec![
            line("turning, paper gains (K_D = 0.016)", y0, 0, false),
            line("turning, ζ = 1 gains (K_D = 0.0059)", y1, 2, false),
            line("auto mode, paper gains", ya, 1, false),
            line("setpoint", sp, 7, true),
        ],
        ..Default::default()
    }
    .write(&out.join("turning"))
    .expect("plot");

    let band = 0.01;
    let mut md = String::new();
    md.push_str("| run | step | overshoot | into ±1 cm after | error at next step | 10–90 % rate |\n|---|---|---|---|---|---|\n");
    md.push_str(&table_depth("diving", &segments(&ds, band, false)));
    md.push_str(&table_depth("auto (heave)", &segments(&au, band, false)));
    md.push_str("\n| run | step | overshoot | into ±2° after | error at next step | peak rate | 10–90 % rate |\n|---|---|---|---|---|---|---|\n");
    md.push_str(&table_yaw(
        "turning, paper gains",
        &segments(&yaw_series(&turn, 0), 2f64.to_radians(), true),
    ));
    md.push_str(&table_yaw(
        "turning, ζ = 1",
        &segments(&yaw_series(&turn1, 0), 2f64.to_radians(), true),
    ));
    md.push_str(&table_yaw(
        "auto (yaw)",
        &segments(&yaw_series(&auto, 1), 2f64.to_radians(), true),
    ));
    let at = |t: f64| bs.iter().find(|p| p.0 >= t).map_or(f64::NAN, |p| p.1);
    let stop = buoy.rows[0]
        .iter()
        .find(|r| r[col::T] > 1.0 && r[col::PUMP] == 0.0)
        .map_or(f64::NAN, |r| r[col::T]);
    let after: Vec<f64> = bs
        .iter()
        .filter(|p| p.0 >= stop + 10.0)
        .map(|p| (p.2 - p.1).abs())
        .collect();
    md.push_str(&format!(
        "\nbuoyancy: depth at 16 s {:.3} m; pump stops (dead zone reached) at {stop:.1} s; largest |error| from {:.0} s to the end {:.1} mm; ballast {:.2} → {:.2} ml\n",
        at(16.0),
        stop + 10.0,
        after.iter().copied().fold(0.0, f64::max) * 1e3,
        buoy.rows[0][0][col::BALLAST] * 1e6,
        buoy.rows[0].last().unwrap()[col::BALLAST] * 1e6,
    ));
    for (i, name) in ["auto-heave", "auto-yaw"].iter().enumerate() {
        let v = &auto.rows[i];
        let drift = v
            .iter()
            .map(|r| (r[col::X] - v[0][col::X]).hypot(r[col::Y] - v[0][col::Y]))
            .fold(0.0, f64::max);
        let umax = v.iter().map(|r| r[col::U].abs()).fold(0.0, f64::max);
        md.push_str(&format!(
            "{name}: largest horizontal drift {:.3} m, largest |surge speed| {:.4} m/s\n",
            drift, umax
        ));
    }
    std::fs::write(out.join("metrics.md"), &md).expect("write metrics");
    println!("{md}\nfigures and metrics.md written to {}", out.display());
}
