//! Writing a vehicle model back as a world file.

use crate::spec::*;

/// Writes a vehicle model as a world file with one vehicle group (`preset = "custom"`), which
/// `shoal run` can load directly.
pub fn vehicle_world_toml(
    spec: &VehicleSpec,
    position: [f64; 3],
) -> Result<String, toml::ser::Error> {
    flight_world_toml(
        spec,
        &Flight {
            position,
            heading_deg: 0.0,
            duration: d_duration_pub(),
            mission: Vec::new(),
            pool: PoolSpec::default(),
            output: OutputSpec::default(),
        },
    )
}

/// One vehicle's flight in a world of its own: where it starts, what it is told, how long,
/// in which pool, and what the run writes.
#[derive(Clone, Debug)]
pub struct Flight {
    /// Initial position of the body origin \[m\].
    pub position: [f64; 3],
    /// Initial heading \[deg\].
    pub heading_deg: f64,
    /// Length of the run \[s\].
    pub duration: f64,
    /// The mission's steps.
    pub mission: Vec<MissionStepSpec>,
    /// The pool.
    pub pool: PoolSpec,
    /// What the run writes.
    pub output: OutputSpec,
}

/// Writes a vehicle model and its flight as a world file with one vehicle group (`preset =
/// "custom"`), which `shoal run` can load directly.
pub fn flight_world_toml(spec: &VehicleSpec, flight: &Flight) -> Result<String, toml::ser::Error> {
    let model = match toml::Value::try_from(spec)? {
        toml::Value::Table(t) => t,
        _ => toml::Table::new(),
    };
    let wf = WorldFile {
        name: Some(spec.name.clone()),
        seed: 0,
        duration: flight.duration,
        dt: 0.01,
        integrator: IntegratorSpec::Rk4,
        pool: flight.pool.clone(),
        water: WaterSpec::default(),
        obstacles: Vec::new(),
        vehicles: vec![VehicleGroupSpec {
            name: Some(spec.name.clone()),
            preset: Some("custom".into()),
            count: 1,
            position: Some(flight.position),
            grid: None,
            random: None,
            heading_deg: flight.heading_deg,
            mission: flight.mission.clone(),
            model: Some(model),
            access: None,
            arq_retries: None,
            ack_timeout: None,
            behaviour: None,
            agent: None,
        }],
        output: flight.output.clone(),
        agents: AgentsSpec::default(),
        ros2: None,
    };
    toml::to_string(&wf)
}

pub(super) fn d_duration_pub() -> f64 {
    60.0
}
