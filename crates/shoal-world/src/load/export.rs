//! Writing a vehicle model back as a world file.

use crate::spec::*;

/// Writes a vehicle model as a world file with one vehicle group (`preset = "custom"`), which
/// `shoal run` can load directly.
pub fn vehicle_world_toml(
    spec: &VehicleSpec,
    position: [f64; 3],
) -> Result<String, toml::ser::Error> {
    let model = match toml::Value::try_from(spec)? {
        toml::Value::Table(t) => t,
        _ => toml::Table::new(),
    };
    let wf = WorldFile {
        name: Some(spec.name.clone()),
        seed: 0,
        duration: d_duration_pub(),
        dt: 0.01,
        integrator: IntegratorSpec::Rk4,
        pool: PoolSpec::default(),
        water: WaterSpec::default(),
        obstacles: Vec::new(),
        vehicles: vec![VehicleGroupSpec {
            name: Some(spec.name.clone()),
            preset: Some("custom".into()),
            count: 1,
            position: Some(position),
            grid: None,
            random: None,
            heading_deg: 0.0,
            mission: Vec::new(),
            model: Some(model),
            behaviour: None,
            agent: None,
        }],
        output: OutputSpec::default(),
        agents: AgentsSpec::default(),
        ros2: None,
    };
    toml::to_string(&wf)
}

pub(super) fn d_duration_pub() -> f64 {
    60.0
}
