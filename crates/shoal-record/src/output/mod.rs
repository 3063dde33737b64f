//! Run outputs: `trajectories.csv` streamed batch by batch (time-major, one row per vehicle and
//! sample, units in the column names), `run.mcap` (when the world asks for it: the run for
//! Foxglove and ROS 2 tools, streamed the same way, [`mcap`]), `summary.json` (small for any
//! vehicle count), `vehicles.csv` (one row per vehicle), and plots (`depth.png/svg`: depth of
//! every vehicle against time with its setpoint; `top.png/svg`: tracks seen from above with
//! the pool and obstacles; `heading.png/svg`; drawn by `plots`). [`Summary::to_text`] is the
//! end-of-run report for people.
//!
//! **Whole files only.** Every file goes through [`shoal_output::files`]: it is written under a
//! temporary name (`.<name>.tmp`) and renamed when complete. `trajectories.csv` is streamed
//! to `.trajectories.csv.tmp` while the world runs and renamed by [`RunOutput::finish`], so
//! under its real name it always ends with a whole row; if a write fails the temporary is
//! removed and the error names the file with the operating system's reason.
//!
//! **Order.** [`RunOutput::finish`] writes `summary.json` first, then the tables
//! (`trajectories.csv`, `vehicles.csv`, the communication tables), then `run.mcap` (when the
//! world asked for it; written during the run, committed here), then `replay.html` (when
//! the run driver set [`RunOutput::replay`]), then the plots, so when a later file fails (a full
//! disk, a file-size limit) the summary is already there. The first summary lists the files
//! the run is about to write; if fewer were written (a failure, or plots skipped after a stop
//! request) it is written again with the files that exist, the error and the stop request.

use crate::comm_report::VehicleComm;
use crate::mcap;
use accumulated::VehicleAcc;
use numbers::write_num;
use shoal_model::prelude::*;
use shoal_output::files::{CsvFile, FileError, write_whole};
use shoal_output::plot::{Plot, PlotError};
use shoal_sim::recorder::{self, RecordBatch, col, mode_of_code};
use shoal_sim::sim::Sim;
use shoal_sim::view::VehicleView;
use shoal_world::cancel::Cancel;
use shoal_world::desc::WorldDesc;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use vehicles_csv::write_vehicles_csv;

mod accumulated;

mod numbers;
mod plots;
mod summary;
mod vehicles_csv;

pub use summary::{GroupSummary, Summary, VehicleSummary, peak_memory_bytes};

/// An output failure (names the file).
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The output folder cannot be created.
    #[error("cannot create the folder {}: {reason}", path.display())]
    Folder {
        /// The folder.
        path: PathBuf,
        /// What the operating system said.
        reason: std::io::Error,
    },
    /// A file cannot be written.
    #[error(transparent)]
    File(#[from] FileError),
    /// A plot cannot be drawn or written.
    #[error(transparent)]
    Plot(#[from] PlotError),
}

/// Most points kept per vehicle for plots.
const PLOT_POINTS: usize = 1500;
/// Most vehicles drawn in a plot.
const PLOT_VEHICLES: usize = 200;

/// Streams a run's outputs into a folder. The run driver ([`crate::run::Run`]) makes one,
/// writes the recorded rows into it as the world runs and finishes it; it gives it what only
/// the driver knows (the agents' reports, the replay, the time spent writing) on the way.
pub struct RunOutput<'d> {
    desc: &'d WorldDesc,
    dir: PathBuf,
    csv: CsvFile,
    /// Per vehicle kind: where each of its row values goes in the CSV record.
    maps: Vec<Vec<usize>>,
    /// Per vehicle: its kind's index in `maps`.
    kind_of: Vec<u32>,
    width: usize,
    names: Vec<String>,
    acc: Vec<VehicleAcc>,
    keep_every: u64,
    plots: bool,
    /// Every this many vehicles one is drawn in the plots (at most [`PLOT_VEHICLES`]).
    plot_stride: usize,
    csv_rows: u64,
    /// `run.mcap`, when the world asks for it (`[output] mcap`).
    mcap: Option<mcap::McapOutput>,
    /// External agents' part of the summary (set by the run driver before `finish`).
    pub(crate) agents: Option<shoal_sim::agents::AgentsSummary>,
    /// The replay to write as `replay.html` (set by the run driver before `finish`, from
    /// [`Sim::take_replay`]).
    pub(crate) replay: Option<crate::replay::ReplayData>,
    /// Called with each output file's final name just before [`RunOutput::finish`] begins
    /// it (set by the run driver: its [`crate::run::Watch::before_file`]).
    pub(crate) before_file: Option<&'d dyn Fn(&Path)>,
    /// Wall time the run driver spent draining recorded rows and writing them while the world
    /// ran \[s\] (added up by the driver; reported in [`Summary::phases_s`]).
    pub(crate) writing_s: f64,
}

impl<'d> RunOutput<'d> {
    /// Creates `dir` (and parents) and starts `trajectories.csv` (under its temporary name),
    /// and `run.mcap` when `desc` asks for it (`[output] mcap`).
    pub fn create(dir: &Path, desc: &'d WorldDesc) -> Result<Self, OutputError> {
        std::fs::create_dir_all(dir).map_err(|reason| OutputError::Folder {
            path: dir.to_path_buf(),
            reason,
        })?;
        let mut csv = CsvFile::create(&dir.join("trajectories.csv"))?;
        // Header: t, vehicle, the fixed columns, then the union of actuator columns.
        let mut header: Vec<String> = vec!["t_s".into(), "vehicle".into()];
        header.extend(recorder::FIXED[1..].iter().map(|s| s.to_string()));
        let mut extra: Vec<String> = Vec::new();
        let mut maps = Vec::new();
        let mut kind_of = Vec::with_capacity(desc.vehicles.len());
        let mut by_kind: HashMap<*const VehicleModel, u32> = HashMap::new();
        for v in &desc.vehicles {
            let key = std::sync::Arc::as_ptr(&v.model);
            let kind = *by_kind.entry(key).or_insert_with(|| {
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
                maps.push(m);
                (maps.len() - 1) as u32
            });
            kind_of.push(kind);
        }
        header.extend(extra);
        let width = header.len();
        csv.write_record(&header)?;
        let expected_rows = (desc.duration * desc.output.record_hz).max(1.0) as u64;
        let mcap = if desc.output.mcap {
            Some(mcap::McapOutput::create(&dir.join(mcap::FILE_NAME), desc)?)
        } else {
            None
        };
        Ok(Self {
            desc,
            dir: dir.to_path_buf(),
            csv,
            maps,
            kind_of,
            width,
            names: desc.vehicles.iter().map(|v| v.name.clone()).collect(),
            acc: vec![VehicleAcc::default(); desc.vehicles.len()],
            keep_every: expected_rows.div_ceil(PLOT_POINTS as u64).max(1),
            plots: desc.output.plots,
            plot_stride: desc.vehicles.len().div_ceil(PLOT_VEHICLES).max(1),
            csv_rows: 0,
            mcap,
            agents: None,
            replay: None,
            before_file: None,
            writing_s: 0.0,
        })
    }

    /// The output folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Steps the world's run has planned.
    pub fn steps(&self) -> u64 {
        self.desc.steps()
    }

    /// Vehicles of the world.
    pub fn vehicles(&self) -> usize {
        self.desc.vehicles.len()
    }

    /// Writes a batch of rows (time-major) to `trajectories.csv` (and `run.mcap`, with the
    /// batch's reception attempts) and updates the statistics.
    pub fn write(&mut self, batch: &RecordBatch) -> Result<(), OutputError> {
        if let Some(m) = &mut self.mcap {
            m.write(batch)?;
        }
        let strides: Vec<usize> = (0..batch.rows.len())
            .map(|i| self.maps[self.kind_of[i] as usize].len())
            .collect();
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
                    let target = self.maps[self.kind_of[i] as usize][j];
                    if j == col::MODE {
                        rec[target].push_str(mode_of_code(*x).name());
                    } else {
                        write_num(*x, &mut rec[target]);
                    }
                }
                rec[1].clone_from(&self.names[i]);
                self.csv.write_record(&rec)?;
                self.csv_rows += 1;
                self.accumulate(i, row);
            }
        }
        Ok(())
    }

    fn accumulate(&mut self, i: usize, row: &[f64]) {
        let keep = self.plots
            && i.is_multiple_of(self.plot_stride)
            && self.acc[i].rows.is_multiple_of(self.keep_every);
        self.acc[i].add_row(row, keep);
    }

    /// Finishes the outputs in the order of the module documentation (summary, tables,
    /// plots) and returns the summary.
    ///
    /// `cancel` is the run's stop request. One made before `finish` marks the summary
    /// interrupted (with its cause), and the plots are still drawn. A further one — a second
    /// request, whenever it came, or the first while a complete run's outputs are written —
    /// skips the plots not yet drawn; the summary and the tables are always finished. The
    /// first write error ends the outputs: it names the file and the reason, and every file
    /// written before it stays.
    pub fn finish(
        self,
        sim: &mut Sim,
        wall_s: f64,
        cancel: &Cancel,
    ) -> Result<Summary, OutputError> {
        let desc = self.desc;
        // The request that ended the run (if any) still has its plots; any other skips them.
        let seen = cancel.requests().min(1);
        sim.fold_comm();
        let sim = &*sim;
        let snaps = sim.views();
        let comm = crate::comm_report::summarize(desc, sim, &snaps);
        let mut plots: Vec<(&'static str, Plot)> = Vec::new();
        if self.plots {
            if let Some(c) = &comm {
                plots.extend(crate::comm_report::plots(desc, sim, &snaps, c));
            }
            let (acc, stride) = (&self.acc, self.plot_stride);
            plots.push(("depth", plots::depth_plot(acc, stride, desc)));
            plots.push(("top", plots::top_plot(acc, stride, desc)));
            if self.acc.iter().any(|a| a.steered) {
                plots.push(("heading", plots::heading_plot(acc, stride, desc)));
            }
        }
        let RunOutput {
            dir,
            csv,
            acc,
            csv_rows,
            mcap,
            agents,
            replay,
            before_file,
            writing_s,
            ..
        } = self;
        let begin = |p: &Path| {
            if let Some(f) = &before_file {
                f(p);
            }
        };
        let json_path = dir.join("summary.json");
        let vehicles_path = dir.join("vehicles.csv");
        let mut planned = vec![
            json_path.clone(),
            csv.path().to_path_buf(),
            vehicles_path.clone(),
        ];
        if comm.is_some() {
            planned.extend(
                crate::comm_report::table_names(snaps.len(), !sim.medium().flows().is_empty())
                    .into_iter()
                    .map(|t| dir.join(t)),
            );
        }
        let mcap_path = dir.join(mcap::FILE_NAME);
        if mcap.is_some() {
            planned.push(mcap_path.clone());
        }
        // Its summary section, so the summary can say what it holds; committed in order.
        let mcap = mcap.map(mcap::McapOutput::finish);
        let replay_path = dir.join("replay.html");
        if replay.is_some() {
            planned.push(replay_path.clone());
        }
        for (stem, _) in &plots {
            let stem = dir.join(stem);
            planned.extend([stem.with_extension("png"), stem.with_extension("svg")]);
        }
        let mut summary = Summary::new(desc, sim, &snaps, &acc, wall_s, cancel.cause());
        summary.phases_s.outputs = writing_s;
        summary.comm = comm;
        summary.agents = agents;
        summary.trajectory_rows = csv_rows;
        summary.mcap = match &mcap {
            Some(Ok(m)) => Some(m.summary.clone()),
            _ => None,
        };
        summary.files = planned.iter().map(|p| p.display().to_string()).collect();
        begin(&json_path);
        write_summary(&json_path, &summary)?;
        let mut written = vec![json_path.clone()];
        let outcome = write_tables_and_plots(
            csv,
            (
                &vehicles_path,
                &summary.vehicle_details,
                summary.comm.as_ref().map(|c| c.vehicles.as_slice()),
            ),
            summary.comm.is_some().then_some(sim),
            mcap,
            replay.as_ref().map(|r| (replay_path.as_path(), r)),
            &snaps,
            &plots,
            &dir,
            || cancel.requests() > seen,
            &begin,
            &mut written,
        );
        if outcome.is_err() || written.len() < planned.len() || cancel.requests() > seen {
            summary.interrupted = cancel.is_requested();
            summary.signal = cancel.cause().map(|c| c.name.to_string());
            summary.files = written.iter().map(|p| p.display().to_string()).collect();
            summary.output_error = outcome.as_ref().err().map(|e| e.to_string());
            // Best effort: when even this fails, the first summary stays.
            let _ = write_summary(&json_path, &summary);
        }
        outcome.map(|()| summary)
    }
}

/// Writes `summary.json` (whole).
fn write_summary(path: &Path, summary: &Summary) -> Result<PathBuf, FileError> {
    let text = serde_json::to_vec_pretty(summary).map_err(|e| FileError {
        path: path.to_path_buf(),
        reason: e.into(),
    })?;
    write_whole(path, &text)
}

/// The part of [`RunOutput::finish`] after the summary: commits the trajectories, writes
/// `vehicles.csv` and the communication tables (when there was traffic), commits `run.mcap`
/// (finished, or the error that finishing it met), writes the replay, and
/// draws the plots until `skip_plots` says so, calling `begin` with each file's name before
/// it begins it and adding each file to `written` as it is complete.
#[allow(clippy::too_many_arguments)]
fn write_tables_and_plots(
    trajectories: CsvFile,
    vehicles: (&Path, &[VehicleSummary], Option<&[VehicleComm]>),
    comm: Option<&Sim>,
    mcap: Option<Result<mcap::FinishedMcap, FileError>>,
    replay: Option<(&Path, &crate::replay::ReplayData)>,
    snaps: &[VehicleView<'_>],
    plots: &[(&'static str, Plot)],
    dir: &Path,
    skip_plots: impl Fn() -> bool,
    begin: &dyn Fn(&Path),
    written: &mut Vec<PathBuf>,
) -> Result<(), OutputError> {
    begin(trajectories.path());
    written.push(trajectories.commit()?);
    begin(vehicles.0);
    written.push(write_vehicles_csv(vehicles.0, vehicles.1, vehicles.2)?);
    if let Some(sim) = comm {
        crate::comm_report::write_tables(dir, sim, snaps, begin, written)?;
    }
    if let Some(m) = mcap {
        let m = m?;
        begin(m.path());
        written.push(m.commit()?);
    }
    if let Some((path, data)) = replay {
        begin(path);
        written.push(crate::replay::html::write(path, data)?);
    }
    for (stem, plot) in plots {
        if skip_plots() {
            break;
        }
        written.extend(plot.write_until(&dir.join(stem), &skip_plots, begin)?);
    }
    Ok(())
}
