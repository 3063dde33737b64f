//! The open-loop simulation of a measured run (its *replay*): the vehicle model driven
//! open-loop by the run's measured inputs.
//!
//! The inputs are held between their samples (zero-order hold). Thruster commands go through
//! the thrust model (curve, lag, effects); tilt angles are the measured angles and are set
//! directly (a log records where the drives stood, not where they were asked to go); the pump
//! command is −1/0/+1. The replay starts from the measured initial state (attitude, position
//! and rates from the first samples; a vehicle whose velocity is not measured starts at rest
//! relative to the water, as the experiments start at rest) and is sampled at the measurement times through the
//! deterministic part of the sensor models: the pressure port's depth (clamped at the
//! surface) plus any depth-sensor effect, attitude, gyro rates plus the gyro bias, tracked
//! position, velocity over ground, all delayed by any sensor delay.
//!
//! Quantisation and noise are not simulated: they are what the residual of a perfect model
//! consists of.
//!
//! A long run may be replayed in horizons, its measured states set to the data again at the
//! start of each ([`anchors`]: a re-anchored replay).
//!
//! A log that carries its controller's references may be given a closed-loop twin: the same
//! model with the controller in the loop, whose commands the replay's command channels show
//! ([`control`]).
//!
//! `setup.rs` holds what a replay starts from (input map, options, initial state),
//! `anchors.rs` where it is re-anchored, `control.rs` the controller of the closed-loop twin,
//! `simulate.rs` steps the model (its replay, its filter and its twin) and `trace.rs` holds
//! what it records.

pub mod anchors;
pub mod control;
mod setup;
mod simulate;
mod trace;

pub use setup::{InitialState, InputMap, MAX_REPLAY_STEPS, ReplayOptions, replay_steps};
pub use simulate::{simulate, simulate_many, simulate_with};
pub use trace::{Trace, grid_position};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::log::run::{ChannelKind, MeasuredRun};
    use shoal_model::rigid_body::Environment;
    use shoal_model::vehicle::VehicleModel;
    use std::path::Path;

    #[test]
    fn input_errors_name_the_file_line_after_comments() {
        let text = "# a comment\n# another\nt,u.port,y.depth\n0,10,1\n0.1,,1\n0.2,120,1\n";
        let mut run = MeasuredRun::parse(text, Path::new("r.csv")).unwrap();
        assert_eq!(run.header_line, 3);
        assert_eq!(run.lines, vec![4, 5, 6]);
        let params = shoal_model::presets::uauv2();
        // A command beyond ±100 % is reported on the row where it is set.
        let e = InputMap::new(&params, &mut run).unwrap_err();
        assert_eq!((e.line, e.column.clone()), (6, Some((2, "u.port".into()))));
        assert!(e.message.contains("−100 … 100 %"), "{}", e.message);
        // An unknown actuator is reported on the header line.
        let text = text.replace("u.port", "u.rudder");
        let mut run = MeasuredRun::parse(&text, Path::new("r.csv")).unwrap();
        let e = InputMap::new(&params, &mut run).unwrap_err();
        assert_eq!(
            (e.line, e.column.clone()),
            (3, Some((2, "u.rudder".into())))
        );
        assert!(e.message.contains("u.port"), "{}", e.message);
    }

    #[test]
    fn a_diving_log_at_the_tilt_limit_is_clamped_and_counted() {
        let mut text = String::from("t,u.top,u.port,u.stbd,u.alpha,u.beta,u.pump,y.depth\n");
        for i in 0..50 {
            let t = f64::from(i) * 0.02;
            text.push_str(&format!("{t},0,40,40,0,-1.5708,0,0.8\n"));
        }
        let mut run = MeasuredRun::parse(&text, Path::new("dive.csv")).unwrap();
        let params = shoal_model::presets::uauv2();
        let map = InputMap::new(&params, &mut run).unwrap();
        assert_eq!(map.clamped.len(), 1, "{:?}", map.clamped);
        let note = &map.clamped[0];
        assert_eq!(
            (note.name.as_str(), note.column, note.count),
            ("u.beta", 6, 50)
        );
        assert_eq!(note.limit, -std::f64::consts::FRAC_PI_2);
        assert!(note.to_string().contains("50 value(s)"), "{note}");
        let beta = run.input("beta").unwrap();
        assert!(
            beta.values
                .iter()
                .all(|&v| v == -std::f64::consts::FRAC_PI_2)
        );
        // The pump takes −1, 0, +1 only, and a failed check leaves the run as it was.
        for bad in ["0.5", "1e9"] {
            let text = text.replacen(
                ",-1.5708,0,0.8\n0.02,",
                &format!(",-1.5708,{bad},0.8\n0.02,"),
                1,
            );
            let mut run = MeasuredRun::parse(&text, Path::new("dive.csv")).unwrap();
            let before = run.clone();
            let e = InputMap::new(&params, &mut run).unwrap_err();
            assert_eq!(
                (e.line, e.column.clone()),
                (2, Some((7, "u.pump".into()))),
                "{e}"
            );
            assert!(
                e.message
                    .contains("allowed: −1 (empty), 0 (off), +1 (fill)"),
                "{e}"
            );
            assert_eq!(run, before);
        }
    }

    #[test]
    fn replay_steps_are_bounded() {
        let mut run =
            MeasuredRun::parse("t,u.port,y.depth\n0,1,1\n1000,1,1\n", Path::new("long.csv"))
                .unwrap();
        let opts = ReplayOptions::default();
        assert_eq!(opts.steps(&run).unwrap(), 100_000);
        for dt in [0.0, -1.0, f64::NAN, 1e-9, 0.5] {
            let e = ReplayOptions { dt, ..opts }.steps(&run).unwrap_err();
            assert!(e.message.contains("allowed: 0.0001 … 0.1 s"), "{dt}: {e}");
        }
        run.t[1] = 1e9;
        let e = opts.steps(&run).unwrap_err();
        assert!(e.message.starts_with("run `long`"), "{e}");
        assert!(e.message.contains("at most 1e7"), "{e}");
        // Even unchecked, a replay never runs past the bound.
        let model = VehicleModel::new(shoal_model::presets::uauv2(), 1000.0);
        let map = InputMap::new(&model.params, &mut run).unwrap();
        let init = InitialState::from_run(&model.params, &run, 0.5);
        let trace = simulate(
            &model,
            &Environment::default(),
            &run,
            &map,
            &init,
            &[ChannelKind::Depth],
            &ReplayOptions {
                dt: f64::NAN,
                ..opts
            },
        );
        assert_eq!(trace.len(), 1);
    }
}
