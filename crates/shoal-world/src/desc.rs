//! The validated world: everything in SI units and radians, vehicles expanded from their
//! groups, models derived and shared, geometry built. Produced only by [`crate::load`].

use crate::geometry::Geometry;
use crate::spec::BehaviourSpec;
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
    /// Initial position of the body origin, world frame [m].
    pub position: Vec3,
    /// Initial attitude.
    pub attitude: Quat,
    /// Built-in behaviour, if any.
    pub behaviour: Option<BehaviourSpec>,
}

/// What a run writes.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputDesc {
    /// Trajectory sample rate [Hz].
    pub record_hz: f64,
    /// Write plots.
    pub plots: bool,
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
    /// Simulated duration [s].
    pub duration: f64,
    /// Physics step [s].
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
}

impl WorldDesc {
    /// Number of physics steps in the run.
    pub fn steps(&self) -> u64 {
        (self.duration / self.dt).round() as u64
    }
}
