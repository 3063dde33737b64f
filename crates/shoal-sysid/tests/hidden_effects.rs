//! Hide each catalogue effect in a simulated μAUV² run (random realistic parameters, sensor
//! noise and quantisation, the run handed over as CSV text) and require the search to name
//! exactly that effect, to cut the validation error of the channels it shows in, and to
//! recover its parameters. Several seeds per effect, in the experiments that excite it: the
//! diving-mode heave run and the turning-mode yaw run of `shoal_testkit::design`.
//!
//! The test suite runs two cases per effect (the first seed of each experiment that excites
//! it, or the first two seeds of the one experiment that does): each case is a whole model
//! search, and the suite must fit its time budget. Every listed case runs with
//! `SHOAL_ALL_SEEDS=1`:
//! `SHOAL_ALL_SEEDS=1 cargo test --release -p shoal-sysid --test hidden_effects`.

mod common;

use common::{Exp, channel_gains, find, measured, realistic};

/// Parameters compared with the truth, and those that could not be.
#[derive(Debug, Default)]
struct Count {
    /// Compared with the truth (within tolerance, or the test failed).
    checked: usize,
    /// The data do not excite them (held at null by the fit).
    not_excited: usize,
    /// Their true value is the null value (the effect hidden without this part).
    truth_at_null: usize,
    /// The search named another form of the family, whose parameters mean something else.
    other_form: usize,
}

/// The cases of `cases` that run: all of them with `SHOAL_ALL_SEEDS=1`, otherwise the first of
/// each experiment, or the first two when all are of one experiment.
fn selected(cases: &[(Exp, u64)]) -> Vec<(Exp, u64)> {
    if std::env::var("SHOAL_ALL_SEEDS").is_ok_and(|v| v == "1") {
        return cases.to_vec();
    }
    let mut out: Vec<(Exp, u64)> = Vec::new();
    for &c in cases {
        if !out.iter().any(|o| o.0 == c.0) {
            out.push(c);
        }
    }
    if out.len() == 1 {
        out = cases.iter().take(2).copied().collect();
    }
    out
}

fn hidden(effect: &str, cases: &[(Exp, u64)]) {
    let mut n = Count::default();
    for (exp, seed) in selected(cases) {
        let truth = realistic(effect, exp, seed);
        let run = measured(exp, &[(effect, truth.clone())], seed);
        let (_, out) = find(run);
        let names = out.chosen.names();
        let ctx = format!("{effect} hidden with {truth:?} in the {exp:?} run, seed {seed}");
        assert_eq!(
            names,
            vec![effect.to_string()],
            "{ctx}: verdict {names:?}; stepwise {:?}; {:?}; candidates {:?}",
            out.stepwise.names(),
            out.verdict,
            out.candidates
                .iter()
                .map(|c| format!("{} ({}): {}", c.effect, c.form, c.note))
                .collect::<Vec<_>>()
        );
        // The error falls substantially where the effect shows, and nowhere grows.
        let gains = channel_gains(&out);
        let best = gains.iter().map(|g| g.1).fold(f64::MIN, f64::max);
        assert!(best > 0.5, "{ctx}: channel gains {gains:?}");
        assert!(gains.iter().all(|g| g.1 > -0.05), "{ctx}: {gains:?}");
        assert!(out.changed_channels_gain_pct().1 > 15.0, "{ctx}");
        // The parameters come back (those of the hidden form: the family's default).
        let found = &out.chosen.effects[0];
        let hidden_form = shoal_model::effects::by_name(effect).unwrap().form();
        if found.effect.form() != hidden_form {
            eprintln!(
                "{ctx}: named form `{}` instead of `{hidden_form}`: parameters not compared",
                found.effect.form()
            );
            n.other_form += truth.len();
            continue;
        }
        for (p, &t) in found.params.iter().zip(&truth) {
            if (t - p.null).abs() < 1e-12 {
                n.truth_at_null += 1;
                continue;
            }
            if !p.excited {
                n.not_excited += 1;
                continue;
            }
            n.checked += 1;
            let tol = if p.name == "delay_s" {
                // The logger's 20 ms sampling of a delayed sensor.
                0.03
            } else {
                0.15 * (t - p.null).abs()
            };
            assert!(
                (p.value - t).abs() <= tol,
                "{ctx}: {} = {} (σ {:?}), truth {t}",
                p.name,
                p.value,
                p.sigma
            );
        }
    }
    // Skipped parameters are counted: at least half of the hidden parameters the search could
    // have returned must have been compared with the truth.
    let skipped = n.not_excited + n.other_form;
    eprintln!("{effect}: {n:?}");
    assert!(
        n.checked > 0 && n.checked >= skipped,
        "{effect}: too few parameters compared with the truth: {n:?}"
    );
}

use Exp::{Heave, Yaw};

#[test]
fn thruster_lag() {
    hidden(
        "thruster_lag",
        &[(Heave, 1), (Heave, 2), (Yaw, 1), (Yaw, 2)],
    );
}

#[test]
fn thrust_gain() {
    hidden("thrust_gain", &[(Heave, 1), (Heave, 2), (Yaw, 1), (Yaw, 2)]);
}

#[test]
fn thrust_asymmetry() {
    hidden(
        "thrust_asymmetry",
        &[(Heave, 1), (Heave, 2), (Yaw, 1), (Yaw, 2)],
    );
}

#[test]
fn thruster_deadband() {
    hidden(
        "thruster_deadband",
        &[(Heave, 1), (Heave, 2), (Yaw, 1), (Yaw, 2)],
    );
}

#[test]
fn battery_sag() {
    hidden("battery_sag", &[(Heave, 1), (Heave, 2), (Yaw, 1), (Yaw, 2)]);
}

#[test]
fn inflow_thrust_loss() {
    hidden("inflow_thrust_loss", &[(Heave, 1), (Heave, 2), (Yaw, 1)]);
}

#[test]
fn buoyancy_offset() {
    hidden("buoyancy_offset", &[(Heave, 1), (Heave, 2), (Yaw, 1)]);
}

#[test]
fn ballast_mass() {
    // Only the heave run pumps.
    hidden("ballast_mass", &[(Heave, 1), (Heave, 2), (Heave, 3)]);
}

#[test]
fn damping_error() {
    hidden(
        "damping_error",
        &[(Heave, 1), (Heave, 2), (Yaw, 1), (Yaw, 2)],
    );
}

#[test]
fn added_mass_error() {
    hidden(
        "added_mass_error",
        &[(Heave, 1), (Heave, 2), (Yaw, 1), (Yaw, 2)],
    );
}

#[test]
fn water_current() {
    // Only the yaw run tracks the position.
    hidden("water_current", &[(Yaw, 1), (Yaw, 2), (Yaw, 3)]);
}

#[test]
fn depth_sensor_bias() {
    hidden("depth_sensor_bias", &[(Heave, 1), (Heave, 2), (Yaw, 1)]);
}

#[test]
fn sensor_delay() {
    hidden(
        "sensor_delay",
        &[(Heave, 1), (Heave, 2), (Yaw, 1), (Yaw, 2)],
    );
}

#[test]
fn thrust_coupling() {
    // Vertical thrust only in the heave run (which also logs the heading).
    hidden("thrust_coupling", &[(Heave, 1), (Heave, 2), (Heave, 3)]);
}

#[test]
fn thrust_saturation() {
    hidden(
        "thrust_saturation",
        &[(Heave, 1), (Heave, 2), (Yaw, 1), (Yaw, 2)],
    );
}

/// What the search cannot see, it does not claim: a current without tracked positions, a pump
/// that never runs.
#[test]
fn unexcited_effects_are_reported_as_such() {
    let run = measured(Heave, &[("water_current", vec![0.05, -0.03])], 4);
    let (_, out) = find(run);
    assert!(out.chosen.names().is_empty(), "{:?}", out.chosen.names());
    let c = out
        .candidates
        .iter()
        .find(|c| c.effect == "water_current")
        .unwrap();
    assert!(
        c.fit.is_none() && c.note.starts_with("not excited"),
        "{}",
        c.note
    );
}
