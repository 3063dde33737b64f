"""The examples run (shortened): numpy flocking of 1,000 vehicles aligns them, the CEM training
writes its learning curve, and every example is an executable script."""

import os
import re
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
    # The figure draws what the run printed: per generation the mean policy's held-out return
    # (blue, solid) and the built-in controller's (orange, dashed), on one vertical axis.
    printed = [re.search(r"generation +(\d+): .*held-out targets +(-?[\d.]+) "
                         r"\(built-in controller (-?[\d.]+)\)", line)
               for line in p.stdout.splitlines() if line.startswith("generation")]
    held = [float(m.group(2)) for m in printed]
    reference = {float(m.group(3)) for m in printed}
    assert len(held) == 2 and len(reference) == 1, p.stdout
    lines = polylines((tmp_path / "learning_curve.svg").read_text())
    legend = [pts for c, w, pts in lines if len(pts) == 2 and pts[0][1] == pts[1][1]
              and abs(pts[1][0] - pts[0][0]) == 24]
    policy = [pts for c, w, pts in lines if (c, w) == ("#1F77B4", 2) and pts not in legend]
    dashes = [pts for c, w, pts in lines if (c, w) == ("#FF7F0E", 1) and pts not in legend]
    assert len(policy) == 1 and [x for x, _ in policy[0]] == sorted(x for x, _ in policy[0])
    assert dashes and len({y for pts in dashes for _, y in pts}) == 1, "the reference is level"
    pairs = list(zip(held, (y for _, y in policy[0]))) + [(reference.pop(), dashes[0][0][1])]
    # Pixels are whole; the printed returns have one decimal (±0.05).
    miss, slope = affine_fit(pairs)
    assert miss <= 1.0 + 0.05 * abs(slope), (pairs, miss, slope)


def polylines(svg):
    """(stroke, width, points) of every polyline of an SVG drawn by shoal's plots."""
    out = []
    for tag in re.findall(r"<polyline [^>]*>", svg):
        attr = dict(re.findall(r'([\w-]+)="([^"]*)"', tag))
        pts = [tuple(float(v) for v in p.split(",")) for p in attr["points"].split()]
        out.append((attr["stroke"], int(attr["stroke-width"]), pts))
    return out


def affine_fit(pairs):
    """Least-squares line through (value, pixel) pairs: the largest miss [px] and the slope."""
    n = len(pairs)
    mu = sum(u for u, _ in pairs) / n
    mp = sum(p for _, p in pairs) / n
    suu = sum((u - mu) ** 2 for u, _ in pairs)
    slope = sum((u - mu) * (p - mp) for u, p in pairs) / suu if suu else 0.0
    return max(abs(p - (mp + slope * (u - mu))) for u, p in pairs), slope
