//! Gaps in time: a log that pauses (the logger stopped, the vehicle was lifted out) is several
//! runs, not one run with a long hold.
//!
//! A step between two rows larger than the **gap limit** is a gap. The limit is
//! `max(factor × median sample period, floor)` — by default max(10 × median, 1 s) — or a fixed
//! number of seconds ([`GapOptions::max_gap`], `shoal validate --max-gap SECONDS`).
//!
//! With [`GapMode::Split`] (the default) the run is cut at every gap; segment *k* (1-based, in
//! file order) becomes its own [`MeasuredRun`] named `<stem>#k`, keeping the file's line numbers.
//! A segment with fewer than [`GapOptions::min_rows`] rows, shorter than
//! [`GapOptions::min_duration`], or without any measurement sample is dropped and counted. With
//! [`GapMode::Error`] the first gap is an error naming its line.
//!
//! Inputs are zero-order held, so a segment starts with the value in force at its first row
//! (possibly set before the gap). Measurements without a sample in a segment are left out of
//! it. The work is linear in the rows; nothing is allocated by the time span.

use crate::log::numbers::short;
use crate::log::run::{Channel, InputColumn, MeasuredRun, RunError};

/// What to do at a gap.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum GapMode {
    /// Cut the run into segments.
    #[default]
    Split,
    /// Refuse the run.
    Error,
}

impl std::str::FromStr for GapMode {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "split" => Ok(GapMode::Split),
            "error" => Ok(GapMode::Error),
            _ => Err(format!("unknown gap mode `{s}` (allowed: split, error)")),
        }
    }
}

/// How gaps are found and handled.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct GapOptions {
    /// Split or refuse.
    pub mode: GapMode,
    /// A gap is a step larger than `factor` × the median sample period … \[-\]
    pub factor: f64,
    /// … and larger than this \[s\].
    pub floor: f64,
    /// A fixed gap limit instead of the two above \[s\].
    pub max_gap: Option<f64>,
    /// Segments with fewer rows are dropped.
    pub min_rows: usize,
    /// Segments shorter than this are dropped \[s\].
    pub min_duration: f64,
}

impl Default for GapOptions {
    fn default() -> Self {
        Self {
            mode: GapMode::Split,
            factor: 10.0,
            floor: 1.0,
            max_gap: None,
            min_rows: 2,
            min_duration: 1.0,
        }
    }
}

/// One segment of a file.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SegmentNote {
    /// 1-based place in the file.
    pub index: usize,
    /// Run name: `<stem>#<index>` (the file stem when the file has no gap).
    pub name: String,
    /// 1-based file line of its first row.
    pub first_line: usize,
    /// 1-based file line of its last row.
    pub last_line: usize,
    /// Rows in it.
    pub rows: usize,
    /// Time of its first row \[s\].
    pub t_start: f64,
    /// Time of its last row \[s\].
    pub t_end: f64,
    /// Why it was dropped (`None`: kept).
    pub dropped: Option<String>,
}

impl std::fmt::Display for SegmentNote {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}: lines {}–{}, {} rows, t = {} … {} s",
            self.name,
            self.first_line,
            self.last_line,
            self.rows,
            short(self.t_start),
            short(self.t_end)
        )?;
        if let Some(why) = &self.dropped {
            write!(f, " — dropped: {why}")?;
        }
        Ok(())
    }
}

/// A run cut at its gaps.
#[derive(Clone, Debug, PartialEq)]
pub struct Segments {
    /// The kept segments, in file order (the run itself when it has no gap).
    pub runs: Vec<MeasuredRun>,
    /// Every segment, kept or dropped.
    pub notes: Vec<SegmentNote>,
    /// Median step between rows \[s\].
    pub median_period: f64,
    /// The gap limit used \[s\].
    pub gap_limit: f64,
}

impl Segments {
    /// Number of dropped segments.
    pub fn dropped(&self) -> usize {
        self.notes.iter().filter(|n| n.dropped.is_some()).count()
    }
}

impl MeasuredRun {
    /// Median step between rows \[s\] (0 for fewer than two rows).
    pub fn median_period(&self) -> f64 {
        let mut d: Vec<f64> = self.t.windows(2).map(|w| w[1] - w[0]).collect();
        if d.is_empty() {
            return 0.0;
        }
        let mid = d.len() / 2;
        let (_, m, _) = d.select_nth_unstable_by(mid, f64::total_cmp);
        *m
    }

    /// The gap limit for this run under `opts` \[s\].
    pub fn gap_limit(&self, opts: &GapOptions) -> f64 {
        opts.max_gap
            .unwrap_or_else(|| (opts.factor * self.median_period()).max(opts.floor))
    }

    /// Cuts the run at its gaps in time (see the module docs), or refuses it at the first gap
    /// with [`GapMode::Error`]. An error also when the options are out of range or every
    /// segment is dropped.
    pub fn split_at_gaps(mut self, opts: &GapOptions) -> Result<Segments, RunError> {
        let err = |line: usize, column: Option<(usize, String)>, message: String| RunError {
            file: self.path.clone(),
            line,
            column,
            message,
        };
        let bad = |x: f64| !(x.is_finite() && x > 0.0);
        if bad(opts.factor) || bad(opts.floor) || opts.max_gap.is_some_and(bad) {
            return Err(err(
                0,
                None,
                format!(
                    "gap options out of range (factor {}, floor {} s, max gap {:?} s); allowed: \
                     finite and > 0",
                    opts.factor, opts.floor, opts.max_gap
                ),
            ));
        }
        if !(opts.min_duration.is_finite() && opts.min_duration >= 0.0) {
            return Err(err(
                0,
                None,
                format!(
                    "minimum segment duration {} s is out of range; allowed: ≥ 0 s",
                    opts.min_duration
                ),
            ));
        }
        let median = self.median_period();
        let limit = self.gap_limit(opts);
        let line_of = |run: &MeasuredRun, row: usize| run.lines.get(row).copied().unwrap_or(0);
        let time_col = (self.ingest.time_column > 0).then(|| {
            let c = self.ingest.time_column;
            (c, self.ingest.time_header.clone())
        });
        // Row indices where a segment starts (after a gap).
        let mut starts = vec![0usize];
        for (i, w) in self.t.windows(2).enumerate() {
            let step = w[1] - w[0];
            if step > limit {
                if opts.mode == GapMode::Error {
                    return Err(err(
                        line_of(&self, i + 1),
                        time_col.clone(),
                        format!(
                            "the time jumps by {} s (from {} s on line {}), more than the gap \
                             limit {} s ({}); allowed: steps up to the limit, or split the run \
                             at its gaps (--gaps split)",
                            short(step),
                            short(w[0]),
                            line_of(&self, i),
                            short(limit),
                            limit_rule(opts, median)
                        ),
                    ));
                }
                starts.push(i + 1);
            }
        }
        self.ingest.gap_limit = limit;
        let stem = self.name.clone();
        if starts.len() == 1 {
            self.ingest.segments = 1;
            let note = SegmentNote {
                index: 1,
                name: stem,
                first_line: line_of(&self, 0),
                last_line: line_of(&self, self.t.len().saturating_sub(1)),
                rows: self.t.len(),
                t_start: self.t.first().copied().unwrap_or(0.0),
                t_end: self.t.last().copied().unwrap_or(0.0),
                dropped: None,
            };
            return Ok(Segments {
                runs: vec![self],
                notes: vec![note],
                median_period: median,
                gap_limit: limit,
            });
        }
        let n = self.t.len();
        let mut notes = Vec::with_capacity(starts.len());
        let mut ranges = Vec::new();
        for (k, &s) in starts.iter().enumerate() {
            let e = starts.get(k + 1).copied().unwrap_or(n);
            let rows = e - s;
            let (t0, t1) = (self.t[s], self.t[e - 1]);
            let sampled = self.channels.iter().any(|c| {
                let a = c.rows.partition_point(|&r| r < s);
                c.rows.get(a).is_some_and(|&r| r < e)
            });
            let dropped = if rows < opts.min_rows.max(2) {
                Some(format!(
                    "{rows} row(s); a segment needs at least {}",
                    opts.min_rows.max(2)
                ))
            } else if t1 - t0 < opts.min_duration {
                Some(format!(
                    "{} s long; a segment needs at least {} s",
                    short(t1 - t0),
                    short(opts.min_duration)
                ))
            } else if !sampled {
                Some("no measurement sample".to_string())
            } else {
                None
            };
            if dropped.is_none() {
                ranges.push((k + 1, s, e));
            }
            notes.push(SegmentNote {
                index: k + 1,
                name: format!("{stem}#{}", k + 1),
                first_line: line_of(&self, s),
                last_line: line_of(&self, e - 1),
                rows,
                t_start: t0,
                t_end: t1,
                dropped,
            });
        }
        if ranges.is_empty() {
            return Err(err(
                0,
                None,
                format!(
                    "the run falls apart at its gaps (> {} s) into {} segments, all too short \
                     (each needs at least {} rows, {} s and a measurement sample); allowed: a \
                     longer --max-gap, or --gaps error to see the first gap",
                    short(limit),
                    notes.len(),
                    opts.min_rows.max(2),
                    short(opts.min_duration)
                ),
            ));
        }
        self.ingest.segments = notes.len();
        self.ingest.dropped_segments = notes.len() - ranges.len();
        let runs = ranges
            .into_iter()
            .map(|(index, s, e)| self.segment(index, s, e))
            .collect();
        Ok(Segments {
            runs,
            notes,
            median_period: median,
            gap_limit: limit,
        })
    }

    /// Rows `s..e` as the run `<stem>#index`.
    fn segment(&self, index: usize, s: usize, e: usize) -> MeasuredRun {
        let cut = |cols: &[InputColumn]| -> Vec<InputColumn> {
            cols.iter()
                .map(|inp| InputColumn {
                    name: inp.name.clone(),
                    column: inp.column,
                    values: inp
                        .values
                        .get(s..e)
                        .map(<[f64]>::to_vec)
                        .unwrap_or_default(),
                    precision: inp
                        .precision
                        .get(s..e)
                        .map(<[f32]>::to_vec)
                        .unwrap_or_default(),
                    first_set: inp.first_set.saturating_sub(s),
                })
                .collect()
        };
        let inputs = cut(&self.inputs);
        let channels = self
            .channels
            .iter()
            .filter_map(|c| {
                let a = c.rows.partition_point(|&r| r < s);
                let b = c.rows.partition_point(|&r| r < e);
                (b > a).then(|| Channel {
                    kind: c.kind,
                    column: c.column,
                    rows: c.rows[a..b].iter().map(|r| r - s).collect(),
                    values: c.values[a..b].to_vec(),
                })
            })
            .collect();
        let mut ingest = self.ingest.clone();
        ingest.segment = Some(index);
        MeasuredRun {
            path: self.path.clone(),
            name: format!("{}#{index}", self.name),
            t: self.t.get(s..e).map(<[f64]>::to_vec).unwrap_or_default(),
            inputs,
            channels,
            references: cut(&self.references),
            extra: self.extra.clone(),
            header_line: self.header_line,
            lines: self
                .lines
                .get(s..e)
                .map(<[usize]>::to_vec)
                .unwrap_or_default(),
            ingest,
        }
    }
}

/// How the gap limit was set, for messages.
fn limit_rule(opts: &GapOptions, median: f64) -> String {
    match opts.max_gap {
        Some(_) => "set by --max-gap".to_string(),
        None => format!(
            "max({} × the median step {} s, {} s)",
            short(opts.factor),
            short(median),
            short(opts.floor)
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::log::run::ReferenceKind;
    use std::fmt::Write;
    use std::path::Path;

    /// A 50 Hz log with its time jumping at the given rows.
    fn log(rows: usize, jumps: &[(usize, f64)]) -> String {
        let mut s = String::from("# logger\nt,u.port,y.depth,y.yaw\n");
        let mut t = 0.0;
        for i in 0..rows {
            if let Some((_, j)) = jumps.iter().find(|(r, _)| *r == i) {
                t += j;
            }
            let port = if i == 0 { "10" } else { "" };
            let yaw = if i % 2 == 0 { "0.5" } else { "" };
            writeln!(s, "{t:.2},{port},{},{yaw}", 1.0 + i as f64 * 1e-3).unwrap();
            t += 0.02;
        }
        s
    }

    fn parse(s: &str) -> MeasuredRun {
        MeasuredRun::parse(s, Path::new("dive.csv")).unwrap()
    }

    #[test]
    fn a_run_without_gaps_stays_whole() {
        let seg = parse(&log(200, &[]))
            .split_at_gaps(&GapOptions::default())
            .unwrap();
        assert_eq!(seg.runs.len(), 1);
        assert_eq!(seg.runs[0].name, "dive");
        assert_eq!(seg.runs[0].ingest.segments, 1);
        assert_eq!(seg.runs[0].ingest.segment, None);
        assert!((seg.median_period - 0.02).abs() < 1e-9);
        assert!((seg.gap_limit - 1.0).abs() < 1e-12);
    }

    #[test]
    fn gaps_split_the_run_into_named_segments() {
        // Gaps before rows 100 (+30 s), 160 (+2 s) and 220 (+5 s), the last one 3 rows before
        // the end.
        let run = parse(&log(223, &[(100, 30.0), (160, 2.0), (220, 5.0)]));
        let seg = run.clone().split_at_gaps(&GapOptions::default()).unwrap();
        let names: Vec<&str> = seg.runs.iter().map(|r| r.name.as_str()).collect();
        assert_eq!(names, ["dive#1", "dive#2", "dive#3"]);
        assert_eq!(seg.notes.len(), 4);
        assert_eq!(seg.dropped(), 1);
        assert!(
            seg.notes[3]
                .dropped
                .as_deref()
                .unwrap()
                .contains("needs at least 1 s")
        );
        assert_eq!(seg.notes[3].name, "dive#4");
        // File lines: comment, header, then row i on line i + 3.
        assert_eq!(
            (seg.notes[1].first_line, seg.notes[1].last_line),
            (103, 162)
        );
        let [a, b, c] = [&seg.runs[0], &seg.runs[1], &seg.runs[2]];
        assert_eq!((a.t.len(), b.t.len(), c.t.len()), (100, 60, 60));
        assert_eq!(b.lines[0], 103);
        assert_eq!(b.t[0], run.t[100]);
        // The held input carries over; channel rows are renumbered.
        assert_eq!(b.inputs[0].values[0], 10.0);
        assert_eq!(b.channels[1].rows[0], 0);
        assert_eq!(b.channels[0].values[0], run.channels[0].values[100]);
        assert_eq!(b.ingest.segment, Some(2));
        assert_eq!((b.ingest.segments, b.ingest.dropped_segments), (4, 1));
        // A fixed limit above the 2 s gap joins the middle.
        let seg = run
            .clone()
            .split_at_gaps(&GapOptions {
                max_gap: Some(3.0),
                ..Default::default()
            })
            .unwrap();
        assert_eq!(seg.runs.len(), 2);
        assert_eq!(seg.runs[1].t.len(), 120);
        // In error mode the first gap is located.
        let e = run
            .split_at_gaps(&GapOptions {
                mode: GapMode::Error,
                ..Default::default()
            })
            .unwrap_err();
        assert_eq!((e.line, e.column.clone()), (103, Some((1, "t".into()))));
        assert!(e.message.contains("jumps by 30.02 s"), "{e}");
        assert!(
            e.message.contains("max(10 × the median step 0.02 s, 1 s)"),
            "{e}"
        );
    }

    #[test]
    fn a_segment_without_samples_is_dropped_and_all_dropped_is_an_error() {
        let text = "t,u.port,y.depth\n0,1,1\n0.5,,\n1.5,,\n100,,\n101,,\n102,,\n200,,\n201,,2\n\
                    202,,\n";
        let seg = parse(text)
            .split_at_gaps(&GapOptions {
                min_duration: 0.0,
                ..Default::default()
            })
            .unwrap();
        // Steps: 0.5, 1, 98.5, 1, 1, 98, 1, 1: median 1 s, limit 10 s.
        assert_eq!(seg.runs.len(), 2);
        assert_eq!(seg.runs[0].t, vec![0.0, 0.5, 1.5]);
        assert_eq!(
            seg.notes[1].dropped.as_deref(),
            Some("no measurement sample")
        );
        assert_eq!(seg.runs[1].name, "dive#3");
        assert_eq!(seg.runs[1].channels[0].rows, vec![1]);
        let text = "t,u.port,y.depth\n0,1,1\n100,1,1\n200,,2\n";
        let e = parse(text)
            .split_at_gaps(&GapOptions {
                max_gap: Some(1.0),
                ..Default::default()
            })
            .unwrap_err();
        assert!(e.message.contains("all too short"), "{e}");
    }

    #[test]
    fn each_segment_keeps_its_references_held_across_the_gap() {
        // Steps of 0.5 s and one of 98.5 s before row 4: two segments of four rows.
        let text = "t,y.depth,r.depth,r.mode\n0,1,1,\n0.5,1,,\n1,1,,\n1.5,1,,\n\
                    100,1,,\n100.5,1,3,\n101,1,,auto\n101.5,1,,\n";
        let seg = parse(text).split_at_gaps(&GapOptions::default()).unwrap();
        assert_eq!(seg.runs.len(), 2);
        let [a, b] = [&seg.runs[0], &seg.runs[1]];
        let column = |r: &MeasuredRun, k: ReferenceKind| r.reference(k).unwrap().clone();
        // r.depth: 1 from row 0, 3 from row 5; the value in force carries over the gap.
        let (depth_a, depth_b) = (
            column(a, ReferenceKind::Depth),
            column(b, ReferenceKind::Depth),
        );
        assert_eq!(depth_a.values, vec![1.0; 4]);
        assert_eq!(depth_b.values, vec![1.0, 3.0, 3.0, 3.0]);
        assert_eq!(depth_b.precision.len(), 4);
        assert_eq!((depth_a.first_set, depth_b.first_set), (0, 0));
        // r.mode: first set (auto, code 5) at row 6, i.e. row 2 of the second segment; the
        // first segment holds that first value throughout.
        let (mode_a, mode_b) = (
            column(a, ReferenceKind::Mode),
            column(b, ReferenceKind::Mode),
        );
        assert_eq!(mode_a.values, vec![5.0; 4]);
        assert_eq!(mode_b.values, vec![5.0; 4]);
        assert_eq!(mode_b.first_set, 2);
        assert_eq!((mode_a.column, mode_b.column), (4, 4));
    }

    #[test]
    fn millisecond_logs_split_in_seconds() {
        let mut s = String::from("t_ms,u.port,y.depth\n");
        for i in 0..200 {
            let t = if i < 100 { i * 20 } else { 60_000 + i * 20 };
            writeln!(s, "{t},1,1").unwrap();
        }
        let seg = parse(&s).split_at_gaps(&GapOptions::default()).unwrap();
        assert_eq!(seg.runs.len(), 2);
        assert!((seg.runs[1].t[0] - 62.0).abs() < 1e-9);
    }
}
