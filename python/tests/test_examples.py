"""The examples run (shortened): numpy flocking of 1,000 vehicles aligns them, the CEM training
writes its learning curve, and every example is an executable script."""

import os
import subprocess
import sys

from conftest import REPO, WORLDS

EXAMPLES = REPO / "python" / "examples"


def test_every_example_is_executable_with_a_shebang():
    for f in EXAMPLES.glob("*.py"):
        assert os.access(f, os.X_OK), f"{f} is not executable"
        assert f.read_text().startswith("#!/usr/bin/env python3\n"), f


def test_flocking_of_1000_vehicles_aligns_neighbours():
    assert len((EXAMPLES / "flock.py").read_text().splitlines()) < 40
    p = subprocess.run([sys.executable, EXAMPLES / "flock.py", WORLDS / "flock_1000.toml", "20"],
                       capture_output=True, text=True, timeout=300, check=True)
    lines = [l for l in p.stdout.splitlines() if l.startswith("t =")]
    first, last = (float(l.split("neighbours ")[1].split(",")[0]) for l in (lines[0], lines[-1]))
    assert first < 0.3 and last > 0.6, p.stdout


def test_cem_training_writes_a_learning_curve(tmp_path):
    p = subprocess.run([sys.executable, EXAMPLES / "train_cem.py", tmp_path, "--generations", "2",
                        "--steps", "40"], capture_output=True, text=True, timeout=300, check=True)
    assert "generation   2" in p.stdout
    png = (tmp_path / "learning_curve.png").read_bytes()
    assert png.startswith(b"\x89PNG") and len(png) > 5000
    assert (tmp_path / "policy.npy").is_file()
