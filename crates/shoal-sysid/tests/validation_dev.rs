//! The development logs in `../shared/data/validation_dev` (six significant digits, as a
//! logger writes them) all load with the μAUV² preset: the diving logs' tilt at −1.5708 is
//! clamped to −π/2 and counted on every row, nothing else is touched.

use shoal_sysid::replay::InputMap;
use shoal_sysid::run::MeasuredRun;
use shoal_sysid::segments::GapOptions;
use std::f64::consts::FRAC_PI_2;
use std::path::Path;

#[test]
fn every_development_log_loads_with_the_uauv2_preset() {
    let dir = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/data/validation_dev"
    ));
    assert!(
        dir.is_dir(),
        "the development logs are missing: expected ../shared/data/validation_dev beside the \
         checkout ({})",
        dir.display()
    );
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "csv"))
        .collect();
    files.sort();
    assert_eq!(files.len(), 16, "{files:?}");
    let params = shoal_model::presets::uauv2();
    for f in &files {
        let run = MeasuredRun::read(f).unwrap_or_else(|e| panic!("{e}"));
        let seg = run
            .split_at_gaps(&GapOptions::default())
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(seg.runs.len(), 1, "{}: no gaps", f.display());
        let mut run = seg.runs.into_iter().next().unwrap();
        let rows = run.t.len();
        assert!(rows >= 4500, "{}: {rows} rows", f.display());
        let map = InputMap::new(&params, &mut run).unwrap_or_else(|e| panic!("{e}"));
        let diving = run.name.starts_with("dev_h_");
        if diving {
            assert_eq!(map.clamped.len(), 1, "{}: {:?}", f.display(), map.clamped);
            let note = &map.clamped[0];
            assert_eq!(
                (note.name.as_str(), note.limit, note.count),
                ("u.beta", -FRAC_PI_2, rows),
                "{note}"
            );
            assert!(note.max_excess < 5e-6, "{note}");
            let beta = run.input("beta").unwrap();
            assert!(beta.values.iter().all(|&v| v == -FRAC_PI_2));
        } else {
            assert!(map.clamped.is_empty(), "{}: {:?}", f.display(), map.clamped);
        }
    }
}
