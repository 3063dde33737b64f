"""Shared fixtures of the Python tests: the repository, its shipped worlds, the `shoal`
binary (SHOAL_BIN, else built with cargo into the workspace's target directory), and for the
ROS 2 tests a DDS domain and namespace per test (`bus`) kept on this machine
(`localhost_dds`)."""

import itertools
import json
import os
import signal
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

_bus_serial = itertools.count()


def bus():
    """A ROS 2 namespace and DDS domain of the calling test's own (from the pid and a counter),
    so that tests and test runs side by side do not hear each other."""
    n = next(_bus_serial)
    pid = os.getpid()
    return f"t{pid}_{n}", 1 + (pid * 7 + n) % 200


@pytest.fixture(scope="session")
def localhost_dds():
    """DDS kept on this machine for the ROS 2 tests: Cyclone DDS (this process and the agents)
    on the loopback interface, unicast (`shoal_ros2.LOCALHOST_CONFIG` as CYCLONEDDS_URI), and
    ROS 2's own variables for the world's side."""
    from shoal_ros2 import LOCALHOST_CONFIG

    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("CYCLONEDDS_URI", LOCALHOST_CONFIG)
        mp.setenv("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
        mp.setenv("ROS_LOCALHOST_ONLY", "1")
        yield


def interruptible() -> None:
    """`preexec_fn` of a child that a test stops with Ctrl-C (SIGINT): the signal at its
    default in the child, as in a terminal. A process started in the background of a
    non-interactive shell (scripts/test.sh runs pytest so) inherits SIGINT ignored, and a
    Python child would then never raise KeyboardInterrupt."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


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
