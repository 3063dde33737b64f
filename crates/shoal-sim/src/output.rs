//! Run outputs: `trajectories.csv` streamed batch by batch (time-major, one row per vehicle and
//! sample, units in the column names), `summary.json`, and plots (`depth.png/svg`: depth of
//! every vehicle against time with its setpoint; `top.png/svg`: tracks seen from above with
//! the pool and obstacles). [`Summary::to_text`] is the end-of-run report for people.

use crate::plot::{Outline, Plot, PlotError, Series};
use crate::recorder::{self, RecordBatch, col, mode_of_code};
use crate::sim::{Sim, VehicleSnapshot};
use serde::Serialize;
use shoal_model::math::wrap_pi;
use shoal_model::prelude::*;
use shoal_world::desc::WorldDesc;
use std::collections::HashMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// An output failure (names the file).
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// Filesystem error.
    #[error("{path}: {source}")]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// CSV error.
    #[error("{path}: {source}")]
    Csv {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: csv::Error,
    },
    /// Plot error.
    #[error(transparent)]
    Plot(#[from] PlotError),
}

/// Most points kept per vehicle for plots.
const PLOT_POINTS: usize = 1500;
/// Most vehicles drawn in a plot.
const PLOT_VEHICLES: usize = 200;

#[derive(Clone, Debug, Default)]
struct VehicleAcc {
    rows: u64,
    last: Vec<f64>,
    distance: f64,
    max_depth: f64,
    max_speed: f64,
    plot: Vec<(f64, f64, f64, f64, f64)>, // t, x, y, depth reading, depth setpoint
}

/// Streams a run's outputs into a folder.
pub struct RunOutput {
    dir: PathBuf,
    csv_path: PathBuf,
    csv: csv::Writer<BufWriter<File>>,
    /// Per vehicle: where each of its row values goes in the CSV record.
    maps: Vec<Vec<usize>>,
    width: usize,
    names: Vec<String>,
    acc: Vec<VehicleAcc>,
    keep_every: u64,
    plots: bool,
    csv_rows: u64,
    /// External agents' part of the summary (set by the run driver before `finish`).
    pub agents: Option<crate::agents::AgentsSummary>,
}

impl RunOutput {
    /// Creates `dir` (and parents) and opens `trajectories.csv`.
    pub fn create(dir: &Path, desc: &WorldDesc) -> Result<Self, OutputError> {
        std::fs::create_dir_all(dir).map_err(|source| OutputError::Io {
            path: dir.to_path_buf(),
            source,
        })?;
        let csv_path = dir.join("trajectories.csv");
        let file = File::create(&csv_path).map_err(|source| OutputError::Io {
            path: csv_path.clone(),
            source,
        })?;
        let mut csv = csv::Writer::from_writer(BufWriter::new(file));
        // Header: t, vehicle, the fixed columns, then the union of actuator columns.
        let mut header: Vec<String> = vec!["t_s".into(), "vehicle".into()];
        header.extend(recorder::FIXED[1..].iter().map(|s| s.to_string()));
        let mut extra: Vec<String> = Vec::new();
        let mut maps = Vec::with_capacity(desc.vehicles.len());
        let mut by_kind: HashMap<*const VehicleModel, Vec<usize>> = HashMap::new();
        for v in &desc.vehicles {
            let key = std::sync::Arc::as_ptr(&v.model);
            let map = by_kind
                .entry(key)
                .or_insert_with(|| {
                    let mut m: Vec<usize> = vec![0];
                    m.extend(2..recorder::FIXED.len() + 1);
                    for c in recorder::columns(&v.model)
                        .into_iter()
                        .skip(recorder::FIXED.len())
                    {
                        let k = match extra.iter().position(|e| *e == c) {
                            Some(k) => k,
                            None => {
                                extra.push(c);
                                extra.len() - 1
                            }
                        };
                        m.push(recorder::FIXED.len() + 1 + k);
                    }
                    m
                })
                .clone();
            maps.push(map);
        }
        header.extend(extra);
        let width = header.len();
        csv.write_record(&header)
            .map_err(|source| OutputError::Csv {
                path: csv_path.clone(),
                source,
            })?;
        let expected_rows = (desc.duration * desc.output.record_hz).max(1.0) as u64;
        Ok(Self {
            dir: dir.to_path_buf(),
            csv_path,
            csv,
            maps,
            width,
            names: desc.vehicles.iter().map(|v| v.name.clone()).collect(),
            acc: vec![VehicleAcc::default(); desc.vehicles.len()],
            keep_every: expected_rows.div_ceil(PLOT_POINTS as u64).max(1),
            plots: desc.output.plots,
            csv_rows: 0,
            agents: None,
        })
    }

    /// The output folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Writes a batch of rows (time-major) and updates the statistics.
    pub fn write(&mut self, batch: &RecordBatch) -> Result<(), OutputError> {
        let strides: Vec<usize> = (0..batch.rows.len()).map(|i| self.maps[i].len()).collect();
        let n = batch
            .rows
            .iter()
            .zip(&strides)
            .map(|(r, s)| r.len() / s)
            .max()
            .unwrap_or(0);
        let mut rec = vec![String::new(); self.width];
        for k in 0..n {
            for (i, rows) in batch.rows.iter().enumerate() {
                let s = strides[i];
                let Some(row) = rows.get(k * s..(k + 1) * s) else {
                    continue;
                };
                rec.iter_mut().for_each(|c| c.clear());
                for (j, x) in row.iter().enumerate() {
                    let target = self.maps[i][j];
                    rec[target] = if j == col::MODE {
                        mode_of_code(*x).name().to_string()
                    } else {
                        format_num(*x)
                    };
                }
                rec[1].clone_from(&self.names[i]);
                self.csv
                    .write_record(&rec)
                    .map_err(|source| OutputError::Csv {
                        path: self.csv_path.clone(),
                        source,
                    })?;
                self.csv_rows += 1;
                self.accumulate(i, row);
            }
        }
        Ok(())
    }

    fn accumulate(&mut self, i: usize, row: &[f64]) {
        let keep = self.acc[i].rows.is_multiple_of(self.keep_every);
        let a = &mut self.acc[i];
        if let Some(last) = (!a.last.is_empty()).then_some(&a.last) {
            let d = ((row[col::X] - last[col::X]).powi(2)
                + (row[col::Y] - last[col::Y]).powi(2)
                + (row[col::Z] - last[col::Z]).powi(2))
            .sqrt();
            a.distance += d;
        }
        a.max_depth = a.max_depth.max(row[col::Z]);
        let speed = (row[col::U].powi(2) + row[col::U + 1].powi(2) + row[col::W].powi(2)).sqrt();
        a.max_speed = a.max_speed.max(speed);
        if keep {
            a.plot.push((
                row[col::T],
                row[col::X],
                row[col::Y],
                row[col::DEPTH_READING],
                row[col::DEPTH_SP],
            ));
        }
        a.rows += 1;
        a.last.clear();
        a.last.extend_from_slice(row);
    }

    /// Flushes the CSV, writes `summary.json` and the plots, and returns the summary.
    pub fn finish(
        mut self,
        desc: &WorldDesc,
        sim: &Sim,
        wall_s: f64,
        interrupted: bool,
    ) -> Result<Summary, OutputError> {
        self.csv.flush().map_err(|source| OutputError::Io {
            path: self.csv_path.clone(),
            source,
        })?;
        let mut files = vec![self.csv_path.clone()];
        let snaps = sim.vehicles();
        let comm = crate::comm_report::summarize(desc, sim, &snaps);
        if let Some(c) = &comm {
            let links = self.dir.join("links.csv");
            crate::comm_report::write_links_csv(&links, &snaps).map_err(|source| {
                OutputError::Csv {
                    path: links.clone(),
                    source,
                }
            })?;
            files.push(links);
            if self.plots {
                files.extend(crate::comm_report::plots(&self.dir, desc, sim, &snaps, c)?);
            }
        }
        if self.plots {
            files.extend(self.depth_plot(desc)?);
            files.extend(self.top_plot(desc)?);
        }
        let json_path = self.dir.join("summary.json");
        files.push(json_path.clone());
        let mut summary = Summary::new(desc, sim, &snaps, &self.acc, wall_s, interrupted);
        summary.comm = comm;
        summary.agents = self.agents.take();
        summary.trajectory_rows = self.csv_rows;
        summary.files = files.iter().map(|p| p.display().to_string()).collect();
        let text = serde_json::to_string_pretty(&summary).unwrap_or_default();
        std::fs::write(&json_path, text).map_err(|source| OutputError::Io {
            path: json_path.clone(),
            source,
        })?;
        Ok(summary)
    }

    fn shown(&self) -> Vec<usize> {
        let n = self.acc.len();
        let step = n.div_ceil(PLOT_VEHICLES).max(1);
        (0..n).step_by(step).collect()
    }

    fn depth_plot(&self, desc: &WorldDesc) -> Result<Vec<PathBuf>, OutputError> {
        let shown = self.shown();
        let mut series = Vec::new();
        let mut labelled = vec![false; desc.groups.len()];
        for &i in &shown {
            let g = desc.vehicles[i].group;
            let a = &self.acc[i];
            series.push(Series {
                label: (!labelled[g]).then(|| desc.groups[g].clone()),
                points: a.plot.iter().map(|p| (p.0, p.3)).collect(),
                color: g,
                ..Default::default()
            });
            labelled[g] = true;
        }
        // One setpoint line per group.
        let mut done = vec![false; desc.groups.len()];
        for &i in &shown {
            let g = desc.vehicles[i].group;
            if !done[g] {
                done[g] = true;
                series.push(Series {
                    points: self.acc[i].plot.iter().map(|p| (p.0, p.4)).collect(),
                    color: g,
                    dashed: true,
                    ..Default::default()
                });
            }
        }
        let note = if shown.len() < self.acc.len() {
            format!(" ({} of {} vehicles)", shown.len(), self.acc.len())
        } else {
            String::new()
        };
        let plot = Plot {
            title: format!(
                "{}: depth reading (solid) and setpoint (dashed){note}",
                desc.name
            ),
            x_label: "time [s]".into(),
            y_label: "depth [m]".into(),
            series,
            y_down: true,
            x_range: Some((0.0, desc.duration)),
            ..Default::default()
        };
        Ok(plot.write(&self.dir.join("depth"))?)
    }

    fn top_plot(&self, desc: &WorldDesc) -> Result<Vec<PathBuf>, OutputError> {
        let pool = desc.geometry.pool;
        // Map view: east to the right, north up.
        let mut outlines = vec![Outline {
            points: vec![(0.0, 0.0), (pool.y, 0.0), (pool.y, pool.x), (0.0, pool.x)],
            filled: false,
        }];
        for ob in &desc.geometry.obstacles {
            let points = ob
                .top_outline(48)
                .into_iter()
                .map(|(x, y)| (y, x))
                .collect();
            outlines.push(Outline {
                points,
                filled: true,
            });
        }
        let mut labelled = vec![false; desc.groups.len()];
        let series = self
            .shown()
            .into_iter()
            .map(|i| {
                let g = desc.vehicles[i].group;
                let s = Series {
                    label: (!labelled[g]).then(|| desc.groups[g].clone()),
                    points: self.acc[i].plot.iter().map(|p| (p.2, p.1)).collect(),
                    color: g,
                    mark_start: true,
                    ..Default::default()
                };
                labelled[g] = true;
                s
            })
            .collect();
        let margin = 0.05 * pool.x.max(pool.y);
        let h = 700u32;
        let w = ((f64::from(h) - 60.0) * (pool.y + 2.0 * margin) / (pool.x + 2.0 * margin) + 80.0)
            .clamp(560.0, 1800.0) as u32;
        let plot = Plot {
            title: format!("{}: tracks from above (dot = start)", desc.name),
            x_label: "east y [m]".into(),
            y_label: "north x [m]".into(),
            series,
            outlines,
            x_range: Some((-margin, pool.y + margin)),
            y_range: Some((-margin, pool.x + margin)),
            size: (w, h),
            ..Default::default()
        };
        Ok(plot.write(&self.dir.join("top"))?)
    }
}

fn format_num(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if x == x.trunc() && x.abs() < 1e15 {
        format!("{x:.0}")
    } else {
        format!("{x:.6e}")
            .parse::<f64>()
            .map_or_else(|_| x.to_string(), |v| v.to_string())
    }
}

/// What happened to one vehicle.
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
    /// Ended early by Ctrl-C.
    pub interrupted: bool,
    /// Ended early because a vehicle's state stopped being finite: which, when, and its last
    /// finite state ([`crate::fault::SimFault`]); results after that step are not physical.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failed: Option<String>,
    /// State digest (hex); equal digests mean bit-identical runs.
    pub digest: String,
    /// Rows written to trajectories.csv.
    pub trajectory_rows: u64,
    /// Per group.
    pub groups: Vec<GroupSummary>,
    /// Per vehicle.
    pub vehicle_details: Vec<VehicleSummary>,
    /// Files written.
    pub files: Vec<String>,
    /// Optical communication (absent when no frame was sent).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub comm: Option<crate::comm_report::CommSummary>,
    /// External agents (absent when no vehicle has one).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub agents: Option<crate::agents::AgentsSummary>,
}

impl Summary {
    fn new(
        desc: &WorldDesc,
        sim: &Sim,
        snaps: &[VehicleSnapshot],
        acc: &[VehicleAcc],
        wall_s: f64,
        interrupted: bool,
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
                    name: s.name.clone(),
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
            interrupted,
            failed: sim.fault().map(|f| f.to_string()),
            digest: format!("{:016x}", sim.digest()),
            trajectory_rows: 0,
            groups,
            vehicle_details: details,
            files: Vec::new(),
            comm: None,
            agents: None,
        }
    }

    /// The report printed at the end of a run.
    pub fn to_text(&self) -> String {
        let mut s = String::new();
        let status = if self.failed.is_some() {
            "FAILED after"
        } else if self.interrupted {
            "INTERRUPTED after"
        } else {
            "simulated"
        };
        s.push_str(&format!(
            "{}: {} vehicles, {status} {:.1} s of {:.1} s in {:.2} s wall time ({:.1}× real time, {} thread{})\n\n",
            self.world,
            self.vehicles,
            self.simulated_s,
            self.planned_s,
            self.wall_s,
            self.real_time_factor,
            self.threads,
            if self.threads == 1 { "" } else { "s" }
        ));
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
        if !self.files.is_empty() {
            s.push_str("wrote:\n");
            for f in &self.files {
                s.push_str(&format!("  {f}\n"));
            }
        }
        s
    }
}
