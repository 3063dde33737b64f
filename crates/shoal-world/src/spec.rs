//! The world-file schema (serde, `deny_unknown_fields` everywhere) and the vehicle-model
//! schema shared by world files and `vehicle.toml` files.
//!
//! Units are SI (metres, seconds, kilograms, newtons, cubic metres); angles are degrees only
//! in fields whose name ends in `_deg` (or `_deg_s` for rates), radians nowhere in files.

use serde::{Deserialize, Serialize};
use shoal_model::ballast::BallastParams;
use shoal_model::optics::{Access, Led, ModemParams, Receiver};
use shoal_model::prelude::*;
use std::collections::BTreeMap;

fn d_duration() -> f64 {
    60.0
}
fn d_dt() -> f64 {
    0.01
}
fn d_count() -> usize {
    1
}
fn d_true() -> bool {
    true
}
fn d_record_hz() -> f64 {
    10.0
}
fn d_density() -> f64 {
    1000.0
}
fn d_pool() -> [f64; 3] {
    [10.0, 10.0, 3.0]
}
fn d_max_command() -> f64 {
    100.0
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
}

/// How the world exchanges with external agents.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TimingSpec {
    /// The world waits for every attached agent on each control period (reproducible).
    #[default]
    Lockstep,
    /// The world never waits; the last command stays in force.
    Free,
}

/// What a vehicle does while its agent is absent, hung or dead.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FallbackSpec {
    /// Hold the depth and heading it had (auto mode, no surge).
    #[default]
    Hold,
    /// Rise to the surface holding its heading.
    Surface,
    /// End the run (outputs are written, the summary says why).
    Stop,
}

/// External agents (`[agents]`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AgentsSpec {
    /// Service-name prefix that isolates this world's agents from other worlds' (letters,
    /// digits, `_`, `-`, `.`; default: the world's name).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub prefix: Option<String>,
    /// Lock-step or free-running.
    #[serde(default)]
    pub timing: TimingSpec,
    /// Lock-step: longest wait for an agent's commands on one control period [s, wall time];
    /// an agent that misses it is treated as hung.
    #[serde(default = "d_agent_timeout")]
    pub timeout: f64,
    /// How long the world waits at the start for its agents to attach [s, wall time].
    #[serde(default = "d_attach_timeout")]
    pub attach_timeout: f64,
    /// What vehicles do without their agent.
    #[serde(default)]
    pub fallback: FallbackSpec,
    /// Whether agents see their vehicle's true position (a real vehicle would not).
    #[serde(default)]
    pub grant_position: bool,
    /// Free-running: simulated seconds per wall-clock second (0: as fast as possible).
    #[serde(default)]
    pub pace: f64,
}

impl Default for AgentsSpec {
    fn default() -> Self {
        Self {
            prefix: None,
            timing: TimingSpec::default(),
            timeout: d_agent_timeout(),
            attach_timeout: d_attach_timeout(),
            fallback: FallbackSpec::default(),
            grant_position: false,
            pace: 0.0,
        }
    }
}

impl AgentsSpec {
    /// Whether every field has its default (then it is not written out).
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }
}

fn d_agent_timeout() -> f64 {
    1.0
}

fn d_attach_timeout() -> f64 {
    10.0
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

/// A rectangular pool: corner at the origin on the surface, x north, y east, z down.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoolSpec {
    /// Length (x), width (y) and depth (z) \[m\].
    #[serde(default = "d_pool")]
    pub size: [f64; 3],
}

impl Default for PoolSpec {
    fn default() -> Self {
        Self { size: d_pool() }
    }
}

/// Beam attenuation of the water: a named water type or a number [1/m].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum AttenuationSpec {
    /// Beam attenuation coefficient c [1/m].
    Coefficient(f64),
    /// `pure_sea`, `clear_ocean`, `coastal`, `turbid_harbour` or `pool`.
    Named(String),
}

impl Default for AttenuationSpec {
    fn default() -> Self {
        AttenuationSpec::Named("pool".into())
    }
}

/// Named water types and their beam attenuation c = a + b at ≈530 nm [1/m] (Mobley via Hanson
/// & Radic 2008; `pool`: clean fresh water, near the pure-water value).
pub const WATER_TYPES: [(&str, f64); 5] = [
    ("pure_sea", 0.056),
    ("clear_ocean", 0.151),
    ("coastal", 0.398),
    ("turbid_harbour", 2.19),
    ("pool", 0.07),
];

/// The water.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WaterSpec {
    /// Density [kg/m³].
    #[serde(default = "d_density")]
    pub density: f64,
    /// Beam attenuation: a water type name or a coefficient [1/m].
    #[serde(default)]
    pub attenuation: AttenuationSpec,
    /// Constant current in the world frame (north, east, down) [m/s].
    #[serde(default)]
    pub current: [f64; 3],
    /// Ambient light just below the surface within the modems' optical band [W/m²]
    /// (0.5: an indoor pool; ≈50: daylight outdoors).
    #[serde(default = "d_ambient")]
    pub ambient_irradiance: f64,
    /// Diffuse attenuation of the ambient light with depth [1/m].
    #[serde(default = "d_kd")]
    pub diffuse_attenuation: f64,
}

fn d_ambient() -> f64 {
    0.5
}
fn d_kd() -> f64 {
    0.1
}

impl Default for WaterSpec {
    fn default() -> Self {
        Self {
            density: d_density(),
            attenuation: AttenuationSpec::default(),
            current: [0.0; 3],
            ambient_irradiance: d_ambient(),
            diffuse_attenuation: d_kd(),
        }
    }
}

/// Obstacle shape kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShapeKind {
    /// Box with full extents `size`.
    Box,
    /// Sphere of `radius`.
    Sphere,
    /// Cylinder of `radius` and full `height` along its local z axis.
    Cylinder,
    /// Capsule of `radius` whose straight part has full `height` along its local z axis.
    Capsule,
}

/// One static obstacle.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleSpec {
    /// Optional name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Shape kind.
    pub shape: ShapeKind,
    /// Full extents of a box (x, y, z) \[m\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<[f64; 3]>,
    /// Radius of a sphere, cylinder or capsule \[m\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Full height of a cylinder, or of a capsule's straight part \[m\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    /// Centre in the world frame \[m\].
    pub position: [f64; 3],
    /// Roll, pitch, yaw of the shape \[deg\].
    #[serde(default)]
    pub rotation_deg: [f64; 3],
}

/// Vehicles placed on a horizontal grid.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridSpec {
    /// Position of the first vehicle \[m\].
    pub origin: [f64; 3],
    /// Spacing along x and along y \[m\].
    pub spacing: [f64; 2],
    /// Vehicles per row (along x).
    pub columns: usize,
}

/// Vehicles placed uniformly at random in a box (rejecting overlaps).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RandomSpec {
    /// Lower corner \[m\].
    pub min: [f64; 3],
    /// Upper corner \[m\].
    pub max: [f64; 3],
    /// Draw each heading uniformly as well.
    #[serde(default)]
    pub random_heading: bool,
}

/// Controller modes as written in files.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ModeSpec {
    /// [`Mode::Off`].
    Off,
    /// [`Mode::Diving`].
    Diving,
    /// [`Mode::Buoyancy`].
    Buoyancy,
    /// [`Mode::Turning`].
    Turning,
    /// [`Mode::Drift`].
    Drift,
    /// [`Mode::Auto`].
    Auto,
    /// [`Mode::Raw`].
    Raw,
}

impl From<ModeSpec> for Mode {
    fn from(m: ModeSpec) -> Mode {
        match m {
            ModeSpec::Off => Mode::Off,
            ModeSpec::Diving => Mode::Diving,
            ModeSpec::Buoyancy => Mode::Buoyancy,
            ModeSpec::Turning => Mode::Turning,
            ModeSpec::Drift => Mode::Drift,
            ModeSpec::Auto => Mode::Auto,
            ModeSpec::Raw => Mode::Raw,
        }
    }
}

/// Pump command as written in files.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PumpSpec {
    /// Pump water out.
    Empty,
    /// Stop.
    Off,
    /// Pump water in.
    Fill,
}

impl From<PumpSpec> for Pump {
    fn from(p: PumpSpec) -> Pump {
        match p {
            PumpSpec::Empty => Pump::Empty,
            PumpSpec::Off => Pump::Off,
            PumpSpec::Fill => Pump::Fill,
        }
    }
}

/// One mission step: at time `t` the given fields take effect.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MissionStepSpec {
    /// Time \[s\].
    pub t: f64,
    /// Mode.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mode: Option<ModeSpec>,
    /// Depth setpoint of the pressure sensor \[m\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth: Option<f64>,
    /// Heading setpoint \[deg\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yaw_deg: Option<f64>,
    /// Surge force \[N\] (drift, auto).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surge: Option<f64>,
    /// Sway force \[N\] (drift).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sway: Option<f64>,
    /// Raw thruster commands by thruster name [% of full scale].
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub thrusters: BTreeMap<String, f64>,
    /// Raw tilt targets by tilt name \[deg\].
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub tilts_deg: BTreeMap<String, f64>,
    /// Raw pump command.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pump: Option<PumpSpec>,
}

/// A group of vehicles of one kind.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleGroupSpec {
    /// Base name; with `count > 1` vehicles are named `name-0`, `name-1`, …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Preset the model starts from (`uauv2`), or `custom` for a complete `model` table.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<String>,
    /// Number of vehicles.
    #[serde(default = "d_count")]
    pub count: usize,
    /// Single position \[m\] (for `count = 1`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<[f64; 3]>,
    /// Grid placement.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid: Option<GridSpec>,
    /// Random placement.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub random: Option<RandomSpec>,
    /// Initial heading \[deg\].
    #[serde(default)]
    pub heading_deg: f64,
    /// Mission steps.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub mission: Vec<MissionStepSpec>,
    /// Model overrides merged over the preset (tables merge; values and arrays replace).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<toml::Table>,
    /// A built-in swarm behaviour run on every control tick.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub behaviour: Option<BehaviourSpec>,
    /// Name of the external agent process that drives this group (see `[agents]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub agent: Option<String>,
}

/// Built-in swarm behaviours (in-process; they see only sensors and received frames).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum BehaviourSpec {
    /// Broadcast a frame of `payload_bytes` every `period` seconds (± `jitter`).
    Beacon {
        /// Interval \[s\].
        period: f64,
        /// Payload size \[bytes\].
        #[serde(default = "d_payload")]
        payload_bytes: usize,
        /// Random offset of each send, uniform in [0, jitter] \[s\].
        #[serde(default)]
        jitter: f64,
    },
    /// Flooding of a value: the origin learns it at `start`; every vehicle that knows it
    /// rebroadcasts it `repeats` times, `interval` apart, after a random delay in [0, jitter].
    Gossip {
        /// This group holds the origin.
        #[serde(default)]
        origin: bool,
        /// Time the value appears at the origin \[s\].
        #[serde(default = "d_gossip_start")]
        start: f64,
        /// Rebroadcasts per vehicle.
        #[serde(default = "d_repeats")]
        repeats: u32,
        /// Time between rebroadcasts \[s\].
        #[serde(default = "d_interval")]
        interval: f64,
        /// Random delay before each rebroadcast, uniform in [0, jitter] \[s\].
        #[serde(default = "d_jitter")]
        jitter: f64,
    },
    /// Flocking that keeps optical contact: every vehicle beacons its heading; it aligns with
    /// the headings it hears, turns towards the modem that hears the weakest neighbours
    /// (cohesion) and away from the strongest (separation), and pushes forward with `surge`.
    /// Alone, it heads for where it last heard the others; after 20 s it searches on the spot.
    Flock {
        /// Forward force \[N\].
        surge: f64,
        /// Beacon interval \[s\].
        #[serde(default = "d_flock_period")]
        period: f64,
        /// Received power above which a neighbour is too close \[W\].
        #[serde(default = "d_too_close")]
        too_close: f64,
        /// Received power below which a neighbour is drifting away \[W\].
        #[serde(default = "d_too_far")]
        too_far: f64,
        /// Weight of cohesion and separation against alignment [-].
        #[serde(default = "d_cohesion")]
        cohesion: f64,
    },
}

fn d_payload() -> usize {
    26
}
fn d_gossip_start() -> f64 {
    1.0
}
fn d_repeats() -> u32 {
    3
}
fn d_interval() -> f64 {
    0.3
}
fn d_jitter() -> f64 {
    0.1
}
fn d_flock_period() -> f64 {
    0.5
}
fn d_too_close() -> f64 {
    2e-7
}
fn d_too_far() -> f64 {
    3e-8
}
fn d_cohesion() -> f64 {
    0.5
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
}

impl Default for OutputSpec {
    fn default() -> Self {
        Self {
            record_hz: d_record_hz(),
            plots: true,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Vehicle model schema
// ---------------------------------------------------------------------------------------------

/// A 3×3 matrix: its diagonal, or all rows.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Mat3Spec {
    /// Diagonal.
    Diagonal([f64; 3]),
    /// Rows.
    Full([[f64; 3]; 3]),
}

/// A 6×6 matrix: its diagonal, or all rows.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Mat6Spec {
    /// Diagonal.
    Diagonal([f64; 6]),
    /// Rows.
    Full(Box<[[f64; 6]; 6]>),
}

/// A complete vehicle model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleSpec {
    /// Name of the vehicle kind.
    pub name: String,
    /// Hull.
    pub body: BodySpec,
    /// Tilt drives.
    #[serde(default)]
    pub tilts: Vec<TiltSpec>,
    /// Thrusters.
    #[serde(default)]
    pub thrusters: Vec<ThrusterSpec>,
    /// Buoyancy tank.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ballast: Option<BallastSpec>,
    /// Pressure sensor.
    pub pressure: PressureSpec,
    /// IMU.
    pub imu: ImuSpec,
    /// Controller.
    pub control: ControlSpec,
    /// Optical modems.
    #[serde(default)]
    pub modems: Vec<ModemSpec>,
    /// Model extensions switched on (catalogue in `shoal_model::effects`), e.g. as found and
    /// fitted by `shoal validate`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub effects: Vec<EffectSpec>,
}

/// A model extension with its parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EffectSpec {
    /// Catalogue name (e.g. `thruster_lag`).
    pub name: String,
    /// Form of the family (e.g. `second_order`; `shoal effects` lists them); absent: the
    /// family's default form.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub form: Option<String>,
    /// Every parameter of the effect by name, each in the unit its name ends with (e.g.
    /// `tau_s` in seconds); `shoal validate` writes them, `shoal check` lists the bounds.
    #[serde(default)]
    pub params: BTreeMap<String, f64>,
}

/// Medium access as written in files.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AccessSpec {
    /// Unslotted ALOHA.
    Aloha,
    /// Listen before talk.
    CarrierSense,
}

fn m0() -> ModemParams {
    presets::uauv2_modem()
}
macro_rules! modem_default {
    ($($f:ident: $t:ty = |$m:ident| $e:expr;)*) => { $( fn $f() -> $t { let $m = m0(); $e } )* };
}
modem_default! {
    dm_name: String = |m| m.name;
    dm_position: [f64; 3] = |m| a3(&m.position);
    dm_direction: [f64; 3] = |m| a3(&m.direction);
    dm_led_power: f64 = |m| m.led.power;
    dm_led_half_angle_deg: f64 = |m| m.led.half_angle.to_degrees();
    dm_rx_area: f64 = |m| m.rx.area;
    dm_rx_fov_deg: f64 = |m| m.rx.fov.to_degrees();
    dm_responsivity: f64 = |m| m.rx.responsivity;
    dm_noise_density: f64 = |m| m.rx.noise_density;
    dm_bandwidth: f64 = |m| m.rx.bandwidth;
    dm_dark_current: f64 = |m| m.rx.dark_current;
    dm_bit_rate: f64 = |m| m.bit_rate;
    dm_bits_per_byte: u32 = |m| m.bits_per_byte;
    dm_header_bytes: usize = |m| m.header_bytes;
    dm_max_payload: usize = |m| m.max_payload;
    dm_queue_frames: usize = |m| m.queue_frames;
    dm_capture_ratio: f64 = |m| m.capture_ratio;
}
fn dm_access() -> AccessSpec {
    AccessSpec::Aloha
}
fn dm_cs_threshold() -> f64 {
    1e-9
}
fn dm_backoff_max() -> f64 {
    0.05
}

/// An optical modem (see [`ModemParams`]); every field defaults to the μAUV²'s modem.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModemSpec {
    /// Name.
    #[serde(default = "dm_name")]
    pub name: String,
    /// Position on the hull, body frame \[m\].
    #[serde(default = "dm_position")]
    pub position: [f64; 3],
    /// LED axis and photodiode normal, body frame (normalised on load).
    #[serde(default = "dm_direction")]
    pub direction: [f64; 3],
    /// LED optical power \[W\].
    #[serde(default = "dm_led_power")]
    pub led_power: f64,
    /// LED half-power half-angle \[deg\].
    #[serde(default = "dm_led_half_angle_deg")]
    pub led_half_angle_deg: f64,
    /// Photodiode area \[m²\].
    #[serde(default = "dm_rx_area")]
    pub rx_area: f64,
    /// Receiver field of view, half-angle \[deg\].
    #[serde(default = "dm_rx_fov_deg")]
    pub rx_fov_deg: f64,
    /// Responsivity [A/W].
    #[serde(default = "dm_responsivity")]
    pub responsivity: f64,
    /// Amplifier noise density [A/√Hz].
    #[serde(default = "dm_noise_density")]
    pub noise_density: f64,
    /// Noise bandwidth \[Hz\].
    #[serde(default = "dm_bandwidth")]
    pub bandwidth: f64,
    /// Dark current \[A\].
    #[serde(default = "dm_dark_current")]
    pub dark_current: f64,
    /// Line rate [bit/s].
    #[serde(default = "dm_bit_rate")]
    pub bit_rate: f64,
    /// Line bits per byte.
    #[serde(default = "dm_bits_per_byte")]
    pub bits_per_byte: u32,
    /// Header per frame \[bytes\].
    #[serde(default = "dm_header_bytes")]
    pub header_bytes: usize,
    /// Largest payload \[bytes\].
    #[serde(default = "dm_max_payload")]
    pub max_payload: usize,
    /// Transmit queue \[frames\].
    #[serde(default = "dm_queue_frames")]
    pub queue_frames: usize,
    /// Capture ratio (optical power ratio ≥ 1).
    #[serde(default = "dm_capture_ratio")]
    pub capture_ratio: f64,
    /// Medium access.
    #[serde(default = "dm_access")]
    pub access: AccessSpec,
    /// Carrier-sense busy threshold \[W\] (carrier_sense only).
    #[serde(default = "dm_cs_threshold")]
    pub cs_threshold: f64,
    /// Longest carrier-sense back-off \[s\] (carrier_sense only).
    #[serde(default = "dm_backoff_max")]
    pub backoff_max: f64,
}

impl ModemSpec {
    /// Model parameters (degrees → radians, axis normalised).
    pub fn to_params(&self) -> ModemParams {
        ModemParams {
            name: self.name.clone(),
            position: v3(self.position),
            direction: unit_or_x(self.direction),
            led: Led {
                power: self.led_power,
                half_angle: self.led_half_angle_deg.to_radians(),
            },
            rx: Receiver {
                area: self.rx_area,
                fov: self.rx_fov_deg.to_radians(),
                responsivity: self.responsivity,
                noise_density: self.noise_density,
                bandwidth: self.bandwidth,
                dark_current: self.dark_current,
            },
            bit_rate: self.bit_rate,
            bits_per_byte: self.bits_per_byte,
            header_bytes: self.header_bytes,
            max_payload: self.max_payload,
            queue_frames: self.queue_frames,
            capture_ratio: self.capture_ratio,
            access: match self.access {
                AccessSpec::Aloha => Access::Aloha,
                AccessSpec::CarrierSense => Access::CarrierSense {
                    threshold: self.cs_threshold,
                    backoff_max: self.backoff_max,
                },
            },
        }
    }

    /// File form of model parameters.
    pub fn from_params(m: &ModemParams) -> Self {
        let (access, cs_threshold, backoff_max) = match m.access {
            Access::Aloha => (AccessSpec::Aloha, dm_cs_threshold(), dm_backoff_max()),
            Access::CarrierSense {
                threshold,
                backoff_max,
            } => (AccessSpec::CarrierSense, threshold, backoff_max),
        };
        Self {
            name: m.name.clone(),
            position: a3(&m.position),
            direction: a3(&m.direction),
            led_power: m.led.power,
            led_half_angle_deg: m.led.half_angle.to_degrees(),
            rx_area: m.rx.area,
            rx_fov_deg: m.rx.fov.to_degrees(),
            responsivity: m.rx.responsivity,
            noise_density: m.rx.noise_density,
            bandwidth: m.rx.bandwidth,
            dark_current: m.rx.dark_current,
            bit_rate: m.bit_rate,
            bits_per_byte: m.bits_per_byte,
            header_bytes: m.header_bytes,
            max_payload: m.max_payload,
            queue_frames: m.queue_frames,
            capture_ratio: m.capture_ratio,
            access,
            cs_threshold,
            backoff_max,
        }
    }
}

/// Hull parameters (see [`BodyParams`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Dry mass \[kg\].
    pub mass: f64,
    /// Inertia about the dry CG [kg·m²].
    pub inertia: Mat3Spec,
    /// Dry centre of gravity, body frame \[m\].
    pub cog: [f64; 3],
    /// Centre of buoyancy, body frame \[m\].
    pub cob: [f64; 3],
    /// Displaced volume \[m³\].
    pub volume: f64,
    /// Added mass M_A [kg, kg·m, kg·m²].
    pub added_mass: Mat6Spec,
    /// Linear damping (X_u, Y_v, Z_w [N·s/m], K_p, M_q, N_r [N·m·s]).
    pub damping_linear: [f64; 6],
    /// Quadratic damping (X_u|u|, Y_v|v|, Z_w|w| [N·s²/m²], K_p|p|, M_q|q|, N_r|r| [N·m·s²]).
    pub damping_quadratic: [f64; 6],
    /// Hull length, width, height \[m\].
    pub hull_size: [f64; 3],
}

/// Tilt drive (see [`TiltParams`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TiltSpec {
    /// Name.
    pub name: String,
    /// Body-frame axis (normalised on load).
    pub axis: [f64; 3],
    /// Lower limit \[deg\].
    pub min_deg: f64,
    /// Upper limit \[deg\].
    pub max_deg: f64,
    /// Rate limit [deg/s].
    pub rate_deg_s: f64,
}

/// Thrust curve.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum CurveSpec {
    /// f = C⁺n² (n ≥ 0), −C⁻n² (n < 0), n in %.
    Quadratic {
        /// C⁺ [N/%²].
        ct_pos: f64,
        /// C⁻ magnitude [N/%²].
        ct_neg: f64,
    },
    /// Table of [command %, thrust N] pairs, increasing in command.
    Table {
        /// The pairs.
        points: Vec<[f64; 2]>,
    },
}

/// Thruster (see [`ThrusterParams`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThrusterSpec {
    /// Name.
    pub name: String,
    /// Body-frame position \[m\].
    pub position: [f64; 3],
    /// Thrust direction at tilt 0, body frame (normalised on load).
    pub direction: [f64; 3],
    /// Name of the tilt drive that turns it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tilt: Option<String>,
    /// Thrust curve.
    pub curve: CurveSpec,
    /// Command limit [%].
    #[serde(default = "d_max_command")]
    pub max_command: f64,
    /// First-order thrust lag time constant \[s\] (0 = none).
    #[serde(default)]
    pub lag: f64,
}

/// Buoyancy tank (see [`BallastParams`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BallastSpec {
    /// Capacity \[m³\].
    pub capacity: f64,
    /// Pump flow [m³/s].
    pub flow: f64,
    /// Tank water centre, body frame \[m\].
    pub position: [f64; 3],
    /// Water aboard at the start \[m³\].
    pub initial_volume: f64,
}

/// Pressure sensor (see [`PressureSensorParams`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PressureSpec {
    /// C₁ [m/V].
    pub c1: f64,
    /// C₂ \[m\].
    pub c2: f64,
    /// Depth per ADC step \[m\].
    pub depth_step: f64,
    /// ADC bits.
    pub bits: u32,
    /// Noise standard deviation \[m\].
    pub noise_std: f64,
    /// Port position, body frame \[m\].
    pub position: [f64; 3],
}

/// IMU (see [`ImuParams`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImuSpec {
    /// Attitude noise per axis \[deg\].
    pub attitude_noise_deg: f64,
    /// Gyro noise [rad/s].
    pub gyro_noise: f64,
    /// Gyro bias [rad/s].
    pub gyro_bias: [f64; 3],
    /// Accelerometer noise [m/s²].
    pub accel_noise: f64,
}

/// PD design (see [`PdDesign`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PdSpec {
    /// Natural frequency [rad/s].
    pub omega: f64,
    /// Damping ratio [-].
    pub zeta: f64,
    /// Explicit K_P [N/m or N·m/rad].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kp: Option<f64>,
    /// Explicit K_D [N·s/m or N·m·s/rad].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kd: Option<f64>,
}

/// Controller (see [`ControlParams`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControlSpec {
    /// Control period \[s\].
    pub period: f64,
    /// Heave PD (diving, auto).
    pub heave: PdSpec,
    /// Heave PD (buoyancy mode).
    pub heave_buoyancy: PdSpec,
    /// Yaw PD.
    pub yaw: PdSpec,
    /// Pump dead zone \[m\].
    pub dead_zone: f64,
    /// Moving-average window \[samples\].
    pub filter_window: usize,
    /// Largest |β| in auto mode \[deg\].
    pub auto_tilt_max_deg: f64,
    /// Depth-rate filter time constant \[s\].
    pub rate_filter: f64,
}

fn v3(a: [f64; 3]) -> Vec3 {
    Vec3::new(a[0], a[1], a[2])
}
fn a3(v: &Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}
fn a6(v: &Vec6) -> [f64; 6] {
    [v[0], v[1], v[2], v[3], v[4], v[5]]
}

impl Mat3Spec {
    fn to_matrix(&self) -> Mat3 {
        match self {
            Mat3Spec::Diagonal(d) => Mat3::from_diagonal(&v3(*d)),
            Mat3Spec::Full(r) => Mat3::from_fn(|i, j| r[i][j]),
        }
    }
    fn from_matrix(m: &Mat3) -> Self {
        if m.is_diagonal(0.0) {
            Mat3Spec::Diagonal([m[(0, 0)], m[(1, 1)], m[(2, 2)]])
        } else {
            Mat3Spec::Full(std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)])))
        }
    }
}

trait IsDiagonal {
    fn is_diagonal(&self, eps: f64) -> bool;
}
impl<const N: usize> IsDiagonal for nalgebra::SMatrix<f64, N, N> {
    fn is_diagonal(&self, eps: f64) -> bool {
        (0..N).all(|i| (0..N).all(|j| i == j || self[(i, j)].abs() <= eps))
    }
}

impl Mat6Spec {
    fn to_matrix(&self) -> Mat6 {
        match self {
            Mat6Spec::Diagonal(d) => Mat6::from_diagonal(&Vec6::from_row_slice(d)),
            Mat6Spec::Full(r) => Mat6::from_fn(|i, j| r[i][j]),
        }
    }
    fn from_matrix(m: &Mat6) -> Self {
        if m.is_diagonal(0.0) {
            Mat6Spec::Diagonal(std::array::from_fn(|i| m[(i, i)]))
        } else {
            Mat6Spec::Full(Box::new(std::array::from_fn(|i| {
                std::array::from_fn(|j| m[(i, j)])
            })))
        }
    }
}

fn pd_to(p: &PdSpec) -> PdDesign {
    PdDesign {
        omega: p.omega,
        zeta: p.zeta,
        kp: p.kp,
        kd: p.kd,
    }
}
fn pd_from(p: &PdDesign) -> PdSpec {
    PdSpec {
        omega: p.omega,
        zeta: p.zeta,
        kp: p.kp,
        kd: p.kd,
    }
}

fn unit_or_x(a: [f64; 3]) -> nalgebra::Unit<Vec3> {
    nalgebra::Unit::try_new(v3(a), 1e-12).unwrap_or(Vec3::x_axis())
}

impl VehicleSpec {
    /// The model parameters (angles converted to radians, directions normalised). Call only
    /// after validation: unknown tilt names map to no tilt.
    pub fn to_params(&self) -> VehicleParams {
        let b = &self.body;
        let tilt_index = |n: &Option<String>| {
            n.as_ref()
                .and_then(|n| self.tilts.iter().position(|t| &t.name == n))
        };
        VehicleParams {
            name: self.name.clone(),
            body: BodyParams {
                mass: b.mass,
                inertia_cg: b.inertia.to_matrix(),
                cog: v3(b.cog),
                cob: v3(b.cob),
                volume: b.volume,
                added_mass: b.added_mass.to_matrix(),
                damping_linear: Vec6::from_row_slice(&b.damping_linear),
                damping_quadratic: Vec6::from_row_slice(&b.damping_quadratic),
                hull_size: v3(b.hull_size),
            },
            thrusters: self
                .thrusters
                .iter()
                .map(|t| ThrusterParams {
                    name: t.name.clone(),
                    position: v3(t.position),
                    direction: unit_or_x(t.direction),
                    tilt: tilt_index(&t.tilt),
                    curve: match &t.curve {
                        CurveSpec::Quadratic { ct_pos, ct_neg } => ThrustCurve::Quadratic {
                            ct_pos: *ct_pos,
                            ct_neg: *ct_neg,
                        },
                        CurveSpec::Table { points } => ThrustCurve::Table {
                            points: points.iter().map(|p| (p[0], p[1])).collect(),
                        },
                    },
                    max_command: t.max_command,
                    lag: t.lag,
                    lag_down: -1.0,
                    lag_stages: 1,
                })
                .collect(),
            tilts: self
                .tilts
                .iter()
                .map(|t| TiltParams {
                    name: t.name.clone(),
                    axis: unit_or_x(t.axis),
                    min: t.min_deg.to_radians(),
                    max: t.max_deg.to_radians(),
                    rate_max: t.rate_deg_s.to_radians(),
                })
                .collect(),
            ballast: self.ballast.as_ref().map(|b| BallastParams {
                capacity: b.capacity,
                flow: b.flow,
                position: v3(b.position),
                initial_volume: b.initial_volume,
            }),
            pressure: PressureSensorParams {
                c1: self.pressure.c1,
                c2: self.pressure.c2,
                depth_step: self.pressure.depth_step,
                bits: self.pressure.bits,
                noise_std: self.pressure.noise_std,
                position: v3(self.pressure.position),
            },
            imu: ImuParams {
                attitude_noise: self.imu.attitude_noise_deg.to_radians(),
                gyro_noise: self.imu.gyro_noise,
                gyro_bias: v3(self.imu.gyro_bias),
                accel_noise: self.imu.accel_noise,
            },
            control: ControlParams {
                period: self.control.period,
                heave: pd_to(&self.control.heave),
                heave_buoyancy: pd_to(&self.control.heave_buoyancy),
                yaw: pd_to(&self.control.yaw),
                dead_zone: self.control.dead_zone,
                filter_window: self.control.filter_window,
                auto_tilt_max: self.control.auto_tilt_max_deg.to_radians(),
                rate_filter: self.control.rate_filter,
            },
            modems: self.modems.iter().map(ModemSpec::to_params).collect(),
        }
    }

    /// The file form of model parameters.
    pub fn from_params(p: &VehicleParams) -> Self {
        let b = &p.body;
        VehicleSpec {
            name: p.name.clone(),
            body: BodySpec {
                mass: b.mass,
                inertia: Mat3Spec::from_matrix(&b.inertia_cg),
                cog: a3(&b.cog),
                cob: a3(&b.cob),
                volume: b.volume,
                added_mass: Mat6Spec::from_matrix(&b.added_mass),
                damping_linear: a6(&b.damping_linear),
                damping_quadratic: a6(&b.damping_quadratic),
                hull_size: a3(&b.hull_size),
            },
            tilts: p
                .tilts
                .iter()
                .map(|t| TiltSpec {
                    name: t.name.clone(),
                    axis: a3(&t.axis),
                    min_deg: t.min.to_degrees(),
                    max_deg: t.max.to_degrees(),
                    rate_deg_s: t.rate_max.to_degrees(),
                })
                .collect(),
            thrusters: p
                .thrusters
                .iter()
                .map(|t| ThrusterSpec {
                    name: t.name.clone(),
                    position: a3(&t.position),
                    direction: a3(&t.direction),
                    tilt: t.tilt.map(|k| p.tilts[k].name.clone()),
                    curve: match &t.curve {
                        ThrustCurve::Quadratic { ct_pos, ct_neg } => CurveSpec::Quadratic {
                            ct_pos: *ct_pos,
                            ct_neg: *ct_neg,
                        },
                        ThrustCurve::Table { points } => CurveSpec::Table {
                            points: points.iter().map(|&(c, f)| [c, f]).collect(),
                        },
                    },
                    max_command: t.max_command,
                    lag: t.lag,
                })
                .collect(),
            ballast: p.ballast.as_ref().map(|b| BallastSpec {
                capacity: b.capacity,
                flow: b.flow,
                position: a3(&b.position),
                initial_volume: b.initial_volume,
            }),
            pressure: PressureSpec {
                c1: p.pressure.c1,
                c2: p.pressure.c2,
                depth_step: p.pressure.depth_step,
                bits: p.pressure.bits,
                noise_std: p.pressure.noise_std,
                position: a3(&p.pressure.position),
            },
            imu: ImuSpec {
                attitude_noise_deg: p.imu.attitude_noise.to_degrees(),
                gyro_noise: p.imu.gyro_noise,
                gyro_bias: a3(&p.imu.gyro_bias),
                accel_noise: p.imu.accel_noise,
            },
            control: ControlSpec {
                period: p.control.period,
                heave: pd_from(&p.control.heave),
                heave_buoyancy: pd_from(&p.control.heave_buoyancy),
                yaw: pd_from(&p.control.yaw),
                dead_zone: p.control.dead_zone,
                filter_window: p.control.filter_window,
                auto_tilt_max_deg: p.control.auto_tilt_max.to_degrees(),
                rate_filter: p.control.rate_filter,
            },
            modems: p.modems.iter().map(ModemSpec::from_params).collect(),
            effects: Vec::new(),
        }
    }

    /// The effects for a vehicle with parameters `params` (from [`VehicleSpec::to_params`]).
    /// Call only after validation: unknown effects are skipped and missing parameters take
    /// their null values.
    pub fn effects(&self, params: &VehicleParams) -> shoal_model::effects::Effects {
        use shoal_model::effects::{EffectInstance, Effects, by_name_form};
        Effects::new(
            self.effects
                .iter()
                .filter_map(|e| {
                    let effect = by_name_form(&e.name, e.form.as_deref())?;
                    let values = effect
                        .params(params)
                        .iter()
                        .map(|p| e.params.get(p.name).copied().unwrap_or(p.null))
                        .collect();
                    Some(EffectInstance {
                        effect,
                        params: values,
                    })
                })
                .collect(),
        )
    }

    /// The file form of a list of effects.
    pub fn effect_specs(
        list: &[shoal_model::effects::EffectInstance],
        params: &VehicleParams,
    ) -> Vec<EffectSpec> {
        list.iter()
            .map(|e| EffectSpec {
                name: e.effect.name().to_string(),
                form: (shoal_model::effects::forms(e.effect.name()).first()
                    != Some(&e.effect.form()))
                .then(|| e.effect.form().to_string()),
                params: e
                    .effect
                    .params(params)
                    .iter()
                    .zip(&e.params)
                    .map(|(p, &x)| (p.name.to_string(), x))
                    .collect(),
            })
            .collect()
    }
}
