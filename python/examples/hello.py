#!/usr/bin/env python3
"""The smallest agent that talks: every vehicle dives to 1.5 m, heads north-east and says
"hello" once a second, and counts what it hears — the snippet of python/README.md.

    shoal run worlds/agents_school.toml                  # terminal 1: the world waits for `school`
    python/examples/hello.py agents_school school        # terminal 2 (in the venv)

Arguments: `PREFIX AGENT`. Exit status 0 when the world ended the run.
"""

import random
import sys

from shoal.agent import ALL_MODEMS, Agent, main, mode, received, send, set_mode


class Hello(Agent):
    def __init__(self):
        self.rng = random.Random(1)   # seeded: a lock-step run stays reproducible
        self.next = {}                # per vehicle: time of its next "hello" [s]
        self.heard = 0

    def tick(self, obs, cmd):
        # obs: Observation (sensors: depth, roll, pitch, yaw, rates, accel, tilts, frames, …)
        # cmd: Command, pre-set to "keep" for obs.vehicle and obs.step
        for payload, modem, power, t in received(obs):
            self.heard += 1                       # frames heard since the last tick
        set_mode(cmd, mode.AUTO, 1.5, 0.785)      # depth 1.5 m, heading 45°, surge 0 N
        # Once a second, at a random instant: a modem is half-duplex (deaf while it
        # transmits), so vehicles that all send at the same instant never hear each other.
        t_next = self.next.setdefault(obs.vehicle, self.rng.uniform(0.0, 1.0))
        if obs.time >= t_next:
            send(cmd, ALL_MODEMS, b"hello", delay=self.rng.uniform(0.0, 0.05))
            self.next[obs.vehicle] = t_next + self.rng.uniform(0.9, 1.1)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: hello.py PREFIX AGENT")
    hello = Hello()
    status = main("hello.py", sys.argv[1], sys.argv[2], hello)
    print(f"hello.py: heard {hello.heard} frames", file=sys.stderr)
    sys.exit(status)
