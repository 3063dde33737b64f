"""The ROS 2 messages of shoal's ROS 2 bridge as Cyclone DDS IDL types.

Each class is the DDS type that ROS 2 itself puts on the wire for the message (its
``rosidl`` IDL struct): the DDS type name is ROS 2's, ``<package>::msg::dds_::<Type>_``
(e.g. ``sensor_msgs::msg::dds_::Imu_``), the fields are those of the ROS 2 ``.msg`` file in
the same order and with the same types, and samples are plain (XCDR1) CDR, so a reader or
writer made from these classes talks to ROS 2 nodes and to ``shoal run`` (ros2-client on
RustDDS) alike. Only the types the bridge uses are here:

* ``builtin_interfaces``: :class:`Time`;
* ``std_msgs``: :class:`Header`;
* ``geometry_msgs``: :class:`Quaternion`, :class:`Vector3`, :class:`Point`, :class:`Pose`,
  :class:`PoseWithCovariance`, :class:`Twist`, :class:`TwistWithCovariance`,
  :class:`Transform`, :class:`TransformStamped`;
* ``sensor_msgs``: :class:`Imu`, :class:`FluidPressure`;
* ``nav_msgs``: :class:`Odometry`;
* ``tf2_msgs``: :class:`TFMessage`;
* ``rosgraph_msgs``: :class:`Clock`;
* ``shoal_msgs`` (``crates/shoal-ros2/shoal_msgs/msg``): :class:`Setpoint`,
  :class:`Actuators`, :class:`OpticalFrame`, :class:`FrameOutcome`.

Units are ROS's (REP 103): SI, angles in radians, frames ENU (world) and FLU (body), except
where a ``shoal_msgs`` field says otherwise (:attr:`Setpoint.heading` is shoal's NED
heading). A ``.msg`` constant is a plain class attribute (``Setpoint.MODE_AUTO``), not a field.
``float64[N]`` fields are Python lists of N floats; ``uint8[]`` fields accept ``bytes`` and
read back as lists of ints.
"""

from dataclasses import dataclass, field

import cyclonedds.idl.types as types
from cyclonedds.idl import IdlStruct
from cyclonedds.idl import annotations as annotate

__all__ = [
    "Actuators",
    "Clock",
    "FluidPressure",
    "FrameOutcome",
    "Header",
    "Imu",
    "Odometry",
    "OpticalFrame",
    "Point",
    "Pose",
    "PoseWithCovariance",
    "Quaternion",
    "Setpoint",
    "TFMessage",
    "Time",
    "Transform",
    "TransformStamped",
    "Twist",
    "TwistWithCovariance",
    "Vector3",
    "ROS_TYPES",
]


def _zeros(n: int):
    return field(default_factory=lambda: [0.0] * n)


# builtin_interfaces -------------------------------------------------------------------------


@dataclass
@annotate.final
class Time(IdlStruct, typename="builtin_interfaces::msg::dds_::Time_"):
    """``builtin_interfaces/msg/Time``: a time since the start of the run (shoal's simulated
    time) or since the epoch."""

    #: Whole seconds [s].
    sec: types.int32 = 0
    #: Nanoseconds past `sec`, 0 … 999 999 999 [ns].
    nanosec: types.uint32 = 0


# std_msgs -----------------------------------------------------------------------------------


@dataclass
@annotate.final
class Header(IdlStruct, typename="std_msgs::msg::dds_::Header_"):
    """``std_msgs/msg/Header``: when the data was sampled and in which frame it is."""

    #: Sampling time (the bridge: simulated time of the control tick).
    stamp: Time = field(default_factory=Time)
    #: Coordinate frame (the bridge: ``<vehicle>/base_link`` for body data).
    frame_id: str = ""


# geometry_msgs ------------------------------------------------------------------------------


@dataclass
@annotate.final
class Quaternion(IdlStruct, typename="geometry_msgs::msg::dds_::Quaternion_"):
    """``geometry_msgs/msg/Quaternion``: a rotation as a unit quaternion (dimensionless)."""

    x: types.float64 = 0.0
    y: types.float64 = 0.0
    z: types.float64 = 0.0
    w: types.float64 = 1.0


@dataclass
@annotate.final
class Vector3(IdlStruct, typename="geometry_msgs::msg::dds_::Vector3_"):
    """``geometry_msgs/msg/Vector3``: a free vector (unit by use: rad/s, m/s², m, …)."""

    x: types.float64 = 0.0
    y: types.float64 = 0.0
    z: types.float64 = 0.0


@dataclass
@annotate.final
class Point(IdlStruct, typename="geometry_msgs::msg::dds_::Point_"):
    """``geometry_msgs/msg/Point``: a position [m]."""

    x: types.float64 = 0.0
    y: types.float64 = 0.0
    z: types.float64 = 0.0


@dataclass
@annotate.final
class Pose(IdlStruct, typename="geometry_msgs::msg::dds_::Pose_"):
    """``geometry_msgs/msg/Pose``: position [m] and orientation."""

    position: Point = field(default_factory=Point)
    orientation: Quaternion = field(default_factory=Quaternion)


@dataclass
@annotate.final
class PoseWithCovariance(IdlStruct, typename="geometry_msgs::msg::dds_::PoseWithCovariance_"):
    """``geometry_msgs/msg/PoseWithCovariance``: a pose and its 6 × 6 covariance, row-major,
    about x, y, z, rotation about x, y, z [m², m·rad, rad²]."""

    pose: Pose = field(default_factory=Pose)
    covariance: types.array[types.float64, 36] = _zeros(36)


@dataclass
@annotate.final
class Twist(IdlStruct, typename="geometry_msgs::msg::dds_::Twist_"):
    """``geometry_msgs/msg/Twist``: linear [m/s] and angular [rad/s] velocity."""

    linear: Vector3 = field(default_factory=Vector3)
    angular: Vector3 = field(default_factory=Vector3)


@dataclass
@annotate.final
class TwistWithCovariance(IdlStruct, typename="geometry_msgs::msg::dds_::TwistWithCovariance_"):
    """``geometry_msgs/msg/TwistWithCovariance``: a twist and its 6 × 6 covariance, row-major
    [(m/s)², m/s·rad/s, (rad/s)²]."""

    twist: Twist = field(default_factory=Twist)
    covariance: types.array[types.float64, 36] = _zeros(36)


@dataclass
@annotate.final
class Transform(IdlStruct, typename="geometry_msgs::msg::dds_::Transform_"):
    """``geometry_msgs/msg/Transform``: translation [m] and rotation of a child frame in its
    parent."""

    translation: Vector3 = field(default_factory=Vector3)
    rotation: Quaternion = field(default_factory=Quaternion)


@dataclass
@annotate.final
class TransformStamped(IdlStruct, typename="geometry_msgs::msg::dds_::TransformStamped_"):
    """``geometry_msgs/msg/TransformStamped``: a transform from `header.frame_id` (parent) to
    `child_frame_id` at `header.stamp`."""

    header: Header = field(default_factory=Header)
    child_frame_id: str = ""
    transform: Transform = field(default_factory=Transform)


# sensor_msgs --------------------------------------------------------------------------------


@dataclass
@annotate.final
class Imu(IdlStruct, typename="sensor_msgs::msg::dds_::Imu_"):
    """``sensor_msgs/msg/Imu``: attitude (FLU body to ENU world), body rates [rad/s] and
    specific force [m/s²] in the FLU body frame. Covariances are 3 × 3, row-major
    [rad², (rad/s)², (m/s²)²]; element 0 = −1 means "no estimate"."""

    header: Header = field(default_factory=Header)
    orientation: Quaternion = field(default_factory=Quaternion)
    orientation_covariance: types.array[types.float64, 9] = _zeros(9)
    angular_velocity: Vector3 = field(default_factory=Vector3)
    angular_velocity_covariance: types.array[types.float64, 9] = _zeros(9)
    linear_acceleration: Vector3 = field(default_factory=Vector3)
    linear_acceleration_covariance: types.array[types.float64, 9] = _zeros(9)


@dataclass
@annotate.final
class FluidPressure(IdlStruct, typename="sensor_msgs::msg::dds_::FluidPressure_"):
    """``sensor_msgs/msg/FluidPressure``: absolute pressure [Pa] and its variance [Pa²]
    (0: unknown)."""

    header: Header = field(default_factory=Header)
    fluid_pressure: types.float64 = 0.0
    variance: types.float64 = 0.0


# nav_msgs -----------------------------------------------------------------------------------


@dataclass
@annotate.final
class Odometry(IdlStruct, typename="nav_msgs::msg::dds_::Odometry_"):
    """``nav_msgs/msg/Odometry``: pose in `header.frame_id` (ENU [m]) and twist in
    `child_frame_id` (the FLU body [m/s, rad/s])."""

    header: Header = field(default_factory=Header)
    child_frame_id: str = ""
    pose: PoseWithCovariance = field(default_factory=PoseWithCovariance)
    twist: TwistWithCovariance = field(default_factory=TwistWithCovariance)


# tf2_msgs, rosgraph_msgs --------------------------------------------------------------------


@dataclass
@annotate.final
class TFMessage(IdlStruct, typename="tf2_msgs::msg::dds_::TFMessage_"):
    """``tf2_msgs/msg/TFMessage``: transforms, as on ``/tf``."""

    transforms: types.sequence[TransformStamped] = field(default_factory=list)


@dataclass
@annotate.final
class Clock(IdlStruct, typename="rosgraph_msgs::msg::dds_::Clock_"):
    """``rosgraph_msgs/msg/Clock``: the simulated time, as on ``/clock`` (what ROS nodes with
    ``use_sim_time`` take as now)."""

    clock: Time = field(default_factory=Time)


# shoal_msgs (crates/shoal-ros2/shoal_msgs/msg) ----------------------------------------------


@dataclass
@annotate.final
class Setpoint(IdlStruct, typename="shoal_msgs::msg::dds_::Setpoint_"):
    """``shoal_msgs/msg/Setpoint``: setpoints for one vehicle's controller, answering the
    control tick `stamp` (published by an agent on ``/<namespace>/<vehicle>/setpoint``)."""

    MODE_KEEP = 0  #: keep the setpoints in force (e.g. a tick that only sends frames)
    MODE_OFF = 1  #: everything off
    MODE_DIVING = 2  #: heave only (paper mode 1)
    MODE_BUOYANCY = 3  #: diving plus the pump (mode 2)
    MODE_TURNING = 4  #: yaw only (mode 3)
    MODE_DRIFT = 5  #: yaw and surge, sway by the top thruster (mode 4)
    MODE_AUTO = 6  #: heave, yaw and surge together (mode 5)

    #: The control tick answered: the time of its ``/clock`` message (simulated).
    stamp: Time = field(default_factory=Time)
    #: One of ``MODE_*``.
    mode: types.uint8 = 0
    #: Depth setpoint [m, positive down].
    depth: types.float64 = 0.0
    #: Heading setpoint [rad], shoal's NED: 0 north, π/2 east.
    heading: types.float64 = 0.0
    #: Surge force [N].
    surge: types.float64 = 0.0
    #: Sway force [N].
    sway: types.float64 = 0.0
    #: modem/tx messages stamped with this tick, sent before this one.
    frames: types.uint32 = 0


@dataclass
@annotate.final
class Actuators(IdlStruct, typename="shoal_msgs::msg::dds_::Actuators_"):
    """``shoal_msgs/msg/Actuators``: raw actuator commands for one vehicle, answering the
    control tick `stamp` (on ``/<namespace>/<vehicle>/actuators``; the controller's raw mode)."""

    #: The control tick answered: the time of its ``/clock`` message (simulated).
    stamp: Time = field(default_factory=Time)
    #: Per thruster, in the vehicle file's order [% of full scale].
    thrusters: types.sequence[types.float64] = field(default_factory=list)
    #: Per tilt drive, in the vehicle file's order [rad].
    tilts: types.sequence[types.float64] = field(default_factory=list)
    #: −1 empty the tank, 0 off, +1 fill it.
    pump: types.int8 = 0
    #: modem/tx messages stamped with this tick, sent before this one.
    frames: types.uint32 = 0


@dataclass
@annotate.final
class OpticalFrame(IdlStruct, typename="shoal_msgs::msg::dds_::OpticalFrame_"):
    """``shoal_msgs/msg/OpticalFrame``: one optical modem frame, received (on
    ``/<namespace>/<vehicle>/modem/rx``, published by the world) or to send (on
    ``…/modem/tx``, by an agent). Vehicles are named by their ROS names, as in their topics
    (``auv-0`` → ``auv_0``, `shoal_ros2.ros_name`)."""

    ALL_MODEMS = -1  #: tx: every modem of the vehicle at once

    #: rx: end of the reception; tx: the control tick it belongs to (simulated).
    stamp: Time = field(default_factory=Time)
    #: rx: the sending vehicle's name; tx: unused ('').
    sender: str = ""
    #: tx: the destination vehicle's name, '' = broadcast; rx: this vehicle's name if it was a
    #: unicast to it, '' for a broadcast.
    to: str = ""
    #: tx: with `to`, acknowledged and retransmitted until it is (stop-and-wait ARQ), its end
    #: published on ``modem/outcome``; rx: unused (False).
    ack: bool = False
    #: tx: a number of the sender's choosing, returned on ``modem/outcome``; rx: unused (0).
    tag: types.uint32 = 0
    #: rx: the sender's frame sequence number; tx: unused (0).
    seq: types.uint32 = 0
    #: rx: the receiving modem's index; tx: the sending one, or ``ALL_MODEMS``.
    modem: types.int32 = 0
    #: rx: received optical power [W]; tx: unused (0).
    power: types.float64 = 0.0
    #: rx: electrical signal-to-noise ratio [-]; tx: unused (0).
    snr: types.float64 = 0.0
    #: tx: delay after the tick before it is handed to the modem [s].
    delay: types.float64 = 0.0
    #: The frame's payload (at most the modem's payload size) [bytes].
    payload: types.sequence[types.uint8] = field(default_factory=list)


@dataclass
@annotate.final
class FrameOutcome(IdlStruct, typename="shoal_msgs::msg::dds_::FrameOutcome_"):
    """``shoal_msgs/msg/FrameOutcome``: what became of one unicast frame sent with
    acknowledgement (on its sender's ``/<namespace>/<vehicle>/modem/outcome``, published by the
    world once it has ended)."""

    #: When it ended: the acknowledgement decoded, or the wait after the last transmission ran
    #: out (simulated).
    stamp: Time = field(default_factory=Time)
    #: The destination vehicle's name (as in its topics).
    to: str = ""
    #: The tag it was sent with on ``modem/tx``.
    tag: types.uint32 = 0
    #: The sender's sequence number of the frame (the destination's ``modem/rx`` ``seq``).
    seq: types.uint32 = 0
    #: Times it went on the air: 1 + retransmissions (0: never, its queue was full).
    transmissions: types.uint32 = 0
    #: True: the destination acknowledged it; False: given up.
    acknowledged: bool = False
    #: When it was handed to the link layer: the tick's time + the frame's delay (simulated).
    sent: Time = field(default_factory=Time)


#: Every type above by its ROS 2 name (``package/msg/Type``).
ROS_TYPES = {
    "builtin_interfaces/msg/Time": Time,
    "std_msgs/msg/Header": Header,
    "geometry_msgs/msg/Quaternion": Quaternion,
    "geometry_msgs/msg/Vector3": Vector3,
    "geometry_msgs/msg/Point": Point,
    "geometry_msgs/msg/Pose": Pose,
    "geometry_msgs/msg/PoseWithCovariance": PoseWithCovariance,
    "geometry_msgs/msg/Twist": Twist,
    "geometry_msgs/msg/TwistWithCovariance": TwistWithCovariance,
    "geometry_msgs/msg/Transform": Transform,
    "geometry_msgs/msg/TransformStamped": TransformStamped,
    "sensor_msgs/msg/Imu": Imu,
    "sensor_msgs/msg/FluidPressure": FluidPressure,
    "nav_msgs/msg/Odometry": Odometry,
    "tf2_msgs/msg/TFMessage": TFMessage,
    "rosgraph_msgs/msg/Clock": Clock,
    "shoal_msgs/msg/Setpoint": Setpoint,
    "shoal_msgs/msg/Actuators": Actuators,
    "shoal_msgs/msg/OpticalFrame": OpticalFrame,
    "shoal_msgs/msg/FrameOutcome": FrameOutcome,
}
