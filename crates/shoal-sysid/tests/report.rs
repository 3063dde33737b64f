//! The report of a search on a synthetic run: per named effect a section with its form, its
//! evidence, parameters with 95 % confidence intervals (±1.96 σ) and a residual-signature
//! plot on disk; the sections for possible, ambiguous and unexplained findings; every plot
//! of the measured runs. The reports stay in the test's temporary folder under `target/` for
//! a look at the figures.

mod common;
#[path = "../../shoal-record/tests/support/plots.rs"]
mod plots;

use common::{Exp, find, measured};
use shoal_model::presets;
use shoal_output::plot::rgb;
use shoal_sysid::log::run::ChannelKind;
use shoal_sysid::report::{ReportInput, write_report};
use shoal_sysid::search::SearchOptions;
use shoal_world::spec::VehicleSpec;
use std::path::PathBuf;

/// Runs the search on a run of `exp` with `hidden`, writes the report into a folder named
/// `name`, and checks it; returns the folder.
fn report(name: &str, exp: Exp, hidden: &[(&str, Vec<f64>)], seed: u64) -> PathBuf {
    let (ds, out) = find(measured(exp, hidden, seed));
    let named = out.chosen.names();
    let mut want: Vec<String> = hidden.iter().map(|h| h.0.to_string()).collect();
    want.sort();
    let mut got = named.clone();
    got.sort();
    assert_eq!(got, want, "{name}: verdict {:?}", out.verdict);
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("report_{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    let spec = VehicleSpec::from_params(&presets::uauv2());
    // The options `find` searched with.
    let opts = SearchOptions {
        threads: 2,
        ..Default::default()
    };
    let written = write_report(
        &dir,
        &ReportInput {
            ds: &ds,
            vehicle: &spec,
            vehicle_source: "the uauv2 preset".into(),
            opts: &opts,
            outcome: &out,
            plots: true,
            next: None,
            log_name: String::new(),
        },
    )
    .expect("report written");
    let md = std::fs::read_to_string(&written.markdown).unwrap();
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&written.json).unwrap()).unwrap();
    // The verdict says what is named with strong evidence and what is only possible.
    assert!(
        md.contains("**Named with strong evidence**")
            && md.contains("**Only possible, not named**"),
        "{md}"
    );
    for section in [
        "## Named effects (strong evidence)",
        "## Possible (not named)",
        "## Ambiguous",
        "## Unexplained structure",
    ] {
        assert!(md.contains(section), "{section} missing");
    }
    for (i, e) in out.chosen.effects.iter().enumerate() {
        let (fam, form) = (e.effect.name(), e.effect.form());
        let head = format!("### {}. `{fam}` — form `{form}`", i + 1);
        let at = md
            .find(&head)
            .unwrap_or_else(|| panic!("{head} missing:\n{md}"));
        // Up to the next heading of any level.
        let body = at + head.len();
        let end = md[body..].find("\n#").map_or(md.len(), |n| body + n);
        let section = &md[at..end];
        for what in [
            "| held-out gain |",
            "| ΔBIC |",
            "| effective ΔBIC |",
            "| held-out block t |",
            "| Wald z |",
            "| stability selection |",
            "Forms compared",
            "95 % confidence interval",
        ] {
            assert!(
                section.contains(what),
                "{fam}: `{what}` missing in\n{section}"
            );
        }
        // Every excited parameter has its interval ±1.96 σ, in the page and in the JSON.
        let jn = &json["verdict"]["named"][i];
        assert_eq!(jn["effect"], fam);
        for (j, p) in e.params.iter().enumerate() {
            let row = section
                .lines()
                .find(|l| l.starts_with(&format!("| `{}`", p.name)))
                .unwrap_or_else(|| panic!("{fam}.{}: no row in\n{section}", p.name));
            if !p.excited {
                assert!(row.contains("held at its null value"), "{row}");
                continue;
            }
            let s = p.sigma.expect("an excited parameter has a σ");
            let ci = jn["params"][j]["ci95"].as_array().expect("interval");
            let (lo, hi) = (ci[0].as_f64().unwrap(), ci[1].as_f64().unwrap());
            assert!((lo - (p.value - 1.96 * s)).abs() <= 1e-12 * (1.0 + p.value.abs()));
            assert!((hi - (p.value + 1.96 * s)).abs() <= 1e-12 * (1.0 + p.value.abs()));
            assert!(row.matches('[').count() >= 1 && row.contains(", "), "{row}");
        }
        // The signature plot before/after is on disk and in the page.
        // Its residuals before (red) and after (green) drawn as dots in the plot area.
        let png = format!("plots/signature_{fam}.png");
        plots::assert_png_colours(&dir.join(&png), &[rgb(3), rgb(2)], 30);
        assert!(section.contains(&format!("]({png})")), "{section}");
        assert_eq!(jn["signature_plot"], png.as_str());
    }
    // How each file was read and what was clamped are in the JSON and on the page.
    for (i, rd) in ds.runs.iter().enumerate() {
        let jr = &json["runs"][i];
        assert_eq!(jr["ingest"]["file_rows"], rd.run.ingest.file_rows, "{jr}");
        assert_eq!(
            jr["ingest"]["time_header"],
            rd.run.ingest.time_header.as_str()
        );
        let clamped = jr["clamped"].as_array().expect("clamp notes");
        assert_eq!(clamped.len(), rd.map.clamped.len());
        for (j, note) in rd.map.clamped.iter().enumerate() {
            assert_eq!(clamped[j]["count"], note.count);
            assert!(md.contains(&note.to_string()), "{note} missing");
        }
        assert!(md.contains(&format!("read as: {}", rd.run.ingest)));
    }
    // Every measured channel of every run is plotted: the measurement (near-black, 1 px, drawn
    // last, on top of the 4-px model lines) in the PNG; in the SVG the baseline (red) and the
    // model with the named effects (green) at every sample of it, and the depth as measured,
    // sample by sample.
    let measured_rgb = (30, 30, 30);
    for rd in &ds.runs {
        for &c in &rd.channels {
            let ch = &rd.run.channels[c];
            let f = dir.join(format!("plots/{}_{}.png", rd.run.name, ch.kind.name()));
            plots::assert_png_colours(&f, &[measured_rgb], 300);
            let svg = std::fs::read_to_string(f.with_extension("svg")).unwrap();
            let mut order = Vec::new();
            for (colour, width) in [(rgb(3), 4), (rgb(2), 4), (measured_rgb, 1)] {
                let n = plots::lines(&svg)
                    .iter()
                    .filter(|l| l.stroke == colour && l.width == width && l.points.len() > 2)
                    .map(|l| l.points.len())
                    .collect::<Vec<_>>();
                assert_eq!(n, [ch.values.len()], "{}: {colour:?}", f.display());
                order.push(
                    plots::lines(&svg)
                        .iter()
                        .position(|l| l.stroke == colour && l.width == width)
                        .unwrap(),
                );
            }
            assert!(
                order[2] > order[0] && order[2] > order[1],
                "measurement on top"
            );
            if ch.kind == ChannelKind::Depth {
                let measured: Vec<(f64, f64)> = ch
                    .rows
                    .iter()
                    .map(|&k| rd.run.t[k])
                    .zip(ch.values.iter().copied())
                    .collect();
                plots::assert_svg_series(&f.with_extension("svg"), 1, &[(measured_rgb, measured)]);
            }
        }
    }
    dir
}

/// A dead band in a heave run: its signature is drawn against the command.
#[test]
fn heave_report_with_a_dead_band() {
    let dir = report(
        "heave_deadband",
        Exp::Heave,
        &[("thruster_deadband", vec![10.0])],
        1,
    );
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("against u.port [%]"), "{md}");
}

/// A sensor delay in a yaw run (heading, yaw rate, a nearly constant quantised depth and a
/// tracked position): its signature is drawn against time.
#[test]
fn yaw_report_with_a_sensor_delay() {
    let dir = report("yaw_delay", Exp::Yaw, &[("sensor_delay", vec![0.25])], 2);
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("against t since the run's start [s]"), "{md}");
}
