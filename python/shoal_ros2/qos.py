"""The QoS of shoal's ROS 2 bridge, as Cyclone DDS ``Qos`` objects.

What the world offers and requests (see docs/ros2.md), and what this package uses:

============================================  ==============  =============  ==========
topic (under ``/<namespace>/<vehicle>/``)     reliability     history        durability
============================================  ==============  =============  ==========
``imu``, ``pressure``, ``odom``, ``/clock``   best effort     keep last 10   volatile
``modem/rx``, ``modem/outcome``               reliable        keep last 100  volatile
``setpoint``, ``actuators``, ``modem/tx``     reliable        keep last 100  volatile
============================================  ==============  =============  ==========

Every profile also asks for plain CDR (XCDR1, ``DataRepresentation`` XCDR1 only), the encoding
of ROS 2 and of RustDDS: Cyclone would otherwise be free to write XCDR2, which ROS 2 nodes on
other DDS implementations cannot read. A best-effort reader matches any writer; a reliable
reader (``modem/rx``, ``modem/outcome``) needs a reliable writer, which the world's is.
"""

from cyclonedds.qos import Policy, Qos
from cyclonedds.util import duration

__all__ = ["COMMANDS", "RECEIVED_FRAMES", "SENSOR_DATA", "XCDR1"]

#: Plain CDR only, as ROS 2 (rmw_cyclonedds_cpp) uses.
XCDR1 = Policy.DataRepresentation(use_cdrv0_representation=True)

#: Sensor data (``imu``, ``pressure``, ``odom``, ``/clock``): best effort, keep last 10,
#: volatile — ROS 2's sensor-data profile with the bridge's depth.
SENSOR_DATA = Qos(
    Policy.Reliability.BestEffort,
    Policy.History.KeepLast(10),
    Policy.Durability.Volatile,
    XCDR1,
)

#: Received frames (``modem/rx``) and the outcomes of acknowledged ones (``modem/outcome``):
#: reliable, keep last 100, volatile.
RECEIVED_FRAMES = Qos(
    Policy.Reliability.Reliable(max_blocking_time=duration(milliseconds=100)),
    Policy.History.KeepLast(100),
    Policy.Durability.Volatile,
    XCDR1,
)

#: Commands (``setpoint``, ``actuators``, ``modem/tx``): reliable, keep last 100, volatile;
#: a write blocks at most 1 s when the world's reader falls 100 samples behind.
COMMANDS = Qos(
    Policy.Reliability.Reliable(max_blocking_time=duration(seconds=1)),
    Policy.History.KeepLast(100),
    Policy.Durability.Volatile,
    XCDR1,
)
