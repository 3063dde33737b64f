//! The library entry point [`shoal_sysid::validate::validate`]: settings are checked before
//! anything is read, with errors a caller can match on; runs given as text are read exactly as
//! files; and on a development log it gives the verdict pinned for that log in
//! `tests/verdicts/validation_dev.tsv` (the search tests' settings: 20 ms replay, 60/40 split).

mod common;

use common::pinned::{Table, check_verdict};
use shoal_sysid::evaluate::dataset::DataError;
use shoal_sysid::validate::{Config, Progress, RunInput, ValidateError, validate};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

fn dev_log(name: &str) -> PathBuf {
    Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/data/validation_dev"
    ))
    .join(format!("{name}.csv"))
}

fn quiet(_: Progress<'_>) {}

fn err(config: &Config, runs: &[RunInput]) -> ValidateError {
    match validate(config, runs, &[], &quiet) {
        Ok(_) => panic!("{config:?} validated"),
        Err(e) => e,
    }
}

#[test]
fn settings_are_checked_first_with_matchable_errors() {
    // A run that does not exist: every setting error comes before it is opened.
    let missing = [RunInput::File(PathBuf::from("/nonexistent/run.csv"))];
    let bad = |f: fn(&mut Config)| {
        let mut c = Config::default();
        f(&mut c);
        err(&c, &missing)
    };
    for (e, want) in [
        (bad(|c| c.dt = 1e-9), "dt"),
        (bad(|c| c.dt = f64::NAN), "dt"),
        (bad(|c| c.max_gap = Some(0.0)), "max_gap"),
        (bad(|c| c.min_segment = -1.0), "min_segment"),
        (bad(|c| c.split = 1.0), "split"),
    ] {
        assert!(
            matches!(&e, ValidateError::Setting { setting, .. } if *setting == want),
            "{want}: {e:?}"
        );
        assert!(e.to_string().starts_with(&format!("{want} = ")), "{e}");
    }
    let e = bad(|c| c.channels = vec!["y.depth".into(), "y.speed".into()]);
    assert!(
        matches!(&e, ValidateError::UnknownName { setting: "channels", name, allowed, .. }
            if name == "y.speed" && allowed.iter().any(|a| a == "y.depth")),
        "{e:?}"
    );
    let e = bad(|c| c.effects = vec!["thruster_lag".into(), "gremlins".into()]);
    assert!(
        matches!(&e, ValidateError::UnknownName { setting: "effects", name, .. } if name == "gremlins"),
        "{e:?}"
    );
    // All settings fine: now the file is opened, and its error names it.
    match err(&Config::default(), &missing) {
        ValidateError::Run(r) => {
            assert_eq!((r.file.as_path(), r.line), (missing[0].path(), 0), "{r}")
        }
        e => panic!("{e:?}"),
    }
    // The split is not checked when hold-out runs are given; a run too short for either side
    // of the split is a data error naming the channel.
    let short = RunInput::Text {
        name: "short.csv".into(),
        csv: "t,u.top,u.port,u.stbd,u.alpha,u.beta,u.pump,y.depth\n\
              0,0,0,0,0,0,0,0.5\n0.1,0,0,0,0,0,0,0.5\n0.2,0,0,0,0,0,0,0.5\n"
            .into(),
    };
    let c = Config {
        split: 5.0,
        ..Config::default()
    };
    let one = std::slice::from_ref(&short);
    match validate(&c, one, one, &quiet) {
        Err(ValidateError::Data(DataError::TooFewSamples { channel, .. })) => {
            assert_eq!(channel.name(), "depth")
        }
        Err(e) => panic!("{e:?}"),
        Ok(_) => panic!("three rows validated"),
    }
}

#[test]
fn a_development_log_gets_its_pinned_verdict_from_a_file_and_from_text() {
    let name = "dev_y_gain";
    let path = dev_log(name);
    let text = std::fs::read_to_string(&path).expect("the development logs beside the checkout");
    let config = Config {
        dt: 0.02,
        threads: Some(1),
        ..Config::default()
    };
    let events = Mutex::new(Vec::new());
    let progress = |p: Progress<'_>| {
        let e = match p {
            Progress::Read { path, segments } => {
                format!("read {} {}", path.display(), segments.runs.len())
            }
            Progress::Clamped { run, .. } => format!("clamped {run}"),
            Progress::Start {
                estimation,
                holdout,
                split,
                ..
            } => {
                format!("start {estimation} {holdout} {split:?}")
            }
            Progress::Stage { stage, .. } => format!("stage {stage}"),
            Progress::Fit { .. } => "fit".into(),
        };
        events.lock().unwrap().push(e);
    };
    let v = validate(&config, &[RunInput::File(path.clone())], &[], &progress).unwrap();
    let table = Table::read(Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/verdicts/validation_dev.tsv"
    )));
    check_verdict(
        &table,
        name,
        &v.outcome.verdict.effects,
        "through validate()",
    );
    let events = events.into_inner().unwrap();
    assert_eq!(events[0], format!("read {} 1", path.display()));
    assert_eq!(events[1], "start 1 0 Some(0.6)");
    // The stages in the order the search runs them, round 1 first, each before its fits.
    let stages: Vec<&str> = events
        .iter()
        .filter_map(|e| e.strip_prefix("stage "))
        .collect();
    assert_eq!(events[2], "stage round 1: every form of every family alone");
    assert_eq!(
        &stages[..4],
        [
            "round 1: every form of every family alone",
            "forward rounds",
            "backward checks and swaps",
            "identifiability"
        ]
    );
    let fits = events.iter().filter(|e| *e == "fit").count();
    // A call per fit: every candidate's, and the refits of the stability and pair checks.
    assert!(
        fits >= v.work().0 && v.work().0 > 0,
        "{fits} calls, {:?}",
        v.work()
    );
    // The before/after table covers the log's channels, and the chosen model is no worse.
    let rows = v.channels();
    assert_eq!(rows.len(), v.dataset.kinds.len());
    assert!(
        rows.iter().all(|r| r.rmse_after <= r.rmse_before),
        "{rows:?}"
    );
    // The same log as text in memory: the same verdict, the same numbers.
    let from_text = validate(
        &config,
        &[RunInput::Text {
            name: format!("{name}.csv"),
            csv: text,
        }],
        &[],
        &quiet,
    )
    .unwrap();
    assert_eq!(from_text.outcome.verdict, v.outcome.verdict);
    assert_eq!(from_text.channels(), rows);
}
