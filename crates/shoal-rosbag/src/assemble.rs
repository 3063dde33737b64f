//! Time series of a bag brought onto one time base: a [`MeasuredRun`], as the CSV reader
//! makes it from a multi-rate log.
//!
//! The rows are the union of every entry's sample times (the CSV format's "multi-rate logs
//! merged on the union of their time stamps"); inputs and the controller's references are held
//! from one message to the next (zero-order hold); a channel is sampled at its own messages'
//! times only, never between them. The run starts when every input and every reference has had
//! its first message — before it, a command is not known (a topic published on change says
//! nothing until its first change), so earlier samples are dropped rather than paired with an
//! invented command — and its time counts from there. Gaps are split afterwards by [`MeasuredRun::split_at_gaps`], as for a
//! CSV.
//!
//! The run's columns are the mapping's entries (column k = the k-th entry), its `path` the
//! bag and its name the bag's stem.

use crate::bag::{BagError, BagSummary, Series};
use crate::mapping::{Clock, Feeds};
use shoal_sysid::log::format::IngestInfo;
use shoal_sysid::log::run::{Channel, InputColumn, MeasuredRun};
use std::path::Path;

/// Clocks further apart than this are not one clock \[ns\] (a day).
const CLOCK_APART_NS: i64 = 86_400_000_000_000;

/// The run of the series read from the bag at `path`.
pub fn assemble(
    path: &Path,
    series: &[Series],
    summary: &BagSummary,
) -> Result<MeasuredRun, BagError> {
    check_one_clock(path, series)?;
    let start = series
        .iter()
        .filter(|s| matches!(s.entry.feeds, Feeds::Input | Feeds::Reference(_)))
        .map(|s| s.t[0])
        .max()
        .unwrap_or(i64::MIN);
    let mut times: Vec<i64> = series
        .iter()
        .flat_map(|s| s.t.iter().copied())
        .filter(|&x| x >= start)
        .collect();
    times.sort_unstable();
    times.dedup();
    if times.len() < 2 {
        return Err(BagError::new(
            path,
            None,
            format!(
                "{} time(s) in the mapped topics once every input and reference has had a \
                 message: a run needs at least two",
                times.len()
            ),
        ));
    }
    let t0 = times[0];
    let t: Vec<f64> = times.iter().map(|&x| (x - t0) as f64 * 1e-9).collect();
    let mut inputs = Vec::new();
    let mut channels = Vec::new();
    let mut references = Vec::new();
    for (k, s) in series.iter().enumerate() {
        let column = k + 1;
        match s.entry.feeds {
            Feeds::Input => inputs.push(held(s, &times, column)),
            Feeds::Reference(_) => references.push(held(s, &times, column)),
            Feeds::Channel(kind) => {
                let mut rows = Vec::with_capacity(s.t.len());
                let mut values = Vec::with_capacity(s.t.len());
                let mut at = 0usize;
                for (&x, &v) in s.t.iter().zip(&s.v).filter(|(x, _)| **x >= t0) {
                    // Both sorted: walk forward to this sample's row.
                    at += times[at..].partition_point(|&r| r < x);
                    rows.push(at);
                    values.push(v);
                }
                if rows.is_empty() {
                    return Err(BagError::new(
                        path,
                        Some(format!("topic `{}`", s.entry.topic)),
                        format!(
                            "`{}` has no sample once every input and reference has had a \
                             message (they start at {:.3} s, its last sample is at {:.3} s)",
                            s.entry.key,
                            t0 as f64 * 1e-9,
                            s.t[s.t.len() - 1] as f64 * 1e-9
                        ),
                    ));
                }
                channels.push(Channel {
                    kind,
                    column,
                    rows,
                    values,
                });
            }
        }
    }
    let name = path
        .file_stem()
        .map_or_else(|| "bag".to_string(), |s| s.to_string_lossy().into_owned());
    let ingest = IngestInfo {
        time_header: "rosbag2".into(),
        file_rows: t.len(),
        source: Some(describe(summary)),
        ..IngestInfo::default()
    };
    Ok(MeasuredRun {
        path: path.to_path_buf(),
        name,
        t,
        inputs,
        channels,
        references,
        extra: Vec::new(),
        header_line: 0,
        lines: Vec::new(),
        ingest,
    })
}

/// An input or reference held from each message to the next.
fn held(s: &Series, times: &[i64], column: usize) -> InputColumn {
    let mut values = Vec::with_capacity(times.len());
    let mut k = 0usize;
    for &x in times {
        while k + 1 < s.t.len() && s.t[k + 1] <= x {
            k += 1;
        }
        values.push(s.v[k]);
    }
    let first_set = times.partition_point(|&r| r < s.t[0]);
    // (`first_set` is 0 for every input and reference: the run starts at the last one's first
    // message.)
    let (_, name) = s.entry.key.split_at("u.".len());
    InputColumn {
        name: name.to_string(),
        column,
        values,
        precision: Vec::new(),
        first_set,
    }
}

/// Topics on clocks a day apart (a header stamp in simulated time beside log times in wall
/// time, say) cannot be merged.
fn check_one_clock(path: &Path, series: &[Series]) -> Result<(), BagError> {
    let span = |s: &Series| (s.t[0], s.t[s.t.len() - 1]);
    for a in series {
        for b in series {
            let ((a0, a1), (b0, b1)) = (span(a), span(b));
            if b0 - a1 > CLOCK_APART_NS || a0 - b1 > CLOCK_APART_NS {
                return Err(BagError::new(
                    path,
                    None,
                    format!(
                        "topic `{}` ({:.3} … {:.3} s) and topic `{}` ({:.3} … {:.3} s) are more \
                         than a day apart: are they on different clocks? Set the same `clock` \
                         (\"header\" or \"log\") for both in the mapping",
                        a.entry.topic,
                        a0 as f64 * 1e-9,
                        a1 as f64 * 1e-9,
                        b.entry.topic,
                        b0 as f64 * 1e-9,
                        b1 as f64 * 1e-9
                    ),
                ));
            }
        }
    }
    Ok(())
}

fn describe(s: &BagSummary) -> String {
    let topics: Vec<String> = s
        .topics
        .iter()
        .map(|(t, ty, c)| {
            let clock = match c {
                Clock::Header => "header stamps",
                Clock::Log => "log times",
            };
            format!("{t} ({ty}, {clock})")
        })
        .collect();
    format!(
        "rosbag2, {} MCAP file(s): {} message(s) of {}; {} of other topics passed over",
        s.files,
        s.decoded,
        topics.join(", "),
        s.passed_over
    )
}
