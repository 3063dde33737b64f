//! The plots of a run checked against its tables: each plot's SVG lines are the numbers of
//! `trajectories.csv`, `links.csv`, `connectivity.csv` or `summary.json` (through one affine
//! map per axis, within a pixel), and each PNG decodes and has drawn pixels of its series'
//! colours inside the plot area (see `shoal-record/tests/support/plots.rs`).

#![allow(dead_code)]

#[path = "../../../shoal-record/tests/support/plots.rs"]
pub mod plots;

use plots::{Rgb, assert_png_colours, assert_svg_lines};
use shoal_output::plot::rgb;
use shoal_record::link_key;
use std::collections::BTreeMap;
use std::path::Path;

/// The rows of the CSV table `path`, as column → text.
fn table(path: &Path) -> Vec<BTreeMap<String, String>> {
    crate::common::read_table(path).1
}

fn num(row: &BTreeMap<String, String>, col: &str) -> f64 {
    row[col]
        .parse()
        .unwrap_or_else(|e| panic!("{col} = {:?}: {e}", row[col]))
}

/// Each vehicle's palette colour (its group's place among the groups, in vehicles.csv
/// order) and its rows of trajectories.csv, in vehicle order.
fn vehicles(out: &Path) -> Vec<(Rgb, Vec<BTreeMap<String, String>>)> {
    let mut groups: Vec<String> = Vec::new();
    let mut list: Vec<(String, Rgb)> = Vec::new();
    for v in table(&out.join("vehicles.csv")) {
        let g = v["group"].clone();
        let k = groups.iter().position(|x| *x == g).unwrap_or_else(|| {
            groups.push(g);
            groups.len() - 1
        });
        list.push((v["name"].clone(), rgb(k)));
    }
    let rows = table(&out.join("trajectories.csv"));
    list.into_iter()
        .map(|(name, c)| {
            (
                c,
                rows.iter()
                    .filter(|r| r["vehicle"] == name)
                    .cloned()
                    .collect(),
            )
        })
        .collect()
}

/// The distinct colours of `series`.
fn colours(series: &[(Rgb, Vec<(f64, f64)>)]) -> Vec<Rgb> {
    let mut c: Vec<Rgb> = series.iter().map(|s| s.0).collect();
    c.dedup();
    c.sort();
    c.dedup();
    c
}

/// `depth` (every vehicle's depth reading against time) and `top` (its track, east against
/// north) of the run in `out` (at most 200 vehicles and 1,500 rows each, so every row is
/// drawn); at least `min_depth` and `min_top` pixels of each group's colour in depth.png and
/// top.png (a short run's tracks are little more than their start dots; a line drawn under
/// others of another group shows little).
pub fn assert_depth_and_top(out: &Path, min_depth: usize, min_top: usize) {
    let v = vehicles(out);
    let series = |x: &str, y: &str| -> Vec<(Rgb, Vec<(f64, f64)>)> {
        v.iter()
            .map(|(c, rows)| (*c, rows.iter().map(|r| (num(r, x), num(r, y))).collect()))
            .collect()
    };
    let depth = series("t_s", "depth_reading_m");
    assert_svg_lines(&out.join("depth.svg"), &depth);
    assert_png_colours(&out.join("depth.png"), &colours(&depth), min_depth);
    let top = series("y_m", "x_m");
    assert_svg_lines(&out.join("top.svg"), &top);
    assert_png_colours(&out.join("top.png"), &colours(&top), min_top);
}

/// The link plots of the run in `out` with `vehicles` vehicles: `links_over_time` (each
/// outcome per second, from links.csv), `connectivity_over_time` (from connectivity.csv),
/// `gossip` (from the summary), and the colours of `delivery_vs_distance` and
/// `connectivity` (of worlds/gossip.toml: one origin, 64 relays).
pub fn assert_gossip_plots(out: &Path, vehicles: usize) {
    let links = table(&out.join("links.csv"));
    // Each outcome in the one colour key's colour (shoal_record::link_key), in the key's order.
    let outcome = |col: &str, o: link_key::Outcome| {
        let pts = links
            .iter()
            .map(|r| (num(r, "t_start_s") + 0.5, num(r, col)))
            .collect();
        (link_key::style(o).rgb, pts)
    };
    let per_second = [
        outcome("delivered", link_key::Outcome::Delivered),
        outcome("collided", link_key::Outcome::Collided),
        outcome("occluded", link_key::Outcome::Occluded),
        outcome("out_of_budget", link_key::Outcome::OutOfBudget),
        outcome("half_duplex", link_key::Outcome::HalfDuplex),
    ];
    assert_svg_lines(&out.join("links_over_time.svg"), &per_second);
    assert_png_colours(
        &out.join("links_over_time.png"),
        &[per_second[0].0, per_second[3].0],
        500,
    );

    let n = vehicles as f64;
    let conn = table(&out.join("connectivity.csv"));
    let line = |f: &dyn Fn(&BTreeMap<String, String>) -> f64| {
        conn.iter()
            .map(|r| (num(r, "t_s"), f(r)))
            .collect::<Vec<_>>()
    };
    let graph = [
        (rgb(0), line(&|r| num(r, "largest_fraction"))),
        (rgb(1), line(&|r| 2.0 * num(r, "edges") / n / (n - 1.0))),
    ];
    assert_svg_lines(&out.join("connectivity_over_time.svg"), &graph);
    assert_png_colours(
        &out.join("connectivity_over_time.png"),
        &colours(&graph),
        500,
    );

    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let g = &s["comm"]["gossip"];
    let mut informed = vec![(g["start_s"].as_f64().unwrap(), 0.0)];
    informed.extend(
        g["informed_over_time"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| (p[0].as_f64().unwrap(), p[1].as_f64().unwrap())),
    );
    assert_svg_lines(&out.join("gossip.svg"), &[(rgb(0), informed)]);
    assert_png_colours(&out.join("gossip.png"), &[rgb(0)], 300);

    // Observed ratios (blue dots and intervals) and the model (grey, dashed).
    assert_png_colours(
        &out.join("delivery_vs_distance.png"),
        &[rgb(0), rgb(7)],
        300,
    );
    // The graph at the end (no edge left: the flood is over): the 64 relays in orange, the
    // origin in blue.
    assert_png_colours(&out.join("connectivity.png"), &[rgb(1)], 1000);
    assert_png_colours(&out.join("connectivity.png"), &[rgb(0)], 30);
}

/// The plots of `shoal validate` into `report` for a hold-out run `holdout` (a CSV with
/// `t` and `y.depth`) in which the model found fits the measurement: `<run>_depth` draws the
/// measured depth (grey, 1 px) as the CSV has it, the extended model (green) within 2 px of
/// it everywhere and the baseline (red) at least 10 px off somewhere; `acf_depth` draws both
/// residual autocorrelations over the same lags, each 1 at lag 0.
pub fn assert_validate_plots(report: &Path, holdout: &Path) {
    let name = holdout.file_stem().unwrap().to_string_lossy();
    let measured: Vec<(f64, f64)> = table(holdout)
        .iter()
        .filter(|r| !r["y.depth"].is_empty())
        .map(|r| (num(r, "t"), num(r, "y.depth")))
        .collect();
    let (red, green, grey, black) = (rgb(3), rgb(2), rgb(7), (30, 30, 30));
    let depth = report.join(format!("plots/{name}_depth.svg"));
    // The measurement: a near-black 1-px line over the 4-px model lines (drawn after them).
    plots::assert_svg_series(&depth, 1, &[(black, measured.clone())]);
    let svg = std::fs::read_to_string(&depth).unwrap();
    let line = |c: Rgb, width: u32| -> Vec<(f64, f64)> {
        let found: Vec<plots::Line> = plots::lines(&svg)
            .into_iter()
            .filter(|l| l.stroke == c && l.width == width && l.points.len() > 2)
            .collect();
        assert_eq!(found.len(), 1, "{}: lines of {c:?}", depth.display());
        found[0].points.clone()
    };
    let seen = line(black, 1);
    let order = |c: Rgb, width: u32| {
        plots::lines(&svg)
            .iter()
            .position(|l| l.stroke == c && l.width == width && l.points.len() > 2)
            .unwrap()
    };
    assert!(order(black, 1) > order(green, 4) && order(black, 1) > order(red, 4));
    let off = |c: Rgb| {
        let l = line(c, 4);
        assert_eq!(l.len(), seen.len(), "{c:?} against the measurement");
        l.iter()
            .zip(&seen)
            .map(|(a, b)| {
                assert_eq!(a.0, b.0, "{c:?}: another time");
                (a.1 - b.1).abs()
            })
            .fold(0.0, f64::max)
    };
    let (found, baseline) = (off(green), off(red));
    assert!(
        found <= 2.0,
        "the extended model is {found} px off the measurement"
    );
    assert!(
        baseline >= 10.0,
        "the baseline is only {baseline} px off the measurement"
    );
    assert_png_colours(&depth.with_extension("png"), &[red, green, black], 300);

    let acf = report.join("plots/acf_depth.svg");
    let svg = std::fs::read_to_string(&acf).unwrap();
    let solid = |c: Rgb| -> Vec<(f64, f64)> {
        plots::lines(&svg)
            .into_iter()
            .find(|l| l.stroke == c && l.width == 2 && l.points.len() > 2)
            .unwrap_or_else(|| panic!("{}: no line of {c:?}", acf.display()))
            .points
    };
    let (before, after) = (solid(red), solid(green));
    assert_eq!(before.len(), 61, "lags 0 … 60");
    let xs = |l: &[(f64, f64)]| l.iter().map(|p| p.0).collect::<Vec<_>>();
    assert_eq!(xs(&before), xs(&after), "the same lags");
    assert_eq!(before[0].1, after[0].1, "both 1 at lag 0");
    assert_png_colours(&acf.with_extension("png"), &[red, green, grey], 100);
}
