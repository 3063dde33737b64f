#!/usr/bin/env python3
"""What stepping a world from Python costs, next to `shoal run` on the same world.

1. A swarm of N μAUV² (default 10,000) on a 0.6 m grid in auto mode (the world of `shoal
   bench`: depth 1.3 m and heading 45°, at 2 s heading −60° with 0.02 N surge), run for
   SECONDS of simulated time three ways, in this one process run:
   - `shoal run` (the binary, `--no-plots --no-replay`, trajectories at 1 Hz): its own
     stepping wall time (summary.json `wall_s`);
   - `World.run(seconds)`: the same steps in one call (Rust only);
   - `World.step(commands)` once per control period, with numpy arrays for all vehicles:
     the mission's setpoints sent again every tick (so the run stays the same — the three
     digests must agree) and the positions, IMU headings and depth readings read back.
2. One vehicle: the cost of a `World.step(commands)` call against the same control period
   stepped inside Rust (`World.run`), i.e. the Python overhead per step (CPU time of the
   calling thread, which also does the stepping on a one-thread world).

    python/bench/step_overhead.py [--vehicles N] [--seconds S] [--threads T] [--repeat R]
                                  [--shoal PATH]

PATH defaults to the release binary of this checkout (`cargo build --release` first).
Each kind is measured in R interleaved rounds (3) and the least time counts, which keeps a
busy machine from favouring one kind. Wall time and CPU time are given: on a machine shared
with other work CPU time is the steadier measure (for `shoal run`: the CPU time of the whole
process minus that of a 1 s run, so loading, building and the final outputs cancel out).
"""

import argparse
import json
import math
import os
import resource
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

import shoal

REPO = Path(__file__).resolve().parents[2]


def swarm(n, spacing=0.6):
    """The world text of `shoal bench`'s quiet swarm of `n` (shoal_sim::bench::swarm_text)."""
    columns = max(1, math.ceil(math.sqrt(n)))
    rows = -(-n // columns)
    lx, ly = columns * spacing + 2.0, rows * spacing + 2.0
    return (f'name = "bench swarm of {n}"\nseed = 1\nduration = 3600\ndt = 0.01\n'
            f"[pool]\nsize = [{lx}, {ly}, 3.0]\n"
            f'[[vehicles]]\nname = "b"\ncount = {n}\n'
            f"grid = {{ origin = [1.0, 1.0, 1.0], spacing = [{spacing}, {spacing}], columns = {columns} }}\n"
            'mission = [{ t = 0, mode = "auto", depth = 1.3, yaw_deg = 45 }, '
            "{ t = 2, surge = 0.02, yaw_deg = -60 }]\n"
            "[output]\nplots = false\nrecord_hz = 1.0\n")


def clocks():
    """Wall time, CPU time of this process (all its threads) and of its finished children [s]."""
    ch = resource.getrusage(resource.RUSAGE_CHILDREN)
    return np.array([time.perf_counter(), time.process_time(), ch.ru_utime + ch.ru_stime])


def by_commands(world, seconds):
    """Steps `world` one control period at a time with the mission's setpoints as numpy
    arrays, reading observations back; returns the wall and CPU time [s]."""
    n = len(world)
    depth = np.full(n, 1.3)
    yaw_0, yaw_2 = np.full(n, math.radians(45)), np.full(n, math.radians(-60))
    surge_0, surge_2 = np.zeros(n), np.full(n, 0.02)
    ticks = round(seconds / world.control_dt)
    start = clocks()
    for _ in range(ticks):
        late = world.time >= 2.0 - 1e-9
        world.step({"mode": "auto", "depth": depth, "yaw": yaw_2 if late else yaw_0,
                    "surge": surge_2 if late else surge_0})
        world.position, world.imu_euler, world.depth_reading
    return (clocks() - start)[:2]


def shoal_run(exe, world_file, out, seconds, threads):
    """`shoal run` of `seconds`: its summary and the CPU time of the whole process [s]."""
    start = clocks()
    subprocess.run([str(exe), "run", str(world_file), "--quiet", "--no-plots", "--no-replay",
                    "--duration", str(seconds), "--threads", str(threads), "--out", str(out)],
                   check=True, capture_output=True)
    return json.loads((out / "summary.json").read_text()), (clocks() - start)[2]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--vehicles", type=int, default=10_000)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--threads", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--repeat", type=int, default=3, help="interleaved rounds")
    ap.add_argument("--shoal", type=Path, default=REPO / "target" / "release" / "shoal")
    args = ap.parse_args()
    n, secs, th = args.vehicles, args.seconds, args.threads
    text = swarm(n)
    steps = round(secs / 0.01)
    kinds = ("shoal run", "World.run", "World.step + numpy")
    wall = {k: [] for k in kinds}
    cpu = {k: [] for k in kinds}
    digests = {}
    with tempfile.TemporaryDirectory() as tmp:
        world_file = Path(tmp) / "swarm.toml"
        world_file.write_text(text)
        w = shoal.World(text, threads=th)
        # Interleaved rounds, the least time of each kind: a busy machine slows single runs.
        for _ in range(args.repeat):
            summary, cpu_long = shoal_run(args.shoal, world_file, Path(tmp) / "a", secs, th)
            # Its stepping CPU time: the run minus a 1 s run (loading, building and the
            # end-of-run outputs cost both the same), scaled to `secs`.
            _, cpu_short = shoal_run(args.shoal, world_file, Path(tmp) / "b", 1.0, th)
            wall["shoal run"].append(summary["wall_s"])
            cpu["shoal run"].append((cpu_long - cpu_short) * secs / (secs - 1.0))
            digests["shoal run"] = summary["digest"]
            w.reset()
            start = clocks()
            w.run(secs)
            took = clocks() - start
            wall["World.run"].append(took[0])
            cpu["World.run"].append(took[1])
            digests["World.run"] = w.digest
            w.reset()
            took = by_commands(w, secs)
            wall["World.step + numpy"].append(took[0])
            cpu["World.step + numpy"].append(took[1])
            digests["World.step + numpy"] = w.digest
    print(f"{n} vehicles, {secs:g} s simulated ({steps} steps, {round(secs / 0.05)} control "
          f"periods), {th} thread(s), least of {args.repeat} interleaved rounds "
          f"(M = million vehicle-steps):")
    for k in kinds:
        print(f"  {k:20s} wall {min(wall[k]):6.2f} s ({n * steps / min(wall[k]) / 1e6:5.2f} M/s, "
              f"×{min(wall[k]) / min(wall['shoal run']):.3f})   CPU {min(cpu[k]):6.2f} s "
              f"({n * steps / min(cpu[k]) / 1e6:5.2f} M per CPU-s, "
              f"×{min(cpu[k]) / min(cpu['shoal run']):.3f} of shoal run, "
              f"×{min(cpu[k]) / min(cpu['World.run']):.3f} of World.run)   digest {digests[k]}")
    print("  all rounds, wall [s]: " + "; ".join(
        f"{k}: {', '.join(f'{x:.2f}' for x in wall[k])}" for k in kinds))
    assert len(set(digests.values())) == 1, "the three runs differ"

    one = shoal.World(swarm(1), threads=1)
    cmd = {"mode": "auto", "depth": 1.3, "yaw": 0.5, "surge": 0.02}
    ticks = 20_000

    def per_call(f):
        """Least CPU time of this thread (which also steps the one-thread world) per call of
        `f` over 5 rounds of `ticks` calls [s]."""
        best = math.inf
        for _ in range(5):
            one.reset()
            t = time.thread_time()
            f()
            best = min(best, (time.thread_time() - t) / ticks)
        return best

    rust = per_call(lambda: one.run(ticks * one.control_dt))
    with_cmd = per_call(lambda: [one.step(cmd) for _ in range(ticks)])
    bare = per_call(lambda: [one.step() for _ in range(ticks)])
    no_step = per_call(lambda: [one.step(cmd, steps=0) for _ in range(ticks)])
    print(f"1 vehicle, one control period ({one.tick_steps} steps): in Rust {rust * 1e6:.1f} µs; "
          f"World.step(commands) {with_cmd * 1e6:.1f} µs (+{(with_cmd - rust) * 1e6:.1f} µs), "
          f"World.step() {bare * 1e6:.1f} µs (+{(bare - rust) * 1e6:.1f} µs); "
          f"World.step(commands, steps=0) — the call and the commands alone — {no_step * 1e6:.1f} µs")


if __name__ == "__main__":
    main()
