#!/usr/bin/env python3
"""The `goto` agent in Python (the same as `crates/shoal-bridge/examples/goto_agent.rs`): every
vehicle it is given goes to one depth and heading in the controller's auto mode. The smallest
useful agent; `shoal bench --agents python` uses it to measure the lock-step round trip.

    shoal run worlds/agents_goto.toml                                    # terminal 1
    python3 python/examples/goto.py agents_goto pilot 1.5 90             # terminal 2 (in the venv)

Arguments: `PREFIX AGENT DEPTH_M HEADING_DEG [--log]`; with `--log` it prints what its first
vehicle observes once per simulated second on stderr (`goto.py: t = 12.00 s, depth 1.234 m,
yaw 45.0°`, then ` (fallback)` while the world holds the vehicle under its fallback), as the
Rust example does. Exit status 0 when the world ended the run,
1 when it fell silent or could not be reached, 2 on bad arguments, 130 on Ctrl-C.
"""

import math
import sys

from shoal import agent as shoal_agent
from shoal.agent import Agent, flags, mode


class Goto(Agent):
    """Depth [m] and heading [rad] for every vehicle."""

    def __init__(self, depth: float, yaw: float, log: bool = False) -> None:
        self.depth = depth
        self.yaw = yaw
        self.log = log
        self.first = None  # the first vehicle's id (logged)
        self.second = None  # the last simulated second logged

    def tick(self, o, cmd) -> None:
        if self.log:
            if self.first is None:
                self.first = o.vehicle
            if o.vehicle == self.first and self.second != int(o.time):
                self.second = int(o.time)
                fallback = " (fallback)" if o.flags & flags.FALLBACK else ""
                print(
                    f"goto.py: t = {o.time:.2f} s, depth {o.depth:.3f} m, "
                    f"yaw {math.degrees(o.yaw):.1f}°{fallback}",
                    file=sys.stderr,
                    flush=True,
                )
        shoal_agent.set_mode(cmd, mode.AUTO, self.depth, self.yaw, 0.0, 0.0)


def main(argv) -> int:
    args = [a for a in argv if not a.startswith("--")]
    try:
        prefix, name, depth, heading = args[0], args[1], float(args[2]), float(args[3])
    except (IndexError, ValueError):
        print("usage: goto.py PREFIX AGENT DEPTH_M HEADING_DEG [--log]", file=sys.stderr)
        return 2
    if not (math.isfinite(depth) and math.isfinite(heading)):
        print("goto.py: DEPTH_M and HEADING_DEG must be finite numbers", file=sys.stderr)
        return 2
    agent = Goto(depth, math.radians(heading), log="--log" in argv)
    return shoal_agent.main("goto.py", prefix, name, agent)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
