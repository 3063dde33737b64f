//! Building a workspace example from a test, for the tests of shoal-cli (the agents) and the
//! root crate (the root examples), which include this file by path.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// Builds the example `name` of the workspace at `repo` in the profile whose folder is
/// `profile_dir` (`target/debug` or `target/release`) and returns its path. Built with
/// `--workspace`, so its features resolve as in `cargo test --workspace`, which has built it
/// already: `-p CRATE` would resolve them differently and build second copies of the
/// dependencies (minutes and a gigabyte of disk on a fresh machine).
pub fn build_example(repo: &Path, profile_dir: &Path, name: &str) -> PathBuf {
    let mut build = Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()));
    build
        .args(["build", "-q", "--workspace", "--example", name])
        .current_dir(repo);
    if profile_dir.ends_with("release") {
        build.arg("--release");
    }
    let o = build.output().unwrap();
    assert!(
        o.status.success(),
        "building {name} failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let exe = profile_dir
        .join("examples")
        .join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    assert!(exe.is_file(), "{} missing", exe.display());
    exe
}
