//! Vehicle groups: how many vehicles of which model, their placement (one position, a grid or
//! random in a box), heading and mission steps, and the behaviour or agent that drives them.

use super::BehaviourSpec;
use serde::{Deserialize, Serialize};
use shoal_model::prelude::{Mode, Pump};
use std::collections::BTreeMap;

fn d_count() -> usize {
    1
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
    /// Medium access of every modem of the model, as a modem's `access` (a protocol's name,
    /// or a table with its `kind` and settings): said once for the group, the preset's modems
    /// included; a modem of `model` must then not set its own.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub access: Option<toml::Value>,
    /// Retransmissions of an unacknowledged unicast frame for every modem of the model, as a
    /// modem's `arq_retries`; a modem of `model` must then not set its own.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub arq_retries: Option<toml::Value>,
    /// Wait for an acknowledgement after a frame ended, for every modem of the model, as a
    /// modem's `ack_timeout` \[s\]; a modem of `model` must then not set its own.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ack_timeout: Option<toml::Value>,
    /// A built-in swarm behaviour run on every control tick.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub behaviour: Option<BehaviourSpec>,
    /// Name of the external agent process that drives this group (see `[agents]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub agent: Option<String>,
}

impl VehicleGroupSpec {
    /// The link-layer settings the group gives for every modem of its model (`access`,
    /// `arq_retries`, `ack_timeout`), by name, those it gives.
    pub fn link(&self) -> Vec<(&'static str, &toml::Value)> {
        [
            ("access", &self.access),
            ("arq_retries", &self.arq_retries),
            ("ack_timeout", &self.ack_timeout),
        ]
        .into_iter()
        .filter_map(|(k, v)| v.as_ref().map(|v| (k, v)))
        .collect()
    }
}
