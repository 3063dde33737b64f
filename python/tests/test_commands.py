"""Bad commands raise `shoal.CommandError` (a ValueError) naming the vehicle, the field and
what is allowed — and change nothing: NaN and infinity are never simulated."""

import math

import numpy as np
import pytest

import shoal

FOUR = """
seed = 2
[pool]
size = [10.0, 10.0, 3.0]
[[vehicles]]
name = "v"
count = 4
grid = { origin = [2.0, 5.0, 0.5], spacing = [2.0, 0.0], columns = 4 }
"""


@pytest.fixture()
def world():
    return shoal.World(FOUR, threads=1)


def test_nan_is_refused_with_vehicle_and_field_and_nothing_changes(world):
    before = world.setpoint
    depth = np.array([1.0, 1.0, np.nan, 1.0])
    with pytest.raises(shoal.CommandError) as e:
        world.step({"depth": depth, "yaw": 0.0})
    err = e.value
    assert (err.vehicle, err.name, err.field) == (2, "v-2", "depth")
    assert "vehicle 2 (`v-2`), depth: NaN is not a number: allowed 0 … 3 m" in str(err)
    np.testing.assert_array_equal(world.setpoint, before)
    np.testing.assert_array_equal(world.mode, [0, 0, 0, 0])
    assert world.step_count == 0, "a refused command does not step"
    for bad in ({"surge": [0, 0, 0, math.inf]}, {"yaw": np.full(4, np.nan)}):
        with pytest.raises(shoal.CommandError, match="not a number"):
            world.step(bad)
    with pytest.raises(shoal.CommandError) as e:
        world.set_actuators(thrusters=[[0, 0, 0]] * 3 + [[0, np.nan, 0]])
    assert (e.value.vehicle, e.value.field) == (3, "thrusters[1]")
    with pytest.raises(shoal.CommandError, match="delay"):
        world.send(0, b"x", delay=np.nan)


def test_values_out_of_range_name_the_range_unless_clipped(world):
    with pytest.raises(shoal.CommandError, match=r"vehicle 0 \(`v-0`\), depth: 4 m is outside the allowed 0 … 3 m"):
        world.set_setpoints(depth=4.0)
    f = world.limits["force_max"][1]
    with pytest.raises(shoal.CommandError, match=r"vehicle 1 .*surge.*outside the allowed"):
        world.set_setpoints(surge=[0.0, 2 * f, 0.0, 0.0])
    world.set_setpoints(depth=4.0, surge=[0.0, 2 * f, 0.0, 0.0], clip=True)
    np.testing.assert_array_equal(world.setpoint[:, 0], 3.0)
    assert world.setpoint[1, 2] == f
    with pytest.raises(shoal.CommandError, match=r"thrusters\[2\]: 150 % is outside the allowed -100 … 100 %"):
        world.set_actuators(thrusters=[0.0, 0.0, 150.0])
    with pytest.raises(shoal.CommandError, match=r"tilts\[0\].*rad"):
        world.set_actuators(tilts=[3.0, 0.0])
    with pytest.raises(shoal.CommandError, match="pump"):
        world.set_actuators(pump=2)
    with pytest.raises(shoal.CommandError, match=r"payload of 100 bytes: allowed 1 … 58"):
        world.send([1], [bytes(100)])
    with pytest.raises(shoal.CommandError, match=r"modem 5 does not exist"):
        world.send(1, b"x", modem=5)
    with pytest.raises(shoal.CommandError, match=r"delay 2 s is outside"):
        world.send(1, b"x", delay=2.0)


def test_malformed_commands_say_what_is_expected(world):
    with pytest.raises(shoal.CommandError, match="3 values for 4 vehicles"):
        world.set_setpoints(depth=[1.0, 1.0, 1.0])
    with pytest.raises(shoal.CommandError, match=r"expected an array of shape \(4, 3\)"):
        world.set_actuators(thrusters=np.zeros((4, 2)))
    with pytest.raises(shoal.CommandError, match="unknown key `dpeth`"):
        world.step({"dpeth": 1.0})
    with pytest.raises(shoal.CommandError, match="setpoints and raw actuator commands at once"):
        world.step({"depth": 1.0, "thrusters": [0, 0, 0]})
    with pytest.raises(shoal.CommandError, match="`hover` is not a mode"):
        world.step({"mode": "hover"})
    with pytest.raises(shoal.CommandError, match="integers"):
        world.set_setpoints(mode=np.array([1.0, 5.0, 5.0, 5.0]))
    with pytest.raises(shoal.CommandError, match="code 6 is not a mode"):
        world.set_setpoints(mode=6)
    with pytest.raises(shoal.CommandError, match="vehicle 4 does not exist"):
        world.set_setpoints(depth=1.0, vehicles=[4])
    with pytest.raises(shoal.CommandError, match="given twice"):
        world.set_setpoints(depth=1.0, vehicles=[1, 1])
    with pytest.raises(shoal.CommandError, match="booleans"):
        world.set_setpoints(depth=1.0, vehicles=np.array([True, False, True, False]))
    with pytest.raises(shoal.CommandError, match="ids are ≥ 0"):
        world.set_setpoints(depth=1.0, vehicles=-1)
    with pytest.raises(shoal.CommandError, match="2 payloads for 3 frames"):
        world.send([0, 1, 2], [b"a", b"b"])
    with pytest.raises(ValueError, match="not a quantity"):
        world.read("speed")
    assert world.step_count == 0
    np.testing.assert_array_equal(world.mode, [0, 0, 0, 0])
