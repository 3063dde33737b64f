//! Helpers shared by the agent tests: the repository root and the example agents of
//! shoal-bridge, built with cargo like the binary under test.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// The repository root.
pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Builds the shoal-bridge example `name` (same profile as the `shoal` binary under test)
/// and returns its path.
pub fn example_agent(name: &str) -> PathBuf {
    let bin_dir = Path::new(env!("CARGO_BIN_EXE_shoal")).parent().unwrap();
    let mut build = Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()));
    build
        .args(["build", "-q", "-p", "shoal-bridge", "--example", name])
        .current_dir(repo());
    if bin_dir.ends_with("release") {
        build.arg("--release");
    }
    let o = build.output().unwrap();
    assert!(
        o.status.success(),
        "building {name} failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let exe = bin_dir
        .join("examples")
        .join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    assert!(exe.exists(), "{} missing", exe.display());
    exe
}
