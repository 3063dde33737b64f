//! A fit's inner loop replays a log only as far as its estimation samples go
//! ([`Part::Estimation`]); everything it computes from that replay must be what the whole
//! replay gives, bit for bit: the weighted residuals (with and without a block-bootstrap
//! resample), the estimation metrics and the likelihood weights — for a model with a sensor
//! delay (which reads the replay earlier), with a depth-sensor effect, on a log whose pump
//! fills and empties the tank within the estimation part, on a 7 ms replay grid the samples
//! fall between, and with a hold-out run (not replayed at all for estimation).

mod common;

use common::replays::{model, offgrid_options as options, pumping_heave_run as heave_run};
use shoal_model::presets;
use shoal_model::rigid_body::Environment;
use shoal_sysid::evaluate::blocks::{Resample, weighted_residuals};
use shoal_sysid::evaluate::dataset::{Dataset, Part};

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Checks every model on `ds`; returns (samples compared by the estimation replays, by the
/// whole ones).
fn same_numbers(ds: &Dataset) -> (usize, usize) {
    let mut sizes = (0, 0);
    for m in [
        model(&[]),
        model(&[("thruster_lag", vec![0.25])]),
        model(&[("sensor_delay", vec![0.13])]),
        model(&[("depth_sensor_bias", vec![0.02, 5e-4])]),
    ] {
        let whole = ds.replayed(&m, Part::All);
        let part = ds.replayed(&m, Part::Estimation);
        let (ew, ep) = (ds.evaluation(&whole), ds.evaluation(&part));
        let factors = ew.ml_factors();
        assert_eq!(factors, ep.ml_factors());
        for (k, mw) in &ew.metrics {
            let mp = &ep.metrics[k];
            assert_eq!(
                (mp.n_est, mp.sse_est.to_bits(), mp.rho1_est.to_bits()),
                (mw.n_est, mw.sse_est.to_bits(), mw.rho1_est.to_bits()),
                "{k:?}"
            );
        }
        let rs = Resample::draw(&ew, 4.0, 11);
        for resample in [None, Some(&rs)] {
            let w = ds.weighted(&whole, &factors, resample).unwrap();
            let p = ds.weighted(&part, &factors, resample).unwrap();
            assert_eq!(bits(&w), bits(&p));
            assert_eq!(bits(&w), bits(&weighted_residuals(&ew, &factors, resample)));
        }
        let count = |e: &shoal_sysid::evaluate::evaluation::Evaluation| {
            e.runs
                .iter()
                .flat_map(|r| &r.channels)
                .map(|c| c.resid.len())
                .sum::<usize>()
        };
        sizes.0 += count(&ep);
        sizes.1 += count(&ew);
    }
    sizes
}

#[test]
fn an_estimation_replay_gives_the_whole_replays_estimation_numbers() {
    let ds = Dataset::new(
        &presets::uauv2(),
        Environment::default(),
        vec![heave_run(1)],
        vec![],
        &options(),
    )
    .unwrap();
    let (part, whole) = same_numbers(&ds);
    // 60/40 split: the estimation replays compare 60 % of the samples.
    let share = part as f64 / whole as f64;
    assert!((0.59..0.61).contains(&share), "{part} of {whole}");
}

#[test]
fn hold_out_runs_are_not_replayed_for_estimation() {
    let ds = Dataset::new(
        &presets::uauv2(),
        Environment::default(),
        vec![heave_run(1)],
        vec![heave_run(2)],
        &options(),
    )
    .unwrap();
    let (part, whole) = same_numbers(&ds);
    // The estimation run whole, the hold-out run not at all.
    let est = ds.replayed(&model(&[]), Part::Estimation);
    let ev = ds.evaluation(&est);
    assert!(ev.runs[1].channels.iter().all(|c| c.resid.is_empty()));
    assert!(ev.runs[0].channels.iter().all(|c| !c.resid.is_empty()));
    assert!(part < whole && part > whole / 3, "{part} of {whole}");
}
