//! Re-anchored replays: at each anchor the replay's measured states are the measurements
//! (through the model's sensors), and a model that drifts away open loop stays near the data
//! when re-anchored, while a model that is right stays right.

mod common;

use common::replays::model;
use common::{Exp, measured};
use shoal_sysid::evaluate::anchoring::Horizon;
use shoal_sysid::evaluate::dataset::Dataset;
use shoal_sysid::evaluate::evaluation::Evaluation;
use shoal_sysid::log::run::ChannelKind;

fn dataset(exp: Exp, hidden: &[(&str, Vec<f64>)]) -> Dataset {
    common::dataset(measured(exp, hidden, 7))
}

fn rmse(e: &Evaluation, k: ChannelKind) -> f64 {
    e.metrics[&k].rmse
}

/// A turning run whose vehicle has 10 % more thrust than the model: open loop the heading
/// runs away by radians over the two minutes; re-anchored, its error is what one horizon
/// accumulates — so halving the horizon about halves it. The true model stays within the
/// noise either way.
#[test]
fn a_drifting_heading_is_held_near_the_data_and_a_true_model_stays_true() {
    let truth = [("thrust_gain", vec![1.1])];
    let mut ds = dataset(Exp::Yaw, &truth);
    let (base, right) = (model(&[]), model(&truth));
    let open = (ds.evaluate(&base), ds.evaluate(&right));
    let a = ds.anchor(Horizon::Every(5.0), &base).clone();
    assert_eq!(a.horizon, Some(5.0));
    assert!(ds.runs[0].init.anchors.len() >= 20, "every 5 s of 120 s");
    let anchored = (ds.evaluate(&base), ds.evaluate(&right));
    ds.anchor(Horizon::Every(2.5), &base);
    let shorter = ds.evaluate(&base);
    let yaw = ChannelKind::Yaw;
    let (o, a5, a25) = (
        rmse(&open.0, yaw),
        rmse(&anchored.0, yaw),
        rmse(&shorter, yaw),
    );
    eprintln!(
        "baseline yaw RMSE open {o:.4}, every 5 s {a5:.4}, every 2.5 s {a25:.4} rad; true model \
         {:.5} / {:.5}",
        rmse(&open.1, yaw),
        rmse(&anchored.1, yaw),
    );
    assert!(o > 0.15, "the open-loop baseline drifts");
    assert!(
        a5 < 0.7 * o && a25 < o / 3.0,
        "re-anchored, the baseline stays nearer the data"
    );
    let ratio = a25 / a5;
    assert!(
        (0.35..=0.7).contains(&ratio),
        "the error grows over a horizon: half the horizon, about half the error ({ratio:.2})"
    );
    // The true model is about as good re-anchored as open loop: anchors add the noise of a
    // local fit.
    for k in [yaw, ChannelKind::R, ChannelKind::Depth] {
        assert!(
            rmse(&anchored.1, k) <= 1.5 * rmse(&open.1, k) + 1e-4,
            "{k:?}: {} vs {}",
            rmse(&anchored.1, k),
            rmse(&open.1, k)
        );
    }
    // Back to open loop: exactly the first evaluation.
    ds.anchor(Horizon::Open, &base);
    assert_eq!(ds.evaluate(&base), open.0);
}

/// Right after an anchor the replayed readings are the measured ones, read through the
/// model's sensor: a heave run of a vehicle 0.3 N heavier than the model, replayed on a model
/// whose depth sensor drifts by 1 mm/s, reads at every anchor what was measured, where open
/// loop the replay is far off by then.
#[test]
fn at_an_anchor_the_replay_reads_what_was_measured() {
    let mut ds = dataset(Exp::Heave, &[("buoyancy_offset", vec![0.3])]);
    let m = model(&[("depth_sensor_bias", vec![0.0, 0.001])]);
    let off_at_anchors = |ds: &Dataset, steps: &[usize]| -> (f64, usize) {
        let e = ds.evaluate(&m);
        let c = e.runs[0]
            .channels
            .iter()
            .find(|c| c.kind == ChannelKind::Depth)
            .unwrap();
        let t0 = c.times[0];
        let (mut worst, mut n) = (0.0f64, 0);
        for &s in steps {
            let t = t0 + s as f64 * 0.02;
            // The first sample after the anchor (the one at its time reads the state just
            // before it), if within one sample period.
            let Some(i) = c.times.iter().position(|&x| x > t + 1e-9) else {
                continue;
            };
            if c.times[i] - t > 0.021 {
                continue;
            }
            // The depth prediction carries a free offset (the residual's mean is removed):
            // compare with the first sample's residual.
            let r = (c.measured[i] - c.predicted[i]) - (c.measured[0] - c.predicted[0]);
            worst = worst.max(r.abs());
            n += 1;
        }
        (worst, n)
    };
    ds.anchor(Horizon::Every(4.0), &m);
    let steps: Vec<usize> = ds.runs[0].init.anchors.iter().map(|a| a.step).collect();
    let (anchored, n) = off_at_anchors(&ds, &steps);
    ds.anchor(Horizon::Open, &m);
    let (open, _) = off_at_anchors(&ds, &steps);
    eprintln!("depth at the anchors: re-anchored within {anchored:.4} m, open loop {open:.3} m");
    assert!(n >= 20, "{n} anchors checked");
    assert!(anchored < 0.01, "{anchored} m");
    assert!(open > 0.1, "{open} m");
}

/// A ten-minute closed-loop mission in gusting water, flown by a hull a few per cent off its
/// nominal parameters, with nothing hidden: replayed open loop from its first sample the
/// baseline leaves the data by decimetres and radians (the controller fought disturbances the
/// replay does not know); replayed re-anchored at the horizon chosen from the data, it stays
/// within twice the sensors' noise on the attitude and yaw rate, and within ten times on the
/// depth, which the vertical gusts (5 mm/s) move by up to a centimetre per horizon. Without
/// the filtered sway velocity at each anchor the hull coasting forward spun off under its Munk
/// moment within a horizon (yaw RMSE 0.08 rad, 9× the noise). What is left on the depth is
/// the water's transport, estimated as a wandering current (`evaluate::current`).
#[test]
fn a_long_closed_loop_mission_is_followed_only_when_re_anchored() {
    use shoal_testkit::closed_loop::{MISSION_S, cases};
    use shoal_testkit::mission::Disturbance;
    let case = cases(MISSION_S)
        .into_iter()
        .find(|c| c.name == "m_null_1")
        .unwrap();
    let csv = case.csv(&Disturbance::default());
    let run = shoal_sysid::log::run::MeasuredRun::parse(&csv, std::path::Path::new("m.csv"))
        .expect("the mission log parses");
    let mut ds = common::dataset(run);
    let base = model(&[]);
    let open = ds.evaluate(&base);
    let chosen = ds.anchor(Horizon::Auto, &base).clone();
    let anchored = ds.evaluate(&base);
    eprintln!("auto: {chosen:?}");
    let h = chosen.horizon.expect("a diverging replay is re-anchored");
    assert!((2.0..=30.0).contains(&h), "horizon {h} s");
    // Sensor noise of the preset: pressure 0.5 mm with 1.8 mm steps (√(0.5² + 1.8²/12) mm),
    // attitude 0.5°, gyro 0.01 rad/s.
    let depth_noise = (0.5e-3f64.powi(2) + 1.8e-3f64.powi(2) / 12.0).sqrt();
    let angle_noise = 0.5f64.to_radians();
    for (k, noise, bound) in [
        (ChannelKind::Depth, depth_noise, 10.0),
        (ChannelKind::Yaw, angle_noise, 2.0),
        (ChannelKind::Roll, angle_noise, 2.0),
        (ChannelKind::Pitch, angle_noise, 2.0),
        (ChannelKind::R, 0.01, 2.0),
    ] {
        let (o, a) = (rmse(&open, k), rmse(&anchored, k));
        eprintln!("{k:?}: open {o:.4}, anchored {a:.4} (noise {noise:.4})");
        assert!(
            a < bound * noise,
            "{k:?}: re-anchored RMSE {a} against noise {noise}"
        );
        if matches!(k, ChannelKind::Depth | ChannelKind::Yaw) {
            assert!(o > 50.0 * noise, "{k:?}: open loop follows ({o})");
        }
    }
    // What is left on the depth is the water's: the gusts flown (5 mm/s over 15 s) come back
    // as the current the report names, and predicted from the samples before, the transport
    // leaves the depth within three times its noise.
    let water = chosen
        .currents
        .get(&ChannelKind::Depth)
        .expect("a current on the depth");
    eprintln!("water: {water:?}");
    assert!((0.0025..=0.010).contains(&water.sigma_m_s), "{water:?}");
    assert!((4.0..=60.0).contains(&water.tau_s), "{water:?}");
    assert!(water.innovation_m < 3.0 * depth_noise, "{water:?}");
    assert!(water.innovation_m < 0.5 * water.residual_m, "{water:?}");
    assert!(
        chosen.why.contains("the water carries y.depth"),
        "{}",
        chosen.why
    );
}
