//! Signals that come while `shoal run` writes its outputs. The binary is held just before a
//! chosen output file (`SHOAL_HOLD_BEFORE_OUTPUT`, see `shoal`'s `signals` module) until the
//! test has sent its signal, so each signal lands exactly where the test says — no race with
//! the writer. In every case: the exit code of the *first* signal, the summary marked
//! interrupted by it and listing exactly the files there are, every file under its final
//! name whole (CSV rows whole, JSON and the replay parse, PNGs decode, SVGs closed), no
//! temporaries. A further signal (or the first after a complete run) skips the plots not
//! yet drawn; the summary and the tables are always finished.

mod common;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Child;
use std::time::Duration;

/// Longest wait for a stage of a run (a hang guard, never a timing assertion).
const GUARD: Duration = Duration::from_secs(60);
/// Longest wait for the exit after the last signal (a hang guard).
const EXIT_GUARD: Duration = Duration::from_secs(30);
/// The marker `shoal` prints when it holds before an output file.
const HOLDING: &str = "shoal: holding before";

/// A world of `duration` seconds with two steered vehicles (so there are depth, top and
/// heading plots) and a replay.
fn world(dir: &Path, duration: f64) -> PathBuf {
    let world = dir.join("world.toml");
    std::fs::write(
        &world,
        format!(
            "name = \"outputs\"\nduration = {duration}\n[pool]\nsize = [10.0, 10.0, 3.0]\n\
             [[vehicles]]\nname = \"a\"\nposition = [5.0, 5.0, 0.5]\n\
             mission = [{{ t = 0, mode = \"auto\", depth = 1.0, yaw_deg = 0 }}, {{ t = 1, surge = 0.03 }}]\n\
             [[vehicles]]\nname = \"b\"\nposition = [2.0, 2.0, 0.5]\n\
             mission = [{{ t = 0, mode = \"auto\", depth = 1.5, yaw_deg = 90 }}]\n"
        ),
    )
    .unwrap();
    world
}

/// Starts the world of `duration` s into `dir/out`, held before the output file `hold`.
fn start(dir: &Path, duration: f64, hold: &str) -> (Child, common::StderrLines, PathBuf) {
    let out = dir.join("out");
    let mut child = common::run_command(&["--quiet"], &out, &world(dir, duration), None)
        .env("SHOAL_HOLD_BEFORE_OUTPUT", hold)
        .spawn()
        .unwrap();
    let stderr = common::StderrLines::take(&mut child);
    (child, stderr, out)
}

/// Lets the run go until rows are being written, then sends `signal`.
fn interrupt_mid_run(child: &mut Child, out: &Path, signal: &str) {
    common::wait_for_size(&out.join(".trajectories.csv.tmp"), 20_000, child);
    common::kill(child, signal);
}

/// Waits for the exit; checks its code and the printed summary's word for the signal.
fn ended(mut child: Child, stderr: common::StderrLines, code: i32, signal: &str) {
    let status = common::wait(&mut child, EXIT_GUARD);
    let o = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    let stderr = stderr.finish();
    assert_eq!(status.code(), Some(code), "{stdout}\n{stderr}");
    assert!(
        stdout.contains(&format!("INTERRUPTED ({signal}) after")),
        "{stdout}"
    );
}

/// Checks that every output in `out` is whole and that the summary (interrupted by
/// `signal`) lists exactly them; returns the summary and the files' names.
fn whole_outputs(out: &Path, signal: &str) -> (serde_json::Value, BTreeSet<String>) {
    let present: BTreeSet<String> = std::fs::read_dir(out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    let temporaries: Vec<&String> = present.iter().filter(|n| n.ends_with(".tmp")).collect();
    assert!(temporaries.is_empty(), "left behind: {temporaries:?}");
    let s = common::summary(out);
    assert_eq!(s["interrupted"], true, "{s}");
    assert_eq!(s["signal"], signal, "{s}");
    assert!(s.get("output_error").is_none(), "{s}");
    let listed: BTreeSet<String> = common::summary_files(&s)
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(listed, present, "the summary's files against the folder");
    for name in &present {
        let path = out.join(name);
        match name.rsplit_once('.').map(|(_, ext)| ext) {
            Some("csv") => {
                let rows = common::whole_csv_rows(&path);
                if name == "trajectories.csv" {
                    assert!(rows > 0);
                    assert_eq!(s["trajectory_rows"].as_u64(), Some(rows as u64));
                }
            }
            Some("png") => {
                let img = image::open(&path)
                    .unwrap_or_else(|e| panic!("{name} does not decode: {e}"))
                    .to_rgb8();
                assert!(img.width() > 100 && img.height() > 100, "{name}");
            }
            Some("svg") => {
                let text = std::fs::read_to_string(&path).unwrap();
                assert!(
                    text.trim_start().starts_with("<svg") && text.trim_end().ends_with("</svg>"),
                    "{name} is not a whole SVG"
                );
            }
            Some("html") => {
                shoal_record::replay::html::read(&path)
                    .unwrap_or_else(|e| panic!("{name} does not read back: {e}"));
            }
            Some("json") => {} // summary.json: parsed above
            _ => panic!("unexpected output {name}"),
        }
    }
    (s, present)
}

/// The plot files (PNG and SVG) among `files`.
fn plots(files: &BTreeSet<String>) -> BTreeSet<&str> {
    files
        .iter()
        .filter(|f| f.ends_with(".png") || f.ends_with(".svg"))
        .map(String::as_str)
        .collect()
}

/// The tables and the replay every interrupted run of [`world`] has.
fn has_tables(files: &BTreeSet<String>) {
    for f in [
        "summary.json",
        "trajectories.csv",
        "vehicles.csv",
        "replay.html",
    ] {
        assert!(files.contains(f), "{f} missing from {files:?}");
    }
}

/// Runs the long world, sends `first` (a signal name such as `TERM`) mid-run and `second`
/// when the run holds before the output `hold`; checks the exit code of `first` and the
/// outputs; returns the names of the files written.
fn signalled_twice(tag: &str, hold: &str, first: &str, second: &str) -> BTreeSet<String> {
    let dir = common::tmp("signals-out", tag);
    let (mut child, mut stderr, out) = start(&dir, 100_000.0, hold);
    interrupt_mid_run(&mut child, &out, first);
    stderr.wait_for(HOLDING, GUARD, &mut child);
    common::kill(&child, second);
    let (name, code) = match first {
        "HUP" => ("SIGHUP", 129),
        "INT" => ("SIGINT", 130),
        _ => ("SIGTERM", 143),
    };
    ended(child, stderr, code, name);
    let (s, files) = whole_outputs(&out, name);
    assert!(s["simulated_s"].as_f64() < s["planned_s"].as_f64(), "{s}");
    has_tables(&files);
    files
}

/// SIGTERM mid-run, then SIGINT while the second plot is about to be drawn: exit 143, the
/// first plot (both files) drawn, the rest skipped.
#[test]
fn a_second_signal_while_the_plots_are_drawn_skips_the_plots_not_yet_drawn() {
    let files = signalled_twice("plots", "top.png", "TERM", "INT");
    assert_eq!(plots(&files), BTreeSet::from(["depth.png", "depth.svg"]));
}

/// SIGHUP mid-run, then SIGTERM between the first plot's PNG and its SVG: exit 129, that
/// PNG alone.
#[test]
fn a_second_signal_between_a_plots_png_and_svg_keeps_the_png_alone() {
    let files = signalled_twice("svg", "depth.svg", "HUP", "TERM");
    assert_eq!(plots(&files), BTreeSet::from(["depth.png"]));
}

/// SIGINT mid-run, then SIGTERM while the tables are written: exit 130, every table and the
/// replay finished, no plot.
#[test]
fn a_second_signal_while_the_tables_are_written_finishes_them_and_draws_no_plot() {
    let files = signalled_twice("tables", "vehicles.csv", "INT", "TERM");
    assert_eq!(plots(&files), BTreeSet::new());
}

/// A run that completed gets its first signal (SIGTERM) while its outputs are written:
/// exit 143, the summary marked interrupted although every step ran, the tables finished,
/// the plots skipped.
#[test]
fn a_first_signal_while_a_complete_runs_outputs_are_written_skips_the_plots() {
    let dir = common::tmp("signals-out", "complete");
    let (mut child, mut stderr, out) = start(&dir, 2.0, "depth.png");
    stderr.wait_for(HOLDING, GUARD, &mut child);
    common::kill(&child, "TERM");
    ended(child, stderr, 143, "SIGTERM");
    let (s, files) = whole_outputs(&out, "SIGTERM");
    assert_eq!(s["simulated_s"], s["planned_s"], "{s}");
    has_tables(&files);
    assert_eq!(plots(&files), BTreeSet::new());
}

/// Two signals before the outputs begin (Ctrl-C pressed twice): the second skips every
/// plot, whether it came before the writing began or during it. The process is stopped
/// (SIGSTOP) while both are sent, so both are pending when it goes on (Linux delivers
/// pending signals lowest number first: SIGINT, then SIGTERM).
#[test]
fn two_signals_mid_run_skip_every_plot() {
    let dir = common::tmp("signals-out", "twice");
    let (mut child, stderr, out) = start(&dir, 100_000.0, "never-written");
    common::wait_for_size(&out.join(".trajectories.csv.tmp"), 20_000, &mut child);
    // Both signals are pending together while the process is stopped; which of its threads
    // takes which first is the kernel's choice, so the run names either one as the cause —
    // with that signal's exit code — and skips the plots for the other.
    for signal in ["STOP", "INT", "TERM", "CONT"] {
        common::kill(&child, signal);
    }
    let status = common::wait(&mut child, EXIT_GUARD);
    let o = child.wait_with_output().unwrap();
    let (stdout, stderr) = (String::from_utf8_lossy(&o.stdout), stderr.finish());
    let (code, first) = if stdout.contains("INTERRUPTED (SIGINT) after") {
        (130, "SIGINT")
    } else {
        (143, "SIGTERM")
    };
    assert!(
        stdout.contains(&format!("INTERRUPTED ({first}) after")),
        "{stdout}\n{stderr}"
    );
    assert_eq!(status.code(), Some(code), "{stdout}\n{stderr}");
    let (_, files) = whole_outputs(&out, first);
    has_tables(&files);
    assert_eq!(plots(&files), BTreeSet::new());
}
