#!/usr/bin/env python3
"""The `school` agent in Python (the same behaviour as
`crates/shoal-bridge/examples/school_agent.rs`, command for command): every vehicle beacons
its heading and depth once a second on all modems and steers towards the mean of its own and
what it heard in the last 3 s; alone, it stops and turns slowly to find the others. It uses
only sensed data and received frames.

    cargo run --release -- run worlds/agents_school.toml      # terminal 1
    python3 python/examples/school.py agents_school            # terminal 2 (in the venv)

Arguments: `PREFIX [AGENT]` (AGENT defaults to `school`). Exit status 0 when the world ended
the run, 1 when it fell silent or could not be reached, 130 on Ctrl-C.
"""

import math
import struct
import sys

from shoal import agent as shoal_agent
from shoal.agent import ALL_MODEMS, Agent, mode

#: Frame tag of a school beacon.
TAG = 0x5C
#: A beacon: tag, heading [rad] and depth [m] as little-endian float32 (9 bytes).
BEACON = struct.Struct("<Bff")


class Schooling:
    """The school behaviour without a transport (shared with `ros2_school.py`): state per
    vehicle, so one instance drives the whole group."""

    def __init__(self) -> None:
        #: Per vehicle: (sender-less) beacons heard as (time, heading, depth).
        self.heard = {}
        #: Per vehicle: time of its next beacon.
        self.next = {}

    def decide(self, vehicle, time, yaw, depth, frames):
        """One tick of vehicle `vehicle` (its id: staggers the beacons) at `time` [s] with
        heading `yaw` [rad] and `depth` [m], having received `frames` ((payload, end of
        reception [s]) in order of arrival). Returns (beacon payload to send on all modems now,
        or None; auto-mode depth [m], heading [rad] and surge [N] setpoints)."""
        heard = self.heard.setdefault(vehicle, [])
        for payload, t in frames:
            if len(payload) == BEACON.size and payload[0] == TAG:
                _, h, d = BEACON.unpack(payload)  # float32 → float, exactly as in Rust
                heard.append((t, h, d))
        heard[:] = [b for b in heard if time - b[0] < 3.0]
        # Beacon once a second, staggered by vehicle id.
        beacon = None
        nxt = self.next.setdefault(vehicle, 0.1 * float(vehicle % 10))
        if time + 1e-9 >= nxt:
            # struct rounds to the nearest float32, as Rust's `as f32`.
            beacon = BEACON.pack(TAG, yaw, depth)
            self.next[vehicle] = nxt + 1.0
        if not heard:
            return beacon, (depth, yaw + 0.4, 0.0)
        # Summed in the same order as in Rust, so the result is bit-identical.
        x, y, d = math.cos(yaw), math.sin(yaw), depth
        for _, h, dd in heard:
            x += math.cos(h)
            y += math.sin(h)
            d += dd
        return beacon, (d / float(len(heard) + 1), math.atan2(y, x), 0.03)


class School(Agent):
    """The school behaviour over shared memory."""

    def __init__(self) -> None:
        self.school = Schooling()

    def tick(self, o, cmd) -> None:
        frames = ((payload, t) for payload, _modem, _power, t in shoal_agent.received(o))
        beacon, (depth, heading, surge) = self.school.decide(o.vehicle, o.time, o.yaw, o.depth,
                                                            frames)
        if beacon is not None:
            shoal_agent.send(cmd, ALL_MODEMS, beacon, 0.0)
        shoal_agent.set_mode(cmd, mode.AUTO, depth, heading, surge, 0.0)


def main(argv) -> int:
    args = [a for a in argv if not a.startswith("--")]
    if not args:
        print("usage: school.py PREFIX [AGENT]", file=sys.stderr)
        return 2
    prefix = args[0]
    name = args[1] if len(args) > 1 else "school"
    return shoal_agent.main("school.py", prefix, name, School())


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
