"""The same world and seed through `shoal.World` and through `shoal run` give the same state
digest — bit-identical runs — whatever the thread counts and however the world is stepped.
A world of 300 beaconing vehicles proves the parallel path ran on 2 threads (the world's
count of loops split over its thread pool)."""

import math

import pytest

import shoal
from conftest import WORLDS, shoal_run


#: 300 beaconing μAUV² at random places in a 14 × 14 m pool: more than the 256 vehicles from
#: which a loop is split over the thread pool, and so dense that more than 256 of them may hear
#: the frames ending in one step, so on 2 threads every kind of loop runs on the pool.
SWARM = """
name = "beaconing swarm"
seed = 2
[pool]
size = [14.0, 14.0, 3.0]
[[vehicles]]
name = "b"
count = 300
random = { min = [0.5, 0.5, 1.0], max = [13.5, 13.5, 2.0], random_heading = true }
behaviour = { kind = "beacon", period = 0.5, payload_bytes = 26, jitter = 0.2 }
"""

#: Loop kinds of `parallel_dispatches`.
LOOPS = ("behaviour", "vehicles", "delivery", "links", "walk")


@pytest.mark.parametrize("name, seed, seconds", [("default", 7, 5.0), ("flock", 3, 4.0),
                                                 ("swarm", 5, 1.0)])
def test_world_and_shoal_run_give_the_same_digest(shoal_bin, tmp_path, name, seed, seconds):
    if name == "swarm":
        world = tmp_path / "swarm.toml"
        world.write_text(SWARM)
    else:
        world = WORLDS / f"{name}.toml"
    summary = shoal_run(shoal_bin, world, tmp_path / "out", "--seed", str(seed),
                        "--duration", str(seconds), "--threads", "1")
    assert summary["seed"] == seed and summary["steps"] == round(seconds / 0.01)
    assert summary["parallel_dispatches"] == dict.fromkeys(LOOPS, 0)
    w = shoal.World(world, seed=seed, threads=2)
    w.run(seconds)
    assert w.digest == summary["digest"]
    if name == "swarm":
        # The 2-thread run took the parallel path in every kind of loop: each step's vehicle
        # pass, each control tick's behaviours (0.05 s), the deliveries of some steps.
        split = w.parallel_dispatches
        assert (split["vehicles"], split["behaviour"]) == (100, 20), split
        assert split["delivery"] > 0, split
    # Stepped one control period at a time (frames collected, arrays read) on one thread.
    w = shoal.World(world, seed=seed, threads=1)
    while w.step_count < summary["steps"]:
        w.step()
        w.observe()
    assert w.digest == summary["digest"]
    assert w.parallel_dispatches == dict.fromkeys(LOOPS, 0)
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
