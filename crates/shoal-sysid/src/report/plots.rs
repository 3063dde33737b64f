//! The report's figures: each measured run against the baseline and the extended model, the
//! residual autocorrelation before and after, and per named effect its residual signature
//! before and after. Drawing rules (axes that cover every drawn point, legends off the data)
//! live in [`shoal_output::plot`]; here the data are chosen and styled.

use super::input::ReportInput;
use super::signature::{self, Regressor};
use super::wording::label;
use crate::evaluate::dataset::RunData;
use crate::evaluate::evaluation::ChannelResult;
use crate::evaluate::stats;
use crate::log::run::ChannelKind;
use crate::search::Outcome;
use shoal_output::plot::{Plot, Series};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A plot in the report: its title and its PNG relative to the report's folder.
#[derive(Clone, Debug)]
pub(super) struct PlotRef {
    pub title: String,
    pub path: String,
}

/// The residual-signature plot of a named effect.
#[derive(Clone, Debug)]
pub(super) struct SignatureRef {
    /// PNG relative to the report's folder.
    pub path: String,
    /// The channel whose residual is shown.
    pub channel: ChannelKind,
    /// What it is plotted against.
    pub x_label: String,
    /// What is plotted (the residual or its rate).
    pub y_label: String,
    /// RMS of what is plotted, baseline and final model, all samples (unit of `y_label`).
    pub rms: (f64, f64),
}

/// Every plot written.
#[derive(Clone, Debug, Default)]
pub(super) struct PlotRefs {
    /// Measured vs baseline vs extended, per run and channel.
    pub runs: Vec<PlotRef>,
    /// Residual autocorrelation per channel.
    pub acf: Vec<PlotRef>,
    /// Residual signature per named effect family.
    pub signatures: BTreeMap<String, SignatureRef>,
}

/// Palette indices.
const GREY: usize = 7;
const RED: usize = 3;
const GREEN: usize = 2;
const BLUE: usize = 0;

/// Colour of the measurement on a run's plot.
pub(super) const MEASURED_RGB: (u8, u8, u8) = (30, 30, 30);

/// Line width of the model replays on a run's plot \[px\] (the measurement is 1 px on top).
const MODEL_WIDTH: u32 = 4;

/// Most points per series of a scatter plot (evenly thinned beyond).
const MAX_DOTS: usize = 4000;

/// Draws every figure into `pdir`, adding the files to `files`.
pub(super) fn write_all(
    pdir: &Path,
    input: &ReportInput<'_>,
    files: &mut Vec<PathBuf>,
) -> PlotRefs {
    let out = input.outcome;
    let ds = input.ds;
    let mut refs = PlotRefs::default();
    let mut put = |plot: &Plot, stem: &str| -> Option<String> {
        let files_now = plot.write(&pdir.join(stem)).ok()?;
        files.extend(files_now);
        Some(format!("plots/{stem}.png"))
    };
    let ext = (!out.chosen.effects.is_empty())
        .then(|| format!("extended ({})", out.chosen.names().join(" + ")));
    for (ri, rd) in ds.runs.iter().enumerate() {
        for (ci, cb) in out.baseline.eval.runs[ri].channels.iter().enumerate() {
            let cf = ext
                .as_ref()
                .map(|l| (&out.chosen.eval.runs[ri].channels[ci], l.as_str()));
            let plot = run_plot(rd, cb, cf);
            let stem = format!("{}_{}", rd.run.name, file_stem(cb.kind));
            if let Some(path) = put(&plot, &stem) {
                refs.runs.push(PlotRef {
                    title: format!("{} {}", rd.run.name, label(cb.kind)),
                    path,
                });
            }
        }
    }
    for &kind in &ds.kinds {
        let plot = acf_plot(
            kind,
            &out.baseline.eval.validation_residuals(kind),
            (!out.chosen.effects.is_empty()).then(|| out.chosen.eval.validation_residuals(kind)),
        );
        if let Some(path) = put(&plot, &format!("acf_{}", file_stem(kind))) {
            refs.acf.push(PlotRef {
                title: format!("residual autocorrelation {}", label(kind)),
                path,
            });
        }
    }
    let Some(kind) = signature_channel(out) else {
        return refs;
    };
    let cmd = signature::command_input(ds);
    for e in &out.chosen.effects {
        let name = e.effect.name();
        // Only catalogue families have a signature to plot.
        let Some(reg) = signature::regressor_of(name) else {
            continue;
        };
        // Without a varying thruster input, time is all there is.
        let input = cmd.as_deref().filter(|_| reg == Regressor::Command);
        let reg = if reg == Regressor::Command && input.is_none() {
            Regressor::Time
        } else {
            reg
        };
        let before = signature::points(ds, &out.baseline.eval, kind, reg, input);
        let after = signature::points(ds, &out.chosen.eval, kind, reg, input);
        let x_label = signature::axis_label(reg, kind, input);
        let y_label = signature::residual_label(reg, kind);
        let rms = |p: &[(f64, f64)]| stats::rms(&p.iter().map(|q| q.1).collect::<Vec<_>>());
        let rms = (rms(&before), rms(&after));
        let plot = signature_plot(
            name,
            e.effect.form(),
            kind,
            (&x_label, &y_label),
            before,
            after,
        );
        if let Some(path) = put(&plot, &format!("signature_{name}")) {
            refs.signatures.insert(
                name.to_string(),
                SignatureRef {
                    path,
                    channel: kind,
                    x_label,
                    y_label,
                    rms,
                },
            );
        }
    }
    refs
}

/// The channel the signatures show: the one whose validation RMSE the final model cut the
/// most (relative to the baseline's).
pub(super) fn signature_channel(out: &Outcome) -> Option<ChannelKind> {
    out.baseline
        .eval
        .metrics
        .iter()
        .filter_map(|(k, mb)| {
            let mf = out.chosen.eval.metrics.get(k)?;
            (mb.rmse > 0.0).then(|| (*k, 1.0 - mf.rmse / mb.rmse))
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(k, _)| k)
}

/// Smallest step between successive different values (the quantisation step of a quantised
/// signal; tiny for a noisy continuous one).
pub(super) fn quantum(values: &[f64]) -> f64 {
    values
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .filter(|d| *d > 1e-12 && d.is_finite())
        .fold(f64::INFINITY, f64::min)
}

/// Smallest vertical span of a measured-run plot of channel `kind` with measurements
/// `measured`: 20 quantisation steps, and never less than a floor in the channel's unit, so a
/// nearly constant, quantised reading stays a thin line instead of a band of steps.
pub(super) fn min_span(kind: ChannelKind, measured: &[f64]) -> f64 {
    let floor: f64 = match kind.unit() {
        "m/s" => 0.02,
        _ => 0.05,
    };
    let q = quantum(measured);
    if q.is_finite() {
        floor.max(20.0 * q)
    } else {
        floor
    }
}

fn zip(t: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    t.iter().copied().zip(y.iter().copied()).collect()
}

/// Measured vs baseline (vs extended, `cf` with its legend label) for one channel of one run:
/// the models as lines, the measurement as a thin line on top, the estimation/validation
/// split as a dashed vertical line.
pub(super) fn run_plot(
    rd: &RunData,
    cb: &ChannelResult,
    cf: Option<(&ChannelResult, &str)>,
) -> Plot {
    let mut series = vec![Series {
        label: Some("baseline".into()),
        points: zip(&cb.times, &cb.predicted),
        color: RED,
        width: MODEL_WIDTH,
        ..Default::default()
    }];
    if let Some((cf, l)) = cf {
        series.push(Series {
            label: Some(l.to_string()),
            points: zip(&cf.times, &cf.predicted),
            color: GREEN,
            width: MODEL_WIDTH,
            ..Default::default()
        });
    }
    // The measurements last, so on top: a thin near-black line (apart from the black frame)
    // over the wider coloured model lines, which stay visible on both sides of it.
    series.push(Series {
        label: Some("measured".into()),
        points: zip(&cb.times, &cb.measured),
        rgb: Some(MEASURED_RGB),
        width: 1,
        ..Default::default()
    });
    if rd.split_time.is_finite() {
        let (lo, hi) = series
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p.1))
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
        if lo <= hi {
            series.push(Series {
                label: Some("estimation | validation".into()),
                points: vec![(rd.split_time, lo), (rd.split_time, hi)],
                color: BLUE,
                dashed: true,
                ..Default::default()
            });
        }
    }
    Plot {
        title: format!(
            "{} — {} ({})",
            rd.run.name,
            label(cb.kind),
            if rd.holdout {
                "hold-out run"
            } else {
                "estimation run"
            }
        ),
        x_label: "t [s]".into(),
        y_label: format!("{} [{}]", label(cb.kind), cb.kind.unit()),
        series,
        y_down: cb.kind == ChannelKind::Depth,
        min_y_span: min_span(cb.kind, &cb.measured),
        size: (1000, 480),
        ..Default::default()
    }
}

/// Residual autocorrelation of the validation residuals before (`rb`) and after (`rf`).
fn acf_plot(kind: ChannelKind, rb: &[f64], rf: Option<Vec<f64>>) -> Plot {
    let lags = 60.min(rb.len().saturating_sub(1));
    let bound = 1.96 / (rb.len().max(1) as f64).sqrt();
    let to_pts = |a: Vec<f64>| -> Vec<(f64, f64)> {
        a.into_iter()
            .enumerate()
            .map(|(k, v)| (k as f64, v))
            .collect()
    };
    let mut series = vec![Series {
        label: Some("baseline".into()),
        points: to_pts(stats::acf(rb, lags)),
        color: RED,
        ..Default::default()
    }];
    if let Some(rf) = rf {
        series.push(Series {
            label: Some("extended".into()),
            points: to_pts(stats::acf(&rf, lags)),
            color: GREEN,
            ..Default::default()
        });
    }
    for (l, b) in [
        (Some("95 % bounds of white noise".to_string()), bound),
        (None, -bound),
    ] {
        series.push(Series {
            label: l,
            points: vec![(0.0, b), (lags as f64, b)],
            color: GREY,
            dashed: true,
            ..Default::default()
        });
    }
    Plot {
        title: format!(
            "Residual autocorrelation, {} (validation data)",
            label(kind)
        ),
        x_label: "lag [samples]".into(),
        y_label: "autocorrelation [-]".into(),
        series,
        y_range: Some((-1.05, 1.05)),
        size: (900, 420),
        ..Default::default()
    }
}

/// Every `k`-th point so that at most `max` remain.
fn thin(p: Vec<(f64, f64)>, max: usize) -> Vec<(f64, f64)> {
    let k = p.len().div_ceil(max.max(1)).max(1);
    p.into_iter().step_by(k).collect()
}

/// The residual signature of effect `name` (form `form`) on channel `kind`: the baseline's
/// residual (`before`) and the final model's (`after`) against the regressor, as dots;
/// `labels` of the horizontal and vertical axes.
pub(super) fn signature_plot(
    name: &str,
    form: &str,
    kind: ChannelKind,
    (x_label, y_label): (&str, &str),
    before: Vec<(f64, f64)>,
    after: Vec<(f64, f64)>,
) -> Plot {
    let (x0, x1) = before
        .iter()
        .chain(&after)
        .map(|p| p.0)
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    let mut series = vec![
        Series {
            label: Some("before: baseline residual".into()),
            points: thin(before, MAX_DOTS),
            color: RED,
            dots: true,
            width: 1,
            ..Default::default()
        },
        Series {
            label: Some("after: final model residual".into()),
            points: thin(after, MAX_DOTS),
            color: GREEN,
            dots: true,
            width: 1,
            ..Default::default()
        },
    ];
    if x0 <= x1 {
        series.push(Series {
            points: vec![(x0, 0.0), (x1, 0.0)],
            color: GREY,
            dashed: true,
            ..Default::default()
        });
    }
    Plot {
        title: format!("{name} ({form}): residual signature on {}", label(kind)),
        x_label: x_label.to_string(),
        y_label: y_label.to_string(),
        series,
        size: (900, 460),
        ..Default::default()
    }
}

/// A channel's part of a plot's file name: the measurement's name (`depth`), or `u_<thruster>`
/// for a command channel.
fn file_stem(kind: ChannelKind) -> String {
    if kind.is_command() {
        format!("u_{}", kind.name())
    } else {
        kind.name().to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evaluate::dataset::unwrap;

    /// Every point of every series of `plot` lies inside its ranges.
    fn covers(plot: &Plot) {
        let ((x0, x1), (y0, y1)) = plot.ranges();
        for s in &plot.series {
            for &(x, y) in &s.points {
                assert!(x >= x0 && x <= x1, "{x} outside {x0}…{x1}");
                assert!(y >= y0 && y <= y1, "{y} outside {y0}…{y1} ({:?})", s.label);
            }
        }
    }

    fn channel(
        kind: ChannelKind,
        t: &[f64],
        measured: Vec<f64>,
        predicted: Vec<f64>,
    ) -> ChannelResult {
        let resid = measured
            .iter()
            .zip(&predicted)
            .map(|(a, b)| a - b)
            .collect();
        ChannelResult {
            kind,
            times: t.to_vec(),
            measured,
            predicted,
            resid,
            est: t.iter().map(|&x| x < 6.0).collect(),
        }
    }

    fn run_data(t: &[f64]) -> RunData {
        let csv: String = std::iter::once("t,u.port,y.depth\n".to_string())
            .chain(t.iter().map(|t| format!("{t},0,1\n")))
            .collect();
        let run = crate::log::run::MeasuredRun::parse(&csv, Path::new("r.csv")).unwrap();
        RunData {
            map: crate::evaluate::open_loop::InputMap::default(),
            init: crate::evaluate::open_loop::InitialState::from_run(
                &shoal_model::presets::uauv2(),
                &run,
                0.5,
            ),
            run,
            channels: vec![0],
            split_time: 6.0,
            holdout: false,
        }
    }

    /// A heading that turns several times: unwrapped, the measurement runs far beyond ±π and
    /// a model that falls behind drifts further; the axis covers both and the split line.
    #[test]
    fn unwrapped_angles_stay_inside_the_axes() {
        let t: Vec<f64> = (0..1000).map(|i| i as f64 * 0.01).collect();
        let mut measured: Vec<f64> = t
            .iter()
            .map(|t| shoal_model::math::wrap_pi(2.5 * t))
            .collect();
        unwrap(&mut measured);
        assert!(measured[999] > 20.0);
        let base: Vec<f64> = t.iter().map(|t| 3.1 * t - 0.5).collect();
        let ext: Vec<f64> = t.iter().map(|t| 2.4 * t + 0.2 * (5.0 * t).sin()).collect();
        let rd = run_data(&t);
        let cb = channel(ChannelKind::Yaw, &t, measured.clone(), base);
        let cf = channel(ChannelKind::Yaw, &t, measured, ext);
        let plot = run_plot(&rd, &cb, Some((&cf, "extended")));
        covers(&plot);
        assert!(plot.series.iter().any(|s| s.dashed), "split line drawn");
    }

    /// A depth held almost constant, quantised to 1.8 mm: the axis covers every sample and
    /// spans at least 20 steps, and the measurement is a thin line, not markers.
    #[test]
    fn quantised_depth_is_a_thin_line_in_a_sensible_range() {
        let t: Vec<f64> = (0..1000).map(|i| i as f64 * 0.01).collect();
        let q = 0.0018;
        let measured: Vec<f64> = t
            .iter()
            .enumerate()
            .map(|(i, t)| {
                ((1.0 + 0.001 * t + if i % 3 == 0 { 0.0012 } else { 0.0 }) / q).round() * q
            })
            .collect();
        let base: Vec<f64> = t.iter().map(|t| 1.0 + 0.0012 * t).collect();
        let rd = run_data(&t);
        let cb = channel(ChannelKind::Depth, &t, measured, base);
        let plot = run_plot(&rd, &cb, None);
        covers(&plot);
        let (_, (y0, y1)) = plot.ranges();
        assert!(y1 - y0 >= 20.0 * q && y1 - y0 >= 0.05, "{y0}…{y1}");
        assert!((quantum(&cb.measured) - q).abs() < 1e-9);
        let m = plot
            .series
            .iter()
            .find(|s| s.label.as_deref() == Some("measured"))
            .unwrap();
        assert!(!m.dots && m.width == 1 && m.rgb == Some(MEASURED_RGB));
        // Drawn after (over) every model line, which is wider.
        let at = |l: &str| {
            plot.series
                .iter()
                .position(|s| s.label.as_deref() == Some(l))
        };
        assert!(at("measured") > at("baseline"));
        assert!(plot.series[at("baseline").unwrap()].width > m.width);
        assert!(plot.y_down);
    }

    #[test]
    fn signature_plots_cover_before_and_after() {
        let before: Vec<(f64, f64)> = (0..9000)
            .map(|i| (i as f64 * 0.01 - 45.0, (i as f64).sin()))
            .collect();
        let after: Vec<(f64, f64)> = before.iter().map(|p| (p.0, 0.01 * p.1)).collect();
        let plot = signature_plot(
            "thruster_deadband",
            "hard",
            ChannelKind::Depth,
            ("u.port [%]", "residual"),
            before,
            after,
        );
        covers(&plot);
        assert!(plot.series[0].points.len() <= MAX_DOTS && plot.series[0].dots);
    }
}
