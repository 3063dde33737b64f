#!/usr/bin/env python3
"""The `school` agent over ROS 2 topics: the behaviour of `school.py` (its `Schooling`, shared),
driving the `agent = "ros2"` vehicles of a world through shoal's ROS 2 bridge with the
`shoal_ros2` package on Cyclone DDS — every vehicle beacons its heading and depth once a second
on `modem/tx` and steers to the mean of its own and what it heard on `modem/rx` in the last
3 s, from its `imu` and `pressure` alone.

    cargo run --release -- run worlds/ros2_school.toml            # terminal 1
    python3 python/examples/ros2_school.py worlds/ros2_school.toml  # terminal 2 (in the venv)

Arguments: `[WORLD]` (default worlds/ros2_school.toml: its `[ros2]` domain and namespace and
its vehicle names are used). Exit status 0 after answering the run's ticks until it went
quiet (10 s without a tick), 1 when no tick came within 60 s, 130 on Ctrl-C, 143 on SIGTERM.
"""

import signal
import sys
from pathlib import Path

from school import Schooling

from shoal_ros2 import OpticalFrame, Ros2Swarm, Setpoint, enu

#: The world when none is given.
WORLD = Path(__file__).resolve().parents[2] / "worlds" / "ros2_school.toml"


def drive(swarm: Ros2Swarm, wait: float = 60.0, idle: float = 10.0) -> int:
    """Answers every tick of `swarm`'s vehicles with the school behaviour until no tick comes
    for `idle` [s] (the first within `wait` [s]); returns the number of ticks answered."""
    school = Schooling()
    ticks = 0
    for tick in swarm.ticks(wait, idle):
        for v, o in tick.observations.items():
            frames = ((bytes(f.payload), enu.seconds(f.stamp)) for f in o.frames)
            beacon, (depth, heading, surge) = school.decide(o.index, o.time, o.yaw, o.depth,
                                                            frames)
            if beacon is not None:
                swarm.send_frame(v, tick.stamp, beacon, OpticalFrame.ALL_MODEMS, 0.0)
            swarm.send_setpoint(v, tick.stamp, Setpoint.MODE_AUTO, depth, heading, surge, 0.0,
                                frames=0 if beacon is None else 1)
        ticks += 1
    return ticks


def main(argv) -> int:
    world = Path(argv[0]) if argv else WORLD
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    try:
        with Ros2Swarm.for_world(world) as swarm:
            print(f"ros2_school.py: {len(swarm.vehicles)} vehicles under /{swarm.namespace} on "
                  f"domain {swarm.domain_id}", file=sys.stderr)
            ticks = drive(swarm)
    except KeyboardInterrupt:
        print("ros2_school.py: interrupted", file=sys.stderr)
        return 130
    if ticks == 0:
        print("ros2_school.py: no tick from the world within 60 s", file=sys.stderr)
        return 1
    print(f"ros2_school.py: answered {ticks} ticks; the world went quiet", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
