//! The communication tables of a run: `links.csv` (per second: reception attempts by
//! outcome), `connectivity.csv` (per second: the communication graph) and `link_pairs.csv`
//! (per sender → receiver), each written whole through [`shoal_output::files`].

use shoal_output::files::FileError;
use shoal_sim::comm::Outcome;
use shoal_sim::sim::Sim;
use shoal_sim::view::VehicleView;
use std::path::{Path, PathBuf};

/// Most vehicles for which `link_pairs.csv` is written (it has up to one row per pair of
/// vehicles within range: ≈ 40 per vehicle in a dense beaconing swarm).
pub const PAIRS_MAX_VEHICLES: usize = 10_000;

/// The communication tables of a run with `vehicles` vehicles, with unicast `flows` or
/// not, in the order [`write_tables`] writes them.
pub fn table_names(vehicles: usize, flows: bool) -> Vec<&'static str> {
    let mut t = vec!["links.csv", "connectivity.csv"];
    if vehicles <= PAIRS_MAX_VEHICLES {
        t.push("link_pairs.csv");
    }
    if flows {
        t.push("flows.csv");
    }
    t
}

/// Writes the communication tables into `dir` (each whole, through [`shoal_output::files`]),
/// calling `begin` with each one's name before it begins it and adding each to `written`
/// when complete: `links.csv` (per second of the run: reception
/// attempts by outcome), `connectivity.csv` (per second: the communication graph), for
/// up to [`PAIRS_MAX_VEHICLES`] vehicles `link_pairs.csv` (per sender → receiver), and when
/// unicast frames were sent `flows.csv` (per flow, sender → destination).
pub fn write_tables(
    dir: &Path,
    sim: &Sim,
    snaps: &[VehicleView<'_>],
    begin: &dyn Fn(&Path),
    written: &mut Vec<PathBuf>,
) -> Result<(), FileError> {
    let links = dir.join("links.csv");
    begin(&links);
    written.push(write_links_csv(&links, sim)?);
    let connectivity = dir.join("connectivity.csv");
    begin(&connectivity);
    written.push(write_connectivity_csv(&connectivity, sim, snaps.len())?);
    if snaps.len() <= PAIRS_MAX_VEHICLES {
        let pairs = dir.join("link_pairs.csv");
        begin(&pairs);
        written.push(write_link_pairs_csv(&pairs, snaps)?);
    }
    if !sim.medium().flows().is_empty() {
        let flows = dir.join("flows.csv");
        begin(&flows);
        written.push(write_flows_csv(&flows, sim, snaps)?);
    }
    Ok(())
}

/// `flows.csv`: one row per unicast flow (sender → destination) with the measures of
/// [`FlowSummary`]; empty fields where a measure does not apply (no frame acknowledged).
pub fn write_flows_csv(
    path: &Path,
    sim: &Sim,
    snaps: &[VehicleView<'_>],
) -> Result<PathBuf, FileError> {
    let mut w = shoal_output::files::CsvFile::create(path)?;
    w.write_record([
        "from",
        "to",
        "offered",
        "delivered",
        "delivery_ratio",
        "offered_bps",
        "goodput_bps",
        "acknowledged",
        "gave_up",
        "delivery_after_retries",
        "retransmissions",
        "latency_p50_s",
        "latency_p95_s",
        "latency_p99_s",
        "led_on_s",
        "led_energy_j",
    ])?;
    let opt = |x: Option<f64>| x.map_or(String::new(), |v| v.to_string());
    for f in super::flow_summaries(sim, snaps, sim.time()) {
        w.write_record([
            f.from,
            f.to,
            f.offered.to_string(),
            f.delivered.to_string(),
            f.delivery_ratio.to_string(),
            f.offered_bps.to_string(),
            f.goodput_bps.to_string(),
            f.acknowledged.to_string(),
            f.gave_up.to_string(),
            opt(f.delivery_after_retries),
            f.retransmissions.to_string(),
            opt(f.latency_p50_s),
            opt(f.latency_p95_s),
            opt(f.latency_p99_s),
            f.led_on_s.to_string(),
            f.led_energy_j.to_string(),
        ])?;
    }
    w.commit()
}

/// `links.csv`: one row per second of the run, `[t_start_s, t_start_s + 1)`, with the
/// reception attempts of frames that ended in it, by outcome. The columns add up to the
/// summary's `comm.receptions`.
pub fn write_links_csv(path: &Path, sim: &Sim) -> Result<PathBuf, FileError> {
    let mut w = shoal_output::files::CsvFile::create(path)?;
    w.write_record([
        "t_start_s",
        "attempted",
        "delivered",
        "collided",
        "occluded",
        "out_of_budget",
        "half_duplex",
        "delivery_ratio",
    ])?;
    for (k, c) in per_second(sim).into_iter().enumerate() {
        let n = |o: Outcome| c[o.index()];
        let attempted: u64 = c.iter().sum();
        w.write_record([
            k.to_string(),
            attempted.to_string(),
            n(Outcome::Delivered).to_string(),
            n(Outcome::Collided).to_string(),
            n(Outcome::Occluded).to_string(),
            n(Outcome::OutOfBudget).to_string(),
            n(Outcome::HalfDuplex).to_string(),
            if attempted > 0 {
                format!("{:.6}", n(Outcome::Delivered) as f64 / attempted as f64)
            } else {
                String::new()
            },
        ])?;
    }
    w.commit()
}

/// The reception attempts of each second of the run by outcome (indexed by
/// [`Outcome::index`]), the seconds after the last attempt included (as zeros): the rows of
/// `links.csv` and the points of `links_over_time`.
pub(crate) fn per_second(sim: &Sim) -> Vec<[u64; 5]> {
    let counted = &sim.medium().per_second;
    let seconds = (sim.time().ceil() as usize).max(counted.len());
    (0..seconds)
        .map(|k| counted.get(k).copied().unwrap_or([0; 5]))
        .collect()
}

/// `connectivity.csv`: one row per sample of the communication graph (every second): an
/// edge joins two vehicles when a frame was delivered either way within the window (2 s).
pub fn write_connectivity_csv(
    path: &Path,
    sim: &Sim,
    vehicles: usize,
) -> Result<PathBuf, FileError> {
    let mut w = shoal_output::files::CsvFile::create(path)?;
    w.write_record([
        "t_s",
        "components",
        "largest_component",
        "largest_fraction",
        "edges",
        "mean_degree",
    ])?;
    let n = vehicles.max(1) as f64;
    for s in &sim.connectivity().samples {
        w.write_record([
            format!("{}", s.t),
            s.components.to_string(),
            s.largest.to_string(),
            format!("{:.6}", s.largest as f64 / n),
            s.edges.to_string(),
            format!("{:.6}", 2.0 * s.edges as f64 / n),
        ])?;
    }
    w.commit()
}

/// `link_pairs.csv`: one row per (sender, receiver) with at least one attempt.
pub fn write_link_pairs_csv(path: &Path, snaps: &[VehicleView<'_>]) -> Result<PathBuf, FileError> {
    let mut w = shoal_output::files::CsvFile::create(path)?;
    w.write_record([
        "sender",
        "receiver",
        "attempts",
        "delivered",
        "lost_range",
        "lost_occlusion",
        "lost_collision",
        "lost_half_duplex",
        "mean_latency_s",
    ])?;
    for rx in snaps {
        let mut links: Vec<_> = rx.comm.links().iter().collect();
        links.sort_by_key(|(from, _)| **from);
        for (from, l) in links {
            let lat = if l.delivered > 0 {
                format!("{:.6}", l.latency_sum_s / l.delivered as f64)
            } else {
                String::new()
            };
            w.write_record([
                snaps[*from as usize].name,
                rx.name,
                &l.attempts.to_string(),
                &l.delivered.to_string(),
                &l.lost_range.to_string(),
                &l.lost_occlusion.to_string(),
                &l.lost_collision.to_string(),
                &l.lost_half_duplex.to_string(),
                &lat,
            ])?;
        }
    }
    w.commit()
}
