//! Aggregates over seeds: `aggregate.csv` (per point: runs complete, and per numeric metric
//! the mean and the half-width of its 95 % confidence interval) and one figure per metric and
//! varied parameter (`plots/<metric>_vs_<parameter>.png` and `.svg`): the metric's mean with
//! its 95 % interval at each value of the parameter, one line per combination of the other
//! parameters, drawn by [`shoal_record::ci_plot`].
//!
//! The interval is Student's t: mean ± t(0.975, n − 1) · s / √n over the n complete runs of a
//! point (s the sample standard deviation). A point with one run has its mean and no interval;
//! failed and missing runs are left out.

use super::metrics::Cell;
use super::plan::Plan;
use super::table::Row;
use shoal_output::files::write_whole;
use shoal_record::ci_plot::{CiGroup, CiPlot, CiPoint};
use statrs::distribution::{ContinuousCDF, StudentsT};
use std::path::{Path, PathBuf};

/// Mean and half-width of the 95 % confidence interval of the mean of `xs` (half-width 0 for
/// one value; `None` for none).
pub fn mean_ci95(xs: &[f64]) -> Option<(f64, f64)> {
    let n = xs.len();
    if n == 0 {
        return None;
    }
    let mean = xs.iter().sum::<f64>() / n as f64;
    if n == 1 {
        return Some((mean, 0.0));
    }
    let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
    let t = StudentsT::new(0.0, 1.0, (n - 1) as f64)
        .map(|d| d.inverse_cdf(0.975))
        .ok()?;
    Some((mean, t * (var / n as f64).sqrt()))
}

/// The numeric value of metric `m` in the complete runs among `rows`.
fn values(rows: &[&Row], m: usize) -> Vec<f64> {
    rows.iter()
        .filter(|r| r.status == "ok")
        .filter_map(|r| match r.metrics[m] {
            Some(Cell::Num(x)) if x.is_finite() => Some(x),
            _ => None,
        })
        .collect()
}

/// Whether metric `m` is a number in some run (text metrics are neither averaged nor drawn).
fn numeric(rows: &[Row], m: usize) -> bool {
    rows.iter()
        .any(|r| matches!(r.metrics[m], Some(Cell::Num(_))))
}

/// The distinct values of `key` over `rows`, in order of first appearance.
fn distinct<T: PartialEq + Clone>(rows: &[Row], key: impl Fn(&Row) -> T) -> Vec<T> {
    let mut out: Vec<T> = Vec::new();
    for r in rows {
        let k = key(r);
        if !out.contains(&k) {
            out.push(k);
        }
    }
    out
}

/// aggregate.csv's text: per point (combination of parameter values), the complete runs and
/// each numeric metric's mean and 95 % half-width.
pub fn aggregate_csv(plan: &Plan, rows: &[Row]) -> anyhow::Result<String> {
    let metrics: Vec<usize> = (0..plan.metrics.len())
        .filter(|&m| numeric(rows, m))
        .collect();
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut head: Vec<String> = plan.parameters.clone();
    head.push("runs_ok".into());
    for &m in &metrics {
        let n = &plan.metrics[m].name;
        head.push(format!("{n}_mean"));
        head.push(format!("{n}_ci95"));
    }
    w.write_record(&head)?;
    for point in distinct(rows, |r| r.values.clone()) {
        let these: Vec<&Row> = rows.iter().filter(|r| r.values == point).collect();
        let mut rec = point.clone();
        rec.push(
            these
                .iter()
                .filter(|r| r.status == "ok")
                .count()
                .to_string(),
        );
        for &m in &metrics {
            match mean_ci95(&values(&these, m)) {
                Some((mean, half)) => {
                    rec.push(format!("{mean}"));
                    rec.push(format!("{half}"));
                }
                None => rec.extend([String::new(), String::new()]),
            }
        }
        w.write_record(&rec)?;
    }
    let bytes = w.into_inner().map_err(|e| anyhow::anyhow!("{e}"))?;
    Ok(String::from_utf8(bytes)?)
}

/// A file-name-safe form of a name (`vehicles.0.count` → `vehicles_0_count`).
fn safe(name: &str) -> String {
    name.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect()
}

/// The figure of metric `m` against parameter `p`.
pub fn figure(plan: &Plan, rows: &[Row], m: usize, p: usize) -> CiPlot {
    let metric = &plan.metrics[m];
    let param = &plan.parameters[p];
    let categories = distinct(rows, |r| r.values[p].clone());
    // The other parameters' values name the lines.
    let others = |r: &Row| -> Vec<String> {
        r.values
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != p)
            .map(|(_, v)| v.clone())
            .collect()
    };
    let other_names: Vec<&String> = plan
        .parameters
        .iter()
        .enumerate()
        .filter(|(i, _)| *i != p)
        .map(|(_, n)| n)
        .collect();
    let groups = distinct(rows, others)
        .into_iter()
        .map(|combo| {
            let label = (!combo.is_empty()).then(|| {
                other_names
                    .iter()
                    .zip(&combo)
                    .map(|(n, v)| format!("{n} = {v}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            });
            let points = categories
                .iter()
                .map(|c| {
                    let these: Vec<&Row> = rows
                        .iter()
                        .filter(|r| r.values[p] == *c && others(r) == combo)
                        .collect();
                    mean_ci95(&values(&these, m)).map(|(mean, half)| CiPoint {
                        mean,
                        low: mean - half,
                        high: mean + half,
                    })
                })
                .collect();
            CiGroup { label, points }
        })
        .collect();
    let how = match (&metric.reduce, &metric.divide_by) {
        (Some(r), Some(d)) => format!("{:?} of {} / {d}", r, metric.path).to_lowercase(),
        (Some(r), None) => format!("{:?} of {}", r, metric.path).to_lowercase(),
        (None, Some(d)) => format!("{} / {d}", metric.path),
        // A field whose name alone misleads is named by what it counts.
        (None, None) => super::metrics::meaning(&metric.path)
            .map_or_else(|| metric.path.clone(), str::to_string),
    };
    CiPlot {
        title: format!(
            "{}: {} against {param} (mean ± 95 % CI over seeds)",
            plan.name, metric.name
        ),
        x_label: param.clone(),
        y_label: format!("{} ({how})", metric.name),
        categories,
        groups,
        size: (0, 0),
    }
}

/// Writes aggregate.csv and every figure into `dir` (figures under `plots/`), looking at
/// `stop` between figures; returns the files written.
pub fn write(
    dir: &Path,
    plan: &Plan,
    rows: &[Row],
    stop: &dyn Fn() -> bool,
) -> anyhow::Result<Vec<PathBuf>> {
    let mut written = vec![write_whole(
        &dir.join("aggregate.csv"),
        aggregate_csv(plan, rows)?.as_bytes(),
    )?];
    if !rows.iter().any(|r| r.status == "ok") || plan.parameters.is_empty() {
        return Ok(written);
    }
    let plots = dir.join("plots");
    std::fs::create_dir_all(&plots)
        .map_err(|e| anyhow::anyhow!("cannot create the folder {}: {e}", plots.display()))?;
    for m in (0..plan.metrics.len()).filter(|&m| numeric(rows, m)) {
        for p in 0..plan.parameters.len() {
            if stop() {
                return Ok(written);
            }
            let stem = plots.join(format!(
                "{}_vs_{}",
                safe(&plan.metrics[m].name),
                safe(&plan.parameters[p])
            ));
            written.extend(figure(plan, rows, m, p).write(&stem)?);
        }
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::metrics::Metric;

    /// The delivery ratio's axis says what it counts, whatever the sweep calls its column.
    #[test]
    fn the_delivery_ratio_axis_names_receptions_in_range() {
        let plan = Plan {
            name: "s".into(),
            sweep_file: String::new(),
            parameters: vec!["water.attenuation".into()],
            metrics: vec![Metric {
                name: "delivery_ratio".into(),
                path: "comm.delivery_ratio".into(),
                reduce: None,
                divide_by: None,
            }],
            runs: Vec::new(),
        };
        let f = figure(&plan, &[], 0, 0);
        assert_eq!(
            f.y_label,
            "delivery_ratio (delivered / receptions by vehicles within the cut-off range)"
        );
    }

    #[test]
    fn the_interval_is_students_t() {
        assert_eq!(mean_ci95(&[]), None);
        assert_eq!(mean_ci95(&[2.0]), Some((2.0, 0.0)));
        // n = 2: t(0.975, 1) = 12.706; s = √2, s/√2 = 1.
        let (m, h) = mean_ci95(&[1.0, 3.0]).unwrap();
        assert_eq!(m, 2.0);
        assert!((h - 12.7062).abs() < 1e-3, "{h}");
        // n = 5: t(0.975, 4) = 2.7764; values 1 … 5: s = √2.5.
        let (m, h) = mean_ci95(&[1.0, 2.0, 3.0, 4.0, 5.0]).unwrap();
        assert_eq!(m, 3.0);
        assert!((h - 2.7764 * (2.5f64 / 5.0).sqrt()).abs() < 1e-3, "{h}");
    }
}
