"""The same world and seed through `shoal.World` and through `shoal run` give the same state
digest — bit-identical runs — whatever the thread counts and however the world is stepped."""

import math

import pytest

import shoal
from conftest import WORLDS, shoal_run


@pytest.mark.parametrize("name, seed, seconds", [("default", 7, 5.0), ("flock", 3, 4.0)])
def test_world_and_shoal_run_give_the_same_digest(shoal_bin, tmp_path, name, seed, seconds):
    world = WORLDS / f"{name}.toml"
    summary = shoal_run(shoal_bin, world, tmp_path / "out", "--seed", str(seed),
                        "--duration", str(seconds), "--threads", "1")
    assert summary["seed"] == seed and summary["steps"] == round(seconds / 0.01)
    w = shoal.World(world, seed=seed, threads=2)
    w.run(seconds)
    assert w.digest == summary["digest"]
    # Stepped one control period at a time (frames collected, arrays read) on one thread.
    w = shoal.World(world, seed=seed, threads=1)
    while w.step_count < summary["steps"]:
        w.step()
        w.observe()
    assert w.digest == summary["digest"]
    # A reset replays it exactly.
    w.reset(seed)
    w.run(seconds)
    assert w.digest == summary["digest"]


#: Four μAUV² whose mission sets auto mode, then (at 2 s) a new heading and surge.
MISSION = """
seed = 9
[pool]
size = [10.0, 10.0, 3.0]
[[vehicles]]
name = "m"
count = 4
grid = { origin = [2.0, 2.0, 1.0], spacing = [2.0, 2.0], columns = 2 }
mission = [{ t = 0, mode = "auto", depth = 1.3, yaw_deg = 45 },
           { t = 2, surge = 0.02, yaw_deg = -60 }]
"""


def test_commands_equal_to_the_mission_leave_the_run_unchanged():
    alone = shoal.World(MISSION, threads=1)
    alone.run(4.0)
    w = shoal.World(MISSION, threads=1)
    for _ in range(80):
        late = w.time >= 2.0
        w.step({"mode": "auto", "depth": 1.3, "yaw": math.radians(-60 if late else 45),
                "surge": 0.02 if late else 0.0})
    assert w.time == alone.time and w.digest == alone.digest
