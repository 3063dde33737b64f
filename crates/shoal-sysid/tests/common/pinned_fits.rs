//! Pinned fits: beside a test set's pinned verdicts (`pinned.rs`: which effects), the forms
//! and parameters of the model the search chose on each log, so that a change that keeps the
//! names but moves a fit — a wrong time stamp, a gravity constant, a held input read a sample
//! late — fails by name with the line to compare.
//!
//! The table is text, one case per line: `case <TAB> forms <TAB> params`, the forms written
//! `effect/form` and the parameters `effect.param=value`, each list sorted and joined by `,`
//! (`-` for none); `#` starts a comment line. A parameter agrees when it is within
//! [`REL_TOL`] of the pinned value; forms and parameter names must be the same. The same table
//! is read by the rosbag2 tests (python/tests/test_rosbag.py), which compare a bag's fit with
//! its CSV's.

#![allow(dead_code)]

use super::pinned::{data_lines, items, set_text};
use shoal_sysid::search::Fit;
use std::path::{Path, PathBuf};

/// How far a parameter may move from its pinned value (fraction of it).
pub const REL_TOL: f64 = 0.10;

/// One line of a table.
#[derive(Clone, Debug, PartialEq)]
pub struct FitRow {
    /// The case (log) name.
    pub case: String,
    /// `effect/form` of each chosen effect, sorted.
    pub forms: Vec<String>,
    /// `(effect.param, value)` of each parameter of the chosen model, sorted by name.
    pub params: Vec<(String, f64)>,
    /// Line in the table file (from 1).
    pub line: usize,
}

/// A fits table, read.
pub struct FitTable {
    /// Its path.
    pub path: PathBuf,
    /// Its rows, in file order.
    pub rows: Vec<FitRow>,
}

impl FitTable {
    /// Reads `path`; a malformed line fails with the file and line.
    pub fn read(path: &Path) -> FitTable {
        let rows = data_lines(path, 3, "case<TAB>forms<TAB>params")
            .into_iter()
            .map(|(line, f)| {
                let params = items(&f[2])
                    .into_iter()
                    .map(|p| {
                        let parsed = p
                            .split_once('=')
                            .and_then(|(n, v)| Some((n.to_string(), v.parse::<f64>().ok()?)));
                        parsed.unwrap_or_else(|| {
                            panic!("{}:{line}: `{p}` is not `name=number`", path.display())
                        })
                    })
                    .collect();
                FitRow {
                    case: f[0].clone(),
                    forms: items(&f[1]),
                    params,
                    line,
                }
            })
            .collect();
        FitTable {
            path: path.to_path_buf(),
            rows,
        }
    }

    /// The row of `case`, if it has one.
    pub fn row(&self, case: &str) -> Option<&FitRow> {
        self.rows.iter().find(|r| r.case == case)
    }

    /// Fails unless the table lists exactly `cases`, in that order.
    pub fn check_cases(&self, cases: &[String]) {
        let have: Vec<&String> = self.rows.iter().map(|r| &r.case).collect();
        let want: Vec<&String> = cases.iter().collect();
        assert_eq!(
            have,
            want,
            "{}: the table's cases are not the test set's",
            self.path.display()
        );
    }
}

/// The forms and parameters of `fit` as a table row of `case` (forms and parameters sorted).
pub fn fit_row(case: &str, fit: &Fit) -> FitRow {
    let mut forms: Vec<String> = fit
        .effects
        .iter()
        .map(|e| format!("{}/{}", e.effect.name(), e.effect.form()))
        .collect();
    forms.sort();
    let mut params: Vec<(String, f64)> = fit
        .effects
        .iter()
        .flat_map(|e| {
            e.params
                .iter()
                .map(move |q| (format!("{}.{}", e.effect.name(), q.name), q.value))
        })
        .collect();
    params.sort_by(|a, b| a.0.cmp(&b.0));
    FitRow {
        case: case.to_string(),
        forms,
        params,
        line: 0,
    }
}

/// `row` as a table line (values to 5 significant digits).
pub fn line_text(row: &FitRow) -> String {
    let params: Vec<String> = row
        .params
        .iter()
        .map(|(n, v)| format!("{n}={v:.4e}"))
        .collect();
    format!(
        "{}\t{}\t{}",
        row.case,
        set_text(&row.forms),
        set_text(&params)
    )
}

/// What differs between a fit and its pinned row (empty: they agree within [`REL_TOL`]).
pub fn differences(pinned: &FitRow, now: &FitRow) -> Vec<String> {
    let mut out = Vec::new();
    if pinned.forms != now.forms {
        out.push(format!("forms {:?} → {:?}", pinned.forms, now.forms));
    }
    let names = |r: &FitRow| r.params.iter().map(|p| p.0.clone()).collect::<Vec<_>>();
    if names(pinned) != names(now) {
        out.push(format!("parameters {:?} → {:?}", names(pinned), names(now)));
        return out;
    }
    for ((name, want), (_, got)) in pinned.params.iter().zip(&now.params) {
        if (got - want).abs() > REL_TOL * want.abs() {
            out.push(format!(
                "{name} = {got} is {:+.1} % from the pinned {want} (allowed ±{:.0} %)",
                100.0 * (got - want) / want.abs(),
                100.0 * REL_TOL
            ));
        }
    }
    out
}

/// Fails with what differs unless the chosen `fit` on `case` agrees with its pinned row.
pub fn check_fit(table: &FitTable, case: &str, fit: &Fit) {
    let now = fit_row(case, fit);
    let Some(pinned) = table.row(case) else {
        panic!(
            "{}: case `{case}` has no line; add\n{}",
            table.path.display(),
            line_text(&now)
        );
    };
    let diff = differences(pinned, &now);
    assert!(
        diff.is_empty(),
        "the fit on `{case}` changed:\n  {}\nIf the change is intended, replace line {} of {} \
         with\n{}",
        diff.join("\n  "),
        pinned.line,
        table.path.display(),
        line_text(&now)
    );
}
