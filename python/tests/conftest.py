"""Shared fixtures of the Python tests: the repository, its shipped worlds and the `shoal`
binary (SHOAL_BIN, else built with cargo into the workspace's target directory)."""

import json
import os
import subprocess
from pathlib import Path

import pytest

try:
    import shoal  # noqa: F401 (the installed package, with its compiled extension)
except ImportError as e:  # e.g. python/shoal (the sources) shadows the installed package
    raise ImportError(
        f"{e}: install the package (scripts/python-env.sh) and run the tests from the "
        "repository root: .venv/bin/pytest python/tests"
    ) from e

#: The repository root.
REPO = Path(__file__).resolve().parents[2]
#: The shipped worlds.
WORLDS = REPO / "worlds"


@pytest.fixture(scope="session")
def shoal_bin() -> Path:
    """The `shoal` binary of this checkout: $SHOAL_BIN, or `cargo build --bin shoal` (fast
    when it is up to date, as after `cargo test --workspace`)."""
    if os.environ.get("SHOAL_BIN"):
        return Path(os.environ["SHOAL_BIN"])
    subprocess.run(["cargo", "build", "-q", "--bin", "shoal"], cwd=REPO, check=True)
    meta = subprocess.run(
        ["cargo", "metadata", "--format-version", "1", "--no-deps"],
        cwd=REPO, check=True, capture_output=True, text=True,
    )
    exe = Path(json.loads(meta.stdout)["target_directory"]) / "debug" / "shoal"
    assert exe.is_file(), f"cargo built no {exe}"
    return exe


def shoal_run(exe: Path, world: Path, out: Path, *args: str, timeout: float = 120.0) -> dict:
    """Runs `shoal run WORLD` quietly without plots or replay into `out`; returns its
    summary.json."""
    cmd = [str(exe), "run", str(world), "--quiet", "--no-plots", "--no-replay", "--out", str(out), *args]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    assert p.returncode == 0, f"{' '.join(cmd)} failed ({p.returncode}):\n{p.stdout}\n{p.stderr}"
    return json.loads((out / "summary.json").read_text())
