//! The world-file schema (serde, `deny_unknown_fields` everywhere) and the vehicle-model
//! schema shared by world files and `vehicle.toml` files.
//!
//! Units are SI (metres, seconds, kilograms, newtons, cubic metres); angles are degrees only
//! in fields whose name ends in `_deg` (or `_deg_s` for rates), radians nowhere in files.
//!
//! One file per concern: `pool` (pool, water, obstacles), `group` (vehicle groups: placement,
//! mission), `behaviour` (built-in behaviours and external agents), `vehicle` (the vehicle
//! model with its effects, and its conversions to and from the model's parameters) and `modem`
//! (optical modems). This file holds the top level ([`WorldFile`]), the integrator and output
//! sections, and re-exports every type, so paths stay `spec::VehicleSpec`, `spec::ModemSpec`, …

mod behaviour;
mod group;
mod modem;
mod pool;
mod vehicle;

pub use behaviour::{AgentsSpec, BehaviourSpec, FallbackSpec, ROS2_AGENT, Ros2Spec, TimingSpec};
pub use group::{GridSpec, MissionStepSpec, ModeSpec, PumpSpec, RandomSpec, VehicleGroupSpec};
pub use modem::ModemSpec;
pub use pool::{AttenuationSpec, ObstacleSpec, PoolSpec, ShapeKind, WATER_TYPES, WaterSpec};
pub use vehicle::{
    BallastSpec, BodySpec, ControlSpec, CurveSpec, EffectSpec, ImuSpec, Mat3Spec, Mat6Spec, PdSpec,
    PressureSpec, ThrusterSpec, TiltSpec, VehicleSpec,
};

use serde::{Deserialize, Serialize};
use shoal_model::prelude::{Vec3, Vec6};

fn d_duration() -> f64 {
    60.0
}
fn d_dt() -> f64 {
    0.01
}
fn d_true() -> bool {
    true
}
fn d_record_hz() -> f64 {
    10.0
}

/// A whole world file.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldFile {
    /// Name shown in summaries.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// World seed: every random draw derives from it.
    #[serde(default)]
    pub seed: u64,
    /// Simulated time \[s\].
    #[serde(default = "d_duration")]
    pub duration: f64,
    /// Physics time step \[s\].
    #[serde(default = "d_dt")]
    pub dt: f64,
    /// Integrator.
    #[serde(default)]
    pub integrator: IntegratorSpec,
    /// The pool.
    #[serde(default)]
    pub pool: PoolSpec,
    /// The water.
    #[serde(default)]
    pub water: WaterSpec,
    /// Obstacles in the pool.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub obstacles: Vec<ObstacleSpec>,
    /// Vehicle groups.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub vehicles: Vec<VehicleGroupSpec>,
    /// What the run writes.
    #[serde(default)]
    pub output: OutputSpec,
    /// How external agent processes attach (used when a vehicle group names an `agent`).
    #[serde(default, skip_serializing_if = "AgentsSpec::is_default")]
    pub agents: AgentsSpec,
    /// The ROS 2 bridge (used when a vehicle group says `agent = "ros2"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ros2: Option<Ros2Spec>,
}

/// Integrator choice.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum IntegratorSpec {
    /// Classic Runge–Kutta 4.
    #[default]
    Rk4,
    /// Semi-implicit Euler.
    SemiImplicitEuler,
}

/// What a run writes.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Trajectory sample rate \[Hz\].
    #[serde(default = "d_record_hz")]
    pub record_hz: f64,
    /// Write PNG/SVG plots.
    #[serde(default = "d_true")]
    pub plots: bool,
    /// Write `replay.html`, the run's interactive 3D replay.
    #[serde(default = "d_true")]
    pub replay: bool,
    /// Write `run.mcap`, the run for Foxglove and ROS 2 tools (off by default).
    #[serde(default)]
    pub mcap: bool,
}

impl Default for OutputSpec {
    fn default() -> Self {
        Self {
            record_hz: d_record_hz(),
            plots: true,
            replay: true,
            mcap: false,
        }
    }
}

// Array ↔ nalgebra helpers shared by the vehicle and modem conversions.

fn v3(a: [f64; 3]) -> Vec3 {
    Vec3::new(a[0], a[1], a[2])
}
fn a3(v: &Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}
fn a6(v: &Vec6) -> [f64; 6] {
    [v[0], v[1], v[2], v[3], v[4], v[5]]
}

fn unit_or_x(a: [f64; 3]) -> nalgebra::Unit<Vec3> {
    nalgebra::Unit::try_new(v3(a), 1e-12).unwrap_or(Vec3::x_axis())
}
