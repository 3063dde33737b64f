"""shoal_ros2: the agent side of shoal's ROS 2 bridge in Python, on Eclipse Cyclone DDS.

A world run by ``shoal run`` whose vehicle groups say ``agent = "ros2"`` publishes each such
vehicle's sensors on ROS 2 topics under ``/<namespace>/<vehicle>/`` and takes its commands
from there (docs/ros2.md). This package speaks that interface without a ROS 2 installation:

- :mod:`shoal_ros2.msgs` — the messages as Cyclone DDS IDL types with ROS 2's DDS type names
  (``sensor_msgs::msg::dds_::Imu_``, ``shoal_msgs::msg::dds_::Setpoint_``, …);
- :mod:`shoal_ros2.qos` — the bridge's QoS (best-effort sensor data, reliable commands and
  frames), plain CDR;
- :mod:`shoal_ros2.enu` — ROS's ENU/FLU frames back to shoal's NED/FRD, depth from pressure,
  stamps to seconds;
- :class:`Ros2World` — a world file's ROS 2 side: its ``agent = "ros2"`` vehicles, domain,
  namespace;
- :class:`Ros2Swarm` — readers and writers for a set of vehicles: wait for a control tick's
  observations (`Ros2Swarm.wait_tick`, with the frames received and the outcomes of
  acknowledged ones), answer with setpoints, raw actuator commands and frames to send
  (broadcasts, or unicasts to one vehicle, acknowledged or not).

Units are SI, angles in radians. Needs the ``cyclonedds`` package from PyPI.
"""

from . import enu, msgs, qos
from .msgs import (
    Actuators,
    Clock,
    FluidPressure,
    FrameOutcome,
    Imu,
    Odometry,
    OpticalFrame,
    Setpoint,
    TFMessage,
    Time,
)
from .swarm import (
    LOCALHOST_CONFIG,
    NotMatched,
    Observation,
    Ros2Swarm,
    Tick,
    dds_topic,
    localhost_only_from_env,
    ros_name,
)
from .world import Ros2World

__all__ = [
    "LOCALHOST_CONFIG",
    "Actuators",
    "Clock",
    "FluidPressure",
    "FrameOutcome",
    "Imu",
    "NotMatched",
    "Observation",
    "Odometry",
    "OpticalFrame",
    "Ros2Swarm",
    "Ros2World",
    "Setpoint",
    "TFMessage",
    "Tick",
    "Time",
    "dds_topic",
    "enu",
    "localhost_only_from_env",
    "msgs",
    "qos",
    "ros_name",
]
