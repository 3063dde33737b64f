#!/usr/bin/env python3
"""`shoal validate` from Python, as in a notebook: a measured log → what the μAUV² model gets
wrong, the effect that explains it, its fitted parameters and the gain on data it did not fit.

    python/examples/validate_log.py [LOG.csv [OUT_DIR]]

Default log: ../shared/data/validation_dev/dev_y_gain.csv (a turning run whose thrusters are
stronger than the model's); OUT_DIR (default out/validate_log) receives report.json,
report.md, the plots and the extended vehicle.toml.
"""

import sys
from pathlib import Path

import numpy as np

import shoal

repo = Path(__file__).resolve().parents[2]
log = Path(sys.argv[1]) if len(sys.argv) > 1 else repo.parent / "shared/data/validation_dev/dev_y_gain.csv"
out = Path(sys.argv[2]) if len(sys.argv) > 2 else repo / "out/validate_log"

# A log is a path, or columns of numbers named as in the CSV format (here read with numpy, as
# data from any other source would be).
header = log.read_text().splitlines()[0].split(",")
data = np.loadtxt(log, delimiter=",", skiprows=1)
columns = {name: data[:, i] for i, name in enumerate(header)}

fits = 0
def progress(kind, message):
    global fits
    fits += kind == "fit"
    if kind != "fit":
        print(f"[{kind}] {message}")

report = shoal.validate((log.stem, columns), dt=0.02, progress=progress)
print(f"\n{report.verdict}\n({fits} fits)\n")
for e in report.effects:
    print(f"{e.name} ({e.form} form, chosen in {100 * e.stability:.0f} % of resamples)")
    for p in e.parameters:
        lo, hi = p.ci95
        print(f"  {p.name} = {p.value:.4g} {p.unit}  (95 %: {lo:.4g} … {hi:.4g})")
print("\nchannel   RMSE before   RMSE after   gain")
for name, c in report.channels.items():
    print(f"{name:8} {c.rmse_before:12.4g} {c.rmse_after:12.4g} {c.gain_pct:6.1f} %")
files = report.write(out)
print(f"\nwrote {files['json']}, {files['markdown']}, {files['vehicle']} ({len(files['plots'])} plots)")
