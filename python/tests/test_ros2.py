"""shoal's ROS 2 bridge from the agent's side: `shoal run` with a vehicle group of
`agent = "ros2"` beside a Python process on Eclipse Cyclone DDS (package `shoal_ros2`; the
world's side is ros2-client on RustDDS, crates/shoal-ros2).

* The message types of `shoal_ros2.msgs` are ROS 2's: PyPI's `rosbags` (its own definitions of
  the standard messages, and the `.msg` files of shoal_msgs) writes and reads the same CDR bytes.
* `Ros2Swarm` assembles a tick from topics arriving in any order and answers on the right
  topics (against a stand-in world made of plain Cyclone DDS readers and writers).
* Against `shoal run` in lock-step (2 vehicles, each test on its own namespace and DDS domain):
  the Imu and FluidPressure the agent receives are the run's own trajectories.csv (depth from
  pressure = the depth reading; attitude and rates within the IMU's noise); the vehicles reach
  the depth and heading sent as setpoints; raw Actuators drive the thrusters and tilts, and
  with positions granted `odom` is the true position; a NaN depth and an unknown mode are
  counted as rejections and not applied; an agent killed mid-run (between two ticks, or after
  answering one of the vehicles) leaves both vehicles to the fallback and the run ends cleanly;
  two runs give the same digest; and `python/examples/ros2_school.py` aligns the school of
  worlds/ros2_school.toml with beacons over modem/tx and modem/rx.

DDS stays on the loopback interface on the agents' side (`localhost_dds`).
"""

import csv
import itertools
import json
import math
import os
import signal
import subprocess
import sys
import time
from collections import defaultdict
from pathlib import Path

import numpy as np
import pytest
from rosbags.interfaces import Nodetype
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from conftest import REPO, WORLDS
from shoal_ros2 import (
    LOCALHOST_CONFIG,
    FluidPressure,
    Imu,
    OpticalFrame,
    Ros2Swarm,
    Setpoint,
    Time,
    dds_topic,
    enu,
    msgs,
    qos,
    ros_name,
)
from shoal_ros2.msgs import Header

HERE = Path(__file__).resolve().parent
AGENT = HERE / "ros2_agent.py"
EXAMPLES = REPO / "python" / "examples"
SHOAL_MSGS = REPO / "crates" / "shoal-ros2" / "shoal_msgs" / "msg"

#: The test world's IMU noise (stated in `world` below): attitude [rad] and rates [rad/s],
#: standard deviations per axis.
ATTITUDE_NOISE = math.radians(0.5)
GYRO_NOISE = 0.01
#: Agreement demanded of a noisy reading with the truth: this many standard deviations.
SIGMAS = 6.0
#: Control period of the μAUV² [s].
TICK = 0.05

_serial = itertools.count()


def bus():
    """A namespace and DDS domain of this test's own (from the pid and a counter), so that
    tests and test runs side by side do not hear each other."""
    n = next(_serial)
    pid = os.getpid()
    return f"t{pid}_{n}", 1 + (pid * 7 + n) % 200


def world(namespace, domain, *, duration, fallback="hold", timeout=2.0, seed=5,
          grant_position=False):
    """Two μAUV² at 0.8 m heading north, driven over ROS 2 in lock-step."""
    return f"""
name = "ros2_test"
seed = {seed}
duration = {duration}
dt = 0.01

[pool]
size = [10.0, 10.0, 3.0]

[agents]
timing = "lockstep"
timeout = {timeout}
attach_timeout = 60.0
fallback = "{fallback}"
grant_position = {str(grant_position).lower()}

[ros2]
domain_id = {domain}
namespace = "{namespace}"

[[vehicles]]
name = "auv"
count = 2
grid = {{ origin = [3.0, 4.5, 0.8], spacing = [4.0, 4.0], columns = 2 }}
agent = "ros2"

[vehicles.model.imu]
attitude_noise_deg = {math.degrees(ATTITUDE_NOISE)}
gyro_noise = {GYRO_NOISE}
gyro_bias = [0.0, 0.0, 0.0]
accel_noise = 0.02

[output]
record_hz = 10.0
"""


#: The test world's vehicle names, as trajectories.csv has them (topics: auv_0, auv_1).
VEHICLES = ["auv-0", "auv-1"]


@pytest.fixture(scope="session")
def localhost_dds():
    """DDS kept on this machine for the tests: Cyclone DDS (this process and the agents) on
    the loopback interface, unicast (`LOCALHOST_CONFIG` as CYCLONEDDS_URI), and ROS 2's own
    variables for the world's side."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("CYCLONEDDS_URI", LOCALHOST_CONFIG)
        mp.setenv("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
        mp.setenv("ROS_LOCALHOST_ONLY", "1")
        yield


@pytest.fixture(scope="session")
def ros2_shoal(shoal_bin, tmp_path_factory, localhost_dds):
    """The `shoal` binary, once it is known to bridge a world to ROS 2: it accepts a world
    with `agent = "ros2"` and `[ros2]`, and running it, publishes a first tick that a
    `Ros2Swarm` here receives within 30 s. Else every test that needs it fails saying so (the
    bridge, crates/shoal-ros2, is not in this binary)."""
    tmp = tmp_path_factory.mktemp("ros2probe")
    namespace, domain = bus()
    path = tmp / "w.toml"
    path.write_text(world(namespace, domain, duration=0.2, timeout=5.0))
    p = subprocess.run([str(shoal_bin), "check", str(path)], capture_output=True, text=True,
                       timeout=60)
    if p.returncode != 0:
        pytest.fail(f"{shoal_bin} has no ROS 2 bridge: `shoal check` refuses a world with "
                    f"agent = \"ros2\" and a [ros2] table:\n{p.stdout}{p.stderr}", pytrace=False)
    with Ros2Swarm(namespace, VEHICLES, domain) as swarm:
        sim = subprocess.Popen([str(shoal_bin), "run", str(path), "--quiet", "--no-plots",
                                "--no-replay", "--out", str(tmp / "out")],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            tick = swarm.wait_tick(30.0)
            if tick is not None:
                for v in VEHICLES:
                    swarm.send_setpoint(v, tick.stamp, Setpoint.MODE_KEEP, 0.0, 0.0)
        finally:
            sim.kill()
            _, err = sim.communicate()
    if tick is None:
        pytest.fail(f"{shoal_bin} has no ROS 2 bridge: running a world with agent = \"ros2\" "
                    f"(domain {domain}, namespace {namespace}), it published no imu and pressure "
                    f"of {VEHICLES} within 30 s:\n{err}", pytrace=False)
    return shoal_bin


class Run:
    """A finished run beside the test agent: summary, trajectories by vehicle, the agent's log
    (one dict per tick) and its report in the summary."""

    def __init__(self, out: Path, log: Path):
        self.summary = json.loads((out / "summary.json").read_text())
        self.rows = defaultdict(list)
        with open(out / "trajectories.csv", newline="") as f:
            for r in csv.DictReader(f):
                self.rows[r["vehicle"]].append(r)
        self.ticks = [json.loads(line) for line in log.read_text().splitlines()]
        self.report = next(a for a in self.summary["agents"]["agents"] if a["name"] == "ros2")

    def tick_at(self, t):
        """The agent's logged tick at time `t` [s]."""
        ns = round(t * 1e9)
        hits = [k for k in self.ticks if k["stamp"][0] * 10**9 + k["stamp"][1] == ns]
        assert len(hits) == 1, f"{len(hits)} ticks stamped {t} s"
        return hits[0]


def run_with_agent(shoal, tmp_path, plan, **world_args):
    """Runs the test world with `ros2_agent.py` following `plan` (see there) and returns the
    `Run`."""
    namespace, domain = bus()
    tmp_path.mkdir(parents=True, exist_ok=True)
    path = tmp_path / "world.toml"
    path.write_text(world(namespace, domain, **world_args))
    out, log = tmp_path / "out", tmp_path / "agent.jsonl"
    agent_err = open(tmp_path / "agent.err", "w+")
    agent = subprocess.Popen(
        [sys.executable, str(AGENT), str(log), namespace, str(domain), ",".join(VEHICLES),
         json.dumps(plan)], stdout=subprocess.DEVNULL, stderr=agent_err)
    sim = subprocess.Popen(
        [str(shoal), "run", str(path), "--quiet", "--no-plots", "--no-replay", "--out",
         str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        _, sim_err = sim.communicate(timeout=300)
        agent.wait(timeout=60)
    finally:
        for p in (sim, agent):
            if p.poll() is None:
                p.kill()
                p.wait()
    agent_err.seek(0)
    said = f"world ({sim.returncode}):\n{sim_err}\nagent ({agent.returncode}):\n{agent_err.read()}"
    assert sim.returncode == 0, said
    if not log.exists() or not log.read_text():
        pytest.fail(f"the agent received no complete tick (imu and pressure of both vehicles) "
                    f"on /{namespace} in domain {domain}: does `shoal run` publish them?\n{said}",
                    pytrace=False)
    assert agent.returncode == (-signal.SIGKILL if "die" in plan else 0), said
    run = Run(out, log)
    first = run.ticks[0]["t"]
    assert first == 0.0, (
        f"the agent's first complete tick is at {first} s: the tick at 0 s never had all its "
        f"samples (imu, pressure{', odom' if plan.get('odometry') else ''}) — lost before DDS "
        f"discovery matched, and not published again while the world waited?")
    return run


def wrapped(a):
    """`a` [rad] wrapped to −π … π."""
    return math.atan2(math.sin(a), math.cos(a))


# The messages ------------------------------------------------------------------------------


def typestore():
    """rosbags' ROS 2 (Humble) messages plus shoal_msgs from its .msg files."""
    ts = get_typestore(Stores.ROS2_HUMBLE)
    types = {}
    for f in sorted(SHOAL_MSGS.glob("*.msg")):
        types.update(get_types_from_msg(f.read_text(), f"shoal_msgs/msg/{f.stem}"))
    ts.register(types)
    return ts


INTS = {"int8": (-128, 127), "uint8": (0, 255), "int32": (-2**31, 2**31 - 1),
        "uint32": (0, 2**32 - 1)}


def filled(ts, name, counter):
    """A rosbags message `name` with every field set to a different value."""
    cls = ts.types[name]

    def value(node):
        kind, desc = node
        if kind == Nodetype.NAME:
            return filled(ts, desc, counter)
        if kind == Nodetype.BASE:
            k = next(counter)
            if desc[0] == "string":
                return f"s{k}"
            if desc[0] in INTS:
                lo, hi = INTS[desc[0]]
                return lo + (k * 37 + 1) % (hi - lo + 1)
            assert desc[0] == "float64", desc
            return k + 0.25
        (sub, count) = desc
        n = count if kind == Nodetype.ARRAY else 3
        items = [value(sub) for _ in range(n)]
        if sub[0] == Nodetype.BASE:
            return np.array(items, dtype={"float64": np.float64, "uint8": np.uint8}[sub[1][0]])
        return items

    return cls(**{f: value(node) for f, node in ts.fielddefs[name][1]})


def same(ts, name, ros, ours):
    """Walks rosbags message `ros` of type `name` and asserts `ours` has every field, equal."""
    for f, (kind, desc) in ts.fielddefs[name][1]:
        a, b = getattr(ros, f), getattr(ours, f)
        if kind == Nodetype.NAME:
            same(ts, desc, a, b)
        elif kind == Nodetype.BASE:
            assert a == b, (name, f)
        elif desc[0][0] == Nodetype.NAME:
            assert len(a) == len(b), (name, f)
            for x, y in zip(a, b):
                same(ts, desc[0][1], x, y)
        else:
            assert list(a) == list(b), (name, f)


@pytest.mark.parametrize("name", sorted(msgs.ROS_TYPES))
def test_the_messages_are_ros_2_s(name):
    """Each type: ROS 2's DDS type name; rosbags' CDR of a message with every field set reads
    back field for field and writes back byte for byte, and the other way round."""
    ts = typestore()
    ours = msgs.ROS_TYPES[name]
    package, _, short = name.split("/")
    assert ours.__idl_typename__ == f"{package}::msg::dds_::{short}_"
    ros = filled(ts, name, itertools.count(1))
    data = bytes(ts.serialize_cdr(ros, name))
    got = ours.deserialize(data)
    same(ts, name, ros, got)
    assert got.serialize() == data
    # From ours: plain little-endian CDR (XCDR1) that rosbags reads.
    assert data[:4] == b"\x00\x01\x00\x00"
    same(ts, name, ts.deserialize_cdr(got.serialize(), name), got)


def test_the_shoal_msgs_constants_are_the_msg_files():
    ts = typestore()
    for name, cls in [("shoal_msgs/msg/Setpoint", Setpoint), ("shoal_msgs/msg/OpticalFrame",
                                                               OpticalFrame)]:
        consts = ts.fielddefs[name][0]
        assert consts, name
        for const, _type, value in consts:
            assert getattr(cls, const) == value, (name, const)


def test_ros_frames_convert_back_to_shoal_s():
    """ENU/FLU → NED/FRD as crates/shoal-model/src/frames.rs converts the other way."""
    # Level, heading east (NED yaw π/2): the FLU body is aligned with ENU — the identity.
    q = enu.attitude_from_ned(0.0, 0.0, math.pi / 2)
    assert [q.x, q.y, q.z] == pytest.approx([0, 0, 0], abs=1e-15) and q.w == pytest.approx(1)
    # Heading north: ENU yaw +π/2 (counter-clockwise from east).
    assert enu.euler_from_quaternion(enu.attitude_from_ned(0, 0, 0))[2] == pytest.approx(
        math.pi / 2)
    # Nose up (NED pitch +) is a negative rotation about FLU's y (port).
    assert enu.euler_from_quaternion(enu.attitude_from_ned(0, 0.2, 0))[1] == pytest.approx(-0.2)
    for rpy in [(0.1, -0.2, 3.0), (-0.3, 0.4, -2.5), (0.0, 0.0, -math.pi / 2)]:
        assert enu.attitude_to_ned(enu.attitude_from_ned(*rpy)) == pytest.approx(rpy)
    assert enu.position_to_ned(msgs.Point(x=2.0, y=1.0, z=-3.0)) == (1.0, 2.0, 3.0)
    assert enu.frd(msgs.Vector3(x=0.1, y=0.2, z=0.3)) == (0.1, -0.2, -0.3)
    assert enu.depth_from_pressure(101325.0 + 1025 * 9.81 * 1.5, density=1025) == (
        pytest.approx(1.5, abs=1e-12))
    assert enu.stamp(12.05) == Time(sec=12, nanosec=50_000_000)
    assert enu.seconds(Time(sec=3, nanosec=250_000_000)) == 3.25


# Ros2Swarm against a stand-in world --------------------------------------------------------


def test_a_tick_is_assembled_from_topics_in_any_order_and_answered(localhost_dds):
    """A stand-in world (plain Cyclone DDS endpoints with the bridge's topics and QoS)
    publishes a tick's imu and pressure out of order, one sample last: the tick is complete only
    then; the answers arrive stamped with it on the right vehicle's topics."""
    from cyclonedds.domain import DomainParticipant
    from cyclonedds.pub import DataWriter
    from cyclonedds.sub import DataReader
    from cyclonedds.topic import Topic

    namespace, domain = bus()
    names = ["a-1", "b"]  # a-1: topics under a_1
    dp = DomainParticipant(domain)

    def topic(cls, v, leaf):
        return Topic(dp, dds_topic(namespace, ros_name(v), leaf), cls)

    imu = {v: DataWriter(dp, topic(Imu, v, "imu"), qos=qos.SENSOR_DATA) for v in names}
    pressure = {v: DataWriter(dp, topic(FluidPressure, v, "pressure"), qos=qos.SENSOR_DATA)
                for v in names}
    rx = {v: DataWriter(dp, topic(OpticalFrame, v, "modem/rx"), qos=qos.RECEIVED_FRAMES)
          for v in names}
    setpoints = {v: DataReader(dp, topic(Setpoint, v, "setpoint"), qos=qos.COMMANDS)
                 for v in names}
    tx = {v: DataReader(dp, topic(OpticalFrame, v, "modem/tx"), qos=qos.COMMANDS) for v in names}

    def head(t):
        return Header(stamp=enu.stamp(t), frame_id="x")

    with Ros2Swarm(namespace, names, domain) as swarm:
        deadline = time.monotonic() + 10
        while not all(w.get_matched_subscriptions() for w in [*imu.values(), *rx.values()]):
            assert time.monotonic() < deadline, "no discovery within 10 s"
            time.sleep(0.01)
        t = 1.25
        rx["b"].write(OpticalFrame(stamp=enu.stamp(1.23), sender=0, modem=2, payload=b"hi"))
        pressure["b"].write(FluidPressure(header=head(t), fluid_pressure=enu.pressure_from_depth(
            0.5)))
        imu["b"].write(Imu(header=head(t), orientation=enu.attitude_from_ned(0.0, 0.0, 2.0),
                           angular_velocity=msgs.Vector3(0.1, 0.2, 0.3)))
        assert swarm.wait_tick(0.3) is None, "a tick without a-1 is not complete"
        imu["a-1"].write(Imu(header=head(t), orientation=enu.attitude_from_ned(0.1, 0.2, -1.0)))
        assert swarm.wait_tick(0.3) is None, "a tick without a-1's pressure is not complete"
        pressure["a-1"].write(FluidPressure(header=head(t), fluid_pressure=enu.pressure_from_depth(
            1.5)))
        tick = swarm.wait_tick(5.0)
        assert tick is not None and tick.time == t and tick.stamp == enu.stamp(t)
        a, b = tick.observations["a-1"], tick.observations["b"]
        assert (a.index, b.index) == (0, 1)
        assert (a.depth, b.depth) == (pytest.approx(1.5, abs=1e-12), pytest.approx(0.5, abs=1e-12))
        assert (a.roll, a.pitch, a.yaw) == pytest.approx((0.1, 0.2, -1.0))
        assert b.yaw == pytest.approx(2.0) and b.rates == pytest.approx((0.1, -0.2, -0.3))
        assert [bytes(f.payload) for f in b.frames] == [b"hi"] and a.frames == []
        assert b.position is None
        swarm.send_frame("b", tick.stamp, b"\x01\x02", modem=3, delay=0.01)
        swarm.send_setpoint("b", tick.stamp, Setpoint.MODE_AUTO, 1.0, 0.5, 0.02, frames=1)
        swarm.send_setpoint("a-1", tick.time, Setpoint.MODE_DIVING, 2.0, -0.5)
        # An older stamp is stale once a tick has been returned.
        imu["a-1"].write(Imu(header=head(1.2)))
        pressure["a-1"].write(FluidPressure(header=head(1.2)))
        imu["b"].write(Imu(header=head(1.2)))
        pressure["b"].write(FluidPressure(header=head(1.2)))
        assert swarm.wait_tick(0.3) is None

        def take(reader, n, within=5.0):
            got, deadline = [], time.monotonic() + within
            while len(got) < n and time.monotonic() < deadline:
                got += reader.take(N=10)
                time.sleep(0.01)
            return got

        (sa,), (sb,), (fb,) = take(setpoints["a-1"], 1), take(setpoints["b"], 1), take(tx["b"], 1)
        assert (sa.stamp, sa.mode, sa.depth, sa.heading) == (enu.stamp(t), 2, 2.0, -0.5)
        assert (sb.stamp, sb.mode, sb.depth, sb.heading, sb.surge, sb.frames) == (
            enu.stamp(t), 6, 1.0, 0.5, 0.02, 1)
        assert (fb.stamp, fb.modem, fb.delay, bytes(fb.payload)) == (enu.stamp(t), 3, 0.01,
                                                                     b"\x01\x02")
        assert take(tx["a-1"], 1, within=0.5) == []
        with pytest.raises(KeyError, match="vehicle `c`"):
            swarm.send_setpoint("c", t, 6, 1.0, 0.0)


# Against `shoal run` -----------------------------------------------------------------------

#: Setpoints of the reaching test: [depth m, heading rad] per vehicle.
SETPOINTS = [[1.2, math.pi / 2], [1.4, -2.0]]


def test_observations_are_the_run_s_and_setpoints_are_reached(ros2_shoal, tmp_path):
    duration = 40.0
    run = run_with_agent(ros2_shoal, tmp_path, {"setpoints": SETPOINTS}, duration=duration)
    # Every control tick once, in order, each answered for both vehicles in time.
    stamps = [k["t"] for k in run.ticks]
    assert stamps == pytest.approx([TICK * i for i in range(len(stamps))], abs=1e-9)
    assert len(stamps) >= round(duration / TICK) - 1, len(stamps)
    assert run.report["commands_applied"] == 2 * len(stamps), run.report
    assert sum(run.report["rejections"].values()) == 0, run.report
    turning = 0
    for v, (depth, heading) in zip(VEHICLES, SETPOINTS):
        rows = run.rows[v]
        assert len(rows) == round(duration * 10) + 1
        for row in rows:
            t = float(row["t_s"])
            if t > stamps[-1] + 1e-9:
                continue  # the last row: after the last tick
            o = run.tick_at(t)["obs"][v]
            assert o["frame_id"] == f"{ros_name(v)}/base_link" and o["variance"] == 0.0
            # Pressure: 101325 Pa + ρ g × the depth reading (CSV: 7 significant digits).
            assert o["depth"] == pytest.approx(float(row["depth_reading_m"]), rel=1e-6,
                                               abs=1e-9), (v, t)
            for name, got in [("roll", o["roll"]), ("pitch", o["pitch"]), ("yaw", o["yaw"])]:
                miss = abs(wrapped(got - float(row[f"{name}_rad"])))
                assert miss < SIGMAS * ATTITUDE_NOISE, (v, t, name, miss)
            for name, got in zip(["p", "q", "r"], o["rates"]):
                miss = abs(got - float(row[f"{name}_rad_s"]))
                assert miss < SIGMAS * GYRO_NOISE, (v, t, name, miss)
            # A row where a wrong sign of r would miss by more than twice the tolerance.
            turning += abs(float(row["r_rad_s"])) > SIGMAS * GYRO_NOISE
        # Reached (40 s: the yaw loop is slow): within 5 cm and 2° at the end.
        last = rows[-1]
        assert abs(float(last["depth_reading_m"]) - depth) < 0.05, last
        assert abs(wrapped(float(last["yaw_rad"]) - heading)) < math.radians(2), last
    # The rates compared include turns (a sign error would show).
    assert turning >= 20, turning


def test_raw_actuator_commands_apply_and_odometry_is_the_true_position(ros2_shoal, tmp_path):
    """`Actuators` drive the thrusters and tilts as sent (trajectories.csv's commands and tilt
    angles); with `grant_position` the `odom` position is the run's true position."""
    thrusters, tilts = [12.0, -8.0, 5.0], [0.2, -0.1]
    run = run_with_agent(ros2_shoal, tmp_path, {"actuators": [thrusters, tilts, 0],
                                                "odometry": True},
                         duration=3.0, grant_position=True)
    assert run.report["commands_applied"] == 2 * len(run.ticks), run.report
    assert sum(run.report["rejections"].values()) == 0, run.report
    compared = 0
    for v in VEHICLES:
        rows = run.rows[v]
        for row in rows[1:]:
            t = float(row["t_s"])
            assert [float(row[f"cmd_{n}_pct"]) for n in ("top", "port", "stbd")] == (
                pytest.approx(thrusters)), row
            if t <= run.ticks[-1]["t"] + 1e-9:
                got = run.tick_at(t)["obs"][v]["position"]
                want = [float(row[c]) for c in ("x_m", "y_m", "z_m")]
                assert got == pytest.approx(want, rel=1e-6, abs=1e-6), (v, t)
                compared += 1
        # The tilt drives have turned to the angles sent.
        assert [float(rows[-1][f"tilt_{n}_rad"]) for n in ("alpha", "beta")] == pytest.approx(
            tilts, abs=1e-3), rows[-1]
    assert compared == 2 * 29, compared


def test_a_nan_depth_and_an_unknown_mode_are_rejected_and_not_applied(ros2_shoal, tmp_path):
    plan = {"setpoints": SETPOINTS, "bad": [[0, 1.0, "nan_depth"], [1, 1.5, "bad_mode"]]}
    run = run_with_agent(ros2_shoal, tmp_path, plan, duration=4.0)
    rejected = run.report["rejections"]
    assert (rejected["non_finite"], rejected["invalid"]) == (1, 1), run.report
    assert run.report["commands_applied"] == 2 * len(run.ticks) - 2, run.report
    for v, (depth, heading) in zip(VEHICLES, SETPOINTS):
        for row in run.rows[v]:
            if float(row["t_s"]) >= 0.5:
                assert row["mode"] == "auto", row
                assert float(row["depth_setpoint_m"]) == pytest.approx(depth, abs=1e-6), row
                assert float(row["yaw_setpoint_rad"]) == pytest.approx(heading, abs=1e-6), row


@pytest.mark.parametrize("answered", [2, 1])
def test_a_killed_agent_leaves_its_vehicles_to_the_fallback(ros2_shoal, tmp_path, answered):
    """The agent SIGKILLed at the tick at 2 s, after answering `answered` of the 2 vehicles (2:
    between ticks; 1: in the middle of one): the first tick not answered in full is `hung`
    after `timeout`; from there both vehicles are under the fallback `surface` (depth setpoint
    0) to the end, and the run ends normally."""
    run = run_with_agent(ros2_shoal, tmp_path, {"setpoints": SETPOINTS, "die": [2.0, answered]},
                         duration=5.0, fallback="surface", timeout=1.0)
    s = run.summary
    assert s["simulated_s"] == pytest.approx(5.0) and not s["interrupted"], s
    assert s["agents"]["stopped"] is None, s["agents"]
    assert run.ticks[-1]["t"] == pytest.approx(2.0 - TICK)
    hung = 2.0 + (TICK if answered == 2 else 0.0)
    events = [(e["what"], e["t"]) for e in run.report["events"]]
    assert events == [("attached", 0.0), ("hung", pytest.approx(hung))], events
    # Every tick before 2 s answered, and at 2 s `answered` vehicles; every vehicle-tick after
    # the hung one under the fallback (and those before the first command: the first).
    assert run.report["commands_applied"] == 2 * 40 + answered, run.report
    after = round((5.0 - hung) / TICK) - 1
    assert 2 * after <= run.report["fallback_ticks"] <= 2 * after + 2, run.report
    for v, (depth, _) in zip(VEHICLES, SETPOINTS):
        for row in run.rows[v]:
            t = float(row["t_s"])
            if 0.5 <= t < hung:
                assert float(row["depth_setpoint_m"]) == pytest.approx(depth), row
            elif t > hung:
                assert float(row["depth_setpoint_m"]) == 0.0, row


def test_two_lock_step_runs_give_the_same_digest(ros2_shoal, tmp_path):
    """Commands that depend on every observation (steer by the heading and depth read): two
    runs with the same seed end in the same state, bit for bit."""
    runs = [run_with_agent(ros2_shoal, tmp_path / str(i), {"follow": True}, duration=4.0)
            for i in range(2)]
    for r in runs:
        assert r.report["commands_applied"] == 2 * len(r.ticks) >= 2 * 79, r.report
    assert runs[0].summary["digest"] == runs[1].summary["digest"]
    yaws = [float(r.rows["auv-0"][-1]["yaw_rad"]) for r in runs]
    assert yaws[0] == yaws[1] and abs(wrapped(yaws[0])) > 0.1, "the vehicles turned"


def test_the_ros2_school_example_aligns_the_school(ros2_shoal, tmp_path):
    """python/examples/ros2_school.py on worlds/ros2_school.toml (on a domain and namespace of
    its own): beacons over modem/tx and modem/rx turn 8 scattered vehicles to one heading."""
    namespace, domain = bus()
    text = (WORLDS / "ros2_school.toml").read_text()
    text = text.replace("domain_id = 0", f"domain_id = {domain}")
    text = text.replace('namespace = "shoal"', f'namespace = "{namespace}"')
    path = tmp_path / "school.toml"
    path.write_text(text)
    out = tmp_path / "out"
    agent = subprocess.Popen([sys.executable, str(EXAMPLES / "ros2_school.py"), str(path)],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    sim = subprocess.Popen([str(ros2_shoal), "run", str(path), "--quiet", "--no-plots",
                            "--no-replay", "--out", str(out)], stdout=subprocess.DEVNULL,
                           stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 300
        while sim.poll() is None:
            if agent.poll() not in (None, 0):  # it gave up: the world would wait for it
                sim.kill()
                break
            assert time.monotonic() < deadline, "the run took more than 300 s"
            time.sleep(0.1)
        sim_err = sim.communicate(timeout=60)[1]
        agent_err = agent.communicate(timeout=60)[1]
    finally:
        for p in (sim, agent):
            if p.poll() is None:
                p.kill()
                p.wait()
    assert sim.returncode == 0 and agent.returncode == 0, f"{sim_err}\n{agent_err}"
    assert "answered 1200 ticks" in agent_err, agent_err
    s = json.loads((out / "summary.json").read_text())
    report = next(a for a in s["agents"]["agents"] if a["name"] == "ros2")
    assert report["commands_applied"] == 8 * 1200 and sum(report["rejections"].values()) == 0
    rx = s["comm"]["receptions"]
    assert s["comm"]["frames_sent"] >= 8 * 59 and rx["delivered"] > 0.3 * rx["attempts"], s["comm"]
    yaws = defaultdict(list)
    with open(out / "trajectories.csv", newline="") as f:
        for r in csv.DictReader(f):
            yaws[float(r["t_s"])].append(float(r["yaw_rad"]))

    def spread(t):
        ys = yaws[t]
        assert len(ys) == 8
        mean = math.atan2(sum(map(math.sin, ys)), sum(map(math.cos, ys)))
        return max(abs(wrapped(y - mean)) for y in ys)

    assert math.degrees(spread(0.0)) > 60.0, "the school starts scattered"
    assert math.degrees(spread(60.0)) < 5.0, "and ends aligned within 5°"
