"""A test agent for shoal's ROS 2 bridge (run as a process by test_ros2_run.py): drives the
given vehicles with `shoal_ros2.Ros2Swarm` on Cyclone DDS and logs what it observed.

    python ros2_agent.py LOG NAMESPACE DOMAIN_ID VEHICLES PLAN

VEHICLES: names separated by commas. PLAN (JSON):

* ``setpoints``: per vehicle ``[depth m, heading rad]`` — auto mode with these setpoints;
* ``follow``: instead, steer by what is observed (depth + 0.1 m, heading + 0.3 rad): commands
  that depend on every observation, for reproducibility checks;
* ``actuators``: ``[thrusters %, tilts rad, pump]`` — raw commands for every vehicle instead;
* ``odometry``: also read ``odom`` (a world that grants positions) and log the position;
* ``bad``: ``[[vehicle index, time s, "nan_depth" | "bad_mode"], …]`` — at that tick send that
  vehicle a Setpoint with depth NaN, or with mode 42 (no such mode), instead;
* ``frames``: ``[[time s, vehicle index, {"payload": text, "to": name, "ack": bool, "tag": n,
  "modem": i}], …]`` — at that tick send these frames from that vehicle (``send_frame``; all
  but the payload optional: a broadcast on every modem), counted in its command's ``frames``;
* ``die``: ``[time s, n]`` — at the tick at that time, answer the first n ≥ 1 vehicles (with
  setpoints), then die by SIGKILL (nothing closed, nothing said; that tick is not logged);
* ``last``: the time of the run's last control tick [s]: once it is answered and logged, wait
  for the end of standard input (the test closes it when the world has ended, so the answers
  are not lost with the participant), then leave — the end counted in ticks, not waited for;
* ``density``: the world's water density [kg/m³] for depth from pressure (default 1000);
* ``wait``, ``idle``: seconds to wait for the first tick, and for any later one before leaving
  (safety nets for a world that stalls or ends early; 60 s each).

With ``odometry`` a tick waits for every vehicle's ``odom`` (a lock-step world publishes it
with the tick, and again while it waits): ``odom_grace`` is as long as ``idle``.

LOG gets one JSON line per tick (flushed): ``{"t": s, "stamp": [sec, nanosec], "obs": {vehicle:
{...}}}`` with each vehicle's converted observation and the raw pressure, variance and frame
id, and the ``modem/rx`` frames (``rx``) and ``modem/outcome`` events (``outcomes``) that came
with the tick (stamps in ns, payloads in hex); after the last tick and the end of standard
input, one line ``{"end": {vehicle: {"rx": [...], "outcomes": [...]}}}`` with those that came
after the last tick. Exit status 0 after at least one tick, 1 when none came within ``wait``.
"""

import json
import math
import os
import signal
import sys

from shoal_ros2 import OpticalFrame, Ros2Swarm, Setpoint


def ns(stamp) -> int:
    """A `Time` in nanoseconds."""
    return stamp.sec * 10**9 + stamp.nanosec


def frames_log(frames, outcomes) -> dict:
    """Received frames and frame outcomes as JSON."""
    return {
        "rx": [{"stamp": ns(f.stamp), "sender": f.sender, "to": f.to, "seq": f.seq,
                "modem": f.modem, "payload": bytes(f.payload).hex()} for f in frames],
        "outcomes": [{"stamp": ns(e.stamp), "to": e.to, "tag": e.tag, "seq": e.seq,
                      "transmissions": e.transmissions, "acknowledged": e.acknowledged,
                      "sent": ns(e.sent)} for e in outcomes],
    }


def main(log_path, namespace, domain_id, vehicles, plan) -> int:
    names = vehicles.split(",")
    plan = json.loads(plan)
    bad = {(int(i), round(float(t) * 1e9)): what for i, t, what in plan.get("bad", [])}
    to_send = {}
    for t, i, spec in plan.get("frames", []):
        to_send.setdefault((int(i), round(float(t) * 1e9)), []).append(spec)
    die_at, die_after = plan.get("die", [math.inf, 0])
    last = plan.get("last", math.inf)
    idle = plan.get("idle", 60.0)
    ticks = 0
    odometry = bool(plan.get("odometry"))
    with open(log_path, "w") as log, Ros2Swarm(namespace, names, int(domain_id),
                                               odometry=odometry, odom_grace=idle,
                                               density=plan.get("density", 1000.0)) as swarm:
        for tick in swarm.ticks(plan.get("wait", 60.0), idle):
            record = {"t": tick.time, "stamp": [tick.stamp.sec, tick.stamp.nanosec], "obs": {}}
            for v, o in tick.observations.items():
                record["obs"][v] = {
                    "depth": o.depth, "roll": o.roll, "pitch": o.pitch, "yaw": o.yaw,
                    "rates": list(o.rates), "accel": list(o.accel),
                    "pressure": o.pressure.fluid_pressure, "variance": o.pressure.variance,
                    "frame_id": o.imu.header.frame_id,
                    "position": o.position,
                    **frames_log(o.frames, o.outcomes),
                }
                specs = to_send.get((o.index, ns(tick.stamp)), [])
                for f in specs:
                    swarm.send_frame(v, tick.stamp, f["payload"].encode(),
                                     f.get("modem", OpticalFrame.ALL_MODEMS), 0.0, f.get("to"),
                                     f.get("ack", False), f.get("tag", 0))
                if "actuators" in plan:
                    thrusters, tilts, pump = plan["actuators"]
                    swarm.send_actuators(v, tick.stamp, thrusters, tilts, pump, len(specs))
                    continue
                if plan.get("follow"):
                    depth, heading = o.depth + 0.1, o.yaw + 0.3
                else:
                    depth, heading = plan["setpoints"][o.index]
                mode = Setpoint.MODE_AUTO
                what = bad.get((o.index, tick.stamp.sec * 10**9 + tick.stamp.nanosec))
                if what == "nan_depth":
                    depth = math.nan
                elif what == "bad_mode":
                    mode = 42
                swarm.send_setpoint(v, tick.stamp, mode, depth, heading, frames=len(specs))
                if abs(tick.time - die_at) < 1e-6 and o.index + 1 == die_after:
                    os.kill(os.getpid(), signal.SIGKILL)
            log.write(json.dumps(record) + "\n")
            log.flush()
            ticks += 1
            if tick.time >= last - 1e-9:
                sys.stdin.read()
                end = {v: frames_log(swarm.received(v), swarm.outcomes(v)) for v in names}
                log.write(json.dumps({"end": end}) + "\n")
                break
    return 0 if ticks else 1


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
