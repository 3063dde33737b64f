//! Run outputs of the optical medium: the communication section of `summary.json`, the tables
//! `links.csv` (per second: reception attempts by outcome), `connectivity.csv` (per second:
//! components, largest component, mean degree of the communication graph) and
//! `link_pairs.csv` (per sender → receiver), and plots (`plots`: delivery ratio against
//! distance with the link-budget curve, link outcomes and connectivity over time, the
//! communication graph, and — when the world floods a value — how many vehicles knew it over
//! time).

use crate::comm::{DIST_BIN, LinkStats, Outcome, latency_bin_centre};
use crate::connectivity::ConnSample;
use crate::sim::Sim;
use crate::view::VehicleView;
use serde::Serialize;
use shoal_output::files::FileError;
use shoal_world::desc::WorldDesc;
use shoal_world::spec::BehaviourSpec;
use std::path::{Path, PathBuf};

mod plots;
pub use plots::{DELIVERY_MARKER_PX, connectivity_plot, delivery_plot, links_plot, plots, wilson};

/// Deliveries within one distance bin.
#[derive(Clone, Debug, Serialize)]
pub struct DistanceBin {
    /// Bin start \[m\].
    pub from_m: f64,
    /// Bin end \[m\].
    pub to_m: f64,
    /// Frames sent by vehicles this far away.
    pub attempts: u64,
    /// Of those, delivered.
    pub delivered: u64,
    /// delivered / attempts.
    pub ratio: f64,
}

/// Result of flooding a value (the `gossip` behaviour).
#[derive(Clone, Debug, Serialize)]
pub struct GossipSummary {
    /// Vehicles running gossip.
    pub vehicles: usize,
    /// Vehicles that learned the value.
    pub informed: usize,
    /// Time the value appeared at the origin \[s\].
    pub start_s: f64,
    /// Time from the start until every vehicle knew it \[s\] (`null` if some never did).
    pub time_to_all_s: Option<f64>,
    /// Time from the start until half the vehicles knew it \[s\].
    pub time_to_half_s: Option<f64>,
    /// Most hops from the origin.
    pub max_hops: u32,
    /// Mean hops from the origin over informed vehicles.
    pub mean_hops: f64,
    /// Mean over informed vehicles of (time learned − start) / hops \[s\].
    pub mean_time_per_hop_s: f64,
    /// (time \[s\], vehicles informed) at every new informed vehicle.
    pub informed_over_time: Vec<(f64, usize)>,
}

/// Communication counters of one vehicle.
#[derive(Clone, Debug, Serialize)]
pub struct VehicleComm {
    /// Name.
    pub name: String,
    /// Frames it put on the air.
    pub sent: u64,
    /// Frames dropped at its full transmit queues.
    pub queue_overflow: u64,
    /// Its receptions by outcome.
    #[serde(flatten)]
    pub rx: LinkStats,
}

/// The communication section of `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct CommSummary {
    /// Beam attenuation of the water [1/m].
    pub attenuation_per_m: f64,
    /// Distance beyond which no frame is decodable \[m\].
    pub cutoff_range_m: f64,
    /// Frames put on the air.
    pub frames_sent: u64,
    /// Frames dropped at full transmit queues.
    pub queue_overflow: u64,
    /// Frames longer than a modem allows (dropped).
    pub oversize: u64,
    /// Carrier-sense deferrals.
    pub cs_deferrals: u64,
    /// All receptions by outcome (a frame counts once per vehicle within the cut-off range).
    pub receptions: LinkStats,
    /// receptions.delivered / receptions.attempts.
    pub delivery_ratio: f64,
    /// Mean hand-over-to-delivery latency \[s\].
    pub latency_mean_s: Option<f64>,
    /// Median latency \[s\] (centre of its histogram bin: ±6 %).
    pub latency_median_s: Option<f64>,
    /// 95th percentile latency \[s\] (centre of its histogram bin: ±6 %).
    pub latency_p95_s: Option<f64>,
    /// Mean frame length on the line \[bits\].
    pub mean_frame_bits: f64,
    /// Delivery ratio against distance.
    pub by_distance: Vec<DistanceBin>,
    /// The communication graph over time (edge: a frame delivered either way in the last 2 s).
    pub connectivity: Vec<ConnSample>,
    /// Flooding result, if the world runs the gossip behaviour.
    pub gossip: Option<GossipSummary>,
    /// Per vehicle.
    /// (written to `vehicles.csv`, not to summary.json, which stays small for any count)
    #[serde(skip)]
    pub vehicles: Vec<VehicleComm>,
}

fn percentile(hist: &[u64], q: f64) -> Option<f64> {
    let total: u64 = hist.iter().sum();
    if total == 0 {
        return None;
    }
    let target = (q * total as f64).ceil().max(1.0) as u64;
    let mut acc = 0;
    for (k, n) in hist.iter().enumerate() {
        acc += n;
        if acc >= target {
            return Some(latency_bin_centre(k));
        }
    }
    None
}

/// The communication section, or `None` when no vehicle sent a frame.
pub fn summarize(desc: &WorldDesc, sim: &Sim, snaps: &[VehicleView<'_>]) -> Option<CommSummary> {
    let sent: u64 = snaps.iter().map(|s| s.comm.sent).sum();
    if sent == 0 {
        return None;
    }
    let mut rx = LinkStats::default();
    for s in snaps {
        rx.add(&s.comm.rx);
    }
    let by_distance = sim.medium().delivery_by_distance();
    let hist = sim.medium().latency_histogram();
    let gossip = gossip_summary(desc, snaps);
    Some(CommSummary {
        attenuation_per_m: desc.attenuation,
        cutoff_range_m: sim.medium().r_cut,
        frames_sent: sent,
        queue_overflow: snaps.iter().map(|s| s.comm.queue_overflow).sum(),
        oversize: snaps.iter().map(|s| s.comm.oversize).sum(),
        cs_deferrals: snaps.iter().map(|s| s.comm.cs_deferrals).sum(),
        delivery_ratio: if rx.attempts > 0 {
            rx.delivered as f64 / rx.attempts as f64
        } else {
            0.0
        },
        latency_mean_s: (rx.delivered > 0).then(|| rx.latency_sum_s / rx.delivered as f64),
        latency_median_s: percentile(&hist, 0.5),
        latency_p95_s: percentile(&hist, 0.95),
        mean_frame_bits: sim.medium().started.1 as f64 / sim.medium().started.0.max(1) as f64,
        receptions: rx,
        by_distance: by_distance
            .iter()
            .enumerate()
            .filter(|(_, b)| b.0 > 0)
            .map(|(k, b)| DistanceBin {
                from_m: k as f64 * DIST_BIN,
                to_m: (k + 1) as f64 * DIST_BIN,
                attempts: b.0,
                delivered: b.1,
                ratio: b.1 as f64 / b.0 as f64,
            })
            .collect(),
        connectivity: sim.connectivity().samples.clone(),
        gossip,
        vehicles: snaps
            .iter()
            .map(|s| VehicleComm {
                name: s.name.to_string(),
                sent: s.comm.sent,
                queue_overflow: s.comm.queue_overflow,
                rx: s.comm.rx,
            })
            .collect(),
    })
}

fn gossip_summary(desc: &WorldDesc, snaps: &[VehicleView<'_>]) -> Option<GossipSummary> {
    let members: Vec<&VehicleView<'_>> = snaps
        .iter()
        .zip(&desc.vehicles)
        .filter(|(_, d)| matches!(d.behaviour, Some(BehaviourSpec::Gossip { .. })))
        .map(|(s, _)| s)
        .collect();
    if members.is_empty() {
        return None;
    }
    let get = |s: &VehicleView<'_>, k: &str| {
        s.behaviour()
            .iter()
            .find(|(n, _)| *n == k)
            .map_or(f64::NAN, |(_, v)| *v)
    };
    let start = desc
        .vehicles
        .iter()
        .find_map(|d| match d.behaviour {
            Some(BehaviourSpec::Gossip {
                origin: true,
                start,
                ..
            }) => Some(start),
            _ => None,
        })
        .unwrap_or(f64::NAN);
    let mut learned: Vec<(f64, f64)> = members
        .iter()
        .map(|s| (get(s, "learned_at"), get(s, "hops")))
        .filter(|(t, _)| t.is_finite())
        .collect();
    learned.sort_by(|a, b| a.0.total_cmp(&b.0));
    let n = members.len();
    let informed = learned.len();
    Some(GossipSummary {
        vehicles: n,
        informed,
        start_s: start,
        time_to_all_s: (informed == n).then(|| learned.last().map_or(0.0, |l| l.0) - start),
        time_to_half_s: learned
            .get(n.div_ceil(2).saturating_sub(1))
            .filter(|_| 2 * informed >= n)
            .map(|l| l.0 - start),
        max_hops: learned.iter().map(|l| l.1 as u32).max().unwrap_or(0),
        mean_hops: if informed > 0 {
            learned.iter().map(|l| l.1).sum::<f64>() / informed as f64
        } else {
            f64::NAN
        },
        mean_time_per_hop_s: {
            let per: Vec<f64> = learned
                .iter()
                .filter(|l| l.1 > 0.0)
                .map(|l| (l.0 - start) / l.1)
                .collect();
            if per.is_empty() {
                f64::NAN
            } else {
                per.iter().sum::<f64>() / per.len() as f64
            }
        },
        informed_over_time: learned
            .iter()
            .enumerate()
            .map(|(i, l)| (l.0, i + 1))
            .collect(),
    })
}

/// Most vehicles for which `link_pairs.csv` is written (it has up to one row per pair of
/// vehicles within range: ≈ 40 per vehicle in a dense beaconing swarm).
pub const PAIRS_MAX_VEHICLES: usize = 10_000;

/// The communication tables of a run with `vehicles` vehicles, in the order
/// [`write_tables`] writes them.
pub fn table_names(vehicles: usize) -> Vec<&'static str> {
    let mut t = vec!["links.csv", "connectivity.csv"];
    if vehicles <= PAIRS_MAX_VEHICLES {
        t.push("link_pairs.csv");
    }
    t
}

/// Writes the communication tables into `dir` (each whole, through [`shoal_output::files`]),
/// calling `begin` with each one's name before it begins it and adding each to `written`
/// when complete: `links.csv` (per second of the run: reception
/// attempts by outcome), `connectivity.csv` (per second: the communication graph) and, for
/// up to [`PAIRS_MAX_VEHICLES`] vehicles, `link_pairs.csv` (per sender → receiver).
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
    Ok(())
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
            n(Outcome::Collision).to_string(),
            n(Outcome::Occluded).to_string(),
            n(Outcome::Range).to_string(),
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
