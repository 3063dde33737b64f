//! `run.mcap`: the run as an [MCAP](https://mcap.dev) file for Foxglove (a 3D scene and
//! plottable numbers) and for ROS 2 tools (sensor and actuator topics typed like a logged
//! vehicle's, e.g. for `shoal validate` through its mapping file). A run writes it when asked
//! (`shoal run --mcap`, or `[output] mcap = true`), beside `trajectories.csv`, sampled like the
//! trajectories (`record_hz`) and streamed: each batch of rows the run driver drains
//! ([`shoal_sim::recorder::RecordBatch`], with the reception attempts of the same steps) is written
//! at once, so memory does not grow with the run beyond the file's index (one chunk of 4 MiB,
//! the attempts of one record interval, and an index entry per channel and chunk: ≈ 40 MB for
//! a file of 1,000 vehicles at its budget).
//!
//! **Topics** (`<vehicle>` is the vehicle's name as in `trajectories.csv`; every vehicle
//! has each of its topics, up to [`MAX_VEHICLES`]):
//!
//! | topic | type | messages | content |
//! |---|---|---|---|
//! | `/tf` | `tf2_msgs/msg/TFMessage` | one per sample | every vehicle's pose: parent `world`, child `<vehicle>` |
//! | `/scene` | `foxglove_msgs/msg/SceneUpdate` | one, at the first sample (latched) | each hull (a cylinder in its vehicle's frame, its name above), the pool's outline, the obstacles |
//! | `/links` | `foxglove_msgs/msg/SceneUpdate` | one per sample interval with attempts | a line per reception attempt, sender → receiver at the sample's poses, coloured by outcome ([`crate::link_key`]), gone after two sample intervals (at least 0.5 s) |
//! | `/optical/frames` | `shoal_msgs/msg/ReceptionAttempt` | one per reception attempt | time, sender, receiver, outcome, payload bytes |
//! | `/<vehicle>/state` | `shoal_msgs/msg/VehicleState` | one per sample | the trajectory row: pose, body velocities, depth reading, mode, setpoints, ballast, pump, demands |
//! | `/<vehicle>/pressure` | `sensor_msgs/msg/FluidPressure` | one per sample | `101325 Pa + ρ g · depth reading` (the world's water density and gravity), variance 0 |
//! | `/<vehicle>/imu` | `sensor_msgs/msg/Imu` | one per sample | attitude and body rates, ENU/FLU; no acceleration (`linear_acceleration_covariance[0] = −1`) |
//! | `/<vehicle>/thrusters` | `std_msgs/msg/Float64MultiArray` | one per sample | one command per thruster in the vehicle file's order \[%\]; the dimension's label names them |
//! | `/<vehicle>/tilts` | `std_msgs/msg/Float64MultiArray` | one per sample | the commanded tilt angles (what the controller or agent sent the drives) in the vehicle file's order \[rad\] |
//! | `/<vehicle>/tilt_angles` | `std_msgs/msg/Float64MultiArray` | one per sample | the drives' angles, lagging the commands by their slew rate \[rad\] |
//! | `/<vehicle>/pump` | `std_msgs/msg/Float64MultiArray` | one per sample | one element: −1 out, 0 off, +1 in |
//!
//! **ROS 2 profile.** The file is a rosbag2 MCAP: profile `ros2`, every schema a `.msg`
//! definition with its dependencies in rosbag2's form (`ros2msg`, [`definition`]), every
//! message CDR with the 4-byte encapsulation header `00 01 00 00` ([`ros2`]), every channel
//! with the QoS rosbag2 records (`offered_qos_profiles`). So `ros2 bag`, PyPI's `rosbags`
//! (`AnyReader`) and `shoal validate` (through a mapping file) read it, and Foxglove draws the
//! scene from `foxglove_msgs` and `/tf`. shoal's own two types are defined in the file
//! ([`plain`]); the scene's follow the `foxglove_msgs` package ([`foxglove`]). The pressure is
//! computed from the depth sensor's reading (noise and quantisation included), but the IMU's
//! attitude and rates are the **true** ones: the recorder keeps no IMU readings.
//!
//! **Time.** Every message's log time and publish time, and every header stamp, is the
//! simulated time of its sample in nanoseconds from the start of the run; an attempt's
//! `/optical/frames` message is at the end of its frame. Messages are written in time order.
//! The commands (`thrusters`, `tilts`, `pump`) are stamped when they came into force, as a
//! logger records a command when it is sent: a trajectory row holds the commands of the
//! interval that *ends* at its time, so a sample's commands are those of the next recorded
//! row (the last sample's, its own). A zero-order-hold replay of the file then applies each
//! command over the interval it acted on, not one control period late.
//!
//! **Frames.** Everything in the file is in ENU (x east, y north, z up; the surface at z = 0)
//! with FLU vehicle frames, converted from shoal's NED/FRD as `shoal_model::frames` says: position
//! `(y, x, −z)`, `roll_ENU = roll`, `pitch_ENU = −pitch`, `yaw_ENU = π/2 − yaw`, body rates
//! `(p, −q, −r)` — except `/<vehicle>/state`, which keeps `trajectories.csv`'s NED/FRD numbers.
//!
//! **Size budget** (`budget.rs`, docs/mcap.md): at most [`MAX_VEHICLES`] vehicles have
//! topics; the per-vehicle topics and `/tf` thin to every k-th sample to stay within
//! [`SAMPLE_BUDGET_BYTES`] (512 MiB of messages before compression), and at most
//! [`FRAME_BUDGET`] attempts (200,000) are written. The chunks are compressed with
//! zstd (≈ 4×). What was left out is in the summary ([`McapSummary`]).
//!
//! **Failures.** The file is written under `.run.mcap.tmp` and appears as `run.mcap` only
//! when complete ([`shoal_output::files`]); an error names `run.mcap` and the reason
//! ([`FileError`]). A write that fails while the world runs stops the run, as one of
//! `trajectories.csv` does.

mod budget;
mod definitions;
mod file;
pub mod foxglove;
mod msgdef;
pub mod plain;
pub mod ros2;
mod scene;
mod topics;

pub use definitions::definition;

#[cfg(test)]
mod tests;

pub use budget::{
    BYTES_PER_ACTUATOR, BYTES_PER_VEHICLE_SAMPLE, FRAME_BUDGET, MAX_VEHICLES, SAMPLE_BUDGET_BYTES,
};

use budget::{FrameQuota, Plan};
use file::McapFile;
use serde::Serialize;
use shoal_output::files::{AtomicFile, FileError};
use shoal_sim::comm::Heard;
use shoal_sim::recorder::{self, RecordBatch, col};
use shoal_world::desc::WorldDesc;
use std::path::{Path, PathBuf};
use topics::{Schemas, VehicleTopics};

/// The file's name in a run's output folder.
pub const FILE_NAME: &str = "run.mcap";

/// What `run.mcap` holds and what the budget left out (in `summary.json` as `mcap`).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct McapSummary {
    /// Length of the file \[bytes\].
    pub bytes: u64,
    /// Messages \[count\].
    pub messages: u64,
    /// Their payloads before compression \[bytes\].
    pub message_bytes: u64,
    /// Vehicles with topics \[count\].
    pub vehicles: usize,
    /// Vehicles in the world \[count\].
    pub vehicles_in_world: usize,
    /// Every how many recorded samples one was written \[count\].
    pub sample_every: u64,
    /// Samples recorded \[count\].
    pub samples_recorded: u64,
    /// Samples written \[count\].
    pub samples_written: u64,
    /// Reception attempts decided \[count\].
    pub frames: u64,
    /// Reception attempts written \[count\].
    pub frames_written: u64,
}

impl McapSummary {
    /// What the size budget left out, in words (`None`: nothing).
    pub fn dropped(&self) -> Option<String> {
        let mut parts = Vec::new();
        if self.vehicles < self.vehicles_in_world {
            parts.push(format!(
                "topics for {} of {} vehicles",
                self.vehicles, self.vehicles_in_world
            ));
        }
        if self.sample_every > 1 {
            parts.push(format!(
                "1 sample in {} ({} of {})",
                self.sample_every, self.samples_written, self.samples_recorded
            ));
        }
        if self.frames_written < self.frames {
            parts.push(format!(
                "{} of {} reception attempts",
                self.frames_written, self.frames
            ));
        }
        (!parts.is_empty())
            .then(|| format!("kept {} (size budget, docs/mcap.md)", parts.join(", ")))
    }
}

/// A finished `run.mcap`, still under its temporary name.
pub struct FinishedMcap {
    file: AtomicFile,
    /// What it holds.
    pub summary: McapSummary,
}

impl FinishedMcap {
    /// The file's final name.
    pub fn path(&self) -> &Path {
        self.file.path()
    }

    /// Gives the file its name; returns it.
    pub fn commit(self) -> Result<PathBuf, FileError> {
        self.file.commit()
    }
}

/// Indices of the shared channels in [`McapOutput::channels`].
const TF: usize = 0;
const SCENE: usize = 1;
const LINKS: usize = 2;
const FRAMES: usize = 3;

/// `run.mcap` being written.
pub struct McapOutput {
    file: McapFile,
    plan: Plan,
    quota: FrameQuota,
    /// Every vehicle's name, by id.
    names: Vec<String>,
    /// Every vehicle's row length, by id.
    strides: Vec<usize>,
    /// The topics of the vehicles of the plan (`Plan::vehicles`), in that order.
    topics: Vec<VehicleTopics>,
    /// `/tf`, `/scene`, `/links`, `/optical/frames`.
    channels: [u16; 4],
    /// The still scene, until it is written with the first sample.
    scene: Option<foxglove::SceneUpdate>,
    lifetime: ros2::Duration,
    /// Attempts drained but not yet written: those after the last sample.
    pending: Vec<Heard>,
    /// Time of the last sample \[s\].
    last_t: f64,
    /// The last written sample whose commands wait for the next recorded row (which holds
    /// the commands in force from that sample on): its time \[ns\] and its own rows (the
    /// fallback at the end of the run), by planned vehicle.
    commands_due: Option<(u64, Vec<Vec<f64>>)>,
    summary: McapSummary,
}

/// Simulated time \[s\] in whole nanoseconds.
fn ns(t: f64) -> u64 {
    (t.max(0.0) * 1e9).round() as u64
}

/// Row `k` of vehicle `i` in `batch` (rows of `strides[i]` values).
fn row_at<'a>(batch: &'a RecordBatch, strides: &[usize], i: usize, k: usize) -> Option<&'a [f64]> {
    let s = *strides.get(i)?;
    batch.rows.get(i)?.get(k * s..(k + 1) * s)
}

impl McapOutput {
    /// Starts `path` for the world `desc`: its schemas, channels and plan (what the size
    /// budget keeps).
    pub fn create(path: &Path, desc: &WorldDesc) -> Result<Self, FileError> {
        let mut file = McapFile::create(path)?;
        let actuators: Vec<usize> = desc
            .vehicles
            .iter()
            .map(|v| v.model.params.thrusters.len() + v.model.params.tilts.len())
            .collect();
        let plan = Plan::new(&actuators, desc.duration, desc.output.record_hz);
        let transforms = file.ros2_schema("tf2_msgs/msg/TFMessage")?;
        let update = file.ros2_schema("foxglove_msgs/msg/SceneUpdate")?;
        let frames = file.ros2_schema(plain::RECEPTION_ATTEMPT)?;
        let mut channels = [0; 4];
        for (c, (schema, topic, latched)) in channels.iter_mut().zip([
            (transforms, "/tf", false),
            (update, "/scene", true),
            (update, "/links", false),
            (frames, "/optical/frames", false),
        ]) {
            *c = file.channel(schema, topic, latched, &[])?;
        }
        let schemas = Schemas::add(&mut file)?;
        let mut topics = Vec::with_capacity(plan.vehicles.len());
        for &i in &plan.vehicles {
            let v = &desc.vehicles[i];
            topics.push(VehicleTopics::add(
                &mut file, &schemas, i, &v.name, &v.model, &desc.env,
            )?);
        }
        let scene = scene::still_scene(desc, &plan.vehicles, ros2::Time::default());
        Ok(Self {
            file,
            quota: FrameQuota::new(desc.duration),
            names: desc.vehicles.iter().map(|v| v.name.clone()).collect(),
            strides: desc
                .vehicles
                .iter()
                .map(|v| recorder::stride(&v.model))
                .collect(),
            topics,
            channels,
            scene: Some(scene),
            lifetime: scene::link_lifetime(desc.output.record_hz),
            pending: Vec::new(),
            last_t: 0.0,
            commands_due: None,
            summary: McapSummary {
                vehicles: plan.vehicles.len(),
                vehicles_in_world: desc.vehicles.len(),
                sample_every: plan.sample_every,
                ..McapSummary::default()
            },
            plan,
        })
    }

    /// Writes a drained batch: for each sample in time order, the attempts that ended since the
    /// last one (and their links), then the sample's messages when the plan keeps it.
    pub fn write(&mut self, batch: &RecordBatch) -> Result<(), FileError> {
        self.pending.extend_from_slice(&batch.frames);
        // A canonical order, whatever order the receivers were decided in.
        self.pending.sort_by(|a, b| {
            a.t.total_cmp(&b.t)
                .then(a.from.cmp(&b.from))
                .then(a.to.cmp(&b.to))
        });
        let samples = batch
            .rows
            .iter()
            .zip(&self.strides)
            .map(|(r, &s)| r.len() / s.max(1))
            .max()
            .unwrap_or(0);
        for k in 0..samples {
            let Some(t) = (0..batch.rows.len())
                .find_map(|i| row_at(batch, &self.strides, i, k).map(|r| r[col::T]))
            else {
                continue;
            };
            // The commands of the last written sample are in this row: in force from then.
            if let Some((at, _)) = self.commands_due.take() {
                for (topics, &i) in self.topics.iter().zip(&self.plan.vehicles) {
                    if let Some(row) = row_at(batch, &self.strides, i, k) {
                        topics.write_commands(&mut self.file, row, at)?;
                    }
                }
            }
            let due = self.pending.partition_point(|h| h.t <= t);
            let due: Vec<Heard> = self.pending.drain(..due).collect();
            let kept = self.frames(&due, t)?;
            if !kept.is_empty() {
                let update = scene::links(
                    &kept,
                    &self.names,
                    |id| row_at(batch, &self.strides, id as usize, k).map(scene::row_position),
                    ros2::Time::from_ns(ns(t)),
                    self.lifetime,
                    self.summary.frames_written - kept.len() as u64,
                );
                self.file.write_cdr(self.channels[LINKS], ns(t), &update)?;
            }
            if self
                .summary
                .samples_recorded
                .is_multiple_of(self.plan.sample_every)
            {
                self.sample(batch, k, ns(t))?;
            }
            self.summary.samples_recorded += 1;
            self.last_t = t;
        }
        Ok(())
    }

    /// Writes the share of the attempts `due` (ended by `t` \[s\]) that the budget keeps to
    /// `/optical/frames`; returns them.
    fn frames(&mut self, due: &[Heard], t: f64) -> Result<Vec<Heard>, FileError> {
        let keep = self.quota.keep(due.len(), t - self.last_t);
        let kept: Vec<Heard> = due
            .iter()
            .enumerate()
            .filter(|(i, _)| keep(*i))
            .map(|(_, h)| *h)
            .collect();
        for h in &kept {
            let msg = plain::ReceptionAttempt::of(h, &self.names);
            self.file.write_cdr(self.channels[FRAMES], ns(h.t), &msg)?;
        }
        self.summary.frames += due.len() as u64;
        self.summary.frames_written += kept.len() as u64;
        Ok(kept)
    }

    /// Writes sample `k` of `batch` at `ns` nanoseconds: the still scene the first time,
    /// `/tf`, and every planned vehicle's state topics; its commands wait for the next row.
    fn sample(&mut self, batch: &RecordBatch, k: usize, ns: u64) -> Result<(), FileError> {
        let stamp = ros2::Time::from_ns(ns);
        let rows: Vec<Vec<f64>> = self
            .plan
            .vehicles
            .iter()
            .map(|&i| row_at(batch, &self.strides, i, k).map_or_else(Vec::new, <[f64]>::to_vec))
            .collect();
        self.commands_due = Some((ns, rows));
        if let Some(mut scene) = self.scene.take() {
            scene.entities.iter_mut().for_each(|e| e.timestamp = stamp);
            self.file.write_cdr(self.channels[SCENE], ns, &scene)?;
        }
        let transforms = self
            .plan
            .vehicles
            .iter()
            .filter_map(|&i| {
                let row = row_at(batch, &self.strides, i, k)?;
                Some(scene::transform(stamp, &self.names[i], row))
            })
            .collect();
        let tf = ros2::TfMessage { transforms };
        self.file.write_cdr(self.channels[TF], ns, &tf)?;
        for (topics, &i) in self.topics.iter().zip(&self.plan.vehicles) {
            if let Some(row) = row_at(batch, &self.strides, i, k) {
                topics.write_state(&mut self.file, row, ns)?;
            }
        }
        self.summary.samples_written += 1;
        Ok(())
    }

    /// Writes the attempts after the last sample (to `/optical/frames` only: no pose to draw
    /// them at) and the file's summary section; returns the file, not yet committed, and
    /// what it holds.
    pub fn finish(mut self) -> Result<FinishedMcap, FileError> {
        // The last sample's commands: no row follows; the interval that ended there is the
        // best account of what was sent last.
        if let Some((at, rows)) = self.commands_due.take() {
            for (topics, row) in self.topics.iter().zip(&rows) {
                if !row.is_empty() {
                    topics.write_commands(&mut self.file, row, at)?;
                }
            }
        }
        let rest = std::mem::take(&mut self.pending);
        if let Some(end) = rest.last().map(|h| h.t) {
            self.frames(&rest, end)?;
        }
        let done = self.file.finish()?;
        let summary = McapSummary {
            bytes: done.bytes,
            messages: done.messages,
            message_bytes: done.message_bytes,
            ..self.summary
        };
        Ok(FinishedMcap {
            file: done.file,
            summary,
        })
    }
}
