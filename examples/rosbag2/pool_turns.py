#!/usr/bin/env python3
"""Writes `pool_turns.mcap`, the bag `bluerov_mavros.toml` maps: a BlueROV (worlds/bluerov1.toml)
simulated by shoal turning one way and the other in a pool at 0.5 m, recorded as a
MAVROS-on-ArduSub vehicle records it — so the mapping's example command runs as written.

    .venv/bin/python examples/rosbag2/pool_turns.py [OUT.mcap]    # default: pool_turns.mcap
    shoal validate pool_turns.mcap --mapping examples/rosbag2/bluerov_mavros.toml \\
        --vehicle worlds/bluerov1.toml --channels y.r,y.yaw,y.depth --out out/turns

Topics (CDR, each with its `ros2msg` definition, as `ros2 bag record` stores them):

* `/mavros/rc/out` (mavros_msgs/msg/RCOut: a header and `uint16[] channels`): the six
  thrusters' commands as ArduSub's servo pulse widths, 1500 µs + 4 µs per % (1100…1900 µs),
  at 20 Hz, plus two unused channels at 1500 µs;
* `/mavros/imu/data` (sensor_msgs/msg/Imu): the IMU's attitude and rates in ROS's ENU/FLU
  axes (Python's one NED↔ENU, `shoal_ros2.enu`) at 50 Hz;
* `/bar30/pressure` (sensor_msgs/msg/FluidPressure): absolute pressure of the depth reading in
  pool water (997 kg/m³, g = 9.80665 m/s², the mapping's) at 20 Hz.

Header stamps are the simulated time; log times the same (a simulator has no transport delay).
Needs the venv of scripts/python-env.sh (shoal, rosbags, mcap).
"""

import sys
from pathlib import Path

import numpy as np
from mcap.writer import Writer
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

import shoal
from shoal_ros2 import enu, msgs

REPO = Path(__file__).resolve().parents[2]
#: Simulated time [s], the IMU's period [s], and every how many IMU samples the others come.
DURATION_S, PERIOD_S, SLOW = 60.0, 0.02, 2
RHO, G = 997.0, 9.80665
RCOUT = "std_msgs/Header header\nuint16[] channels\n"


def commands(t: float) -> list:
    """Thruster commands [% of full scale], t1…t6: hold 0.5 m, turn one way for 10 s, stop,
    the other way, … (t1–t4 the vectored horizontal thrusters, t5–t6 the vertical ones)."""
    phase = int(t // 10.0) % 4
    yaw = {0: 35.0, 1: 0.0, 2: -35.0, 3: 0.0}[phase]
    return [yaw, -yaw, -yaw, yaw, -8.0, -8.0]


def main(out: Path) -> Path:
    ts = get_typestore(Stores.ROS2_HUMBLE)
    ts.register(get_types_from_msg(RCOUT, "mavros_msgs/msg/RCOut"))
    world = shoal.World(REPO / "worlds" / "bluerov1.toml", seed=1)
    world.step({"depth": 0.5, "yaw": 0.0})
    world.run(5.0)  # settle at depth on the built-in controller
    Header = ts.types["std_msgs/msg/Header"]
    Time = ts.types["builtin_interfaces/msg/Time"]
    Quaternion = ts.types["geometry_msgs/msg/Quaternion"]
    Vector3 = ts.types["geometry_msgs/msg/Vector3"]
    types = {
        "/mavros/rc/out": "mavros_msgs/msg/RCOut",
        "/mavros/imu/data": "sensor_msgs/msg/Imu",
        "/bar30/pressure": "sensor_msgs/msg/FluidPressure",
    }
    steps = round(PERIOD_S / world.dt)
    with open(out, "wb") as f:
        w = Writer(f)
        w.start(profile="ros2", library="shoal examples/rosbag2/pool_turns.py")
        ids = {}
        for topic, ty in types.items():
            text = ts.generate_msgdef(ty, ros_version=2)[0]
            schema = w.register_schema(name=ty, encoding="ros2msg", data=text.encode())
            ids[topic] = w.register_channel(topic=topic, message_encoding="cdr", schema_id=schema)
        for k in range(round(DURATION_S / PERIOD_S)):
            t = k * PERIOD_S
            u = commands(t)
            world.step({"thrusters": [u]}, steps=steps)
            ns = round(t * 1e9)
            head = Header(stamp=Time(sec=ns // 10**9, nanosec=ns % 10**9), frame_id="base_link")
            roll, pitch, yaw = world.read("imu_euler")[0]
            o = enu.attitude_from_ned(roll, pitch, yaw)
            p, q, r = world.read("gyro")[0]
            wx, wy, wz = enu.frd(msgs.Vector3(x=p, y=q, z=r))
            zero = Vector3(x=0.0, y=0.0, z=0.0)
            out_msgs = [("/mavros/imu/data", ts.types["sensor_msgs/msg/Imu"](
                header=head, orientation=Quaternion(x=o.x, y=o.y, z=o.z, w=o.w),
                orientation_covariance=np.zeros(9), angular_velocity=Vector3(x=wx, y=wy, z=wz),
                angular_velocity_covariance=np.zeros(9), linear_acceleration=zero,
                linear_acceleration_covariance=np.array([-1.0] + [0.0] * 8)))]
            if k % SLOW == 0:
                pwm = np.array([round(1500 + 4 * x) for x in u] + [1500, 1500], dtype=np.uint16)
                out_msgs.append(("/mavros/rc/out", ts.types["mavros_msgs/msg/RCOut"](
                    header=head, channels=pwm)))
                depth = float(world.read("depth_reading")[0])
                out_msgs.append(("/bar30/pressure", ts.types["sensor_msgs/msg/FluidPressure"](
                    header=head, fluid_pressure=enu.pressure_from_depth(depth, RHO, G),
                    variance=0.0)))
            for seq, (topic, m) in enumerate(out_msgs):
                w.add_message(channel_id=ids[topic], log_time=ns, publish_time=ns,
                              sequence=k * 4 + seq, data=ts.serialize_cdr(m, types[topic]))
        w.finish()
    return out


if __name__ == "__main__":
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("pool_turns.mcap")
    print(main(out))
