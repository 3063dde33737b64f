//! The development logs of `../shared/data/validation_dev/` (made outside this repository,
//! written as a real logger writes them: six significant digits, the tilt at its mechanical
//! limit, closed-loop commands; effects in forms that differ from the catalogue's): the verdict
//! must name exactly the hidden effects — none missing, none extra — on at least 15 of the 16
//! logs, and both null logs must give an empty verdict.
//!
//! The folder must be there (it is beside the repository on every machine of this project);
//! a missing folder fails the test instead of skipping it.

use shoal_model::presets;
use shoal_model::rigid_body::Environment;
use shoal_sysid::data::{DataOptions, Dataset};
use shoal_sysid::replay::ReplayOptions;
use shoal_sysid::run::MeasuredRun;
use shoal_sysid::search::{SearchOptions, search};
use std::collections::BTreeMap;
use std::path::PathBuf;

fn folder() -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/data/validation_dev"
    ))
}

#[test]
fn development_logs_get_exact_verdicts() {
    let dir = folder();
    let expected = std::fs::read_to_string(dir.join("expected.json")).unwrap_or_else(|e| {
        panic!(
            "the development logs are missing at {} ({e}); they belong beside the repository",
            dir.display()
        )
    });
    let expected: BTreeMap<String, Vec<String>> =
        serde_json::from_str(&expected).expect("expected.json parses");
    assert_eq!(expected.len(), 16, "16 development logs");
    let base = presets::uauv2();
    let mut exact = 0;
    let mut table = Vec::new();
    for (name, want) in &expected {
        let path = dir.join(format!("{name}.csv"));
        let run = MeasuredRun::read(&path).unwrap_or_else(|e| panic!("{e}"));
        let ds = Dataset::new(
            &base,
            Environment::default(),
            vec![run],
            vec![],
            &DataOptions {
                replay: ReplayOptions {
                    dt: 0.02,
                    ..Default::default()
                },
                ..Default::default()
            },
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        let opts = SearchOptions {
            threads: 2,
            ..Default::default()
        };
        let out = search(&ds, &base, &opts, &|_| {});
        let mut got = out.verdict.effects.clone();
        got.sort();
        let mut want = want.clone();
        want.sort();
        let ok = got == want;
        exact += usize::from(ok);
        if want.is_empty() {
            assert!(got.is_empty(), "{name}: false discovery {got:?}");
        }
        table.push(format!(
            "{name:16} {} want {want:?} got {got:?} (forms {:?}; possible {:?})",
            if ok { "ok  " } else { "MISS" },
            out.verdict.forms,
            out.verdict
                .possible
                .iter()
                .map(|p| p.effect.as_str())
                .collect::<Vec<_>>()
        ));
    }
    eprintln!("{}", table.join("\n"));
    assert!(
        exact >= 15,
        "exact verdicts on {exact} of 16 logs (need ≥ 15):\n{}",
        table.join("\n")
    );
}
