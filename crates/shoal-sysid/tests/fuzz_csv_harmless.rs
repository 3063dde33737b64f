//! Harmless mutations of valid measured-run logs must be *read*, with the same data. The
//! format (docs/validation.md, "Logs are read as loggers write them"; `shoal_sysid::log::ingest`)
//! promises that comment lines anywhere (indented or not), blank lines, `\n`, `\r\n` or `\r`
//! line ends, a UTF-8 byte-order mark, spaces around cells, quoted cells and one trailing
//! separator on the header or a row change nothing but the line numbers: a random valid log
//! is written plainly and with random such mutations, and both readings must agree on the
//! times, every input (values, precision, first set row), every measurement (rows and
//! values) and the ignored columns, with each row's line number where it was written and
//! the comment and blank lines counted. `fuzz_csv.rs` checks the other direction (no
//! mutation makes the reader panic or accept an inconsistent run).
//!
//! `cargo test` runs 256 cases per property; a long run:
//! `PROPTEST_CASES=100000 cargo test --release -p shoal-sysid --test fuzz_csv_harmless`.

use proptest::prelude::*;
use shoal_sysid::log::format::ReadOptions;
use shoal_sysid::log::run::{ChannelKind, MeasuredRun};
use std::path::Path;

/// A valid log: its header cells and its data rows' cells.
#[derive(Clone, Debug)]
struct Log {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
    sep: char,
}

/// A change the format promises to read as the same data.
#[derive(Clone, Debug)]
enum Harmless {
    /// A comment line (`#` after optional spaces and tabs) before line `at` (0: the top).
    Comment { at: usize, text: String },
    /// A line of spaces and tabs only (or empty) before line `at`.
    Blank { at: usize, text: String },
    /// Spaces before and after a cell of a line (header or row).
    Pad {
        line: usize,
        cell: usize,
        before: usize,
        after: usize,
    },
    /// A cell of a line written in double quotes (once).
    Quote { line: usize, cell: usize },
    /// One extra, empty last field on a line (header or row).
    Trailing { line: usize },
}

/// How the file is written around its lines.
#[derive(Clone, Debug)]
struct Style {
    eol: &'static str,
    bom: bool,
    changes: Vec<Harmless>,
}

/// A number as a logger writes it, from `x` and a number of decimals.
fn num(x: f64, decimals: usize) -> String {
    format!("{x:.decimals$}")
}

fn log() -> impl Strategy<Value = Log> {
    (
        2usize..40,
        prop::sample::select(vec![',', ';', '\t']),
        prop::sample::select(vec!["t", "t_s", "t[s]", "t_ms", "t[ms]"]),
        any::<bool>(),
        prop::collection::vec((-100.0..100.0f64, 0.0..3.0f64, -3.0..3.0f64), 40),
        prop::collection::vec(0u8..4, 40),
        0usize..5,
    )
        .prop_map(|(n, sep, time, extra, values, sampled, decimals)| {
            let ms = time.contains("ms");
            let mut header: Vec<String> = [time, "u.port", "u.stbd", "u.pump", "y.depth", "y.yaw"]
                .map(String::from)
                .to_vec();
            if extra {
                header.push("x.note".into());
            }
            let rows = (0..n)
                .map(|i| {
                    let (cmd, depth, yaw) = values[i];
                    let t = if ms {
                        format!("{}", i * 20)
                    } else {
                        num(i as f64 * 0.02, 2)
                    };
                    // Inputs are set in the first row and then now and then; yaw is sampled
                    // in the first row and then now and then (empty: not sampled).
                    let sometimes = |s: String| {
                        if i == 0 || sampled[i] == 0 {
                            s
                        } else {
                            String::new()
                        }
                    };
                    let mut row = vec![
                        t,
                        num(cmd, decimals),
                        sometimes(num(-cmd, decimals)),
                        sometimes(["0", "1", "-1"][i % 3].into()),
                        num(depth, decimals + 1),
                        sometimes(num(yaw, 4)),
                    ];
                    if extra {
                        row.push(format!("note {i}"));
                    }
                    row
                })
                .collect();
            Log { header, rows, sep }
        })
}

fn style() -> impl Strategy<Value = Style> {
    let ix = 0usize..1000;
    let change = prop_oneof![
        (ix.clone(), "[ \t]{0,3}#[ -~]{0,12}")
            .prop_map(|(at, text)| Harmless::Comment { at, text }),
        (ix.clone(), "[ \t]{0,3}").prop_map(|(at, text)| Harmless::Blank { at, text }),
        (ix.clone(), ix.clone(), 0usize..3, 0usize..3).prop_map(|(line, cell, before, after)| {
            Harmless::Pad {
                line,
                cell,
                before,
                after,
            }
        }),
        (ix.clone(), ix.clone()).prop_map(|(line, cell)| Harmless::Quote { line, cell }),
        ix.prop_map(|line| Harmless::Trailing { line }),
    ];
    (
        prop::sample::select(vec!["\n", "\r\n", "\r"]),
        any::<bool>(),
        prop::collection::vec(change, 0..12),
    )
        .prop_map(|(eol, bom, changes)| Style { eol, bom, changes })
}

/// One line of the written file: the cells of the header or a row, or a raw line.
enum Written {
    Cells {
        row: Option<usize>,
        cells: Vec<String>,
        trailing: bool,
    },
    Raw(String),
}

/// `log` written plainly (`style` `None`) or with `style`; returns the text and, for each
/// data row, the 1-based line it is written on.
fn write(log: &Log, style: Option<&Style>) -> (String, Vec<usize>) {
    let mut lines: Vec<Written> = std::iter::once((None, &log.header))
        .chain(log.rows.iter().enumerate().map(|(i, r)| (Some(i), r)))
        .map(|(row, cells)| Written::Cells {
            row,
            cells: cells.clone(),
            trailing: false,
        })
        .collect();
    let (eol, bom) = style.map_or(("\n", false), |s| (s.eol, s.bom));
    // Cell changes are made before lines are inserted, so `line` counts header and rows;
    // quotes go on before the padding, which then leaves quoted cells alone.
    let mut changes: Vec<&Harmless> = style
        .map(|s| s.changes.iter().collect())
        .unwrap_or_default();
    changes.sort_by_key(|c| match c {
        Harmless::Quote { .. } => 0,
        Harmless::Pad { .. } | Harmless::Trailing { .. } => 1,
        Harmless::Comment { .. } | Harmless::Blank { .. } => 2,
    });
    let cells_lines = lines.len();
    for c in changes {
        match c {
            Harmless::Pad {
                line,
                cell,
                before,
                after,
            } => {
                if let Written::Cells { cells, .. } = &mut lines[line % cells_lines] {
                    let k = cell % cells.len();
                    // Quoted cells too (`spaces_around_a_quoted_cell_are_ignored`).
                    cells[k] = format!("{}{}{}", " ".repeat(*before), cells[k], " ".repeat(*after));
                }
            }
            Harmless::Quote { line, cell } => {
                if let Written::Cells { cells, .. } = &mut lines[line % cells_lines] {
                    let k = cell % cells.len();
                    if !cells[k].starts_with('"') {
                        cells[k] = format!("\"{}\"", cells[k]);
                    }
                }
            }
            Harmless::Trailing { line } => {
                if let Written::Cells { trailing, .. } = &mut lines[line % cells_lines] {
                    *trailing = true;
                }
            }
            Harmless::Comment { at, text } | Harmless::Blank { at, text } => {
                let n = lines.len();
                lines.insert(at % (n + 1), Written::Raw(text.clone()));
            }
        }
    }
    let mut text = String::from(if bom { "\u{feff}" } else { "" });
    let mut row_lines = vec![0; log.rows.len()];
    for (k, l) in lines.iter().enumerate() {
        match l {
            Written::Cells {
                row,
                cells,
                trailing,
            } => {
                text.push_str(&cells.join(&log.sep.to_string()));
                if *trailing {
                    text.push(log.sep);
                }
                if let Some(i) = row {
                    row_lines[*i] = k + 1;
                }
            }
            Written::Raw(s) => text.push_str(s),
        }
        text.push_str(eol);
    }
    (text, row_lines)
}

/// The data of a run: times, inputs (name, values, precision, first set row), measurements
/// (kind, rows, values) and the ignored columns.
type Data = (
    Vec<f64>,
    Vec<(String, Vec<f64>, Vec<f32>, usize)>,
    Vec<(ChannelKind, Vec<usize>, Vec<f64>)>,
    Vec<String>,
);

fn data(r: &MeasuredRun) -> Data {
    (
        r.t.clone(),
        r.inputs
            .iter()
            .map(|i| {
                (
                    i.name.clone(),
                    i.values.clone(),
                    i.precision.clone(),
                    i.first_set,
                )
            })
            .collect(),
        r.channels
            .iter()
            .map(|c| (c.kind, c.rows.clone(), c.values.clone()))
            .collect(),
        r.extra.clone(),
    )
}

fn read(text: &str) -> Result<MeasuredRun, shoal_sysid::log::run::RunError> {
    MeasuredRun::from_reader(
        text.as_bytes(),
        Path::new("log.csv"),
        &ReadOptions::default(),
    )
}

proptest! {
    #[test]
    fn harmless_mutations_are_read_as_the_same_data(log in log(), style in style()) {
        let (plain, _) = write(&log, None);
        let base = read(&plain).unwrap_or_else(|e| panic!("the plain log is refused: {e}\n{plain}"));
        prop_assert_eq!(base.t.len(), log.rows.len());
        let (text, row_lines) = write(&log, Some(&style));
        let run = read(&text).unwrap_or_else(|e| panic!("refused: {e}\n{text:?}"));
        prop_assert_eq!(data(&run), data(&base), "{:?}", text);
        prop_assert_eq!(&run.lines, &row_lines, "{:?}", text);
        let count = |f: fn(&Harmless) -> bool| style.changes.iter().filter(|c| f(c)).count();
        prop_assert_eq!(run.ingest.comment_lines, count(|c| matches!(c, Harmless::Comment { .. })));
        prop_assert_eq!(run.ingest.blank_lines, count(|c| matches!(c, Harmless::Blank { .. })));
        prop_assert_eq!(
            run.ingest.trailing_separator,
            count(|c| matches!(c, Harmless::Trailing { .. })) > 0
        );
    }
}

/// Spaces around a quoted cell: the format says cells may be quoted and spaces around cells
/// are ignored — before the opening quote too (the csv reader alone would take the cell as
/// the text `"2"`, quotes included: a number cell refused as not a number, a header cell as an
/// unknown column), and a doubled quote inside is one quote.
#[test]
fn spaces_around_a_quoted_cell_are_ignored() {
    let plain = read("t,u.port,y.depth\n0,1,2\n0.1,1,3\n").unwrap();
    for text in [
        "t,u.port,y.depth\n0,1, \"2\"\n0.1,1,3\n",
        "t,u.port,y.depth\n0,1,\"2\" \n0.1,1,3\n",
        "t, \"u.port\" ,y.depth\n0,1,2\n0.1,1,3\n",
        "t,u.port,y.depth\n0, \"1\" , \"2\"\n0.1,1,3\n",
    ] {
        let run = read(text).unwrap_or_else(|e| panic!("{text:?}: {e}"));
        assert_eq!(data(&run), data(&plain), "{text:?}");
    }
}
