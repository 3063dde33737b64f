//! Writes the misspecified-form test set (`shoal_testkit::testset`) as files: one CSV per case in
//! the logger's format, `expected.json` (case → catalogue families of an exact verdict, the
//! format of the shared `validation_dev/expected.json`) and `truth.json` (the hidden forms and
//! their parameter values, for debugging a verdict).
//!
//! ```sh
//! cargo run --release -p shoal-testkit --example make_testset -- --out out/testset
//! cargo run --release -p shoal-testkit --example make_testset -- --out out/pinned --subset pinned
//! cargo run --release -p shoal-testkit --example make_testset -- --out out/long --length 240 --noise 2
//! ```
//!
//! Options: `--subset full|pinned` (default full: 328 cases; pinned: the 65 whose verdicts the
//! tests pin), `--length S` log length in seconds (default 120), `--noise M` sensor noise as a
//! multiple of the μAUV² preset's (default 1). The output is deterministic.

use shoal_testkit::testset::{Conditions, expected_json, full, pinned_subset, truth_json};
use std::path::PathBuf;
use std::process::ExitCode;

fn usage() -> ExitCode {
    eprintln!(
        "usage: make_testset --out DIR [--subset full|pinned] [--length SECONDS] [--noise MULTIPLE]"
    );
    ExitCode::from(2)
}

fn main() -> ExitCode {
    let mut out: Option<PathBuf> = None;
    let mut subset = "full".to_string();
    let mut cond = Conditions::default();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let Some(v) = args.next() else {
            eprintln!("{a} needs a value");
            return usage();
        };
        match a.as_str() {
            "--out" => out = Some(PathBuf::from(v)),
            "--subset" => subset = v,
            "--length" | "--noise" => {
                let Ok(x) = v.parse::<f64>() else {
                    eprintln!("{a} takes a number, got `{v}`");
                    return usage();
                };
                if !(x.is_finite() && x >= 0.0) || (a == "--length" && x < 10.0) {
                    eprintln!("{a} {x} is out of range (length ≥ 10 s, noise ≥ 0)");
                    return usage();
                }
                if a == "--length" {
                    cond.duration = x;
                } else {
                    cond.noise = x;
                }
            }
            _ => {
                eprintln!("unknown option `{a}`");
                return usage();
            }
        }
    }
    let Some(dir) = out else {
        return usage();
    };
    let cases = match subset.as_str() {
        "full" => full(),
        "pinned" => pinned_subset(),
        other => {
            eprintln!("unknown subset `{other}` (allowed: full, pinned)");
            return usage();
        }
    };
    if let Err(e) = std::fs::create_dir_all(&dir) {
        eprintln!("cannot create {}: {e}", dir.display());
        return ExitCode::FAILURE;
    }
    let write = |name: &str, text: &str| -> Result<(), ExitCode> {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|e| {
            eprintln!("cannot write {}: {e}", path.display());
            ExitCode::FAILURE
        })
    };
    for (i, spec) in cases.iter().enumerate() {
        if let Err(code) = write(&format!("{}.csv", spec.name), &spec.csv(&cond)) {
            return code;
        }
        eprint!("\r{}/{} cases", i + 1, cases.len());
    }
    eprintln!();
    for (name, text) in [
        ("expected.json", expected_json(&cases)),
        ("truth.json", truth_json(&cases)),
    ] {
        if let Err(code) = write(name, &text) {
            return code;
        }
    }
    println!(
        "wrote {} logs ({} s, noise ×{}), expected.json and truth.json to {}",
        cases.len(),
        cond.duration,
        cond.noise,
        dir.display()
    );
    ExitCode::SUCCESS
}
