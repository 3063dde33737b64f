//! The run's own plots, drawn from the samples kept of the vehicles shown ([`VehicleAcc`]):
//! `depth` (depth reading and setpoint against time), `heading` (heading and setpoint against
//! time, continuous through ±180°) and `top` (tracks from above on the pool and obstacles, at
//! one scale north and east).

use super::accumulated::{PlotPoint, VehicleAcc};
use shoal_model::math::wrap_pi;
use shoal_output::plot::{Plot, Series};
use shoal_world::desc::WorldDesc;

/// The vehicles drawn: every `stride`-th.
fn shown(acc: &[VehicleAcc], stride: usize) -> Vec<usize> {
    (0..acc.len()).step_by(stride).collect()
}

/// Depth reading against time for the vehicles drawn (every `stride`-th), with one setpoint
/// line per group, drawn only where the vehicle holds a depth (a gap while it is off, turning,
/// drifting or under raw commands: [`PlotPoint::depth_sp`]).
pub(super) fn depth_plot(acc: &[VehicleAcc], stride: usize, desc: &WorldDesc) -> Plot {
    let shown = shown(acc, stride);
    let mut series = Vec::new();
    let mut labelled = vec![false; desc.groups.len()];
    for &i in &shown {
        let g = desc.vehicles[i].group;
        let a = &acc[i];
        series.push(Series {
            label: (!labelled[g]).then(|| desc.groups[g].clone()),
            points: a.plot.iter().map(|p| (p.t, p.depth)).collect(),
            color: g,
            ..Default::default()
        });
        labelled[g] = true;
    }
    // One setpoint line per group.
    let mut done = vec![false; desc.groups.len()];
    for &i in &shown {
        let g = desc.vehicles[i].group;
        if !done[g] {
            done[g] = true;
            series.push(Series {
                points: acc[i].plot.iter().map(|p| (p.t, p.depth_sp)).collect(),
                color: g,
                dashed: true,
                ..Default::default()
            });
        }
    }
    let note = if shown.len() < acc.len() {
        format!(" ({} of {} vehicles)", shown.len(), acc.len())
    } else {
        String::new()
    };
    Plot {
        title: format!(
            "{}: depth reading (solid) and setpoint (dashed, where depth is held){note}",
            desc.name
        ),
        x_label: "time [s]".into(),
        y_label: "depth [m]".into(),
        series,
        y_down: true,
        x_range: Some((0.0, desc.duration)),
        ..Default::default()
    }
}

/// Heading against time with the setpoint, for the vehicles drawn (degrees, continuous:
/// [`heading_series`]).
pub(super) fn heading_plot(acc: &[VehicleAcc], stride: usize, desc: &WorldDesc) -> Plot {
    let tracks: Vec<(usize, &[PlotPoint])> = shown(acc, stride)
        .into_iter()
        .filter(|&i| acc[i].steered)
        .map(|i| (desc.vehicles[i].group, acc[i].plot.as_slice()))
        .collect();
    Plot {
        title: format!("{}: heading (solid) and setpoint (dashed)", desc.name),
        x_label: "time [s]".into(),
        y_label: "heading [°], continuous through ±180°".into(),
        series: heading_series(&tracks, &desc.groups),
        x_range: Some((0.0, desc.duration)),
        min_y_span: 20.0,
        ..Default::default()
    }
}

/// Tracks from above of the vehicles drawn (every `stride`-th), zoomed to where they went.
pub(super) fn top_plot(acc: &[VehicleAcc], stride: usize, desc: &WorldDesc) -> Plot {
    let mut labelled = vec![false; desc.groups.len()];
    let series: Vec<Series> = shown(acc, stride)
        .into_iter()
        .map(|i| {
            let g = desc.vehicles[i].group;
            let s = Series {
                label: (!labelled[g]).then(|| desc.groups[g].clone()),
                points: acc[i].plot.iter().map(|p| (p.y, p.x)).collect(),
                color: g,
                mark_start: true,
                ..Default::default()
            };
            labelled[g] = true;
            s
        })
        .collect();
    // Zoomed to where the vehicles went.
    let focus: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| s.points.iter().copied())
        .collect();
    crate::map::map_plot(
        format!("{}: tracks from above (dot = start)", desc.name),
        &desc.geometry,
        series,
        focus,
        700,
    )
}

/// One vehicle's headings \[rad\] as a continuous line in degrees: each sample is the one
/// before plus the wrapped change, so a turn through ±180° goes on past it instead of jumping
/// to the other end of the axis. A non-finite heading breaks the line (NaN) and the next
/// finite one continues from the last.
pub(super) fn unwrap_deg(samples: impl IntoIterator<Item = (f64, f64)>) -> Vec<(f64, f64)> {
    let mut last: Option<(f64, f64)> = None; // (heading [rad], drawn [°])
    samples
        .into_iter()
        .map(|(t, yaw)| {
            if !yaw.is_finite() {
                return (t, f64::NAN);
            }
            let d = match last {
                Some((prev, drawn)) => drawn + wrap_pi(yaw - prev).to_degrees(),
                None => wrap_pi(yaw).to_degrees(),
            };
            last = Some((yaw, d));
            (t, d)
        })
        .collect()
}

/// The heading plot's lines: for each track `(group, samples)` its heading, unwrapped
/// ([`unwrap_deg`]) and shifted by whole turns so that its mean is within 180° of the mean of
/// the first track of its group (one group stays one bundle of lines), labelled once per
/// group; and
/// for the first track of each group its setpoint (dashed), drawn where the controller sees
/// it: the track's heading plus the wrapped setpoint error, broken where that jumps by more
/// than 180° (a setpoint exactly behind the vehicle).
pub(super) fn heading_series(tracks: &[(usize, &[PlotPoint])], groups: &[String]) -> Vec<Series> {
    let mut series = Vec::new();
    // Per group: the mean drawn heading of its first track [°].
    let mut reference: Vec<Option<f64>> = vec![None; groups.len()];
    for &(g, pts) in tracks {
        let mut line = unwrap_deg(pts.iter().map(|p| (p.t, p.yaw)));
        let finite: Vec<f64> = line.iter().map(|p| p.1).filter(|d| d.is_finite()).collect();
        let leader = reference[g].is_none();
        if !finite.is_empty() {
            let mean = finite.iter().sum::<f64>() / finite.len() as f64;
            let r = *reference[g].get_or_insert(mean);
            let turns = ((r - mean) / 360.0).round() * 360.0;
            line.iter_mut().for_each(|p| p.1 += turns);
        }
        if leader {
            let mut sp: Vec<(f64, f64)> = Vec::with_capacity(pts.len());
            for (p, h) in pts.iter().zip(&line) {
                let d = h.1 + wrap_pi(p.yaw_sp - p.yaw).to_degrees();
                if let Some(&(_, prev)) = sp.last()
                    && (d - prev).abs() > 180.0
                {
                    sp.push((f64::NAN, f64::NAN));
                }
                sp.push((p.t, d));
            }
            series.push(Series {
                points: sp,
                color: g,
                dashed: true,
                ..Default::default()
            });
        }
        series.push(Series {
            label: leader.then(|| groups[g].clone()),
            points: line,
            color: g,
            ..Default::default()
        });
    }
    series
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samples every second with headings `deg` \[°\] and the setpoint `sp` \[°\].
    fn track(deg: &[f64], sp: f64) -> Vec<PlotPoint> {
        deg.iter()
            .enumerate()
            .map(|(k, d)| PlotPoint {
                t: k as f64,
                yaw: d.to_radians(),
                yaw_sp: sp.to_radians(),
                ..Default::default()
            })
            .collect()
    }

    /// Largest step between neighbouring points of a line, and whether it has a break.
    fn steps(s: &Series) -> (f64, bool) {
        let jump = s
            .points
            .windows(2)
            .map(|w| (w[1].1 - w[0].1).abs())
            .filter(|d| d.is_finite())
            .fold(0.0, f64::max);
        (jump, s.points.iter().any(|p| !p.1.is_finite()))
    }

    /// A group turning through ±180° (the default world's relays turn from 0° to 180° and
    /// settle around it; a neighbour starts just the other side of ±180°) is one bundle of
    /// continuous lines, and its setpoint lies on them.
    #[test]
    fn headings_through_the_wrap_stay_one_continuous_group() {
        let a = track(&[0.0, 90.0, 170.0, 179.0, -179.0, 178.0, -178.0], 180.0);
        let b = track(
            &[-179.0, 179.5, -179.5, 179.0, -178.5, 179.0, -179.0],
            180.0,
        );
        let groups = vec!["relay".to_string()];
        let lines = heading_series(&[(0, &a), (0, &b)], &groups);
        // Setpoint, then the two headings.
        assert_eq!(lines.len(), 3);
        assert!(lines[0].dashed && lines[0].label.is_none());
        assert_eq!(lines[1].label.as_deref(), Some("relay"));
        assert!(lines[2].label.is_none());
        for s in &lines[1..] {
            let (jump, broken) = steps(s);
            assert!(jump < 100.0 && !broken, "{:?}", s.points);
        }
        // Both vehicles end near 180° (not one at +180° and one at −180°).
        let ends: Vec<f64> = lines[1..]
            .iter()
            .map(|s| s.points.last().unwrap().1)
            .collect();
        for e in &ends {
            assert!((e - 180.0).abs() < 3.0, "{ends:?}");
        }
        // Every line of the group within one band once settled.
        let settled: Vec<f64> = lines[1..]
            .iter()
            .flat_map(|s| s.points[3..].iter().map(|p| p.1))
            .collect();
        let span = settled.iter().fold(f64::NEG_INFINITY, |m, &v| m.max(v))
            - settled.iter().fold(f64::INFINITY, |m, &v| m.min(v));
        assert!(span < 5.0, "{settled:?}");
        // The setpoint (180°) is drawn at 180° beside the heading, without breaks.
        for p in &lines[0].points {
            assert!((p.1 - 180.0).abs() < 1e-9, "{:?}", lines[0].points);
        }
    }

    #[test]
    fn unwrapping_continues_through_gaps_and_whole_turns() {
        // Three quarter turns left, past −180°, a gap, then on.
        let pts = [0.0, -90.0, -180.0, -270.0, f64::NAN, -300.0]
            .iter()
            .enumerate()
            .map(|(k, d): (usize, &f64)| (k as f64, d.to_radians()));
        let u = unwrap_deg(pts);
        let want = [0.0, -90.0, -180.0, -270.0, f64::NAN, -300.0];
        for (p, w) in u.iter().zip(want) {
            assert!(
                (p.1.is_nan() && w.is_nan()) || (p.1 - w).abs() < 1e-9,
                "{u:?}"
            );
        }
    }
}
