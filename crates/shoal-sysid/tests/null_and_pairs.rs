//! No false discovery: runs that the baseline explains (only sensor noise and quantisation)
//! give an empty verdict. And two effects hidden together are both named.

mod common;

use common::{Exp, channel_gains, find, measured};

#[test]
fn null_runs_give_an_empty_verdict() {
    for exp in [Exp::Heave, Exp::Yaw] {
        for seed in [11, 12, 13] {
            let (_, out) = find(measured(exp, &[], seed));
            assert!(
                out.chosen.names().is_empty(),
                "{exp:?} seed {seed}: false discovery {:?}",
                out.chosen.names()
            );
            // Nothing to gain, and the baseline residuals are white noise.
            assert!(out.validation_gain_pct().abs() < 1e-9);
            for (k, m) in &out.baseline.eval.metrics {
                assert!(
                    m.ljung_box.p_value > 0.001,
                    "{exp:?} seed {seed}: {k:?} residuals not white: {:?}",
                    m.ljung_box
                );
            }
        }
    }
}

fn pair(exp: Exp, a: (&str, Vec<f64>), b: (&str, Vec<f64>), seed: u64) {
    let (_, out) = find(measured(exp, &[a.clone(), b.clone()], seed));
    let mut names = out.chosen.names();
    names.sort();
    let mut want = vec![a.0.to_string(), b.0.to_string()];
    want.sort();
    assert_eq!(
        names,
        want,
        "{exp:?} seed {seed}; stepwise {:?}; {:?}; candidates {:?}",
        out.stepwise.names(),
        out.verdict,
        out.candidates
            .iter()
            .map(|c| format!("r{} {} ({}): {}", c.round, c.effect, c.form, c.note))
            .collect::<Vec<_>>()
    );
    let gains = channel_gains(&out);
    assert!(
        gains.iter().map(|g| g.1).fold(f64::MIN, f64::max) > 0.5,
        "{gains:?}"
    );
}

#[test]
fn lag_and_buoyancy_offset_in_heave() {
    pair(
        Exp::Heave,
        ("thruster_lag", vec![0.3]),
        ("buoyancy_offset", vec![-0.002]),
        1,
    );
}

#[test]
fn battery_sag_and_depth_drift_in_heave() {
    pair(
        Exp::Heave,
        ("battery_sag", vec![0.002]),
        ("depth_sensor_bias", vec![0.0, 0.0008]),
        2,
    );
}

#[test]
fn pump_flow_and_added_mass_in_heave() {
    pair(
        Exp::Heave,
        ("ballast_mass", vec![0.15]),
        ("added_mass_error", vec![1.5]),
        1,
    );
}

#[test]
fn asymmetry_and_current_in_yaw() {
    pair(
        Exp::Yaw,
        ("thrust_asymmetry", vec![0.8]),
        ("water_current", vec![0.04, 0.02]),
        1,
    );
}

/// Thrust gain and sensor delay in a yaw run: a gain is exactly equivalent to scaling damping
/// and inertia together, and the search has to prefer the one-parameter explanation.
#[test]
fn gain_and_delay_in_yaw() {
    pair(
        Exp::Yaw,
        ("thrust_gain", vec![1.2]),
        ("sensor_delay", vec![0.2]),
        2,
    );
}
