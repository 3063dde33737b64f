//! Measures `shoal_record::replay::gif::render` on synthetic 100-s replays of 12 and 1,000
//! vehicles circling in formation, with links to their formation neighbours.
//!
//! ```sh
//! cargo run --release -p shoal-record --example gif_render [OUT_DIR]
//! ```
//! Prints vehicles, replay frames, GIF frames, image size, render time and file size; the GIFs
//! are left in OUT_DIR (default: the system's temporary folder).

use shoal_record::replay::gif::{GifOptions, View, render};
use shoal_record::replay::{GroupMeta, LinkEvent, Meta, Outcome, ReplayData, Timeline};
use std::f64::consts::{PI, TAU};
use std::path::PathBuf;
use std::time::Instant;

const PALETTE: [&str; 5] = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd"];

/// A replay of `cols × rows` vehicles on a grid of `spacing` metres in `pool`, each circling its
/// grid point (radius `r`, period 40 s, its own phase) and bobbing in depth; every vehicle
/// sends to `fanout` formation neighbours once a second.
fn formation(
    cols: usize,
    rows: usize,
    spacing: f64,
    r: f64,
    pool: [f64; 3],
    fanout: usize,
) -> ReplayData {
    let n = cols * rows;
    let duration = 100.0;
    // The replay's own rule: pose arrays within 12 MiB, at most 20 frames per second.
    let budget = (12usize << 20) / (12 * n);
    let frames = budget.min(20 * 100 + 1).min(2001);
    let dt = duration / (frames - 1) as f64;
    let groups = 5.min(n.div_ceil(4));
    let home = |v: usize| {
        let (c, w) = (v % cols, v / cols);
        let x0 = 0.5 * (pool[0] - (rows - 1) as f64 * spacing);
        let y0 = 0.5 * (pool[1] - (cols - 1) as f64 * spacing);
        (x0 + w as f64 * spacing, y0 + c as f64 * spacing)
    };
    let mut pos = Vec::with_capacity(frames * n * 3);
    let mut att = Vec::with_capacity(frames * n * 3);
    for f in 0..frames {
        let t = f as f64 * dt;
        for v in 0..n {
            let (hx, hy) = home(v);
            let phase = v as f64 * 0.7;
            let a = TAU * t / 40.0 + phase;
            let p = [
                hx + r * a.cos(),
                hy + r * a.sin(),
                pool[2] * (0.5 + 0.25 * (TAU * t / 30.0 + phase).sin()),
            ];
            for k in 0..3 {
                pos.push((p[k].clamp(0.0, pool[k]) / pool[k] * 65535.0).round() as u16);
            }
            // Heading along the circle (counter-clockwise seen from above in x–y: yaw a + 90°).
            let yaw = (a + PI / 2.0 + PI).rem_euclid(TAU) - PI;
            att.extend([0, 0, (yaw / PI * 32767.0).round() as i16]);
        }
    }
    let neighbours = |v: usize| {
        let (c, w) = (v % cols, v / cols);
        let mut out = Vec::new();
        if c + 1 < cols {
            out.push(v + 1);
        }
        if w + 1 < rows {
            out.push(v + cols);
        }
        if c > 0 {
            out.push(v - 1);
        }
        if w > 0 {
            out.push(v - cols);
        }
        out.truncate(fanout);
        out
    };
    let mut links = Vec::new();
    let outcomes = [
        Outcome::Delivered,
        Outcome::Delivered,
        Outcome::Delivered,
        Outcome::Delivered,
        Outcome::Delivered,
        Outcome::Delivered,
        Outcome::Collided,
        Outcome::Occluded,
        Outcome::OutOfBudget,
        Outcome::HalfDuplex,
    ];
    for s in 0..100 {
        for v in 0..n {
            let t = s as f64 + (v as f64 * 0.618).fract();
            for (k, to) in neighbours(v).into_iter().enumerate() {
                links.push(LinkEvent {
                    t: t as f32,
                    from: v as u32,
                    to: to as u32,
                    outcome: outcomes[(v * 7 + s * 3 + k) % outcomes.len()],
                    ack: false,
                });
            }
        }
    }
    links.sort_by(|a, b| a.t.total_cmp(&b.t));
    let group_of: Vec<u32> = (0..n).map(|v| (v * groups / n) as u32).collect();
    let meta = Meta {
        version: 1,
        world: format!("formation of {n}"),
        seed: 1,
        duration_s: duration,
        frame_dt: dt,
        panel_dt: 1.0,
        frames,
        vehicles: n,
        pool,
        obstacles: Vec::new(),
        groups: (0..groups)
            .map(|g| GroupMeta {
                name: format!("group {g}"),
                color: PALETTE[g].into(),
                count: group_of.iter().filter(|&&x| x as usize == g).count(),
            })
            .collect(),
        group_of,
        names: (0..n).map(|v| format!("v{v}")).collect(),
        hull: vec![[0.3, 0.15, 0.1]; groups],
        modem_range_m: 3.0,
        panel: Vec::new(),
        modes: Vec::new(),
        links_kept: links.len(),
        links_total: links.len() as u64,
        timeline: Timeline::default(),
        outcomes: shoal_record::replay::outcome_key(),
        ack_label: shoal_record::link_key::ACK_LABEL.to_string(),
    };
    ReplayData {
        meta,
        pos,
        att,
        panel: Vec::new(),
        links,
    }
}

fn main() {
    let out = std::env::args()
        .nth(1)
        .map_or_else(std::env::temp_dir, PathBuf::from);
    let runs = [
        ("12", formation(4, 3, 3.0, 1.5, [20.0, 12.0, 4.0], 4)),
        ("1000", formation(25, 40, 1.2, 1.0, [60.0, 40.0, 10.0], 2)),
    ];
    for (name, data) in &runs {
        for (view, label) in [(View::Both, "both"), (View::Top, "top")] {
            for links in [true, false] {
                let opts = GifOptions {
                    view,
                    links,
                    ..GifOptions::default()
                };
                let path = out.join(format!("shoal-{name}-{label}-links{links}.gif"));
                let t0 = Instant::now();
                match render(data, &path, &opts) {
                    Ok(p) => {
                        let secs = t0.elapsed().as_secs_f64();
                        let bytes = std::fs::metadata(&p).map_or(0, |m| m.len());
                        println!(
                            "{:>5} vehicles, {} replay frames, {} link events, view {label}, \
                             links {links}: {:.2} s, {:.2} MB  {}",
                            data.meta.vehicles,
                            data.meta.frames,
                            data.links.len(),
                            secs,
                            bytes as f64 / 1e6,
                            p.display()
                        );
                    }
                    Err(e) => eprintln!("{e}"),
                }
            }
        }
    }
}
