//! Fuzzing the measured-run ingestion: arbitrary bytes, and structured mutations of a valid
//! μAUV² log (cells deleted, duplicated or garbled, rows dropped or repeated, separators mixed,
//! comments and blank lines inserted, huge or millisecond times, gaps, NaN, long lines, header
//! names changed), fed to the reader, the gap splitter and the input limits. Each must answer
//! `Ok` or `Err` — never panic — and what it accepts must be a consistent run. That the
//! harmless mutations among them are *accepted*, with the same data, is
//! `fuzz_csv_harmless.rs`.
//!
//! `cargo test` runs 256 cases per property; a long run:
//! `PROPTEST_CASES=200000 cargo test --release -p shoal-sysid --test fuzz_csv`.
//! The code under test is linear in the input (one pass over the bytes, one over the rows),
//! so every case finishes; no wall-clock bound is asserted here.

use proptest::prelude::*;
use shoal_sysid::evaluate::open_loop::{InputMap, ReplayOptions};
use shoal_sysid::log::format::{ReadOptions, TimeUnit};
use shoal_sysid::log::run::MeasuredRun;
use shoal_sysid::log::segments::{GapMode, GapOptions};
use std::path::Path;

/// A run the reader accepted must be consistent.
fn check_run(r: &MeasuredRun) {
    let n = r.t.len();
    assert!(n >= 2, "at least two rows");
    assert!(r.t.iter().all(|t| t.is_finite()));
    assert!(r.t.windows(2).all(|w| w[0] < w[1]), "time increases");
    assert_eq!(r.lines.len(), n);
    assert!(r.lines.windows(2).all(|w| w[0] < w[1]), "lines increase");
    assert!(r.lines.first().is_some_and(|&l| l > r.header_line));
    for inp in &r.inputs {
        assert_eq!(inp.values.len(), n);
        assert_eq!(inp.precision.len(), n);
        assert!(inp.first_set < n);
        assert!(inp.values.iter().all(|v| v.is_finite()));
    }
    assert!(!r.channels.is_empty());
    for c in &r.channels {
        assert!(!c.values.is_empty());
        assert_eq!(c.rows.len(), c.values.len());
        assert!(c.rows.windows(2).all(|w| w[0] < w[1]));
        assert!(c.rows.iter().all(|&row| row < n));
        assert!(c.values.iter().all(|v| v.is_finite()));
    }
}

/// The whole ingestion path of `shoal validate` on `bytes`.
fn ingest(bytes: &[u8], time_unit: Option<TimeUnit>) {
    let params = shoal_model::presets::uauv2();
    let Ok(run) =
        MeasuredRun::from_reader(bytes, Path::new("fuzz.csv"), &ReadOptions { time_unit })
    else {
        return;
    };
    check_run(&run);
    for mode in [GapMode::Split, GapMode::Error] {
        let opts = GapOptions {
            mode,
            ..Default::default()
        };
        let Ok(seg) = run.clone().split_at_gaps(&opts) else {
            continue;
        };
        assert!(!seg.runs.is_empty());
        assert_eq!(seg.notes.len() - seg.dropped(), seg.runs.len());
        for mut r in seg.runs {
            check_run(&r);
            let before = r.clone();
            match InputMap::new(&params, &mut r) {
                Ok(map) => {
                    for &(i, k) in &map.thrusters {
                        let max = params.thrusters[i].max_command;
                        assert!(r.inputs[k].values.iter().all(|v| v.abs() <= max));
                    }
                    for &(i, k) in &map.tilts {
                        let (lo, hi) = (params.tilts[i].min, params.tilts[i].max);
                        assert!(r.inputs[k].values.iter().all(|v| (lo..=hi).contains(v)));
                    }
                    if let Some(k) = map.pump {
                        assert!(
                            r.inputs[k]
                                .values
                                .iter()
                                .all(|v| [-1.0, 0.0, 1.0].contains(v))
                        );
                    }
                    let _ = ReplayOptions::default().steps(&r);
                }
                Err(e) => {
                    assert_eq!(r, before, "a refused run is left unchanged");
                    assert!(!e.message.is_empty());
                }
            }
        }
    }
}

/// A line of the log before rendering.
#[derive(Clone, Debug)]
enum Line {
    Cells(Vec<String>),
    Raw(String),
}

#[derive(Clone, Debug)]
enum Mutation {
    Cell {
        row: usize,
        col: usize,
        text: String,
    },
    DeleteCell {
        row: usize,
        col: usize,
    },
    DuplicateCell {
        row: usize,
        col: usize,
    },
    DeleteRow(usize),
    DuplicateRow(usize),
    SwapRows(usize, usize),
    Comment {
        row: usize,
        text: String,
    },
    Blank {
        row: usize,
        text: String,
    },
    Trailing(usize),
    Time {
        row: usize,
        t: f64,
    },
    Gap {
        row: usize,
        dt: f64,
    },
    LongCell {
        row: usize,
        col: usize,
        len: usize,
    },
    OtherSeparator {
        row: usize,
        sep: char,
    },
}

#[derive(Clone, Debug)]
struct Case {
    rows: usize,
    sep: char,
    crlf: bool,
    ms: bool,
    time_unit: Option<TimeUnit>,
    mutations: Vec<Mutation>,
}

const HEADER: [&str; 9] = [
    "t", "u.top", "u.port", "u.stbd", "u.alpha", "u.beta", "u.pump", "y.depth", "y.yaw",
];

impl Case {
    /// The valid log this case starts from: a diving run at 50 Hz, tilt at −1.5708.
    fn base(&self) -> Vec<Line> {
        let mut lines = vec![Line::Cells(
            HEADER
                .iter()
                .map(|h| {
                    if *h == "t" && self.ms {
                        "t_ms".to_string()
                    } else {
                        h.to_string()
                    }
                })
                .collect(),
        )];
        for i in 0..self.rows {
            let t = if self.ms {
                format!("{}", i * 20)
            } else {
                format!("{}", i as f64 * 0.02)
            };
            let cmd = format!("{}", ((i * 37) % 201) as f64 - 100.0);
            let pump = ["0", "1", "-1"][(i / 7) % 3];
            lines.push(Line::Cells(vec![
                t,
                "0".into(),
                cmd.clone(),
                cmd,
                "0".into(),
                "-1.5708".into(),
                pump.into(),
                format!("{:.4}", 0.8 + i as f64 * 1e-3),
                if i % 3 == 0 {
                    format!("{:.6}", 0.3 + i as f64 * 1e-4)
                } else {
                    String::new()
                },
            ]));
        }
        lines
    }

    fn render(&self) -> String {
        let mut lines = self.base();
        for m in &self.mutations {
            apply(&mut lines, m, self.ms);
        }
        let eol = if self.crlf { "\r\n" } else { "\n" };
        let mut out = String::new();
        for l in &lines {
            match l {
                Line::Cells(c) => out.push_str(&c.join(&self.sep.to_string())),
                Line::Raw(s) => out.push_str(s),
            }
            out.push_str(eol);
        }
        out
    }
}

fn cells(lines: &mut [Line], row: usize) -> Option<&mut Vec<String>> {
    let n = lines.len();
    match lines.get_mut(row % n.max(1)) {
        Some(Line::Cells(c)) => Some(c),
        _ => None,
    }
}

fn apply(lines: &mut Vec<Line>, m: &Mutation, ms: bool) {
    let n = lines.len();
    if n == 0 {
        return;
    }
    match m {
        Mutation::Cell { row, col, text } => {
            if let Some(c) = cells(lines, *row) {
                let k = col % c.len().max(1);
                if let Some(x) = c.get_mut(k) {
                    x.clone_from(text);
                }
            }
        }
        Mutation::DeleteCell { row, col } => {
            if let Some(c) = cells(lines, *row)
                && !c.is_empty()
            {
                let k = col % c.len();
                c.remove(k);
            }
        }
        Mutation::DuplicateCell { row, col } => {
            if let Some(c) = cells(lines, *row)
                && !c.is_empty()
            {
                let k = col % c.len();
                let x = c[k].clone();
                c.insert(k, x);
            }
        }
        Mutation::DeleteRow(r) => {
            lines.remove(r % n);
        }
        Mutation::DuplicateRow(r) => {
            let l = lines[r % n].clone();
            lines.insert(r % n, l);
        }
        Mutation::SwapRows(a, b) => lines.swap(a % n, b % n),
        Mutation::Comment { row, text } => lines.insert(row % (n + 1), Line::Raw(text.clone())),
        Mutation::Blank { row, text } => lines.insert(row % (n + 1), Line::Raw(text.clone())),
        Mutation::Trailing(r) => {
            if let Some(c) = cells(lines, *r) {
                c.push(String::new());
            }
        }
        Mutation::Time { row, t } => {
            if let Some(c) = cells(lines, *row)
                && let Some(x) = c.first_mut()
            {
                *x = format!("{t}");
            }
        }
        Mutation::Gap { row, dt } => {
            let dt = if ms { dt * 1000.0 } else { *dt };
            for l in lines.iter_mut().skip(1 + row % n) {
                if let Line::Cells(c) = l
                    && let Some(x) = c.first_mut()
                    && let Ok(v) = x.parse::<f64>()
                {
                    *x = format!("{}", v + dt);
                }
            }
        }
        Mutation::LongCell { row, col, len } => {
            if let Some(c) = cells(lines, *row) {
                let k = col % c.len().max(1);
                if let Some(x) = c.get_mut(k) {
                    *x = "1".repeat(*len);
                }
            }
        }
        Mutation::OtherSeparator { row, sep } => {
            if let Some(Line::Cells(c)) = lines.get(row % n) {
                let joined = c.join(&sep.to_string());
                lines[row % n] = Line::Raw(joined);
            }
        }
    }
}

fn token() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::sample::select(vec![
            "",
            "nan",
            "NaN",
            "inf",
            "-inf",
            "1e400",
            "-1e400",
            "1e-400",
            "0.5",
            "1e9",
            "-1e9",
            "-1.5708",
            "1.5708",
            "-1.5709",
            "-1.571",
            "-1.6",
            "-2",
            "100",
            "100.0005",
            "100.01",
            "101",
            "-0",
            "+.5e-3",
            ".",
            "-",
            "e5",
            "1,5",
            "#",
            "1 # note",
            "\"",
            "\"\"",
            "\"a,b\"",
            "\"1\n2\"",
            "0x10",
            "１",
            "\u{feff}1",
            " 1 ",
            "\t",
            "t",
            "t_ms",
            "t[s]",
            "y.dpth",
            "u.",
            "x.a",
            "u.rudder",
            "y.depth",
            "u.pump",
            "1e308",
            "-1e-320",
        ])
        .prop_map(str::to_string),
        any::<f64>().prop_map(|x| format!("{x}")),
        (-1e6..1e6f64).prop_map(|x| format!("{x}")),
        "[ -~]{0,12}",
        "\\PC{0,6}",
    ]
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let ix = 0usize..10_000;
    prop_oneof![
        4 => (ix.clone(), ix.clone(), token()).prop_map(|(row, col, text)| Mutation::Cell { row, col, text }),
        1 => (ix.clone(), ix.clone()).prop_map(|(row, col)| Mutation::DeleteCell { row, col }),
        1 => (ix.clone(), ix.clone()).prop_map(|(row, col)| Mutation::DuplicateCell { row, col }),
        1 => ix.clone().prop_map(Mutation::DeleteRow),
        1 => ix.clone().prop_map(Mutation::DuplicateRow),
        1 => (ix.clone(), ix.clone()).prop_map(|(a, b)| Mutation::SwapRows(a, b)),
        2 => (ix.clone(), "[ \t]{0,3}#[ -~]{0,10}").prop_map(|(row, text)| Mutation::Comment { row, text }),
        1 => (ix.clone(), "[ \t]{0,3}").prop_map(|(row, text)| Mutation::Blank { row, text }),
        1 => ix.clone().prop_map(Mutation::Trailing),
        1 => (ix.clone(), prop_oneof![
            Just(1e300), Just(1e15), Just(-1e9), Just(0.0), Just(f64::MAX), Just(f64::MIN_POSITIVE),
            -1e3..1e3f64,
        ]).prop_map(|(row, t)| Mutation::Time { row, t }),
        2 => (ix.clone(), prop_oneof![0.5..5.0f64, 10.0..1e4f64, Just(1e12), Just(1e300)])
            .prop_map(|(row, dt)| Mutation::Gap { row, dt }),
        1 => (ix.clone(), ix.clone(), 100usize..20_000).prop_map(|(row, col, len)| Mutation::LongCell { row, col, len }),
        1 => (ix, prop::sample::select(vec![',', ';', '\t', ' ', '|']))
            .prop_map(|(row, sep)| Mutation::OtherSeparator { row, sep }),
    ]
}

fn case() -> impl Strategy<Value = Case> {
    (
        0usize..80,
        prop::sample::select(vec![',', ';', '\t']),
        any::<bool>(),
        any::<bool>(),
        prop_oneof![
            Just(None),
            Just(Some(TimeUnit::Seconds)),
            Just(Some(TimeUnit::Milliseconds))
        ],
        prop::collection::vec(mutation(), 0..8),
    )
        .prop_map(|(rows, sep, crlf, ms, time_unit, mutations)| Case {
            rows,
            sep,
            crlf,
            ms,
            time_unit,
            mutations,
        })
}

/// Bytes from the alphabet of a log, so that the reader gets past the header more often.
fn log_bytes() -> impl Strategy<Value = Vec<u8>> {
    let alphabet = b"t,;\t\n\r #\"u.y.xdepthportbetapump0123456789.-+eE".to_vec();
    (
        prop::sample::select(vec![
            &b""[..],
            b"t,u.port,y.depth\n",
            b"t;u.beta;u.pump;y.depth;y.yaw\n",
            b"t_ms\tu.top\ty.r\n",
        ]),
        prop::collection::vec(prop::sample::select(alphabet), 0..600),
    )
        .prop_map(|(head, body)| [head, &body[..]].concat())
}

proptest! {
    #[test]
    fn arbitrary_bytes_never_panic(
        bytes in prop::collection::vec(any::<u8>(), 0..2048),
        ms in any::<bool>(),
    ) {
        ingest(&bytes, ms.then_some(TimeUnit::Milliseconds));
    }

    #[test]
    fn log_like_bytes_never_panic(bytes in log_bytes(), ms in any::<bool>()) {
        ingest(&bytes, ms.then_some(TimeUnit::Milliseconds));
    }

    #[test]
    fn mutated_logs_never_panic(case in case()) {
        let text = case.render();
        ingest(text.as_bytes(), case.time_unit);
    }
}

/// The unmutated logs the mutations start from are read, in every separator and line end,
/// and their tilt at −1.5708 is clamped on every row.
#[test]
fn the_base_logs_are_valid() {
    let params = shoal_model::presets::uauv2();
    for sep in [',', ';', '\t'] {
        for crlf in [false, true] {
            for ms in [false, true] {
                let case = Case {
                    rows: 60,
                    sep,
                    crlf,
                    ms,
                    time_unit: None,
                    mutations: Vec::new(),
                };
                let text = case.render();
                let mut run = MeasuredRun::parse(&text, Path::new("base.csv")).unwrap();
                check_run(&run);
                assert_eq!(run.t.len(), 60);
                assert!((run.t[59] - 59.0 * 0.02).abs() < 1e-9);
                let map = InputMap::new(&params, &mut run).unwrap();
                assert_eq!(map.clamped.len(), 1);
                assert_eq!(
                    (map.clamped[0].name.as_str(), map.clamped[0].count),
                    ("u.beta", 60)
                );
            }
        }
    }
}
