//! The replay of a real run end to end: `shoal run` writes `replay.html` by default; headless
//! Chromium opens it from `file://` and the page reports that it rendered the run's vehicles
//! without an error; the page reaches nothing outside itself; its timeline adds up to the
//! summary; `shoal render` draws a GIF of it; `--no-replay` skips it; bad render input is
//! refused with a located message. Chromium: `scripts/install-chromium.sh` (run by
//! `scripts/test.sh`).

#[path = "../../shoal-record/tests/support/browser.rs"]
mod browser;

use browser::{assert_no_outside_requests, assert_offline, chromium_observed, html_attr};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn shoal() -> Command {
    Command::new(env!("CARGO_BIN_EXE_shoal"))
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("shoal-replay-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn ok(o: &Output) -> String {
    let (stdout, stderr) = (
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr),
    );
    assert!(o.status.success(), "{}\n{stdout}\n{stderr}", o.status);
    stdout.into_owned()
}

fn summary(out: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
}

/// Frames and size of a GIF, and the RGB colours of its first frame.
fn gif_facts(path: &Path) -> (usize, (u16, u16), std::collections::HashSet<[u8; 3]>) {
    let mut o = gif::DecodeOptions::new();
    o.set_color_output(gif::ColorOutput::RGBA);
    let mut d = o.read_info(std::fs::File::open(path).unwrap()).unwrap();
    let size = (d.width(), d.height());
    let mut frames = 0;
    let mut colours = std::collections::HashSet::new();
    while let Some(f) = d.read_next_frame().unwrap() {
        if frames == 0 {
            for p in f.buffer.chunks_exact(4) {
                colours.insert([p[0], p[1], p[2]]);
            }
        }
        frames += 1;
    }
    (frames, size, colours)
}

#[test]
fn the_default_run_writes_a_replay_that_chromium_plays_and_render_draws() {
    let out = tmp("default");
    let stdout = ok(&shoal()
        .args(["run", "--quiet", "--duration", "20", "--out"])
        .arg(&out)
        .output()
        .unwrap());
    let page = std::fs::canonicalize(out.join("replay.html")).unwrap();
    assert!(stdout.contains("replay.html"), "{stdout}");
    let s = summary(&out);
    assert!(
        s["files"]
            .as_array()
            .unwrap()
            .iter()
            .any(|f| f.as_str().unwrap().ends_with("replay.html")),
        "summary files: {}",
        s["files"]
    );

    // The page's data is the run: 12 vehicles, 20 s, and a timeline that adds up to the
    // summary's link totals.
    let data = shoal_record::replay::html::read(&page).unwrap();
    let m = &data.meta;
    assert_eq!(m.vehicles, 12);
    assert!((m.duration_s - 20.0).abs() < 1e-9, "{}", m.duration_s);
    assert_eq!(m.world, s["world"].as_str().unwrap());
    let rx = &s["comm"]["receptions"];
    let sum = |v: &[u64]| v.iter().sum::<u64>();
    assert_eq!(sum(&m.timeline.attempted), rx["attempts"].as_u64().unwrap());
    assert_eq!(
        sum(&m.timeline.delivered),
        rx["delivered"].as_u64().unwrap()
    );
    assert_eq!(
        sum(&m.timeline.occluded),
        rx["lost_occlusion"].as_u64().unwrap()
    );
    assert!(
        sum(&m.timeline.occluded) > 0,
        "the pillar blocks some frames"
    );
    assert_eq!(m.links_total, rx["attempts"].as_u64().unwrap());
    assert_eq!(m.timeline.largest_fraction.len(), 20);

    // Headless Chromium plays it: rendered frames, the run's vehicle count, no error.
    let (run, requests) =
        chromium_observed(&page, "", &["--virtual-time-budget=3000", "--dump-dom"]);
    let dom = String::from_utf8_lossy(&run.stdout);
    assert_eq!(
        html_attr(&dom, "data-errors"),
        None,
        "the page reported errors"
    );
    assert_eq!(
        html_attr(&dom, "data-status").as_deref(),
        Some("ok"),
        "{}",
        &dom[..dom.len().min(2000)]
    );
    assert_eq!(html_attr(&dom, "data-vehicles").as_deref(), Some("12"));
    let frames: u32 = html_attr(&dom, "data-frames-rendered")
        .and_then(|f| f.parse().ok())
        .unwrap_or(0);
    assert!(frames >= 1, "frames rendered: {frames}");
    assert!(dom.contains("default swarm"), "the page names the world");
    assert_no_outside_requests(&requests);
    assert_offline(&std::fs::read_to_string(&page).unwrap());

    // `shoal render` draws it without a browser: both views for 12 vehicles, 20 s at 4× and
    // 10 fps = 50 frames, the group colours (tab10 blue, orange, green) on the first.
    let gif_path = out.join("run.gif");
    let said = ok(&shoal()
        .args(["render"])
        .arg(&out)
        .args(["--width", "400", "--gif"])
        .arg(&gif_path)
        .output()
        .unwrap());
    assert!(said.contains("run.gif"), "{said}");
    let (frames, (w, h), colours) = gif_facts(&gif_path);
    assert_eq!(w, 400);
    assert!(h > 400, "top and side views stacked: {w} × {h}");
    assert!((50..=52).contains(&frames), "{frames} GIF frames");
    for c in [[31, 119, 180], [255, 127, 14], [44, 160, 44]] {
        assert!(colours.contains(&c), "group colour {c:?} missing");
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn no_replay_skips_the_page_and_render_says_why_it_cannot() {
    let out = tmp("skip");
    ok(&shoal()
        .args([
            "run",
            "--quiet",
            "--no-replay",
            "--no-plots",
            "--duration",
            "2",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap());
    assert!(!out.join("replay.html").exists());
    let s = summary(&out);
    assert!(
        !s["files"].to_string().contains("replay.html"),
        "{}",
        s["files"]
    );
    let o = shoal().arg("render").arg(&out).output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("replay.html does not exist") && err.contains("--no-replay"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn render_refuses_bad_options_and_pages_with_located_messages() {
    let out = tmp("bad");
    ok(&shoal()
        .args(["run", "--quiet", "--no-plots", "--duration", "2", "--out"])
        .arg(&out)
        .output()
        .unwrap());
    for (flag, value, says) in [
        ("--width", "100", "240"),
        ("--fps", "0", "fps"),
        ("--speed", "-1", "speed"),
    ] {
        let o = shoal()
            .arg("render")
            .arg(&out)
            .arg(format!("{flag}={value}"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{flag} {value}: {err}");
        assert!(err.contains(says), "{flag} {value}: {err}");
        assert!(!out.join("replay.gif").exists());
    }
    // A page that is not a replay: the message names the file.
    let fake = out.join("fake.html");
    std::fs::write(&fake, "<html><body>hello</body></html>").unwrap();
    let o = shoal().arg("render").arg(&fake).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("fake.html"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    let _ = std::fs::remove_dir_all(&out);
}
