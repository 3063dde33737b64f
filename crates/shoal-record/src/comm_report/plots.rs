//! The communication plots of a run: delivery ratio against distance with the link-budget
//! curve (`delivery_vs_distance`), the communication graph seen from above
//! (`connectivity`), link outcomes per second in the colours of [`crate::link_key`]
//! (`links_over_time`), the graph over time (`connectivity_over_time`), when the world
//! floods a value, how many vehicles knew it over time (`gossip`) and, when vehicles sent
//! unicasts, each flow's goodput against what it offered (`flows`).

use super::envelope::delivery_envelope;
use super::summary::{CommSummary, DistanceBin};
use super::tables::per_second;
use crate::link_key;
use shoal_output::plot::{Plot, Series};
use shoal_sim::comm::Outcome;
use shoal_sim::connectivity::Connectivity;
use shoal_sim::sim::Sim;
use shoal_sim::view::VehicleView;
use shoal_world::desc::WorldDesc;

/// The 95 % Wilson score interval of a proportion: `k` successes in `n` trials (n > 0).
/// Unlike the normal approximation it stays within [0, 1] and is honest for k near 0 or n.
pub fn wilson(k: u64, n: u64) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let (n, z) = (n as f64, 1.959_963_984_540_054);
    let p = k as f64 / n;
    let z2n = z * z / n;
    let centre = (p + 0.5 * z2n) / (1.0 + z2n);
    let half = z / (1.0 + z2n) * (p * (1.0 - p) / n + 0.25 * z2n / n).sqrt();
    ((centre - half).max(0.0), (centre + half).min(1.0))
}

/// The communication plots, each with the stem of its files (drawn by the caller, one at a
/// time, so a stop request is answered between plots).
pub fn plots(
    desc: &WorldDesc,
    sim: &Sim,
    snaps: &[VehicleView<'_>],
    c: &CommSummary,
) -> Vec<(&'static str, Plot)> {
    let mut plots = vec![
        (
            "delivery_vs_distance",
            delivery_plot(
                &desc.name,
                &c.by_distance,
                c.cutoff_range_m,
                budget_curve(desc, snaps, c),
            ),
        ),
        (
            "connectivity",
            connectivity_plot(desc, sim.connectivity(), snaps),
        ),
        (
            "links_over_time",
            // Every second of the run, as in links.csv (a quiet second is a zero, not a gap).
            links_plot(&desc.name, &per_second(sim), desc.duration),
        ),
        (
            "connectivity_over_time",
            connectivity_over_time_plot(desc, sim.connectivity(), snaps.len()),
        ),
    ];
    if !sim.medium().flows().is_empty() {
        plots.push(("flows", flows_plot(&desc.name, sim, snaps)));
    }
    if let Some(g) = &c.gossip {
        let mut pts = vec![(g.start_s, 0.0)];
        pts.extend(g.informed_over_time.iter().map(|(t, n)| (*t, *n as f64)));
        plots.push((
            "gossip",
            Plot {
                title: format!(
                    "{}: vehicles that know the value ({} of {}{})",
                    desc.name,
                    g.informed,
                    g.vehicles,
                    g.time_to_all_s
                        .map_or(String::new(), |t| format!(", all after {t:.2} s"))
                ),
                x_label: "time [s]".into(),
                y_label: "vehicles informed".into(),
                series: vec![Series {
                    points: pts,
                    color: 0,
                    ..Default::default()
                }],
                y_range: Some((0.0, g.vehicles as f64 * 1.05)),
                ..Default::default()
            },
        ));
    }
    plots
}

/// Every unicast flow's goodput against the load it offered (payload bit/s over the run),
/// with the line where all of it arrives: a flow below the line lost frames on the way
/// (given up, or unacknowledged frames lost).
fn flows_plot(world: &str, sim: &Sim, snaps: &[VehicleView<'_>]) -> Plot {
    let flows = super::summary::flow_summaries(sim, snaps, sim.time());
    let points: Vec<(f64, f64)> = flows
        .iter()
        .map(|f| (f.offered_bps, f.goodput_bps))
        .collect();
    let top = points.iter().map(|p| p.0).fold(0.0, f64::max).max(1.0) * 1.05;
    Plot {
        title: format!(
            "{world}: unicast flows (sender → destination), {} in all",
            flows.len()
        ),
        x_label: "offered payload [bit/s]".into(),
        y_label: "goodput: payload the destination took [bit/s]".into(),
        series: vec![
            Series {
                label: Some("all delivered".into()),
                points: vec![(0.0, 0.0), (top, top)],
                color: 7,
                dashed: true,
                ..Default::default()
            },
            Series {
                label: Some("one flow".into()),
                points,
                color: 0,
                dots: true,
                width: 4,
                ..Default::default()
            },
        ],
        x_range: Some((0.0, top)),
        y_range: Some((0.0, top)),
        ..Default::default()
    }
}

/// The link budget's best case for the run's vehicles and water ([`delivery_envelope`]) as
/// the dashed curve the observed ratios lie under, labelled with what it assumes.
fn budget_curve(desc: &WorldDesc, snaps: &[VehicleView<'_>], c: &CommSummary) -> Option<Series> {
    let bits = c.mean_frame_bits.round().max(1.0) as u64;
    let e = delivery_envelope(desc, snaps, c.cutoff_range_m, bits)?;
    Some(Series {
        label: Some(e.label),
        points: e.points,
        color: 7,
        dashed: true,
        ..Default::default()
    })
}

/// Radius of the markers of observed delivery ratios \[px\].
pub const DELIVERY_MARKER_PX: u32 = 4;
/// Bins with fewer attempts than this are not drawn.
const MIN_ATTEMPTS: u64 = 5;

/// Delivery against distance (up to `cutoff_range_m`): the observed ratio of each distance
/// bin of `by_distance` (of at least 5 attempts) as a marker drawn over its 95 % Wilson
/// interval (a thin, lighter bar), and `curve` (the link budget). The vertical axis starts a
/// little below 0, so a bin where nothing was delivered shows a whole marker on the 0 line.
pub fn delivery_plot(
    world: &str,
    by_distance: &[DistanceBin],
    cutoff_range_m: f64,
    curve: Option<Series>,
) -> Plot {
    let bins: Vec<&DistanceBin> = by_distance
        .iter()
        .filter(|b| b.attempts >= MIN_ATTEMPTS)
        .collect();
    // The bars in the markers' colour, halfway to white.
    let (r, g, b) = shoal_output::plot::rgb(0);
    let light = |v: u8| v + (255 - v) / 2;
    let bar = (light(r), light(g), light(b));
    let mut series: Vec<Series> = bins
        .iter()
        .map(|bin| {
            let (lo, hi) = wilson(bin.delivered, bin.attempts);
            let d = 0.5 * (bin.from_m + bin.to_m);
            Series {
                points: vec![(d, lo), (d, hi)],
                rgb: Some(bar),
                width: 1,
                ..Default::default()
            }
        })
        .collect();
    series.push(Series {
        label: Some("observed (all angles), with its 95 % Wilson interval".into()),
        points: bins
            .iter()
            .map(|b| (0.5 * (b.from_m + b.to_m), b.ratio))
            .collect(),
        color: 0,
        dots: true,
        width: DELIVERY_MARKER_PX,
        ..Default::default()
    });
    series.extend(curve);
    Plot {
        title: format!("{world}: delivery ratio against distance"),
        x_label: "distance between vehicles [m]".into(),
        y_label: "frames delivered / sent within range".into(),
        series,
        x_range: Some((0.0, cutoff_range_m)),
        y_range: Some((-0.04, 1.04)),
        ..Default::default()
    }
}

/// The colour of the communication graph's edges (navy): a link is a delivered frame, so not
/// the grey that [`crate::link_key`] gives frames out of budget, nor any colour of that key
/// or of the first groups.
pub const EDGE_RGB: (u8, u8, u8) = (20, 40, 90);

/// The communication graph seen from above, at the last sample that had an edge (the end of
/// the run when there was traffic to the end; otherwise the last window with a delivered
/// frame, and the title says so), with the vehicles where they are at the end.
pub fn connectivity_plot(desc: &WorldDesc, conn: &Connectivity, snaps: &[VehicleView<'_>]) -> Plot {
    let pos = |i: u32| {
        let p = snaps[i as usize].state.rigid.position;
        (p.y, p.x)
    };
    let busy = conn.last_busy();
    let edges = busy.map_or(&[][..], |b| b.1);
    let mut series: Vec<Series> = edges
        .iter()
        .enumerate()
        .map(|(k, &(a, b))| Series {
            label: (k == 0).then(|| format!("link: a frame delivered within {} s", conn.window)),
            points: vec![pos(a), pos(b)],
            rgb: Some(EDGE_RGB),
            ..Default::default()
        })
        .collect();
    for s in snaps {
        // Each vehicle as a short heading mark with a dot at its position.
        let p = s.state.rigid.position;
        let yaw = s.state.rigid.attitude.euler_angles().2;
        let l = 0.2;
        series.push(Series {
            points: vec![(p.y, p.x), (p.y + l * yaw.sin(), p.x + l * yaw.cos())],
            color: desc.vehicles[s.id as usize].group,
            mark_start: true,
            ..Default::default()
        });
    }
    let last_t = conn.samples.last().map_or(0.0, |s| s.t);
    let title = match busy {
        Some((s, e)) if s.t == last_t => format!(
            "{}: links at t = {:.0} s ({} edges, largest group {} of {})",
            desc.name,
            s.t,
            e.len(),
            s.largest,
            snaps.len()
        ),
        Some((s, e)) => format!(
            "{}: links in t = {:.0}–{:.0} s, the last window with traffic ({} edges, largest group {} of {})",
            desc.name,
            s.t - conn.window,
            s.t,
            e.len(),
            s.largest,
            snaps.len()
        ),
        None => format!("{}: no frame delivered", desc.name),
    };
    crate::map::map_plot(
        title,
        &desc.geometry,
        series,
        snaps.iter().map(|s| pos(s.id)),
        800,
    )
}

/// Reception attempts per second by outcome (`per_second[k]` counts the attempts of second
/// `k` by [`Outcome::index`]), each outcome in its colour and with its label from
/// [`crate::link_key`].
pub fn links_plot(world: &str, per_second: &[[u64; 5]], duration: f64) -> Plot {
    // In the key's order (the outcomes' code order).
    let series = Outcome::ALL
        .iter()
        .map(|&o| {
            let key = link_key::style(o);
            Series {
                label: Some(if key.detail.is_empty() {
                    key.label.to_string()
                } else {
                    format!("{} ({})", key.label, key.detail)
                }),
                points: per_second
                    .iter()
                    .enumerate()
                    .map(|(k, c)| (k as f64 + 0.5, c[o.index()] as f64))
                    .collect(),
                rgb: Some(key.rgb),
                ..Default::default()
            }
        })
        .collect();
    Plot {
        title: format!("{world}: reception attempts per second by outcome"),
        x_label: "time [s]".into(),
        y_label: "receptions per second".into(),
        series,
        x_range: Some((0.0, duration)),
        ..Default::default()
    }
}

/// The largest connected group and the mean degree over time.
fn connectivity_over_time_plot(desc: &WorldDesc, conn: &Connectivity, vehicles: usize) -> Plot {
    let n = vehicles.max(1) as f64;
    Plot {
        title: format!(
            "{}: communication graph over time (edge: a frame delivered within {} s)",
            desc.name, conn.window
        ),
        x_label: "time [s]".into(),
        y_label: "fraction of the vehicles".into(),
        series: vec![
            Series {
                label: Some("largest connected group".into()),
                points: conn
                    .samples
                    .iter()
                    .map(|s| (s.t, s.largest as f64 / n))
                    .collect(),
                color: 0,
                ..Default::default()
            },
            Series {
                label: Some("mean degree / (vehicles − 1)".into()),
                points: conn
                    .samples
                    .iter()
                    .map(|s| (s.t, 2.0 * s.edges as f64 / n / (n - 1.0).max(1.0)))
                    .collect(),
                color: 1,
                ..Default::default()
            },
        ],
        x_range: Some((0.0, desc.duration)),
        y_range: Some((0.0, 1.05)),
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use super::wilson;

    #[test]
    fn wilson_interval_matches_hand_values() {
        // 8 of 10: Wilson 95 % = [0.4902, 0.9433] (Newcombe 1998, method 3).
        let (lo, hi) = wilson(8, 10);
        assert!(
            (lo - 0.4902).abs() < 1e-4 && (hi - 0.9433).abs() < 1e-4,
            "{lo} {hi}"
        );
        // 0 of 20: the lower end is 0, the upper 0.1611; all of 20: mirrored.
        let (lo, hi) = wilson(0, 20);
        assert!(lo == 0.0 && (hi - 0.1611).abs() < 1e-4, "{lo} {hi}");
        let (lo, hi) = wilson(20, 20);
        assert!(
            (lo - 0.8389).abs() < 1e-4 && (hi - 1.0).abs() < 1e-12,
            "{lo} {hi}"
        );
        // It narrows as 1/√n around the ratio.
        let (lo, hi) = wilson(5000, 10000);
        assert!((hi - lo - 2.0 * 1.96 * 0.005).abs() < 1e-4);
    }
}
