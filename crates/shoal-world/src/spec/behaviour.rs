//! What drives a vehicle besides its mission: the built-in swarm behaviours, and external
//! agents (`[agents]`: how they attach, lock-step or free timing, the fallback without them).

use serde::{Deserialize, Serialize};

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

/// The ROS 2 bridge (`[ros2]`): vehicle groups with `agent = "ros2"` are driven by ROS 2 nodes
/// over DDS (crate `shoal-ros2`); timing, timeouts, fallback and positions as in `[agents]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Ros2Spec {
    /// DDS domain (ROS_DOMAIN_ID), 0 … 232.
    #[serde(default)]
    pub domain_id: u16,
    /// ROS namespace of the vehicles' topics (`/<namespace>/<vehicle>/imu`); letters, digits
    /// and `_`, starting with a letter.
    #[serde(default = "d_ros2_namespace")]
    pub namespace: String,
    /// Free-running: simulated seconds per wall-clock second (real-time factor; 0: as fast as
    /// possible).
    #[serde(default = "d_rtf")]
    pub rtf: f64,
    /// Keep DDS on the loopback interface (no discovery traffic leaves the machine), as ROS 2's
    /// `ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST` does (which also turns it on).
    #[serde(default)]
    pub localhost_only: bool,
}

impl Default for Ros2Spec {
    fn default() -> Self {
        Self {
            domain_id: 0,
            namespace: d_ros2_namespace(),
            rtf: d_rtf(),
            localhost_only: false,
        }
    }
}

/// The agent name that puts a vehicle group on the ROS 2 bridge.
pub const ROS2_AGENT: &str = "ros2";

fn d_ros2_namespace() -> String {
    "shoal".into()
}

fn d_rtf() -> f64 {
    1.0
}

fn d_agent_timeout() -> f64 {
    1.0
}

fn d_attach_timeout() -> f64 {
    10.0
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
    /// Frames at the arrival times of a Poisson process of `rate` frames per second (offered
    /// traffic for studies of medium access), on every modem: broadcast, or for the vehicle
    /// named `to`, with acknowledgement and retries if `ack`.
    Poisson {
        /// Mean frames per second \[1/s\].
        rate: f64,
        /// Payload size \[bytes\].
        #[serde(default = "d_payload")]
        payload_bytes: usize,
        /// The destination vehicle's name (none: broadcast).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        to: Option<String>,
        /// Ask the destination to acknowledge (stop-and-wait ARQ).
        #[serde(default)]
        ack: bool,
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
    /// Leader of a formation: tells each follower (by name), by an acknowledged unicast every
    /// `period` seconds, the heading, depth and surge it steers for.
    Leader {
        /// The followers' names.
        followers: Vec<String>,
        /// Time between orders \[s\].
        #[serde(default = "d_order_period")]
        period: f64,
    },
    /// Follower of a formation: steers (auto mode) for the heading, depth and surge its
    /// leader last sent.
    Follower {},
    /// Flooding of a value by acknowledged unicasts: every vehicle says hello every `hello`
    /// seconds; one that knows the value hands it to each neighbour it has heard, one
    /// unicast each, acknowledged and retried by the link layer. The origin learns it at
    /// `start`.
    ReliableGossip {
        /// This group holds the origin.
        #[serde(default)]
        origin: bool,
        /// Time the value appears at the origin \[s\].
        #[serde(default = "d_gossip_start")]
        start: f64,
        /// Time between hellos \[s\].
        #[serde(default = "d_hello")]
        hello: f64,
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
fn d_order_period() -> f64 {
    1.0
}
fn d_hello() -> f64 {
    0.5
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
