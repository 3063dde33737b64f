"""From ROS's frames back to shoal's, and the bridge's time stamps and pressures.

shoal's world frame is **NED** (x north, y east, z down; the surface at z = 0) and its body
frame **FRD** (x forward, y starboard, z down); attitudes are ZYX Euler angles roll, pitch, yaw
[rad] in them. ROS (REP 103) uses **ENU** world frames (x east, y north, z up) and **FLU** body
frames (x forward, y port, z up). The bridge publishes in ENU/FLU, converted as the Rust side's
``crates/shoal-model/src/frames.rs`` says; this module undoes it:

* position: ``(north, east, down) = (y, x, −z)`` of an ENU point [m];
* attitude: ``roll = roll_ENU``, ``pitch = −pitch_ENU``, ``yaw = π/2 − yaw_ENU`` [rad], yaw
  wrapped to −π … π;
* body vectors (rates [rad/s], specific force [m/s²], velocities [m/s]): ``(x, −y, −z)``;
* depth from pressure: ``(p − 101325 Pa) / (ρ g)`` [m].

Times: a ``builtin_interfaces/Time`` is converted to and from seconds of simulated time.
"""

import math
from typing import Tuple

from .msgs import Point, Quaternion, Time, Vector3

__all__ = [
    "GRAVITY",
    "SURFACE_PRESSURE_PA",
    "WATER_DENSITY",
    "attitude_from_ned",
    "attitude_to_ned",
    "depth_from_pressure",
    "euler_from_quaternion",
    "frd",
    "heading_from_enu",
    "heading_to_enu",
    "position_to_ned",
    "pressure_from_depth",
    "quaternion_from_euler",
    "seconds",
    "stamp",
    "wrap",
]

#: Atmospheric pressure at the water's surface, added by the bridge [Pa].
SURFACE_PRESSURE_PA = 101325.0
#: shoal's gravity (fixed; shoal_model::math::GRAVITY) [m/s²].
GRAVITY = 9.81
#: shoal's default water density (a world's ``[water] density``) [kg/m³].
WATER_DENSITY = 1000.0

_NS = 1_000_000_000


def wrap(angle: float) -> float:
    """`angle` [rad] wrapped to −π … π [rad]."""
    return math.atan2(math.sin(angle), math.cos(angle))


def seconds(t: Time) -> float:
    """A ``Time`` as seconds [s]."""
    return t.sec + t.nanosec * 1e-9


def stamp(s: float) -> Time:
    """`s` seconds [s] (≥ 0) as a ``Time``, rounded to the nearest nanosecond — the way the
    bridge stamps the tick at simulated time `s`."""
    ns = round(s * _NS)
    return Time(sec=ns // _NS, nanosec=ns % _NS)


def quaternion_from_euler(roll: float, pitch: float, yaw: float) -> Quaternion:
    """The rotation R_z(yaw) R_y(pitch) R_x(roll) (ZYX Euler angles [rad]) as a quaternion."""
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return Quaternion(
        x=sr * cp * cy - cr * sp * sy,
        y=cr * sp * cy + sr * cp * sy,
        z=cr * cp * sy - sr * sp * cy,
        w=cr * cp * cy + sr * sp * sy,
    )


def euler_from_quaternion(q: Quaternion) -> Tuple[float, float, float]:
    """ZYX Euler angles (roll, pitch, yaw) [rad] of the rotation `q` (normalised first);
    pitch −π/2 … π/2, roll and yaw −π … π."""
    n = math.sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w) or 1.0
    x, y, z, w = q.x / n, q.y / n, q.z / n, q.w / n
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return roll, pitch, yaw


def heading_to_enu(yaw: float) -> float:
    """shoal's NED heading [rad] (0 north, π/2 east) as an ENU yaw [rad] (0 east, π/2
    north), −π … π."""
    return wrap(math.pi / 2 - yaw)


def heading_from_enu(yaw_enu: float) -> float:
    """An ENU yaw [rad] as shoal's NED heading [rad], −π … π (the same formula both ways)."""
    return heading_to_enu(yaw_enu)


def attitude_to_ned(q: Quaternion) -> Tuple[float, float, float]:
    """The shoal attitude (roll, pitch, yaw) [rad] — FRD body in NED — of the FLU-body-to-ENU
    orientation `q` (an ``Imu.orientation`` or an odometry pose's)."""
    roll, pitch, yaw = euler_from_quaternion(q)
    return roll, -pitch, heading_from_enu(yaw)


def attitude_from_ned(roll: float, pitch: float, yaw: float) -> Quaternion:
    """The FLU-body-to-ENU orientation of shoal's attitude (roll, pitch, yaw) [rad]."""
    return quaternion_from_euler(roll, -pitch, math.pi / 2 - yaw)


def frd(v: Vector3) -> Tuple[float, float, float]:
    """A FLU body vector (rates [rad/s], specific force [m/s²], velocity [m/s]) in shoal's FRD
    body frame: ``(x, −y, −z)``, in the vector's unit."""
    return v.x, -v.y, -v.z


def position_to_ned(p: Point) -> Tuple[float, float, float]:
    """An ENU position [m] as shoal's (north, east, down) [m]: ``(y, x, −z)``."""
    return p.y, p.x, -p.z


def depth_from_pressure(
    pressure: float, density: float = WATER_DENSITY, gravity: float = GRAVITY
) -> float:
    """The depth [m, positive down] of an absolute `pressure` [Pa] in water of `density`
    [kg/m³] under `gravity` [m/s²]: ``(p − 101325 Pa) / (ρ g)``."""
    return (pressure - SURFACE_PRESSURE_PA) / (density * gravity)


def pressure_from_depth(
    depth: float, density: float = WATER_DENSITY, gravity: float = GRAVITY
) -> float:
    """The absolute pressure [Pa] at `depth` [m, positive down]: ``101325 Pa + ρ g · depth``."""
    return SURFACE_PRESSURE_PA + density * gravity * depth
