//! `next_experiment.toml`: the suggested flight as a world file — the vehicle as given (not
//! the fitted model: the flight is for the real vehicle, or for whatever model a user wants
//! to try it on), started where the log's flight starts, its commands as raw-mode mission
//! steps, logged at the log's rate into `run.mcap`, which `shoal validate` reads back.

use super::NextExperiment;
use shoal_model::vehicle::VehicleParams;
use shoal_world::load::{Flight, flight_world_toml};
use shoal_world::spec::{MissionStepSpec, ModeSpec, OutputSpec, PoolSpec, PumpSpec, VehicleSpec};
use std::collections::BTreeMap;

/// Side of the square pool the flight is put in \[m\]: room for the longest holds at speed.
const POOL_SIDE_M: f64 = 40.0;

/// The mission steps of the experiment's schedule: raw mode, each change of a command a step
/// (thrusters in %, tilt drives in degrees, the pump as a word).
fn mission(x: &NextExperiment, params: &VehicleParams) -> Vec<MissionStepSpec> {
    let s = &x.schedule;
    s.steps
        .iter()
        .enumerate()
        .map(|(i, (t, values))| {
            let mut thrusters = BTreeMap::new();
            let mut tilts_deg = BTreeMap::new();
            let mut pump = None;
            for (name, v) in s.inputs.iter().zip(values) {
                if params.thrusters.iter().any(|th| &th.name == name) {
                    thrusters.insert(name.clone(), *v);
                } else if name == "pump" {
                    pump = Some(if *v > 0.0 {
                        PumpSpec::Fill
                    } else if *v < 0.0 {
                        PumpSpec::Empty
                    } else {
                        PumpSpec::Off
                    });
                } else {
                    tilts_deg.insert(name.clone(), v.to_degrees());
                }
            }
            MissionStepSpec {
                t: *t,
                mode: (i == 0).then_some(ModeSpec::Raw),
                depth: None,
                yaw_deg: None,
                surge: None,
                sway: None,
                thrusters,
                tilts_deg,
                pump,
            }
        })
        .collect()
}

/// A separation in words: `0.15 × the residual on y.depth (evidence 135)`.
pub fn describe(s: &super::Separation) -> String {
    format!(
        "{:.2} × the residual on {} (evidence {:.0})",
        s.ratio,
        s.channel.label(),
        s.evidence
    )
}

/// The text of `next_experiment.toml` for the vehicle `spec` (its header says what the flight
/// is for and how to use it; `log_name` names the log it follows).
pub fn world_toml(
    x: &NextExperiment,
    spec: &VehicleSpec,
    log_name: &str,
) -> Result<String, toml::ser::Error> {
    let params = spec.to_params();
    let (z, yaw) = x.start_pose(&params);
    let flight = Flight {
        position: [POOL_SIDE_M / 2.0, POOL_SIDE_M / 2.0, z],
        heading_deg: yaw.to_degrees(),
        duration: x.schedule.duration,
        mission: mission(x, &params),
        pool: PoolSpec {
            size: [POOL_SIDE_M, POOL_SIDE_M, (z + 3.0).max(5.0)],
        },
        output: OutputSpec {
            record_hz: 1.0 / x.period_s,
            plots: true,
            replay: false,
            mcap: true,
        },
    };
    let questions: Vec<String> = x
        .questions
        .iter()
        .map(|q| {
            let sep = |s: &Option<super::Separation>| s.map_or("—".to_string(), |s| describe(&s));
            format!(
                "#   {} or {}: apart by {} on the log's held-out part, by {} predicted here\n",
                q.a,
                q.b,
                sep(&q.on_log),
                sep(&q.on_flight)
            )
        })
        .collect();
    let header = format!(
        "# The next experiment `shoal validate` suggests after `{log_name}`: {} — {}.\n\
         # It answers what the log left open, the rival models' predictions apart by:\n{}\
         # Fly it (in the water, or here: shoal run next_experiment.toml), log the same channels\n\
         # and validate both logs together: shoal validate {log_name} <the new log> …\n",
        x.manoeuvre,
        x.what,
        questions.concat()
    );
    Ok(header + &flight_world_toml(spec, &flight)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiment::library::Schedule;
    use crate::log::run::ChannelKind;
    use shoal_model::ballast::Pump;
    use shoal_model::presets;
    use std::path::Path;

    /// The world file flies the schedule: loaded back, its mission has a step per change, in
    /// raw mode, with the thrusters in %, the tilt in radians again and the pump's three
    /// states; the vehicle starts level at the log's depth reading less the pressure port's
    /// height, heading as the log did.
    #[test]
    fn the_world_file_is_the_schedule() {
        let half_pi = std::f64::consts::FRAC_PI_2;
        let inputs = ["top", "port", "stbd", "beta", "pump"]
            .map(String::from)
            .to_vec();
        let steps = vec![
            (0.0, vec![0.0, 40.0, 40.0, -half_pi, 1.0]),
            (8.0, vec![0.0, -40.0, -40.0, -half_pi, 0.0]),
            (14.0, vec![0.0, 0.0, 0.0, -half_pi, -1.0]),
        ];
        let x = NextExperiment {
            manoeuvre: "test".into(),
            what: "a test".into(),
            questions: Vec::new(),
            schedule: Schedule {
                inputs,
                steps,
                duration: 30.0,
            },
            period_s: 0.05,
            start: vec![(ChannelKind::Depth, 1.2), (ChannelKind::Yaw, 0.5)],
            tried: Vec::new(),
        };
        let params = presets::uauv2();
        let spec = VehicleSpec::from_params(&params);
        let text = world_toml(&x, &spec, "log.csv").unwrap();
        let world = shoal_world::load::load_str(&text, Path::new("next_experiment.toml")).unwrap();
        assert_eq!(world.duration, 30.0);
        assert!((world.output.record_hz - 20.0).abs() < 1e-9 && world.output.mcap);
        let v = &world.vehicles[0];
        assert!((v.position.z - (1.2 - params.pressure.position.z)).abs() < 1e-12);
        let (_, _, yaw) = shoal_model::math::euler_rpy(&v.attitude);
        assert!((yaw - 0.5).abs() < 1e-9, "{yaw}");
        let m = &v.mission.steps;
        assert_eq!(m.len(), 3);
        assert_eq!(m[0].mode, Some(shoal_model::control::Mode::Raw));
        assert_eq!(m[1].mode, None);
        let pumps: Vec<_> = m.iter().map(|s| s.pump).collect();
        assert_eq!(
            pumps,
            [Some(Pump::Fill), Some(Pump::Off), Some(Pump::Empty)]
        );
        let port = params
            .thrusters
            .iter()
            .position(|t| t.name == "port")
            .unwrap();
        assert!(m[1].thrusters.contains(&(port, -40.0)));
        let beta = params.tilts.iter().position(|t| t.name == "beta").unwrap();
        let (_, b) = m[2].tilts.iter().find(|(i, _)| *i == beta).unwrap();
        assert!((b + half_pi).abs() < 1e-12, "{b}");
    }
}
