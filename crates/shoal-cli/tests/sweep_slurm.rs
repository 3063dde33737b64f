//! `shoal sweep --engine slurm` on a real single-node Slurm cluster (slurmctld, slurmd and a
//! private munged, started by `.ci/slurm-up`): the smoke sweep as a job array gives the same
//! table as on this machine (every column but the wall time), a failing task is reported and,
//! once its cause is gone, re-submitted alone, and a run that went missing is re-submitted
//! alone and picked up by `shoal sweep collect` while the job runs.
//!
//! The cluster is the one scripts/test.sh started (`SHOAL_SLURM_CONF`), or else this test
//! starts one with `.ci/slurm-up` and stops it afterwards. When no cluster can be started
//! (not root, no Debian packages), the test fails with the script's reason: it is never
//! skipped.

mod common;
mod sweep_common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};
use sweep_common::*;

/// The project's test cluster, stopped on drop if this test started it.
struct Cluster {
    conf: PathBuf,
    started_here: bool,
}

impl Cluster {
    fn get() -> Cluster {
        if let Some(conf) = std::env::var_os("SHOAL_SLURM_CONF") {
            return Cluster {
                conf: conf.into(),
                started_here: false,
            };
        }
        let o = Command::new(repo().join(".ci/slurm-up")).output().unwrap();
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(
            o.status.success(),
            "no Slurm cluster for the test: .ci/slurm-up failed ({}):\n{}{}",
            o.status,
            out,
            String::from_utf8_lossy(&o.stderr)
        );
        let conf = out
            .lines()
            .rev()
            .find_map(|l| l.strip_prefix("SLURM_CONF="))
            .expect(".ci/slurm-up names SLURM_CONF");
        Cluster {
            conf: conf.into(),
            started_here: true,
        }
    }

    /// `shoal` with this cluster's configuration.
    fn shoal(&self, args: &[&str]) -> Output {
        Command::new(env!("CARGO_BIN_EXE_shoal"))
            .args(args)
            .env("SLURM_CONF", &self.conf)
            .output()
            .unwrap()
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        if self.started_here {
            let _ = Command::new(repo().join(".ci/slurm-down")).status();
        }
    }
}

/// The job id and array of the one submission `o` printed.
fn submitted(o: &Output) -> (String, String) {
    let out = String::from_utf8_lossy(&o.stdout);
    let line = out
        .lines()
        .find(|l| l.starts_with("shoal: submitted Slurm job "))
        .unwrap_or_else(|| panic!("no submission in\n{}", text(o)));
    let rest = &line["shoal: submitted Slurm job ".len()..];
    let (job, rest) = rest.split_once(": array ").unwrap();
    let array = rest.split_once(' ').unwrap().0;
    assert_eq!(
        out.matches("submitted Slurm job").count(),
        1,
        "one array expected: {out}"
    );
    (job.to_string(), array.to_string())
}

fn task_logs(dir: &Path, job: &str) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir.join("slurm"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(&format!("{job}_")) && n.ends_with(".out"))
        .collect();
    v.sort();
    v
}

#[test]
fn a_slurm_job_array_gives_the_local_table_and_resubmits_only_what_is_missing_or_failed() {
    let t0 = Instant::now();
    let cluster = Cluster::get();
    let dir = tmp("slurm");
    let smoke = smoke();
    let smoke = smoke.to_str().unwrap();

    // The reference: the same sweep on this machine.
    let local = dir.join("local");
    let o = shoal(&["sweep", smoke, "--out", local.to_str().unwrap(), "-q"]);
    assert!(o.status.success(), "{}", text(&o));
    let (header, reference) = table(&local);
    let reference = without_wall(&reference);

    // Run 3 cannot write its summary (a folder stands where the file goes): its task fails.
    let out = dir.join("slurm-out");
    let planted = out
        .join("runs")
        .join(&reference[3]["run"])
        .join("summary.json");
    std::fs::create_dir_all(planted.join("in-the-way")).unwrap();
    let o = cluster.shoal(&[
        "sweep",
        smoke,
        "--out",
        out.to_str().unwrap(),
        "--engine",
        "slurm",
        "--max-parallel",
        "2",
        "--partition",
        "debug",
        "--time",
        "5:00",
        "--wait",
        "-q",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let (job1, array) = submitted(&o);
    assert_eq!(array, "0-7%2");
    assert!(
        String::from_utf8_lossy(&o.stdout).contains("8 runs: 7 ok, 1 failed, 0 missing"),
        "{}",
        text(&o)
    );
    assert_eq!(task_logs(&out, &job1).len(), 8);
    let log = std::fs::read_to_string(out.join(format!("slurm/{job1}_3.out"))).unwrap();
    assert!(log.contains("run 3") && log.contains("failed"), "{log}");
    let (h, rows) = table(&out);
    assert_eq!(h, header);
    let rows = without_wall(&rows);
    for (i, (r, want)) in rows.iter().zip(&reference).enumerate() {
        if i == 3 {
            assert_eq!(r["status"], "failed");
            assert!(
                r["error"].contains("summary.json") && r["error"].contains("Is a directory"),
                "{r:?}"
            );
        } else {
            assert_eq!(r, want, "row {i}");
        }
    }

    // The cause removed, the failed run is re-submitted alone, and the table is the local one.
    std::fs::remove_dir_all(&planted).unwrap();
    let o = cluster.shoal(&[
        "sweep",
        smoke,
        "--out",
        out.to_str().unwrap(),
        "--engine",
        "slurm",
        "--retry-failed",
        "--wait",
        "-q",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let (job2, array) = submitted(&o);
    assert_eq!(array, "3");
    assert_ne!(job2, job1);
    assert_eq!(task_logs(&out, &job2), [format!("{job2}_3.out")]);
    assert_eq!(without_wall(&table(&out).1), reference);

    // A run whose result went missing is re-submitted alone; without --wait the command
    // returns at once and `collect` builds the table from whatever is done.
    std::fs::remove_file(
        out.join("runs")
            .join(&reference[5]["run"])
            .join("result.json"),
    )
    .unwrap();
    let o = cluster.shoal(&[
        "sweep",
        smoke,
        "--out",
        out.to_str().unwrap(),
        "--engine",
        "slurm",
        "-q",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let (job3, array) = submitted(&o);
    assert_eq!(array, "5");
    let start = Instant::now();
    loop {
        let o = cluster.shoal(&["sweep", "collect", out.to_str().unwrap()]);
        if o.status.success() {
            break;
        }
        assert_eq!(o.status.code(), Some(1), "{}", text(&o));
        assert!(
            String::from_utf8_lossy(&o.stdout).contains("8 runs: 7 ok, 0 failed, 1 missing"),
            "{}",
            text(&o)
        );
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "run 5 of job {job3} did not finish"
        );
        std::thread::sleep(Duration::from_millis(200));
    }
    assert_eq!(task_logs(&out, &job3), [format!("{job3}_5.out")]);
    assert_eq!(without_wall(&table(&out).1), reference);

    // Nothing left: nothing is submitted.
    let o = cluster.shoal(&[
        "sweep",
        smoke,
        "--out",
        out.to_str().unwrap(),
        "--engine",
        "slurm",
        "--wait",
        "-q",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        String::from_utf8_lossy(&o.stdout).contains("nothing to submit"),
        "{}",
        text(&o)
    );
    let jobs: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("slurm/jobs.json")).unwrap())
            .unwrap();
    let indices: Vec<String> = jobs
        .as_array()
        .unwrap()
        .iter()
        .map(|j| j["indices"].to_string())
        .collect();
    assert_eq!(indices, ["[0,1,2,3,4,5,6,7]", "[3]", "[5]"]);
    std::fs::remove_dir_all(&dir).ok();
    println!(
        "the Slurm sweep test took {:.1} s (cluster start included when it started one)",
        t0.elapsed().as_secs_f64()
    );
}
