//! A file-size limit hit while `shoal run` writes its outputs (RLIMIT_FSIZE set with
//! `prlimit`, as a full disk would): one error that names the file and the reason, exit 1,
//! the files finished before it whole and listed in summary.json (written first), nothing
//! truncated under an output's name and no temporaries. With SIGXFSZ at its default action
//! (shoal catches it) and ignored (`trap '' XFSZ`, as some shells and services start it).

mod common;

use std::path::Path;
use std::process::{Command, Output};

/// Runs `shoal run --quiet <extra> --out <dir>/out <world>` with files limited to `limit`
/// bytes.
fn run_limited(dir: &Path, world: &Path, limit: u64, ignore_xfsz: bool, extra: &[&str]) -> Output {
    let trap = if ignore_xfsz { "trap '' XFSZ; " } else { "" };
    Command::new("sh")
        .args([
            "-c",
            &format!("{trap}exec prlimit --fsize={limit} -- \"$@\""),
            "sh",
        ])
        .arg(env!("CARGO_BIN_EXE_shoal"))
        .args(["run", "--quiet"])
        .args(extra)
        .arg("--out")
        .arg(dir.join("out"))
        .arg(world)
        .output()
        .expect("sh and prlimit (util-linux) run")
}

/// One vehicle for `duration` s, with plots.
fn world(dir: &Path, duration: f64) -> std::path::PathBuf {
    let p = dir.join("world.toml");
    std::fs::write(
        &p,
        format!(
            "name = \"limited\"\nduration = {duration}\n[pool]\nsize = [10.0, 10.0, 3.0]\n\
             [[vehicles]]\nname = \"auv\"\nposition = [5.0, 5.0, 0.5]\n\
             mission = [{{ t = 0, mode = \"auto\", depth = 1.0, yaw_deg = 0 }}]\n"
        ),
    )
    .unwrap();
    p
}

/// The `error:` lines of stderr.
fn errors(o: &Output) -> Vec<String> {
    String::from_utf8_lossy(&o.stderr)
        .lines()
        .filter(|l| l.starts_with("error:"))
        .map(str::to_string)
        .collect()
}

/// A 2 s run: the summary (≈ 1 kB) and 21 trajectory rows (≈ 5 kB) fit under 20 kB, the
/// next file does not: `replay.html` (≈ 0.7 MB), or with `--no-replay` the first plot
/// (≈ 100 kB).
fn next_file_over_the_limit(ignore_xfsz: bool, replay: bool) {
    let dir = common::tmp("disk-full", &format!("{ignore_xfsz}-{replay}"));
    let extra: &[&str] = if replay { &[] } else { &["--no-replay"] };
    let o = run_limited(&dir, &world(&dir, 2.0), 20_000, ignore_xfsz, extra);
    let out = dir.join("out");
    let errs = errors(&o);
    assert_eq!(o.status.code(), Some(1), "{errs:?}");
    assert_eq!(errs.len(), 1, "{errs:?}");
    let failed = if replay { "replay.html" } else { "depth.png" };
    assert_eq!(
        errs[0],
        format!(
            "error: cannot write {}: File too large (os error 27)",
            out.join(failed).display()
        )
    );
    // The summary was written first, whole, and then told what exists.
    let s = common::summary(&out);
    assert_eq!(s["vehicles"], 1);
    assert_eq!(s["steps"], 200);
    assert_eq!(s["interrupted"], false);
    assert_eq!(s["trajectory_rows"], 21);
    assert!(
        s["output_error"]
            .as_str()
            .is_some_and(|e| e.contains(failed) && e.contains("File too large")),
        "{s}"
    );
    assert_eq!(
        common::summary_files(&s),
        [
            out.join("summary.json"),
            out.join("trajectories.csv"),
            out.join("vehicles.csv")
        ]
    );
    assert_eq!(common::whole_csv_rows(&out.join("trajectories.csv")), 21);
    // Nothing else: no truncated page or plot under its name, no temporaries.
    let mut present: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    present.sort();
    assert_eq!(
        present,
        ["summary.json", "trajectories.csv", "vehicles.csv"]
    );
}

#[test]
fn plot_over_the_file_size_limit_is_named_and_the_summary_stays() {
    next_file_over_the_limit(false, false);
}

#[test]
fn plot_over_the_file_size_limit_with_sigxfsz_ignored() {
    next_file_over_the_limit(true, false);
}

#[test]
fn replay_over_the_file_size_limit_is_named_and_leaves_no_partial_page() {
    next_file_over_the_limit(false, true);
}

/// The trajectories outgrow the limit while the world runs (60 s: 601 rows ≈ 150 kB): the
/// run stops with the error naming trajectories.csv, and no part of the table is left.
#[test]
fn trajectories_over_the_file_size_limit_leave_no_partial_table() {
    let dir = common::tmp("disk-full", "trajectories");
    let o = run_limited(&dir, &world(&dir, 60.0), 20_000, false, &[]);
    let out = dir.join("out");
    let errs = errors(&o);
    assert_eq!(o.status.code(), Some(1), "{errs:?}");
    assert_eq!(
        errs,
        [format!(
            "error: cannot write {}: File too large (os error 27)",
            out.join("trajectories.csv").display()
        )]
    );
    let present: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(present.is_empty(), "{present:?}");
}
