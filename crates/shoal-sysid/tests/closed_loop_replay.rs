//! The controller in the replay (`evaluate::open_loop::control`, `evaluate::controlled`): a
//! mission log that carries its controller's references is replayed with a closed-loop twin —
//! the same model with the vehicle's own controller reading the twin's sensors and following
//! the logged references — and the logged thruster commands are compared, as channels, with
//! the twin's.
//!
//! The missions here are flown by the test kit (`shoal_testkit::mission::fly`) with noise-free
//! sensors (no noise, a 1-nm depth step) in still water, at the replay's own physics step, so
//! that a replay of the true model must send the logged commands to within rounding; what the
//! model gets wrong then shows in the commands.

use shoal_model::effects::{EffectInstance, Effects, by_name_form};
use shoal_model::presets;
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::{VehicleModel, VehicleParams};
use shoal_sysid::evaluate::anchoring::Horizon;
use shoal_sysid::evaluate::dataset::{DataOptions, Dataset};
use shoal_sysid::evaluate::evaluation::Evaluation;
use shoal_sysid::evaluate::open_loop::ReplayOptions;
use shoal_sysid::log::run::{ChannelKind, MeasuredRun};
use shoal_testkit::mission::{Disturbance, fly, uauv2_mission};

/// Physics step of the flights and the replays \[s\].
const DT: f64 = 0.005;

/// The μAUV² preset with sensors that neither add noise nor round.
fn clean_sensors() -> VehicleParams {
    let mut p = presets::uauv2();
    p.pressure.noise_std = 0.0;
    p.pressure.depth_step = 1e-9;
    p.pressure.bits = 32;
    p.imu.attitude_noise = 0.0;
    p.imu.gyro_noise = 0.0;
    p.imu.accel_noise = 0.0;
    p
}

fn with(effect: &str, form: Option<&str>, params: &[f64]) -> VehicleModel {
    let effect = by_name_form(effect, form).expect("a catalogue effect");
    VehicleModel::with_effects(
        clean_sensors(),
        Effects::new(vec![EffectInstance {
            effect,
            params: params.to_vec(),
        }]),
        1000.0,
    )
}

/// Mission `seed`, `length` seconds, flown by `truth` under the preset's controller.
fn flown(truth: &VehicleModel, seed: u64, length: f64) -> MeasuredRun {
    let designed = VehicleModel::new(clean_sensors(), 1000.0);
    let plan = uauv2_mission(seed, length);
    fly(
        truth,
        &designed,
        &Environment::default(),
        &plan,
        &Disturbance::NONE,
        DT,
        seed,
        &mut (),
    )
}

/// The run replayed on `model` with its closed-loop twin (`--horizon closed`: re-anchored with
/// the logged commands; the twin, the controller designed on the clean preset in the loop,
/// predicts the command channels).
fn replayed(run: &MeasuredRun, model: &VehicleModel) -> (Dataset, Evaluation) {
    let params = clean_sensors();
    let mut ds = Dataset::new(
        &params,
        Environment::default(),
        vec![run.clone()],
        vec![],
        &DataOptions {
            replay: ReplayOptions {
                dt: DT,
                ..Default::default()
            },
            ..Default::default()
        },
    )
    .expect("a dataset");
    ds.anchor(Horizon::Closed, &VehicleModel::new(params, 1000.0));
    let ev = ds.evaluate(model);
    (ds, ev)
}

/// RMS of a command channel's residual over the whole run, and RMS of the command itself \[%\].
fn command_rms(ev: &Evaluation, thruster: &str) -> (f64, f64) {
    let kind = ChannelKind::command(thruster);
    let c = ev.runs[0]
        .channels
        .iter()
        .find(|c| c.kind == kind)
        .expect("a command channel");
    let rms = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt();
    (rms(&c.resid), rms(&c.measured))
}

/// Replayed closed loop, the true model sends the commands the log holds — to within the
/// logger's rounding (the kit logs full precision) and a few 1e-3 % from where the flight and the
/// replay integrate differently (the flight steps the hull between control ticks with its
/// own stepper) — and its depth and heading stay on the logged ones; every leg of the mission
/// (diving, buoyancy with the pump, turning, drift, auto) is in it.
#[test]
fn replayed_with_its_controller_the_true_model_sends_the_logged_commands() {
    let truth = VehicleModel::new(clean_sensors(), 1000.0);
    let run = flown(&truth, 3, 240.0);
    let (ds, ev) = replayed(&run, &truth);
    assert!(ds.anchoring.closed_loop, "{}", ds.anchoring.why);
    for th in ["port", "stbd", "top"] {
        let (resid, cmd) = command_rms(&ev, th);
        assert!(cmd > 5.0, "{th}: the mission commands {cmd} % RMS");
        assert!(resid < 1e-3 * cmd, "{th}: {resid} % off a {cmd} % command");
    }
    let depth = &ev.metrics[&ChannelKind::Depth];
    assert!(depth.rmse < 1e-4, "depth {} m off", depth.rmse);
}

/// A battery that sags is answered by larger commands while the depth stays where it was asked
/// to be: the log of a hull that loses a fifth of its thrust over four minutes is replayed by
/// the baseline with a command error that grows towards the end (the controller in the replay
/// needs less), and by the true model with none; relative to what they vary, the depth
/// shows a fraction of it.
#[test]
fn a_sagging_battery_shows_in_the_commands_not_in_the_depth() {
    // 1 − a·(t/100 s)², a such that 20 % is lost by 240 s.
    let a = 0.2 / 2.4f64.powi(2);
    let truth = with("battery_sag", Some("power"), &[a, 2.0]);
    let run = flown(&truth, 5, 240.0);
    let baseline = VehicleModel::new(clean_sensors(), 1000.0);
    let (_, ev_base) = replayed(&run, &baseline);
    let (_, ev_true) = replayed(&run, &truth);
    for th in ["port", "stbd"] {
        let (base, cmd) = command_rms(&ev_base, th);
        let (tru, _) = command_rms(&ev_true, th);
        assert!(
            base > 0.03 * cmd,
            "{th}: baseline {base} % off a {cmd} % command"
        );
        assert!(
            tru < 0.01 * base,
            "{th}: true model {tru} %, baseline {base} %"
        );
    }
    // Relative error of the baseline's replay, 1 − fit: the commands' is more than twice the
    // depth's (measured: 0.105 and 0.036 on port).
    let miss = |k: ChannelKind| 1.0 - ev_base.metrics[&k].fit_pct / 100.0;
    let depth = miss(ChannelKind::Depth);
    for th in ["port", "stbd"] {
        let cmd = miss(ChannelKind::command(th));
        assert!(
            cmd > 2.0 * depth,
            "{th}: relative error {cmd}, depth {depth}"
        );
    }
}

/// A sensor delay delays what the controller answers to: a log flown with readings 0.1 s late
/// is replayed by the model with that delay with the logged commands, by the model without it
/// with commands off by far more — the controller in the replay reads the replayed sensors
/// as late as the model says.
#[test]
fn the_controller_in_the_replay_reads_as_late_as_the_model_says() {
    let truth = with("sensor_delay", None, &[0.1]);
    let run = flown(&truth, 7, 180.0);
    let (_, ev_true) = replayed(&run, &truth);
    let (_, ev_none) = replayed(&run, &VehicleModel::new(clean_sensors(), 1000.0));
    for th in ["port", "stbd"] {
        let (tru, cmd) = command_rms(&ev_true, th);
        let (none, _) = command_rms(&ev_none, th);
        assert!(
            tru < 1e-3 * cmd,
            "{th}: delayed model {tru} % off a {cmd} % command"
        );
        assert!(
            none > 100.0 * tru,
            "{th}: without delay {none} %, with {tru} %"
        );
    }
}

/// With the preset's noisy, quantised sensors the real controller answers its own noise
/// (the depth rate from 1.8-mm steps, times the derivative gain): the replay's controller
/// reads the model's sensors plus the fast part of the measured ones, and the true model's
/// replay then sends the logged commands far more closely than it does reading the model's
/// sensors alone (measured: 2.3 % against 4.8 % RMS on port, of a 31.5 % RMS command).
#[test]
fn the_replay_controller_answers_the_noise_the_real_one_read() {
    let noisy = VehicleModel::new(presets::uauv2(), 1000.0);
    let designed = VehicleModel::new(presets::uauv2(), 1000.0);
    let plan = uauv2_mission(5, 240.0);
    let run = fly(
        &noisy,
        &designed,
        &Environment::default(),
        &plan,
        &Disturbance::NONE,
        DT,
        5,
        &mut (),
    );
    let (mut ds, ev) = replayed(&run, &noisy);
    let ctl = ds.runs[0]
        .init
        .control
        .clone()
        .expect("a closed-loop replay");
    // Without the measurements the controller reads the model's sensors alone.
    let mut deaf = (*ctl).clone();
    deaf.measured.iter_mut().for_each(|f| *f = [f64::NAN; 3]);
    ds.runs[0].init.control = Some(std::sync::Arc::new(deaf));
    let ev_deaf = ds.evaluate(&noisy);
    for th in ["port", "stbd"] {
        let (with, cmd) = command_rms(&ev, th);
        let (without, _) = command_rms(&ev_deaf, th);
        assert!(
            with < 0.6 * without,
            "{th}: {with} % with the fast part, {without} % without (command {cmd} %)"
        );
    }
}

/// The replay chooses itself (`--horizon choose`, the default): a 300-s mission log is
/// re-anchored (a mission), with or without its references, its first two minutes open loop
/// as a designed experiment is; each choice says why and what the log's commands were — no
/// evidence, and for a log with references that `--horizon closed` compares them.
#[test]
fn the_replay_chooses_itself_from_the_length_and_says_what_the_commands_were() {
    let truth = VehicleModel::new(clean_sensors(), 1000.0);
    let run = flown(&truth, 3, 300.0);
    let chosen = |run: MeasuredRun, horizon: Horizon| {
        let params = clean_sensors();
        let mut ds = Dataset::new(
            &params,
            Environment::default(),
            vec![run],
            vec![],
            &DataOptions::default(),
        )
        .expect("a dataset");
        ds.anchor(horizon, &VehicleModel::new(params, 1000.0));
        ds.anchoring.clone()
    };
    let a = chosen(run.clone(), Horizon::Choose);
    assert!(!a.closed_loop && a.horizon.is_some(), "{a:?}");
    assert!(
        a.why.contains("300 s") && a.why.contains("--horizon closed"),
        "{}",
        a.why
    );
    let a = chosen(run.clone(), Horizon::Closed);
    assert!(a.closed_loop && a.horizon.is_some(), "{a:?}");
    assert!(a.why.contains("u.port"), "{}", a.why);
    let mut bare = run.clone();
    bare.references.clear();
    let a = chosen(bare.clone(), Horizon::Choose);
    assert!(!a.closed_loop && a.horizon.is_some(), "{a:?}");
    assert!(a.why.contains("no references"), "{}", a.why);
    // Asked for a closed loop without references: re-anchored as auto, saying why.
    let a = chosen(bare.clone(), Horizon::Closed);
    assert!(!a.closed_loop, "{a:?}");
    assert!(a.why.starts_with("no closed-loop replay"), "{}", a.why);
    // The first two minutes.
    let rows = bare.t.iter().take_while(|&&t| t <= 120.0).count();
    bare.t.truncate(rows);
    for i in &mut bare.inputs {
        i.values.truncate(rows);
    }
    for c in &mut bare.channels {
        let n = c.rows.iter().take_while(|&&r| r < rows).count();
        c.rows.truncate(n);
        c.values.truncate(n);
    }
    let a = chosen(bare, Horizon::Choose);
    assert!(!a.closed_loop && a.horizon.is_none(), "{a:?}");
    assert!(a.why.contains("no references"), "{}", a.why);
}
