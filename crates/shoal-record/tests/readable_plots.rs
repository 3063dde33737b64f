//! The run's plots read the way they are meant to, checked on the pictures themselves (PNG
//! decoded) where the fault was in the picture:
//!
//! * maps (`top.png`, `connectivity.png`) draw 1 m north as long as 1 m east: the default
//!   world's round pillar is a circle in `top.png`, not an ellipse;
//! * in `delivery_vs_distance.png` each observed ratio is a marker drawn over its interval bar,
//!   and a distance bin with nothing delivered reads as 0 (a whole marker on the 0 line);
//! * `depth.png` draws a depth setpoint only where the vehicle holds a depth (not the 0 a
//!   vehicle records while off);
//! * the link budget curve in `delivery_vs_distance.png` is the model's best case, labelled
//!   so, and the observed ratios lie under it;
//! * the gossip world's communication graph shows the links of its flood, which ends long
//!   before the run does;
//! * `links_over_time` colours each outcome by the one key of `shoal_record::link_key`, and
//!   the communication graph's edges are in a colour that key does not use.

mod support;

use shoal_record::comm_report::{self, DistanceBin};
use shoal_record::link_key::{LINK_KEY, Outcome};
use shoal_record::output::RunOutput;
use shoal_sim::prelude::*;
use shoal_world::cancel::Cancel;
use std::path::{Path, PathBuf};

fn world(name: &str) -> shoal_world::desc::WorldDesc {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../worlds/{name}.toml"));
    shoal_world::load::load_file(&path).unwrap()
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("shoal-plots-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Runs `desc` as `shoal run` does (recording, every output) into `out`; the world at the
/// end.
fn run_with_outputs(desc: &shoal_world::desc::WorldDesc, out: &Path) -> Sim {
    let mut sim = Sim::new(
        desc,
        SimOptions {
            threads: 1,
            record: true,
        },
    );
    let mut output = RunOutput::create(out, desc).unwrap();
    let steps = desc.steps();
    while sim.step_count() < steps {
        sim.run(500.min(steps - sim.step_count()));
        output.write(&sim.drain()).unwrap();
    }
    output.finish(&mut sim, 1.0, &Cancel::default()).unwrap();
    sim
}

/// The bounding box (x0, y0, x1, y1) of the largest connected area of colour `c` whose
/// first pixel has a 5 × 5 neighbourhood of that colour (a filled shape, not a line of the
/// grid), and its pixels.
fn blob(img: &image::RgbImage, c: [u8; 3]) -> ((u32, u32, u32, u32), usize) {
    let (w, h) = img.dimensions();
    let is = |x: u32, y: u32| x < w && y < h && img.get_pixel(x, y).0 == c;
    let filled = |x: u32, y: u32| {
        x >= 2 && y >= 2 && (x - 2..=x + 2).all(|a| (y - 2..=y + 2).all(|b| is(a, b)))
    };
    let Some((sx, sy)) = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .find(|&(x, y)| filled(x, y))
    else {
        return ((0, 0, 0, 0), 0);
    };
    let mut seen = vec![false; (w * h) as usize];
    let mut stack = vec![(sx, sy)];
    let (mut x0, mut y0, mut x1, mut y1, mut n) = (sx, sy, sx, sy, 0);
    while let Some((x, y)) = stack.pop() {
        if !is(x, y) || std::mem::replace(&mut seen[(y * w + x) as usize], true) {
            continue;
        }
        (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
        n += 1;
        stack.extend([
            (x + 1, y),
            (x.wrapping_sub(1), y),
            (x, y + 1),
            (x, y.wrapping_sub(1)),
        ]);
    }
    ((x0, y0, x1, y1), n)
}

/// The filled grey of obstacles in the plots.
const OBSTACLE_FILL: [u8; 3] = [170, 170, 170];

#[test]
fn maps_draw_north_and_east_at_one_scale() {
    let desc = world("default");
    let out = dir("maps");
    let sim = run_with_outputs(&desc, &out);
    // The default world's pillar, a vertical cylinder, in top.png.
    let img = image::open(out.join("top.png")).unwrap().to_rgb8();
    let ((x0, y0, x1, y1), n) = blob(&img, OBSTACLE_FILL);
    assert!(n > 100, "top.png: the pillar is not drawn ({n} px)");
    let (w, h) = (x1 - x0 + 1, y1 - y0 + 1);
    eprintln!("top.png: the pillar is {w} × {h} px");
    assert!(
        w.abs_diff(h) <= 1,
        "top.png: the round pillar is drawn {w} px wide and {h} px high"
    );
    // The communication graph (zoomed to the vehicles at the end, the pillar outside): its
    // scales differ by less than a pixel over the whole plot.
    let plot = comm_report::connectivity_plot(&desc, sim.connectivity(), &sim.views());
    let at = plot.ranges_drawn().unwrap();
    let span = (at.x.1 - at.x.0).max(at.y.1 - at.y.0);
    assert!(
        (at.scale.0 - at.scale.1).abs() * span < 1.0,
        "connectivity: {:.2} px per m east, {:.2} px per m north",
        at.scale.0,
        at.scale.1
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// A vehicle that starts off (not yet commanded, its depth setpoint recorded as 0) and is
/// told to hold 0.5 m at t = 2 s: `depth.svg` draws the setpoint (dashed) only from then on,
/// not as a line at 0 m while the vehicle is off.
#[test]
fn the_depth_setpoint_is_drawn_only_where_depth_is_held() {
    let text = r#"
name = "off_then_diving"
seed = 1
duration = 4.0
dt = 0.01
[pool]
size = [4.0, 4.0, 3.0]
[[vehicles]]
name = "auv"
position = [2.0, 2.0, 1.0]
mission = [
  { t = 0, mode = "off" },
  { t = 2, mode = "diving", depth = 0.5 },
]
[output]
record_hz = 20.0
"#;
    let desc = shoal_world::load::load_str(text, Path::new("off_then_diving.toml")).unwrap();
    let out = dir("setpoint");
    run_with_outputs(&desc, &out);
    let svg = std::fs::read_to_string(out.join("depth.svg")).unwrap();
    let (x0, _, x1, _) = support::plots::plot_area(&svg);
    // The horizontal axis is the run's time, 0 to 4 s.
    let t = |x: f64| (x - x0) / (x1 - x0) * desc.duration;
    // The setpoint's dashes: 1 px lines in the vehicle's group colour (the reading is 2 px).
    let dashes: Vec<f64> = support::plots::lines(&svg)
        .iter()
        .filter(|l| l.width == 1 && l.stroke == shoal_output::plot::rgb(0))
        .flat_map(|l| l.points.iter().map(|p| t(p.0)))
        .collect();
    let first = dashes.iter().copied().fold(f64::INFINITY, f64::min);
    let last = dashes.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    eprintln!("setpoint dashes from t = {first:.2} s to {last:.2} s");
    assert!(
        (first - 2.0).abs() < 0.15,
        "the setpoint is drawn from t = {first:.2} s; the vehicle holds a depth from 2 s \
         (off before: no setpoint)"
    );
    assert!(
        last > 3.7,
        "the setpoint ends at t = {last:.2} s, the run at 4 s"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// Bins of 0.1 m: all of 100 delivered at 0.55 m, half of 200 at 2.05 m, none of 200 at
/// 3.55 m.
fn bins() -> Vec<DistanceBin> {
    [(5, 100, 100), (20, 200, 100), (35, 200, 0)]
        .iter()
        .map(|&(k, attempts, delivered)| DistanceBin {
            from_m: f64::from(k) * 0.1,
            to_m: f64::from(k + 1) * 0.1,
            attempts,
            delivered,
            ratio: delivered as f64 / attempts as f64,
        })
        .collect()
}

#[test]
fn a_bin_with_nothing_delivered_reads_as_zero_and_markers_are_on_top() {
    let plot = comm_report::delivery_plot("test", &bins(), 5.4, None);
    let d = dir("delivery");
    std::fs::create_dir_all(&d).unwrap();
    plot.write(&d.join("delivery")).unwrap();
    let img = image::open(d.join("delivery.png")).unwrap().to_rgb8();
    let at = plot.ranges_drawn().unwrap();
    let (r, g, b) = shoal_output::plot::rgb(0);
    let marker = [r, g, b];
    // A marker clearly visible: at least 3 px in radius.
    let radius = 3.0;
    assert!(f64::from(comm_report::DELIVERY_MARKER_PX) >= radius);
    for bin in bins() {
        let (cx, cy) = at.pixel((0.5 * (bin.from_m + bin.to_m), bin.ratio));
        // The marker's pixels around where its ratio is drawn.
        let (mut n, mut sy) = (0.0, 0.0);
        for y in (cy - 2.0 * radius) as u32..=(cy + 2.0 * radius) as u32 {
            for x in (cx - 2.0 * radius) as u32..=(cx + 2.0 * radius) as u32 {
                if img.get_pixel(x, y).0 == marker {
                    n += 1.0;
                    sy += f64::from(y);
                }
            }
        }
        let want = std::f64::consts::PI * radius * radius;
        eprintln!("ratio {}: a marker of {n} px", bin.ratio);
        assert!(
            n > 0.7 * want,
            "ratio {}: a marker of {n} px (a whole one has ≈ {want:.0})",
            bin.ratio
        );
        let centre = sy / n;
        assert!(
            (centre - cy).abs() <= 1.0,
            "ratio {}: the marker is centred at y = {centre:.1} px, the ratio is at {cy:.1} px",
            bin.ratio
        );
        // Its centre is the marker's colour, not its interval bar's.
        assert_eq!(
            img.get_pixel(cx.round() as u32, cy.round() as u32).0,
            marker,
            "ratio {}: the interval bar is drawn over the marker",
            bin.ratio
        );
    }
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn the_gossip_graph_shows_the_links_of_its_flood() {
    let (desc, sim) = support::world::run_world_file("gossip");
    let snaps = sim.views();
    // The flood is over within a second of t = 2 s, long before the end (20 s): the graph at
    // the end is empty.
    assert!(sim.connectivity().last_edges.is_empty());
    let plot = comm_report::connectivity_plot(&desc, sim.connectivity(), &snaps);
    // Edges are the two-point lines without a start mark (vehicles are marked).
    let edge_lines: Vec<_> = plot
        .series
        .iter()
        .filter(|s| s.points.len() == 2 && !s.mark_start)
        .collect();
    let edges = edge_lines.len();
    // An edge (a delivered frame) is in a colour of its own: none of the link key's (grey
    // there is "out of budget"), told apart as the key tells its colours apart, nor a
    // vehicle's.
    let vehicles: Vec<_> = plot.series.iter().filter(|s| s.mark_start).collect();
    for e in &edge_lines {
        let c = e.drawn_rgb();
        for key in &LINK_KEY {
            assert!(
                colour_distance(c, key.rgb) > 120,
                "edges drawn in {c:?}, like \"{}\" {:?} of the link key",
                key.label,
                key.rgb
            );
        }
        assert!(
            vehicles.iter().all(|v| v.drawn_rgb() != c),
            "edges in a vehicle's colour"
        );
    }
    let n = desc.vehicles.len();
    assert!(
        edges >= n - 1,
        "{edges} edges drawn; every one of the {n} vehicles learned the value, so its graph \
         connects them all"
    );
    assert!(
        plot.title
            .contains("links in t = 2–4 s, the last window with traffic")
            && plot.title.contains(&format!("largest group {n} of {n}")),
        "{}",
        plot.title
    );
}

/// The link budget curve of `delivery_vs_distance` is the best case the model allows for the
/// run's vehicles and water, and says so: in the gossip world (vehicles a metre or two apart,
/// 4 LED copies each) every distance bin with a delivered frame lies within its range, and no
/// bin's ratio is clearly above it (the lower end of its 95 % interval at most the curve at
/// the bin's nearer edge).
#[test]
fn observed_delivery_lies_under_the_link_budget_curve() {
    let (desc, sim) = support::world::run_world_file("gossip");
    let snaps = sim.views();
    let c = comm_report::summarize(&desc, &sim, &snaps).unwrap();
    let plots = comm_report::plots(&desc, &sim, &snaps, &c);
    let plot = &plots
        .iter()
        .find(|(name, _)| *name == "delivery_vs_distance")
        .unwrap()
        .1;
    let curve = plot
        .series
        .iter()
        .find(|s| s.dashed && s.label.is_some())
        .expect("a labelled link-budget curve");
    // The curve at distance `d`: its value at the nearest sample at or before `d` (it falls
    // with distance, so this is not below it).
    let at = |d: f64| {
        curve
            .points
            .iter()
            .rev()
            .find(|p| p.0 <= d)
            .map_or(1.0, |p| p.1)
    };
    let mut checked = 0;
    for b in c
        .by_distance
        .iter()
        .filter(|b| b.attempts >= 5 && b.delivered > 0)
    {
        let (lo, _) = comm_report::wilson(b.delivered, b.attempts);
        let bound = at(b.from_m);
        eprintln!(
            "{:.1}–{:.1} m: {} of {} delivered, curve {bound:.3}",
            b.from_m, b.to_m, b.delivered, b.attempts
        );
        assert!(
            bound > 0.0 && lo <= bound,
            "{:.1}–{:.1} m: {} of {} delivered (95 % interval from {lo:.3}), the curve says at \
             most {bound:.3}",
            b.from_m,
            b.to_m,
            b.delivered,
            b.attempts
        );
        checked += 1;
    }
    assert!(checked >= 3, "only {checked} distance bins with deliveries");
    let label = curve.label.as_deref().unwrap();
    for words in [
        "best case (upper bound)",
        "LED copies on axis",
        "receiver at the floor",
        "no interference",
        "frames (run mean)",
    ] {
        assert!(
            label.contains(words),
            "the curve's label does not say \"{words}\": {label}"
        );
    }
}

/// How far apart two colours are: the sum of their channels' differences (the measure of
/// the link key's own test).
fn colour_distance(a: (u8, u8, u8), b: (u8, u8, u8)) -> u32 {
    u32::from(a.0.abs_diff(b.0)) + u32::from(a.1.abs_diff(b.1)) + u32::from(a.2.abs_diff(b.2))
}

#[test]
fn link_outcomes_are_drawn_in_the_colours_of_the_one_key() {
    // Each second: 1 out of budget, 2 occluded, 3 half-duplex, 4 collided, 5 delivered
    // (counts by `Outcome::index`).
    let mut second = [0u64; 5];
    for (o, n) in [
        (Outcome::OutOfBudget, 1),
        (Outcome::Occluded, 2),
        (Outcome::HalfDuplex, 3),
        (Outcome::Collided, 4),
        (Outcome::Delivered, 5),
    ] {
        second[o.index()] = n;
    }
    let per_second = [second; 3];
    let want = |label: &str| match label {
        "out of budget" => 1.0,
        "occluded" => 2.0,
        "half-duplex" => 3.0,
        "collided" => 4.0,
        "delivered" => 5.0,
        other => panic!("unknown outcome {other}"),
    };
    let plot = comm_report::links_plot("test", &per_second, 3.0);
    assert_eq!(plot.series.len(), LINK_KEY.len());
    for (s, key) in plot.series.iter().zip(&LINK_KEY) {
        let label = s.label.as_deref().unwrap();
        assert!(label.starts_with(key.label), "{label} for {key:?}");
        assert_eq!(s.drawn_rgb(), key.rgb, "{label} is not in its key colour");
        assert!(s.points.iter().all(|p| p.1 == want(key.label)), "{label}");
    }
}
