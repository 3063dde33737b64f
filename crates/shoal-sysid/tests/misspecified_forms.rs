//! The search must recognise an effect's physics when its true functional form is not the
//! catalogue's: the CI subset of the misspecified-form test set (`shoal_testkit::testset`) —
//! every truth form once (an underdamped motor for a lag, a ramped dead band, a compressing air
//! bubble for a buoyancy offset, a boxcar-filtering sensor for a delay, …), 8 pairs of
//! families and 4 null runs — simulated through the full sensor models, written as a real
//! logger writes them (six significant digits, the tilt at −1.5708, 1.8 mm depth steps,
//! 50 Hz) and handed to the search as CSV text only (μAUV² preset baseline, 60/40 split,
//! 20 ms replay).
//!
//! Each case's verdict is pinned in `tests/verdicts/misspecified_forms.tsv`: one trial per case
//! (`case::<name>`) searches its log and fails with the difference when the verdict is not the
//! pinned one — a fix in one family cannot hide a new miss in another. The trial `table` checks
//! the table itself: it lists exactly the CI subset, the chosen set of effects equals the
//! hidden families exactly (none missing, none extra) in at least 90 % of the cases, and every
//! null run gives an empty verdict; it prints the table per family and form (`--nocapture`).
//! Improving a case means updating its line in the same commit.
//!
//! The cases are independent trials, so cargo-nextest runs them side by side (about 35 CPU
//! minutes in all, 2026 development VM); `cargo test -p shoal-sysid --test misspecified_forms
//! -- case::h_` runs a selection.

mod common;

use common::pinned::{Table, check_verdict, set_text};
use libtest_mimic::{Arguments, Failed, Trial};
use shoal_testkit::recovery::judge;
use shoal_testkit::testset::{CaseSpec, Conditions, ci_subset};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// Smallest fraction of exact verdicts.
const REQUIRED_RATE: f64 = 0.9;

fn table_path() -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/verdicts/misspecified_forms.tsv"
    ))
}

/// What a row of the per-family table is about: the form for single-form cases, `pair`, `null`.
fn group(spec: &CaseSpec) -> String {
    match spec.hidden.as_slice() {
        [] => "null".to_string(),
        [h] => h.form.name.to_string(),
        _ => "pair".to_string(),
    }
}

/// The pinned table: the CI subset's cases, the rate, clean null runs; the table per family.
fn table() -> Result<(), Failed> {
    let specs = ci_subset();
    let table = Table::read(&table_path());
    let cases: Vec<(String, Vec<String>)> = specs
        .iter()
        .map(|s| (s.name.clone(), s.expected()))
        .collect();
    table.check_cases(&cases);

    println!("\n| group | case | hidden | found | exact |");
    println!("|---|---|---|---|---|");
    let mut per_family: BTreeMap<String, (usize, usize)> = BTreeMap::new();
    for (spec, row) in specs.iter().zip(&table.rows) {
        let hidden: Vec<String> = spec.hidden.iter().map(|h| h.describe()).collect();
        println!(
            "| {} | {} | {} | {} | {} |",
            group(spec),
            spec.name,
            if hidden.is_empty() {
                "—".to_string()
            } else {
                hidden.join("; ")
            },
            set_text(&row.found),
            if row.exact() { "yes" } else { "**no**" }
        );
        let families = if row.expected.is_empty() {
            vec!["(null)".to_string()]
        } else {
            row.expected.clone()
        };
        for f in families {
            let t = per_family.entry(f).or_default();
            t.0 += 1;
            t.1 += usize::from(row.exact());
        }
    }
    println!("\n| family | cases | exact |");
    println!("|---|---|---|");
    for (family, (n, exact)) in &per_family {
        println!("| {family} | {n} | {exact} |");
    }
    let dirty: Vec<String> = table
        .rows
        .iter()
        .filter(|r| r.expected.is_empty() && !r.found.is_empty())
        .map(|r| format!("{}: {}", r.case, set_text(&r.found)))
        .collect();
    if !dirty.is_empty() {
        return Err(format!("null runs with a verdict: {dirty:?}").into());
    }
    let (exact, n) = table.exact();
    let rate = exact as f64 / n as f64;
    println!("\nexact verdicts: {exact} of {n} ({:.1} %)", 100.0 * rate);
    if rate < REQUIRED_RATE {
        return Err(format!(
            "exact verdicts in {exact} of {n} cases ({:.1} %, required {:.0} %)",
            100.0 * rate,
            100.0 * REQUIRED_RATE
        )
        .into());
    }
    Ok(())
}

/// One case: its log searched (one search thread: the cases run side by side), the verdict
/// compared with the pinned one.
fn case(spec: CaseSpec) -> Result<(), Failed> {
    let case = spec.generate(&Conditions::default());
    let v = judge(&case, 1);
    if let Some(e) = &v.error {
        return Err(format!("{}: the log could not be searched: {e}", spec.name).into());
    }
    let table = Table::read(&table_path());
    let hidden: Vec<String> = spec.hidden.iter().map(|h| h.describe()).collect();
    check_verdict(
        &table,
        &spec.name,
        &v.found,
        &format!("  forms: {}", hidden.join("; ")),
    );
    Ok(())
}

fn main() {
    let args = Arguments::from_args();
    let mut trials = vec![Trial::test("table", table)];
    for spec in ci_subset() {
        let name = format!("case::{}", spec.name);
        trials.push(Trial::test(name, move || case(spec)));
    }
    libtest_mimic::run(&args, trials).exit();
}
