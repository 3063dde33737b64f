//! The validated world: everything in SI units and radians, vehicles expanded from their
//! groups, models derived and shared, geometry built. Produced only by [`crate::load`].

use crate::geometry::Geometry;
use crate::spec::{BehaviourSpec, FallbackSpec};
use shoal_model::optics::Ambient;
use shoal_model::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;

/// One vehicle to spawn.
#[derive(Clone, Debug)]
pub struct VehicleDesc {
    /// Unique name.
    pub name: String,
    /// Index of its group in the world file.
    pub group: usize,
    /// Its model (shared by the group).
    pub model: Arc<VehicleModel>,
    /// Its mission (shared by the group).
    pub mission: Arc<Mission>,
    /// Initial position of the body origin, world frame \[m\].
    pub position: Vec3,
    /// Initial attitude.
    pub attitude: Quat,
    /// Built-in behaviour, if any.
    pub behaviour: Option<BehaviourSpec>,
    /// Name of the external agent that drives it, if any.
    pub agent: Option<String>,
    /// Link layer (medium access, retries) of each of its modems, in the model's order
    /// (shared by the group).
    pub link: Arc<[crate::access::LinkParams]>,
}

/// How external agents attach (see [`crate::spec::AgentsSpec`]).
#[derive(Clone, Debug, PartialEq)]
pub struct AgentsDesc {
    /// Service-name prefix of this world.
    pub prefix: String,
    /// Wait for agents each control period (`true`) or never.
    pub lockstep: bool,
    /// Longest wait for one agent's commands [s, wall time].
    pub timeout: f64,
    /// Longest wait at the start for the agents to attach [s, wall time].
    pub attach_timeout: f64,
    /// What vehicles do without their agent.
    pub fallback: FallbackSpec,
    /// Agents see true positions.
    pub grant_position: bool,
    /// Free-running pace [simulated s per wall s]; 0 = as fast as possible.
    pub pace: f64,
    /// Names of the agents the vehicles name, sorted — but `ros2` (the ROS 2 bridge), when a
    /// group names it, last: agent indices below it belong to iceoryx2 agents.
    pub names: Vec<String>,
    /// The ROS 2 bridge, when a vehicle group says `agent = "ros2"`.
    pub ros2: Option<Ros2Desc>,
}

/// The ROS 2 bridge of a world (see [`crate::spec::Ros2Spec`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Ros2Desc {
    /// DDS domain id (0 … 232).
    pub domain_id: u16,
    /// ROS namespace of the vehicles' topics.
    pub namespace: String,
    /// Free-running real-time factor [simulated s per wall s]; 0 = as fast as possible.
    pub rtf: f64,
    /// Keep DDS on the loopback interface.
    pub localhost_only: bool,
    /// Agent index of the bridge (the last of [`AgentsDesc::names`]).
    pub agent: usize,
}

/// What a run writes.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputDesc {
    /// Trajectory sample rate \[Hz\].
    pub record_hz: f64,
    /// Write plots.
    pub plots: bool,
    /// Write `replay.html`.
    pub replay: bool,
    /// Write `run.mcap`.
    pub mcap: bool,
}

/// A validated world.
#[derive(Clone, Debug)]
pub struct WorldDesc {
    /// Name for summaries.
    pub name: String,
    /// Where it came from.
    pub source: PathBuf,
    /// World seed.
    pub seed: u64,
    /// Simulated duration \[s\].
    pub duration: f64,
    /// Physics step \[s\].
    pub dt: f64,
    /// Integrator.
    pub integrator: Integrator,
    /// Water density, gravity and current.
    pub env: Environment,
    /// Beam attenuation coefficient of the water [1/m].
    pub attenuation: f64,
    /// Ambient light for the optical receivers.
    pub ambient: Ambient,
    /// Pool and obstacles.
    pub geometry: Geometry,
    /// Vehicles in spawn order.
    pub vehicles: Vec<VehicleDesc>,
    /// Name of each vehicle group (indexed by [`VehicleDesc::group`]).
    pub groups: Vec<String>,
    /// Output settings.
    pub output: OutputDesc,
    /// External agents.
    pub agents: AgentsDesc,
    /// Advice on what the file says but probably does not mean (e.g. vehicles far from
    /// neutral buoyancy); the world is valid.
    pub warnings: Vec<String>,
}

impl WorldDesc {
    /// Number of physics steps in the run.
    pub fn steps(&self) -> u64 {
        (self.duration / self.dt).round() as u64
    }
}
