//! The communication section of `summary.json` ([`CommSummary`], built by [`summarize`]):
//! frames and receptions by outcome, latency, delivery ratio against distance, the
//! communication graph over time, the result of flooding a value, and each vehicle's counters
//! (for `vehicles.csv`).

use serde::Serialize;
use shoal_sim::comm::{DIST_BIN, LinkStats, latency_percentile};
use shoal_sim::connectivity::ConnSample;
use shoal_sim::sim::Sim;
use shoal_sim::view::VehicleView;
use shoal_world::desc::WorldDesc;
use shoal_world::spec::BehaviourSpec;

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
    /// The link layer: acknowledged unicasts and what became of them (`None` when no frame
    /// asked for an acknowledgement).
    pub link_layer: Option<LinkLayerSummary>,
    /// Time the LEDs were on, all modems of all vehicles \[s\].
    pub led_on_s: f64,
    /// Optical energy the LEDs sent \[J\].
    pub led_energy_j: f64,
    /// Per vehicle.
    /// (written to `vehicles.csv`, not to summary.json, which stays small for any count)
    #[serde(skip)]
    pub vehicles: Vec<VehicleComm>,
}

/// The `q` quantile of a dense latency histogram \[s\] (see [`latency_percentile`]).
fn percentile(hist: &[u64], q: f64) -> Option<f64> {
    latency_percentile(hist.iter().copied().enumerate(), q)
}

/// Unicast frames sent with acknowledgement, whole world.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LinkLayerSummary {
    /// Frames acknowledged.
    pub acknowledged: u64,
    /// Frames given up after their last retransmission (or refused at a full queue).
    pub gave_up: u64,
    /// acknowledged / (acknowledged + gave_up).
    pub delivery_after_retries: f64,
    /// Retransmissions.
    pub retransmissions: u64,
    /// Acknowledgement frames sent.
    pub acks_sent: u64,
    /// Median, 95th and 99th percentile of the hand-over-to-acknowledgement latency \[s\]
    /// (centres of histogram bins: ±6 %).
    pub latency_p50_s: Option<f64>,
    /// 95th percentile \[s\].
    pub latency_p95_s: Option<f64>,
    /// 99th percentile \[s\].
    pub latency_p99_s: Option<f64>,
    /// Unicast flows (sender → destination), all of them.
    pub flows_total: usize,
    /// The flow whose destination took the smallest share of what was offered, of all flows
    /// (among equals the one with the fewest acknowledged; then the first by sender and
    /// destination id).
    pub least_delivered: Option<FlowSummary>,
    /// The first [`FLOWS_IN_SUMMARY`] flows by sender and destination id (every flow is in
    /// `flows.csv`).
    pub flows: Vec<FlowSummary>,
}

/// Most flows listed in summary.json (which stays small for any count).
pub const FLOWS_IN_SUMMARY: usize = 100;

/// One unicast flow, sender → destination, over the whole run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FlowSummary {
    /// Sender's name.
    pub from: String,
    /// Destination's name.
    pub to: String,
    /// Frames handed over for the destination.
    pub offered: u64,
    /// Frames the destination took (each once).
    pub delivered: u64,
    /// delivered / offered.
    pub delivery_ratio: f64,
    /// Offered payload per second of the run [bit/s].
    pub offered_bps: f64,
    /// Delivered payload per second of the run (goodput) [bit/s].
    pub goodput_bps: f64,
    /// Frames acknowledged.
    pub acknowledged: u64,
    /// Frames given up.
    pub gave_up: u64,
    /// acknowledged / (acknowledged + gave_up), if any frame asked for acknowledgement.
    pub delivery_after_retries: Option<f64>,
    /// Retransmissions.
    pub retransmissions: u64,
    /// Hand-over → acknowledgement, median \[s\] (bin centre, ±6 %).
    pub latency_p50_s: Option<f64>,
    /// 95th percentile \[s\].
    pub latency_p95_s: Option<f64>,
    /// 99th percentile \[s\].
    pub latency_p99_s: Option<f64>,
    /// LED time of its frames and their acknowledgements \[s\].
    pub led_on_s: f64,
    /// Their optical energy \[J\].
    pub led_energy_j: f64,
}

/// Every unicast flow of the run, by sender and destination id, with the vehicles' names
/// (`snaps`, in id order), over `duration` \[s\].
pub fn flow_summaries(sim: &Sim, snaps: &[VehicleView<'_>], duration: f64) -> Vec<FlowSummary> {
    let name = |id: u32| {
        snaps
            .get(id as usize)
            .filter(|s| s.id == id)
            .map_or_else(|| id.to_string(), |s| s.name.to_string())
    };
    let per_s = |bytes: u64| 8.0 * bytes as f64 / duration.max(f64::MIN_POSITIVE);
    sim.medium()
        .flows()
        .iter()
        .map(|(&(from, to), f)| FlowSummary {
            from: name(from),
            to: name(to),
            offered: f.offered,
            delivered: f.delivered,
            delivery_ratio: f.delivered as f64 / f.offered.max(1) as f64,
            offered_bps: per_s(f.offered_bytes),
            goodput_bps: per_s(f.delivered_bytes),
            acknowledged: f.acknowledged,
            gave_up: f.gave_up,
            delivery_after_retries: f.delivery_after_retries(),
            retransmissions: f.retransmissions,
            latency_p50_s: f.latency_quantile(0.5),
            latency_p95_s: f.latency_quantile(0.95),
            latency_p99_s: f.latency_quantile(0.99),
            led_on_s: f.led_on_s,
            led_energy_j: f.led_energy_j,
        })
        .collect()
}

/// The link-layer section: `None` when no unicast frame was handed over and no frame asked
/// for an acknowledgement.
fn link_layer(sim: &Sim, snaps: &[VehicleView<'_>]) -> Option<LinkLayerSummary> {
    let hist = sim.medium().ack_latency_histogram();
    let acknowledged: u64 = hist.iter().sum();
    let gave_up: u64 = snaps.iter().map(|s| s.comm.gave_up).sum();
    let acks_sent: u64 = snaps.iter().map(|s| s.comm.acks_sent).sum();
    if acknowledged + gave_up + acks_sent == 0 && sim.medium().flows().is_empty() {
        return None;
    }
    let mut flows = flow_summaries(sim, snaps, sim.time());
    let flows_total = flows.len();
    let least_delivered = (flows.iter())
        .filter(|f| f.offered > 0)
        .min_by(|a, b| {
            let after = |f: &FlowSummary| f.delivery_after_retries.unwrap_or(1.0);
            (a.delivery_ratio.total_cmp(&b.delivery_ratio)).then(after(a).total_cmp(&after(b)))
        })
        .cloned();
    flows.truncate(FLOWS_IN_SUMMARY);
    Some(LinkLayerSummary {
        acknowledged,
        gave_up,
        delivery_after_retries: acknowledged as f64 / (acknowledged + gave_up).max(1) as f64,
        retransmissions: snaps.iter().map(|s| s.comm.retransmissions).sum(),
        acks_sent,
        latency_p50_s: percentile(hist, 0.5),
        latency_p95_s: percentile(hist, 0.95),
        latency_p99_s: percentile(hist, 0.99),
        flows_total,
        least_delivered,
        flows,
    })
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
        link_layer: link_layer(sim, snaps),
        led_on_s: snaps.iter().map(|s| s.comm.led_on_s).sum(),
        led_energy_j: snaps.iter().map(|s| s.comm.led_energy_j).sum(),
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
        .filter(|(_, d)| {
            matches!(
                d.behaviour,
                Some(BehaviourSpec::Gossip { .. } | BehaviourSpec::ReliableGossip { .. })
            )
        })
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
            Some(
                BehaviourSpec::Gossip {
                    origin: true,
                    start,
                    ..
                }
                | BehaviourSpec::ReliableGossip {
                    origin: true,
                    start,
                    ..
                },
            ) => Some(start),
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
