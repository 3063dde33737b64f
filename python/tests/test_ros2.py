"""shoal's ROS 2 bridge from the agent's side, the package `shoal_ros2` on its own (Eclipse
Cyclone DDS; the world's side is ros2-client on RustDDS, crates/shoal-ros2; against `shoal run`:
test_ros2_run.py).

* The message types of `shoal_ros2.msgs` are ROS 2's: PyPI's `rosbags` (its own definitions of
  the standard messages, and the `.msg` files of shoal_msgs) writes and reads the same CDR bytes.
* `shoal_ros2.enu` converts ROS's ENU/FLU frames back to shoal's NED/FRD, by hand values.
* `Ros2Swarm` assembles a tick from topics arriving in any order and answers on the right
  topics (against a stand-in world made of plain Cyclone DDS readers and writers).

DDS stays on the loopback interface (`localhost_dds`).
"""

import itertools
import math
import time

import numpy as np
import pytest
from rosbags.interfaces import Nodetype
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from conftest import REPO, bus
from shoal_ros2 import (
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

SHOAL_MSGS = REPO / "crates" / "shoal-ros2" / "shoal_msgs" / "msg"


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
