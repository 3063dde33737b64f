"""shoal's ROS 2 bridge from the agent's side, the package `shoal_ros2` on its own (Eclipse
Cyclone DDS; the world's side is ros2-client on RustDDS, crates/shoal-ros2; against `shoal run`:
test_ros2_run.py).

* The message types of `shoal_ros2.msgs` are ROS 2's: PyPI's `rosbags` (its own definitions of
  the standard messages, and the `.msg` files of shoal_msgs) writes and reads the same CDR bytes.
* `shoal_ros2.enu` converts ROS's ENU/FLU frames back to shoal's NED/FRD, by hand values.
* `Ros2Swarm` assembles a tick from topics arriving in any order and answers on the right
  topics, against a stand-in world made of plain Cyclone DDS readers and writers in this
  process: a tick lacking a vehicle, or a vehicle's pressure, is seen incomplete (an older tick
  written after it is the one returned), a stale stamp makes no tick, each answer goes
  once to its own vehicle's topics (the next sample on each is one sent after it), frames
  received and the outcomes of acknowledged ones come with the tick, and a unicast goes out
  with its destination's ROS name, `ack` and `tag`.

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
    FrameOutcome,
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
            if desc[0] == "bool":
                return k % 2 == 1
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
    then (seen by the ticks returned before it, not by waiting); the received frames and
    frame outcomes written before it come with it, on the right vehicle; the answers arrive
    stamped with it on the right vehicle's topics (a unicast with its destination's ROS name,
    `ack` and `tag`); its samples again, and older ones, make no tick."""
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
    outcome = {v: DataWriter(dp, topic(FrameOutcome, v, "modem/outcome"),
                             qos=qos.RECEIVED_FRAMES) for v in names}
    setpoints = {v: DataReader(dp, topic(Setpoint, v, "setpoint"), qos=qos.COMMANDS)
                 for v in names}
    tx = {v: DataReader(dp, topic(OpticalFrame, v, "modem/tx"), qos=qos.COMMANDS) for v in names}
    # The stand-in's own reader of b's pressure, beside the swarm's.
    witness = DataReader(dp, topic(FluidPressure, "b", "pressure"), qos=qos.SENSOR_DATA)

    def head(t):
        return Header(stamp=enu.stamp(t), frame_id="x")

    def sensors(v, t, depth=0.0, rpy=(0.0, 0.0, 0.0), rates=(0.0, 0.0, 0.0), order="ip"):
        """Vehicle `v`'s imu (i) and pressure (p) stamped `t`, in `order`."""
        for what in order:
            if what == "i":
                imu[v].write(Imu(header=head(t), orientation=enu.attitude_from_ned(*rpy),
                                 angular_velocity=msgs.Vector3(*rates)))
            else:
                pressure[v].write(FluidPressure(header=head(t),
                                                fluid_pressure=enu.pressure_from_depth(depth)))

    def complete(t):
        """Every vehicle's samples stamped `t` (depth `t` m); the tick the swarm returns next."""
        for v in names:
            sensors(v, t, depth=t)
        got = swarm.wait_tick(60.0)  # returns once complete: a safety net, not a claim
        assert got is not None, f"the tick at {t} s never completed"
        return got

    with Ros2Swarm(namespace, names, domain) as swarm:
        deadline = time.monotonic() + 60  # a safety net, not a claim
        while not all(w.get_matched_subscriptions()
                      for w in [*imu.values(), *pressure.values(), *rx.values(),
                                *outcome.values()]):
            assert time.monotonic() < deadline, "no discovery within 60 s"
            time.sleep(0.01)
        t = 1.25
        sensors("b", t, depth=0.5, rpy=(0.0, 0.0, 2.0), rates=(0.1, 0.2, 0.3), order="pi")
        # Each writer's samples arrive in the order written (or not at all): once a tick written
        # after b's samples is complete, b's samples of t have arrived. The swarm returns the
        # newest complete tick: it returns the older one, so t was not complete.
        got = complete(1.15)
        assert got.time == 1.15, "a tick without a-1 is not complete"
        assert got.observations["b"].depth == pytest.approx(1.15), "and t's b is not in it"
        sensors("a-1", t, rpy=(0.1, 0.2, -1.0), order="i")
        assert complete(1.2).time == 1.2, "a tick without a-1's pressure is not complete"
        rx["b"].write(OpticalFrame(stamp=enu.stamp(1.23), sender="a_1", to="b", seq=5, modem=2,
                                   payload=b"hi"))
        ended = FrameOutcome(stamp=enu.stamp(1.24), to="b", tag=7, seq=5, transmissions=2,
                             acknowledged=True, sent=enu.stamp(1.2))
        outcome["a-1"].write(ended)
        sensors("a-1", t, depth=1.5, order="p")
        tick = swarm.wait_tick(60.0)
        assert tick is not None and tick.time == t and tick.stamp == enu.stamp(t)
        a, b = tick.observations["a-1"], tick.observations["b"]
        assert (a.index, b.index) == (0, 1)
        assert (a.depth, b.depth) == (pytest.approx(1.5, abs=1e-12), pytest.approx(0.5, abs=1e-12))
        assert (a.roll, a.pitch, a.yaw) == pytest.approx((0.1, 0.2, -1.0))
        assert b.yaw == pytest.approx(2.0) and b.rates == pytest.approx((0.1, -0.2, -0.3))
        # Written before the tick's last sample (reliable writers of this process: delivered
        # within write()), they are the tick's, on their own vehicle only.
        assert [(bytes(f.payload), f.sender, f.to, f.seq) for f in b.frames] == [
            (b"hi", "a_1", "b", 5)] and a.frames == []
        assert a.outcomes == [ended] and b.outcomes == []
        assert b.position is None
        swarm.send_frame("b", tick.stamp, b"\x01\x02", modem=3, delay=0.01)
        swarm.send_frame("b", tick.stamp, b"u", to="a-1", ack=True, tag=2**32 - 1)
        swarm.send_setpoint("b", tick.stamp, Setpoint.MODE_AUTO, 1.0, 0.5, 0.02, frames=2)
        swarm.send_setpoint("a-1", tick.time, Setpoint.MODE_DIVING, 2.0, -0.5)
        # Once t has been returned, its samples again (as a world republishes a tick it waits
        # for) and older ones are stale: they make no tick. Cyclone DDS delivers to the readers
        # of this process within write() — the witness has them as soon as it returns — so a
        # poll right after sees them in the swarm's readers too.
        witness.take(N=100)
        for s in (t, 1.2):
            for v in names:
                sensors(v, s)
        assert [enu.seconds(s.header.stamp) for s in witness.take(N=100)] == [t, 1.2]
        assert swarm.wait_tick(0.0) is None, "a stale stamp made a tick"
        assert complete(1.3).time == 1.3, "and the next tick is the one after t"

        def take(reader, n, within=60.0):  # returns once n have come: a safety net
            got, deadline = [], time.monotonic() + within
            while len(got) < n and time.monotonic() < deadline:
                got += reader.take(N=10)
                time.sleep(0.01)
            return got

        # Each answer once, on its vehicle's topics only: after it, the next sample on each
        # topic is one sent now (a reliable writer's samples arrive in the order written).
        for v in names:
            swarm.send_frame(v, 1.3, b"now")
            swarm.send_setpoint(v, 1.3, Setpoint.MODE_KEEP, 0.0, 0.0)
        (sa, na), (sb, nb) = take(setpoints["a-1"], 2), take(setpoints["b"], 2)
        assert (sa.stamp, sa.mode, sa.depth, sa.heading) == (enu.stamp(t), 2, 2.0, -0.5)
        assert (sb.stamp, sb.mode, sb.depth, sb.heading, sb.surge, sb.frames) == (
            enu.stamp(t), 6, 1.0, 0.5, 0.02, 2)
        assert na.stamp == nb.stamp == enu.stamp(1.3)
        (fb, ub, nfb) = take(tx["b"], 3)
        assert (fb.stamp, fb.modem, fb.delay, bytes(fb.payload)) == (enu.stamp(t), 3, 0.01,
                                                                     b"\x01\x02")
        assert (fb.to, fb.ack, fb.tag) == ("", False, 0), "a broadcast"
        # A unicast names its destination as its topics do (a-1: a_1).
        assert (ub.stamp, ub.modem, ub.to, ub.ack, ub.tag, bytes(ub.payload)) == (
            enu.stamp(t), OpticalFrame.ALL_MODEMS, "a_1", True, 2**32 - 1, b"u")
        assert bytes(nfb.payload) == b"now"
        assert [bytes(f.payload) for f in take(tx["a-1"], 1)] == [b"now"]
        with pytest.raises(KeyError, match="vehicle `c`"):
            swarm.send_setpoint("c", t, 6, 1.0, 0.0)
