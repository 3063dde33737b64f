//! The run's summary: what happened to each vehicle ([`VehicleSummary`], a row of
//! `vehicles.csv`) and group ([`GroupSummary`]), and the whole run ([`Summary`]: written as
//! `summary.json`, printed by [`Summary::to_text`] at the end of a run).

use super::accumulated::VehicleAcc;
use serde::Serialize;
use shoal_model::math::wrap_pi;
use shoal_model::prelude::*;
use shoal_output::words::{count, factor};
use shoal_sim::parallel::Dispatches;
use shoal_sim::phases::{ByPhase, RunPhases};
use shoal_sim::sim::Sim;
use shoal_sim::view::VehicleView;
use shoal_world::cancel::Cause;
use shoal_world::desc::WorldDesc;

/// What happened to one vehicle (a row of `vehicles.csv`).
#[derive(Clone, Debug, Serialize)]
pub struct VehicleSummary {
    /// Name.
    pub name: String,
    /// Group name.
    pub group: String,
    /// Final mode.
    pub mode: String,
    /// Final position, world frame \[m\].
    pub final_position_m: [f64; 3],
    /// Final heading \[deg\].
    pub final_yaw_deg: f64,
    /// Final depth reading \[m\].
    pub final_depth_reading_m: f64,
    /// Final depth setpoint minus reading \[m\].
    pub depth_error_m: f64,
    /// Final heading setpoint minus heading, wrapped \[deg\].
    pub yaw_error_deg: f64,
    /// Path length over the recorded samples \[m\].
    pub distance_m: f64,
    /// Deepest body-origin depth \[m\].
    pub max_depth_m: f64,
    /// Largest speed through the water [m/s].
    pub max_speed_m_s: f64,
    /// Impacts with walls, floor or obstacles.
    pub impacts: u64,
    /// Steps spent in contact.
    pub steps_in_contact: u64,
    /// Final ballast water \[ml\].
    pub ballast_ml: f64,
}

/// Aggregates of one vehicle group.
#[derive(Clone, Debug, Serialize)]
pub struct GroupSummary {
    /// Group name.
    pub name: String,
    /// Vehicles.
    pub count: usize,
    /// Final mode of its first vehicle.
    pub mode: String,
    /// Mean |final depth error| \[m\].
    pub mean_abs_depth_error_m: f64,
    /// Mean |final heading error| \[deg\].
    pub mean_abs_yaw_error_deg: f64,
    /// Mean path length \[m\].
    pub mean_distance_m: f64,
    /// Total impacts.
    pub impacts: u64,
}

/// The machine-readable end-of-run summary (`summary.json`).
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// World name.
    pub world: String,
    /// World file.
    pub source: String,
    /// World seed.
    pub seed: u64,
    /// Vehicles.
    pub vehicles: usize,
    /// Working threads.
    pub threads: usize,
    /// The loops split over the thread pool, per kind (all zero on one thread and for loops
    /// under [`shoal_sim::parallel::MIN_PARALLEL`] vehicles): proof that a run took the parallel
    /// path.
    pub parallel_dispatches: Dispatches,
    /// Where the wall time went, by phase of the step and the writing of rows during the run
    /// \[s\] (the step's phases are zero when the world was not timed,
    /// [`Sim::time_phases`]).
    pub phases_s: RunPhases,
    /// Physics step \[s\].
    pub dt_s: f64,
    /// Steps run.
    pub steps: u64,
    /// Simulated time \[s\].
    pub simulated_s: f64,
    /// Planned duration \[s\].
    pub planned_s: f64,
    /// Wall-clock time \[s\].
    pub wall_s: f64,
    /// Simulated seconds per wall-clock second.
    pub real_time_factor: f64,
    /// The process's peak resident memory when the summary was made (after the world ran and
    /// the end-of-run tables were gathered) \[bytes\]; absent where the system does not say
    /// (it is read from `/proc/self/status`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_memory_bytes: Option<u64>,
    /// Stopped early by a stop request (Ctrl-C, SIGTERM, SIGHUP): the run, or — when
    /// `simulated_s` equals `planned_s` — the writing of its plots (`files` lists what exists).
    pub interrupted: bool,
    /// Ended early because a vehicle's state stopped being finite: which, when, and its last
    /// finite state ([`shoal_sim::fault::SimFault`]); results after that step are not physical.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failed: Option<String>,
    /// What asked for the stop, e.g. `SIGTERM` (absent when not interrupted).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub signal: Option<String>,
    /// The write error that cut the outputs short, naming the file (absent when all were
    /// written).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub output_error: Option<String>,
    /// State digest (hex); equal digests mean bit-identical runs.
    pub digest: String,
    /// Rows written to trajectories.csv.
    pub trajectory_rows: u64,
    /// Per group.
    pub groups: Vec<GroupSummary>,
    /// Per vehicle; written to `vehicles.csv`, not to summary.json (which stays small for
    /// any vehicle count).
    #[serde(skip)]
    pub vehicle_details: Vec<VehicleSummary>,
    /// Files written.
    pub files: Vec<String>,
    /// Optical communication (absent when no frame was sent).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub comm: Option<crate::comm_report::CommSummary>,
    /// External agents (absent when no vehicle has one).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub agents: Option<shoal_sim::agents::AgentsSummary>,
    /// What `run.mcap` holds and what its size budget left out (absent when it was not
    /// asked for, or could not be finished).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mcap: Option<crate::mcap::McapSummary>,
}

impl Summary {
    pub(super) fn new(
        desc: &WorldDesc,
        sim: &Sim,
        snaps: &[VehicleView<'_>],
        acc: &[VehicleAcc],
        wall_s: f64,
        interrupted: Option<Cause>,
    ) -> Self {
        let details: Vec<VehicleSummary> = snaps
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let r = &s.state.rigid;
                let (_, _, yaw) = r.attitude.euler_angles();
                let a = acc.get(i).cloned().unwrap_or_default();
                let uses_depth = !matches!(
                    s.setpoints.mode,
                    Mode::Turning | Mode::Drift | Mode::Off | Mode::Raw
                );
                let uses_yaw = matches!(s.setpoints.mode, Mode::Turning | Mode::Drift | Mode::Auto);
                VehicleSummary {
                    name: s.name.to_string(),
                    group: desc.groups[desc.vehicles[i].group].clone(),
                    mode: s.setpoints.mode.name().into(),
                    final_position_m: [r.position.x, r.position.y, r.position.z],
                    final_yaw_deg: yaw.to_degrees(),
                    final_depth_reading_m: s.sensors.depth,
                    depth_error_m: if uses_depth {
                        s.setpoints.depth - s.sensors.depth
                    } else {
                        f64::NAN
                    },
                    yaw_error_deg: if uses_yaw {
                        wrap_pi(s.setpoints.yaw - yaw).to_degrees()
                    } else {
                        f64::NAN
                    },
                    distance_m: a.distance,
                    max_depth_m: a.max_depth,
                    max_speed_m_s: a.max_speed,
                    impacts: s.contacts.impacts,
                    steps_in_contact: s.contacts.steps_in_contact,
                    ballast_ml: s.state.ballast_volume * 1e6,
                }
            })
            .collect();
        let groups = desc
            .groups
            .iter()
            .enumerate()
            .map(|(g, name)| {
                let members: Vec<&VehicleSummary> = details
                    .iter()
                    .enumerate()
                    .filter(|(i, _)| desc.vehicles[*i].group == g)
                    .map(|(_, d)| d)
                    .collect();
                let mean = |f: &dyn Fn(&VehicleSummary) -> f64| {
                    let vals: Vec<f64> = members
                        .iter()
                        .map(|d| f(d))
                        .filter(|x| x.is_finite())
                        .collect();
                    if vals.is_empty() {
                        f64::NAN
                    } else {
                        vals.iter().sum::<f64>() / vals.len() as f64
                    }
                };
                GroupSummary {
                    name: name.clone(),
                    count: members.len(),
                    mode: members.first().map(|d| d.mode.clone()).unwrap_or_default(),
                    mean_abs_depth_error_m: mean(&|d| d.depth_error_m.abs()),
                    mean_abs_yaw_error_deg: mean(&|d| d.yaw_error_deg.abs()),
                    mean_distance_m: mean(&|d| d.distance_m),
                    impacts: members.iter().map(|d| d.impacts).sum(),
                }
            })
            .collect();
        let simulated = sim.time();
        Summary {
            world: desc.name.clone(),
            source: desc.source.display().to_string(),
            seed: desc.seed,
            vehicles: snaps.len(),
            threads: sim.threads(),
            parallel_dispatches: sim.parallel_dispatches(),
            phases_s: RunPhases {
                steps: ByPhase(sim.phase_times().seconds),
                outputs: 0.0,
            },
            dt_s: desc.dt,
            steps: sim.step_count(),
            simulated_s: simulated,
            planned_s: desc.duration,
            wall_s,
            real_time_factor: if wall_s > 0.0 {
                simulated / wall_s
            } else {
                f64::INFINITY
            },
            peak_memory_bytes: peak_memory_bytes(),
            interrupted: interrupted.is_some(),
            failed: sim.fault().map(|f| f.to_string()),
            signal: interrupted.map(|c| c.name.to_string()),
            output_error: None,
            digest: format!("{:016x}", sim.digest()),
            trajectory_rows: 0,
            groups,
            vehicle_details: details,
            files: Vec::new(),
            comm: None,
            agents: None,
            mcap: None,
        }
    }

    /// The report printed at the end of a run.
    pub fn to_text(&self) -> String {
        let mut s = String::new();
        let status = match (&self.failed, &self.signal, self.interrupted) {
            (Some(_), _, _) => "FAILED after".into(),
            (None, Some(sig), true) => format!("INTERRUPTED ({sig}) after"),
            (None, None, true) => "INTERRUPTED after".into(),
            (None, _, false) => "simulated".into(),
        };
        s.push_str(&format!(
            "{}: {}, {status} {:.1} s of {:.1} s in {:.2} s wall time ({}× real time, {})\n",
            self.world,
            count(self.vehicles, "vehicle"),
            self.simulated_s,
            self.planned_s,
            self.wall_s,
            factor(self.real_time_factor),
            count(self.threads, "thread"),
        ));
        if let Some(b) = self.peak_memory_bytes {
            let b = b as f64;
            let size = if b >= 1e9 {
                format!("{:.2} GB", b / 1e9)
            } else {
                format!("{:.0} MB", b / 1e6)
            };
            // Per vehicle once the vehicles dominate the process's fixed part.
            let each = if self.vehicles >= 10_000 {
                format!(" ({:.1} KB per vehicle)", b / 1024.0 / self.vehicles as f64)
            } else {
                String::new()
            };
            s.push_str(&format!("peak memory {size}{each}\n"));
        }
        s.push('\n');
        if let Some(f) = &self.failed {
            s.push_str(&format!("FAILED: {f}\n\n"));
        }
        s.push_str(&format!(
            "{:<16} {:>5}  {:<9} {:>14} {:>16} {:>13} {:>8}\n",
            "group", "count", "mode", "|depth err| m", "|heading err| °", "distance m", "impacts"
        ));
        let opt = |x: f64, p: usize| {
            if x.is_finite() {
                format!("{x:.p$}")
            } else {
                "—".into()
            }
        };
        for g in &self.groups {
            s.push_str(&format!(
                "{:<16} {:>5}  {:<9} {:>14} {:>16} {:>13} {:>8}\n",
                g.name,
                g.count,
                g.mode,
                opt(g.mean_abs_depth_error_m, 4),
                opt(g.mean_abs_yaw_error_deg, 1),
                opt(g.mean_distance_m, 2),
                g.impacts
            ));
        }
        if let Some(c) = &self.comm {
            let r = &c.receptions;
            let pct = |x: u64| {
                if r.attempts > 0 {
                    100.0 * x as f64 / r.attempts as f64
                } else {
                    0.0
                }
            };
            s.push_str(&format!(
                "\noptical link: {} frames sent; {} of {} receptions in range delivered ({:.1} %)\n  lost: {:.1} % range/angle/bit errors, {:.1} % occlusion, {:.1} % collision, {:.1} % half-duplex; {} queue overflows\n",
                c.frames_sent,
                r.delivered,
                r.attempts,
                pct(r.delivered),
                pct(r.lost_range),
                pct(r.lost_occlusion),
                pct(r.lost_collision),
                pct(r.lost_half_duplex),
                c.queue_overflow
            ));
            if let (Some(m), Some(p)) = (c.latency_median_s, c.latency_p95_s) {
                s.push_str(&format!(
                    "  latency: median ≈ {:.0} ms, 95 % ≈ {:.0} ms (hand-over to delivery)\n",
                    m * 1e3,
                    p * 1e3
                ));
            }
            if let Some(l) = &c.link_layer {
                let ms = |x: Option<f64>| x.map_or("—".into(), |v| format!("{:.0}", v * 1e3));
                s.push_str(&format!(
                    "  link layer: {} unicasts acknowledged, {} given up ({:.1} % delivered after retries); {} retransmissions, {} acknowledgements sent; latency to acknowledgement p50/p95/p99 ≈ {}/{}/{} ms\n",
                    l.acknowledged,
                    l.gave_up,
                    100.0 * l.delivery_after_retries,
                    l.retransmissions,
                    l.acks_sent,
                    ms(l.latency_p50_s),
                    ms(l.latency_p95_s),
                    ms(l.latency_p99_s)
                ));
                if let Some(w) = &l.least_delivered {
                    s.push_str(&format!(
                        "  flows: {} unicast flows (flows.csv); the least delivered {} → {}: {} of {} frames taken ({:.1} %), {} acknowledged, {} given up; {:.0} bit/s of goodput\n",
                        l.flows_total,
                        w.from,
                        w.to,
                        w.delivered,
                        w.offered,
                        100.0 * w.delivery_ratio,
                        w.acknowledged,
                        w.gave_up,
                        w.goodput_bps
                    ));
                }
            }
            s.push_str(&format!(
                "  LEDs on {:.1} s in all, {:.3} J of light\n",
                c.led_on_s, c.led_energy_j
            ));
            if let (Some(last), Some(max)) = (
                c.connectivity.last(),
                c.connectivity.iter().map(|s| s.largest).max(),
            ) {
                s.push_str(&format!(
                    "  largest group in optical contact (a frame either way within 2 s): {} of {} at most, {} at the end\n",
                    max, self.vehicles, last.largest
                ));
            }
            if let Some(g) = &c.gossip {
                match g.time_to_all_s {
                    Some(t) => s.push_str(&format!(
                        "  gossip: the value reached all {} vehicles {:.2} s after it appeared (half after {:.2} s; up to {} hops, mean {:.1}; {:.0} ms per hop)\n",
                        g.vehicles, t, g.time_to_half_s.unwrap_or(f64::NAN), g.max_hops, g.mean_hops, g.mean_time_per_hop_s * 1e3
                    )),
                    None => s.push_str(&format!("  gossip: the value reached {} of {} vehicles\n", g.informed, g.vehicles)),
                }
            }
        }
        if let Some(a) = &self.agents {
            s.push_str(&format!(
                "\nagents ({}, prefix `{}`, fallback {}):\n",
                a.timing, a.prefix, a.fallback
            ));
            for r in &a.agents {
                let rt = &r.round_trip;
                s.push_str(&format!(
                    "  {:<12} {} vehicle(s), {} commands applied, {} rejected or clamped, {} vehicle-ticks in fallback{}\n",
                    r.name,
                    r.vehicles,
                    r.commands_applied,
                    r.rejections.total(),
                    r.fallback_ticks,
                    if rt.count > 0 {
                        format!("; round trip median {:.0} µs, 99 % {:.0} µs", rt.median_us, rt.p99_us)
                    } else {
                        String::new()
                    }
                ));
                const SHOWN: usize = 12;
                for e in r.events.iter().take(SHOWN) {
                    s.push_str(&format!(
                        "    t = {:>8.2} s  {:<10} {}\n",
                        e.t, e.what, e.detail
                    ));
                }
                let more = r.events.len().saturating_sub(SHOWN) as u64 + r.events_omitted;
                if more > 0 {
                    s.push_str(&format!("    … and {more} more events (summary.json)\n"));
                }
                if r.events.is_empty() {
                    s.push_str("    never attached: its vehicles held depth and heading\n");
                }
            }
            if let Some(why) = &a.stopped {
                s.push_str(&format!("  STOPPED: {why}\n"));
            }
        }
        s.push_str(&format!(
            "\ndigest {}  ·  {} trajectory rows\n",
            self.digest, self.trajectory_rows
        ));
        if let Some(m) = &self.mcap {
            s.push_str(&format!(
                "run.mcap: {} messages, {:.1} MB ({:.1} MB of messages before compression){}\n",
                m.messages,
                m.bytes as f64 / 1e6,
                m.message_bytes as f64 / 1e6,
                m.dropped().map(|d| format!("; {d}")).unwrap_or_default()
            ));
        }
        if !self.files.is_empty() {
            s.push_str("wrote:\n");
            for f in &self.files {
                s.push_str(&format!("  {f}\n"));
            }
        }
        s
    }
}

/// Peak resident memory of this process (`VmHWM` of `/proc/self/status`) \[bytes\].
pub fn peak_memory_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let kb: u64 = status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))?
        .split_whitespace()
        .next()?
        .parse()
        .ok()?;
    Some(kb * 1024)
}
