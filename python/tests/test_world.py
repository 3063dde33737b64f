"""`shoal.World` on shipped worlds and small worlds in TOML text: array shapes, types and
units, stepping, setpoints and raw actuators that move the vehicles as the physics says,
frames actually delivered between vehicles (and lost to half-duplex when modems start
together), reset and seeds."""

import math

import numpy as np
import pytest

import shoal
from conftest import WORLDS

#: Two μAUV² 1.25 m apart facing each other, one front modem each (the preset's).
PAIR = """
seed = 5
[pool]
size = [10.0, 6.0, 3.0]
[[vehicles]]
name = "a"
position = [4.0, 3.0, 1.5]
[[vehicles]]
name = "b"
position = [5.25, 3.0, 1.5]
heading_deg = 180
"""

#: Three μAUV² floating at 0.5 m, no mission.
THREE = """
seed = 2
[pool]
size = [10.0, 10.0, 3.0]
[[vehicles]]
name = "v"
count = 3
grid = { origin = [2.0, 5.0, 0.5], spacing = [3.0, 0.0], columns = 3 }
"""


@pytest.fixture(scope="module")
def default_world():
    return shoal.World(WORLDS / "default.toml", threads=1)


def test_every_quantity_has_its_shape_type_and_units(default_world):
    w = default_world
    n = len(w)
    assert n == w.n == 12 and w.names[:2] == ["west-0", "west-1"]
    assert w.tick_steps == 5 and w.dt == 0.01 and math.isclose(w.control_dt, 0.05)
    obs = w.observe()
    assert list(obs) == shoal.QUANTITIES
    widths = {"position": 3, "attitude": 4, "euler": 3, "velocity": 6, "world_velocity": 3,
              "imu_euler": 3, "gyro": 3, "accel": 3, "tilt_reading": 2, "thrust": 3,
              "tilt_angle": 2, "thruster_command": 3, "setpoint": 4, "modem_queued": 4,
              "frames_lost": 4}
    for name, a in obs.items():
        assert isinstance(a, np.ndarray) and a.flags.c_contiguous, name
        assert a.shape == ((n, widths[name]) if name in widths else (n,)), name
        kind = {"tank_full": "b", "touching": "b", "mode": "i", "modem_queued": "i",
                "frames_sent": "i", "frames_received": "i", "frames_lost": "i"}.get(name, "f")
        assert a.dtype.kind == kind, name
        np.testing.assert_array_equal(a, w.read(name))
        np.testing.assert_array_equal(a, getattr(w, name))
    # The grid of the world file, in metres, depth positive down; unit quaternions.
    np.testing.assert_allclose(obs["position"][:4], [[0.5, 2.2, 0.6], [1.1, 2.2, 0.6],
                                                      [1.7, 2.2, 0.6], [2.3, 2.2, 0.6]])
    np.testing.assert_allclose(np.linalg.norm(obs["attitude"], axis=1), 1.0)
    # The pressure sensor sits 0.091 m above the body origin, reads with 1.8 mm steps.
    np.testing.assert_allclose(obs["depth_reading"], obs["position"][:, 2] - 0.091, atol=0.005)
    assert w.pool_size == (8.0, 6.0, 2.0)
    lim = w.limits
    assert lim["depth_max"] == 2.0 and lim["force_max"].shape == (n,)
    assert (lim["payload_max"] == 58).all() and lim["has_tank"].all()
    np.testing.assert_array_equal(w.actuator_counts, np.tile([3, 2, 4], (n, 1)))


def test_stepping_advances_time_and_frames_are_delivered_between_vehicles():
    w = shoal.World(WORLDS / "default.toml", threads=1)
    w.run(5.0)
    assert w.step_count == 500 and math.isclose(w.time, 5.0)
    assert len(w.received["t"]) == 0, "run() keeps no frames"
    before = w.frames_received.copy()
    got = 0
    for _ in range(40):  # 2 s: each vehicle beacons twice a second
        t0 = w.time
        w.step()
        rx = w.received
        got += len(rx["t"])
        np.testing.assert_array_equal(np.bincount(rx["vehicle"], minlength=len(w)), w.received_count)
        assert (rx["vehicle"] != rx["sender"]).all()
        assert ((rx["t"] > t0) & (rx["t"] <= w.time + 1e-9)).all()
        assert (rx["sent"] < rx["t"]).all() and (rx["power"] > 0).all()
        assert (rx["length"] == 20).all() and rx["payload"].shape == (len(rx["t"]), 58)
    assert got > 100, f"only {got} frames in 2 s"
    assert got == (w.frames_received - before).sum(), "every delivery is reported once"


def test_setpoints_bring_every_vehicle_to_its_depth_and_heading():
    w = shoal.World(THREE, threads=1)
    depth, yaw = np.array([0.8, 1.4, 2.0]), np.array([0.5, -2.0, 3.0])
    w.step({"mode": "auto", "depth": depth, "yaw": yaw})
    for _ in range(round(60.0 / w.control_dt) - 1):
        w.step()  # the setpoints stay in force
    np.testing.assert_allclose(w.depth_reading, depth, atol=0.03)
    err = (w.imu_euler[:, 2] - yaw + math.pi) % (2 * math.pi) - math.pi
    assert np.abs(err).max() < math.radians(3), err
    np.testing.assert_array_equal(w.mode, [5, 5, 5])
    np.testing.assert_allclose(w.setpoint[:, :2], np.column_stack([depth, yaw]))


def test_raw_actuators_drive_forward_and_a_subset_is_commanded_by_id():
    w = shoal.World(THREE, threads=1)
    x0 = w.position[:, 0].copy()
    # Vehicle 2 only: side thrusters at 40 %, drives level.
    w.set_actuators(thrusters=[0.0, 40.0, 40.0], tilts=[0.0, 0.0], pump=0, vehicles=[2])
    w.step(steps=500)
    np.testing.assert_array_equal(w.mode, [0, 0, 6])
    np.testing.assert_array_equal(w.thruster_command[2], [0.0, 40.0, 40.0])
    moved = w.position[:, 0] - x0
    assert moved[2] > 0.2 and np.abs(moved[:2]).max() < 0.01, moved
    assert (w.thrust[2, 1:] > 0).all() and (w.thrust[:2] == 0).all()


def test_every_reported_mode_code_names_a_mode_in_MODES():
    # python/README.md: `mode` is a code into shoal.MODES, 6 being raw actuator commands.
    assert shoal.MODES == ["off", "diving", "buoyancy", "turning", "drift", "auto", "raw"]
    w = shoal.World(THREE, threads=1)
    w.set_actuators(thrusters=[0.0, 10.0, 10.0], tilts=[0.0, 0.0], pump=0, vehicles=[1])
    w.step()
    assert [shoal.MODES[m] for m in w.mode] == ["off", "raw", "off"]
    w.set_setpoints(depth=0.5, yaw=0.0, surge=0.0, sway=0.0, mode="drift", vehicles=[2])
    w.step()
    assert [shoal.MODES[m] for m in w.mode] == ["off", "raw", "drift"]


def test_jittered_frames_are_heard_and_simultaneous_ones_are_lost_to_half_duplex():
    w = shoal.World(PAIR, threads=1)
    w.send([0, 1], [b"from a", b"from b"], delay=[0.0, 0.02])  # 20 ms apart
    heard = []
    for _ in range(10):
        w.step()
        rx = w.received
        heard += [(int(v), int(s), bytes(p[:n])) for v, s, p, n in
                  zip(rx["vehicle"], rx["sender"], rx["payload"], rx["length"])]
    assert sorted(heard) == [(0, 1, b"from b"), (1, 0, b"from a")]
    w.reset()
    with pytest.warns(UserWarning, match="same instant"):
        w.send([0, 1], b"hello")  # both modems start at the same instant
    w.step(steps=50)
    assert w.received_count.sum() == 0
    np.testing.assert_array_equal(w.frames_lost[:, 3], [1, 1])  # lost to half-duplex


def test_reset_reproduces_a_seed_and_another_seed_differs():
    w = shoal.World(WORLDS / "default.toml", seed=3, threads=1)
    w.run(3.0)
    a = (w.digest, w.position.copy())
    w.reset()
    assert w.time == 0.0 and w.seed == 3
    w.run(3.0)
    assert w.digest == a[0]
    np.testing.assert_array_equal(w.position, a[1])
    w.reset(4)
    w.run(3.0)
    assert w.seed == 4 and w.digest != a[0]


def test_arrays_are_the_callers_and_inputs_may_be_any_array_like():
    w = shoal.World(THREE, threads=1)
    p = w.position
    p[:] = 0.0  # a copy: the world is untouched
    assert (w.position[:, 0] == [2.0, 5.0, 8.0]).all()
    before = w.position
    w.step({"depth": np.array([1.0, 1.0, 1.0], dtype=np.float32)}, steps=100)
    assert (before[:, 2] == 0.5).all(), "an array read before the step does not change"
    deep = np.zeros((3, 2))
    deep[:, 0] = [1.1, 1.2, 1.3]
    w.set_setpoints(depth=deep[:, 0], yaw=[0.1, 0.2, 0.3], surge=0)  # strided, list, int
    np.testing.assert_allclose(w.setpoint, [[1.1, 0.1, 0, 0], [1.2, 0.2, 0, 0], [1.3, 0.3, 0, 0]])


def test_worlds_from_text_paths_and_errors():
    assert shoal.World(str(WORLDS / "agents_goto.toml")).name == "agents_goto"
    assert len(shoal.World()) == 12, "no argument: the embedded default world"
    with pytest.raises(shoal.WorldError, match=r"<world text>:2:.*durration.*did you mean `duration`"):
        shoal.World("seed = 1\ndurration = 5\n")
    with pytest.raises(shoal.WorldError, match="cannot read"):
        shoal.World("no/such/world.toml")
    with pytest.raises(ValueError, match="threads"):
        shoal.World(THREE, threads=0)
    with pytest.raises(ValueError, match="seconds"):
        shoal.World(THREE).run(float("nan"))
    assert issubclass(shoal.WorldError, ValueError) and issubclass(shoal.CommandError, ValueError)
