"""A measured-run CSV written again as a ROS 2 logger writes it: a rosbag2 (MCAP storage)
made by PyPI's `rosbags` (not by shoal), with the standard message types and one vendor type.

Each signal is its own topic, at its own rate, on its own clock — as `ros2 bag record` stores
what a vehicle's drivers publish:

* `/uauv2/thrusters` (std_msgs/msg/Float64MultiArray, no header: the bag's log time): the
  three thruster commands as PWM pulse widths, 1500 µs + 4 µs per % (top, port, starboard),
  published when they change (and once at the start);
* `/uauv2/tilts` (std_msgs/msg/Float64MultiArray, log time): alpha and beta [rad], on change;
* `/uauv2/pump` (uauv2_msgs/msg/Pump, a vendor type with a header: `int8 direction`), on
  change, header-stamped;
* `/uauv2/pressure` (sensor_msgs/msg/FluidPressure, header stamps): absolute pressure
  101 325 Pa + ρ g depth (ρ = 1000 kg/m³, g = 9.80665 m/s²) at 40 Hz — every fifth of the
  log's 50-Hz samples is not published — starting `LATE_S` late;
* `/uauv2/imu` (sensor_msgs/msg/Imu, header stamps; logs with yaw only): orientation and
  angular velocity in ROS's axes (REP 103: yaw_enu = π/2 − yaw, ω_z = −r), at the log's rate;
* `/diagnostics_counter` (std_msgs/msg/UInt32), a topic the mapping does not name.

Header stamps carry a jitter of up to ±`JITTER_NS` around the sample time and log times a
transport latency of 0.2–3 ms after it; commands are logged when sent (their log time is the
log's time: a command's effect starts then). `MAPPING` is the mapping file these bags need.
"""

from __future__ import annotations

import csv
import math
import random
from pathlib import Path

import numpy as np
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from shoal_ros2 import enu, msgs

#: Header-stamp jitter around each sample's time [ns].
JITTER_NS = 400_000
#: How late the measurement topic starts [s].
LATE_S = 0.4
#: Water density and gravity of the pressure conversion.
RHO, G, P_SURFACE = 1000.0, 9.80665, 101_325.0

PUMP_MSG = "std_msgs/Header header\nint8 direction\n"

#: The mapping file for these bags (shoal validate --mapping).
MAPPING = """\
# The development logs as rosbag2s (python/tests/rosbag_writer.py).
[inputs]
"u.top"   = { topic = "/uauv2/thrusters", field = "data[0]", scale = 0.25, offset = -375.0 }
"u.port"  = { topic = "/uauv2/thrusters", field = "data[1]", scale = 0.25, offset = -375.0 }
"u.stbd"  = { topic = "/uauv2/thrusters", field = "data[2]", scale = 0.25, offset = -375.0 }
"u.alpha" = { topic = "/uauv2/tilts", field = "data[0]" }
"u.beta"  = { topic = "/uauv2/tilts", field = "data[1]" }
"u.pump"  = { topic = "/uauv2/pump", field = "direction" }

[channels]
"y.depth" = { topic = "/uauv2/pressure", field = "fluid_pressure", depth_from_pressure = { density_kg_m3 = 1000.0 } }
"y.yaw"   = { topic = "/uauv2/imu", field = "orientation" }
"y.r"     = { topic = "/uauv2/imu", field = "angular_velocity.z" }
"""


def typestore():
    ts = get_typestore(Stores.ROS2_HUMBLE)
    ts.register(get_types_from_msg(PUMP_MSG, "uauv2_msgs/msg/Pump"))
    return ts


def read_csv(path: Path) -> dict:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    cols = {}
    for k, name in enumerate(header):
        cols[name] = np.array([float(r[k]) if r[k] != "" else math.nan for r in body])
    return cols


def _ns(t: float) -> int:
    return int(round(t * 1e9))


def write_bag(csv_path: Path, out: Path, seed: int = 1, channels: tuple = ("y.depth", "y.yaw", "y.r")) -> Path:
    """Writes the log at `csv_path` as a rosbag2 folder `out` and returns it. Only the CSV's
    channels among `channels` are written (a mapping entry for a topic the bag lacks is an
    error, so the mapping used must name exactly the written ones)."""
    rng = random.Random(seed)
    ts = typestore()
    cols = read_csv(csv_path)
    t = cols["t"]
    t_ns = [_ns(x) for x in t]
    Header = ts.types["std_msgs/msg/Header"]
    Time = ts.types["builtin_interfaces/msg/Time"]
    F64Array = ts.types["std_msgs/msg/Float64MultiArray"]
    Layout = ts.types["std_msgs/msg/MultiArrayLayout"]
    FluidPressure = ts.types["sensor_msgs/msg/FluidPressure"]
    Imu = ts.types["sensor_msgs/msg/Imu"]
    Quaternion = ts.types["geometry_msgs/msg/Quaternion"]
    Vector3 = ts.types["geometry_msgs/msg/Vector3"]
    Pump = ts.types["uauv2_msgs/msg/Pump"]
    UInt32 = ts.types["std_msgs/msg/UInt32"]

    def header(ns: int, frame: str):
        return Header(stamp=Time(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000), frame_id=frame)

    def jitter(ns: int) -> int:
        return ns + rng.randint(-JITTER_NS, JITTER_NS)

    def latency(ns: int) -> int:
        return ns + rng.randint(200_000, 3_000_000)

    messages = []  # (log time, topic, message, type)

    def on_change(topic: str, names: list, make):
        last = None
        for k, ns in enumerate(t_ns):
            values = tuple(cols[n][k] for n in names)
            if values != last:
                messages.append((ns, topic, make(ns, values), None))
                last = values

    layout = Layout(dim=[], data_offset=0)
    on_change("/uauv2/thrusters", ["u.top", "u.port", "u.stbd"],
              lambda ns, v: F64Array(layout=layout, data=np.array([1500.0 + 4.0 * x for x in v])))
    on_change("/uauv2/tilts", ["u.alpha", "u.beta"],
              lambda ns, v: F64Array(layout=layout, data=np.array(v, dtype=np.float64)))
    on_change("/uauv2/pump", ["u.pump"],
              lambda ns, v: Pump(header=header(ns, "pump"), direction=int(v[0])))
    start = t_ns[0] + _ns(LATE_S)
    if "y.depth" in cols and "y.depth" in channels:
        for k, ns in enumerate(t_ns):
            if ns < start or k % 5 == 4:
                continue
            stamp = jitter(ns)
            p = P_SURFACE + RHO * G * cols["y.depth"][k]
            msg = FluidPressure(header=header(stamp, "pressure"), fluid_pressure=p, variance=0.0)
            messages.append((latency(stamp), "/uauv2/pressure", msg, None))
    if "y.yaw" in cols and "y.yaw" in channels:
        for k, ns in enumerate(t_ns):
            if ns < start:
                continue
            stamp = jitter(ns)
            # Python's one NED→ENU (shoal_ros2.enu): attitude, and FRD rates as FLU.
            o = enu.attitude_from_ned(0.0, 0.0, cols["y.yaw"][k])
            q = Quaternion(x=o.x, y=o.y, z=o.z, w=o.w)
            wx, wy, wz = enu.frd(msgs.Vector3(x=0.0, y=0.0, z=cols["y.r"][k]))
            w = Vector3(x=wx, y=wy, z=wz)
            msg = Imu(header=header(stamp, "imu"), orientation=q,
                      orientation_covariance=np.zeros(9), angular_velocity=w,
                      angular_velocity_covariance=np.zeros(9),
                      linear_acceleration=Vector3(x=0.0, y=0.0, z=9.80665),
                      linear_acceleration_covariance=np.zeros(9))
            messages.append((latency(stamp), "/uauv2/imu", msg, None))
    for k in range(0, len(t_ns), 50):
        messages.append((latency(t_ns[k]), "/diagnostics_counter", UInt32(data=k), None))

    messages.sort(key=lambda m: m[0])
    types = {
        "/uauv2/thrusters": "std_msgs/msg/Float64MultiArray",
        "/uauv2/tilts": "std_msgs/msg/Float64MultiArray",
        "/uauv2/pump": "uauv2_msgs/msg/Pump",
        "/uauv2/pressure": "sensor_msgs/msg/FluidPressure",
        "/uauv2/imu": "sensor_msgs/msg/Imu",
        "/diagnostics_counter": "std_msgs/msg/UInt32",
    }
    with Writer(out, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        conns = {}
        for topic in sorted({m[1] for m in messages}):
            conns[topic] = writer.add_connection(topic, types[topic], typestore=ts)
        for log_ns, topic, msg, _ in messages:
            data = ts.serialize_cdr(msg, types[topic])
            writer.write(conns[topic], log_ns, data)
    return out


def mapping_for(cols: dict) -> str:
    """`MAPPING` without the channels the log does not have."""
    keep = []
    for line in MAPPING.splitlines():
        if line.startswith('"y.') and line.split('"')[1] not in cols:
            continue
        keep.append(line)
    return "\n".join(keep) + "\n"
