#!/usr/bin/env python3
"""Convert the original-BlueROV pool logs of Aili & Ekelund (2016) into shoal measured runs.

The logs are public but not licensed for redistribution, so shoal does not ship them: this
script reads them where they are (``../shared/data/bluerov1_liu2016`` beside a shoal checkout,
see its README and PROVENANCE.txt) and writes one CSV per run in the format of
``docs/validation.md`` (``t``, ``u.<thruster>``, ``y.<measurement>``), ready for

    shoal validate out/bluerov1/runs/yaw_1.csv ... --vehicle worlds/bluerov1.toml --out ...

Columns written (Python standard library only, no numpy):

* ``t`` [s] — time since the first thruster message of the bag (before it the inputs are
  unknown, so earlier samples are dropped);
* ``u.t1`` … ``u.t6`` [% of full scale] — ESC pulse widths, (pwm − 1500 µs)/4 µs per %, so that
  ±400 µs is ±100 % as in the thesis' thrust table; published only when they change
  (zero-order hold);
* ``y.p``, ``y.q``, ``y.r`` [rad/s] — raw MPU6000 gyro rates (bias not removed);
* ``y.roll``, ``y.pitch``, ``y.yaw`` [rad] — attitude of the on-board EKF (decimated ×5);
* ``y.depth`` [m] — pressure sensor: relative pressure / (1000 kg/m³ · 9.81 m/s²).

Usage:
    python3 examples/bluerov1/convert.py [DATA_DIR] [OUT_DIR] [RUN_PREFIX ...]

Defaults: DATA_DIR = ../shared/data/bluerov1_liu2016, OUT_DIR = out/bluerov1/runs, and the
runs yaw_1 … yaw_5. Prefixes select bags by name (e.g. ``yaw_4 all_2 pitch_roll_1``).
"""

import csv
import glob
import os
import sys

RHO_G = 1000.0 * 9.81


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def one(folder, topic):
    files = glob.glob(os.path.join(folder, f"*__{topic}.csv"))
    return read(files[0]) if files else []


def convert(folder, out_path):
    thr = one(folder, "thrusters")
    imu = one(folder, "imu")
    prs = one(folder, "pressure")
    sts = one(folder, "states_dec5")
    if not thr:
        raise SystemExit(f"{folder}: no thruster messages, nothing drives the vehicle")
    t0 = float(thr[0]["t_rel_s"])
    # (time, column, value) events merged on the union of time stamps.
    rows = {}

    def put(t, col, value):
        t = float(t) - t0
        if t < -1e-9:
            return
        key = round(max(t, 0.0), 6)
        rows.setdefault(key, {})[col] = value

    prev = None
    for r in thr:
        cmds = tuple((float(r[f"pwm{i}_us"]) - 1500.0) / 4.0 for i in range(1, 7))
        if cmds != prev:
            for i, c in enumerate(cmds, start=1):
                put(r["t_rel_s"], f"u.t{i}", f"{c:g}")
            prev = cmds
    for r in imu:
        put(r["t_rel_s"], "y.p", r["gyro_x_radps"])
        put(r["t_rel_s"], "y.q", r["gyro_y_radps"])
        put(r["t_rel_s"], "y.r", r["gyro_z_radps"])
    for r in prs:
        put(r["t_rel_s"], "y.depth", f"{float(r['water_pressure_rel_Pa']) / RHO_G:.5f}")
    for r in sts:
        put(r["t_rel_s"], "y.roll", r["roll_rad"])
        put(r["t_rel_s"], "y.pitch", r["pitch_rad"])
        put(r["t_rel_s"], "y.yaw", r["yaw_rad"])
    cols = [f"u.t{i}" for i in range(1, 7)] + [
        "y.depth", "y.roll", "y.pitch", "y.yaw", "y.p", "y.q", "y.r",
    ]
    os.makedirs(os.path.dirname(out_path) or ".", exist_ok=True)
    with open(out_path, "w", newline="") as f:
        f.write("# converted by examples/bluerov1/convert.py from " + os.path.basename(folder) + "\n")
        w = csv.writer(f)
        w.writerow(["t"] + cols)
        for t in sorted(rows):
            r = rows[t]
            w.writerow([f"{t:.6f}"] + [r.get(c, "") for c in cols])
    return len(rows)


def main(argv):
    data = argv[1] if len(argv) > 1 else "../shared/data/bluerov1_liu2016"
    out = argv[2] if len(argv) > 2 else "out/bluerov1/runs"
    prefixes = argv[3:] or [f"yaw_{i}" for i in range(1, 6)]
    if not os.path.isdir(data):
        raise SystemExit(f"no data folder {data} (see ../shared/data/README.md)")
    for p in prefixes:
        folders = sorted(glob.glob(os.path.join(data, p + "_2016-*")))
        if not folders:
            raise SystemExit(f"{data}: no run named {p}_2016-…")
        for folder in folders:
            path = os.path.join(out, p + ".csv")
            n = convert(folder, path)
            print(f"{path}: {n} rows from {os.path.basename(folder)}")


if __name__ == "__main__":
    main(sys.argv)
