//! Pinned verdicts: a checked-in table of what the search says on each log of a test set, so
//! that a changed verdict fails by name with a readable difference (instead of hiding behind an
//! overall rate), and improving a case means updating its line of the table in the same commit.
//!
//! The table is text, one case per line: `case <TAB> expected <TAB> found`, each set written as
//! its effect names sorted and joined by `,` (`-` for none); `#` starts a comment line.
//!
//! The tests built on it run one trial per case (a libtest-compatible harness, so that
//! cargo-nextest runs the searches side by side) and one cheap trial that checks the table
//! itself: its cases are the set's, and the rates it claims hold.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// One line of a table.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Row {
    /// The case (log) name.
    pub case: String,
    /// The effects hidden in it, sorted.
    pub expected: Vec<String>,
    /// The effects the search names on it, sorted.
    pub found: Vec<String>,
    /// Line in the table file (from 1).
    pub line: usize,
}

impl Row {
    /// Whether the verdict names exactly the hidden effects.
    pub fn exact(&self) -> bool {
        self.expected == self.found
    }
}

/// A set written as in the table.
pub fn set_text(set: &[String]) -> String {
    if set.is_empty() {
        "-".to_string()
    } else {
        set.join(",")
    }
}

/// The items of a set or list written as in the table (`-`: none), in written order.
pub fn items(s: &str) -> Vec<String> {
    if s == "-" {
        Vec::new()
    } else {
        s.split(',').map(|x| x.trim().to_string()).collect()
    }
}

fn parse_set(s: &str) -> Vec<String> {
    let mut v = items(s);
    v.sort();
    v
}

/// The data lines of the table file at `path` (comments and blank lines left out), each with
/// its 1-based line number and its tab-separated fields; fails with the file and line unless
/// a line has `fields` fields (`what` names them in the message).
pub fn data_lines(path: &Path, fields: usize, what: &str) -> Vec<(usize, Vec<String>)> {
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("{}: cannot read the pinned table: {e}", path.display()));
    let mut out = Vec::new();
    for (i, l) in text.lines().enumerate() {
        let l = l.trim_end();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        let f: Vec<String> = l.split('\t').map(String::from).collect();
        assert!(
            f.len() == fields,
            "{}:{}: expected `{what}`, got {l:?}",
            path.display(),
            i + 1
        );
        out.push((i + 1, f));
    }
    out
}

/// A table file, read.
pub struct Table {
    /// Its path.
    pub path: PathBuf,
    /// Its rows, in file order.
    pub rows: Vec<Row>,
}

impl Table {
    /// Reads `path`; a malformed line fails with the file and line.
    pub fn read(path: &Path) -> Table {
        let rows = data_lines(path, 3, "case<TAB>expected<TAB>found")
            .into_iter()
            .map(|(line, f)| Row {
                case: f[0].clone(),
                expected: parse_set(&f[1]),
                found: parse_set(&f[2]),
                line,
            })
            .collect();
        Table {
            path: path.to_path_buf(),
            rows,
        }
    }

    /// The row of `case`.
    pub fn row(&self, case: &str) -> &Row {
        self.rows
            .iter()
            .find(|r| r.case == case)
            .unwrap_or_else(|| {
                panic!(
                    "{}: case `{case}` has no line; add `{case}\t…\t…`",
                    self.path.display()
                )
            })
    }

    /// Fails unless the table lists exactly `cases` (name, expected effects), in that order.
    pub fn check_cases(&self, cases: &[(String, Vec<String>)]) {
        let want: Vec<(String, Vec<String>)> = cases.to_vec();
        let have: Vec<(String, Vec<String>)> = self
            .rows
            .iter()
            .map(|r| (r.case.clone(), r.expected.clone()))
            .collect();
        if want != have {
            let w: BTreeSet<_> = want.iter().collect();
            let h: BTreeSet<_> = have.iter().collect();
            panic!(
                "{}: the table's cases are not the test set's\n  missing: {:?}\n  extra: {:?}",
                self.path.display(),
                w.difference(&h).collect::<Vec<_>>(),
                h.difference(&w).collect::<Vec<_>>(),
            );
        }
    }

    /// Exact rows and rows.
    pub fn exact(&self) -> (usize, usize) {
        (
            self.rows.iter().filter(|r| r.exact()).count(),
            self.rows.len(),
        )
    }
}

/// Fails with a readable difference unless the search's verdict `found` on `case` is the
/// pinned one.
pub fn check_verdict(table: &Table, case: &str, found: &[String], detail: &str) {
    let row = table.row(case);
    let mut found = found.to_vec();
    found.sort();
    if found == row.found {
        return;
    }
    let mark = |f: &[String]| {
        if f == row.expected {
            "exact"
        } else {
            "not exact"
        }
    };
    panic!(
        "the verdict on `{case}` changed\n  hidden: {{{}}}\n  pinned: {{{}}} ({})\n  now:    {{{}}} ({})\n\
         {detail}\nIf the change is intended (an improvement, or a loss the commit explains), \
         replace line {} of {} with\n{case}\t{}\t{}",
        row.expected.join(", "),
        row.found.join(", "),
        mark(&row.found),
        found.join(", "),
        mark(&found),
        row.line,
        table.path.display(),
        set_text(&row.expected),
        set_text(&found),
    );
}
