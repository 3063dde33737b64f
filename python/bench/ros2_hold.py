"""The ROS 2 agent of `shoal bench --agents ros2`: drives every vehicle of the benchmark swarm
(their ROS names under `/<namespace>/` given by the bench) in auto mode to 1.3 m depth and heading 45°, as the
iceoryx2 goto example's `pilot 1.3 45` does, answering each lock-step tick as soon as that
vehicle's IMU and pressure for it have arrived (shoal_ros2.Ros2Swarm on Cyclone DDS).

Usage: ros2_hold.py NAMESPACE DOMAIN_ID VEHICLE... Ends with status 0 when no tick came for 5 s after
the first one (the world has ended), 1 when none came within 60 s.
"""

import math
import sys

from shoal_ros2 import Ros2Swarm, Setpoint


def main() -> int:
    namespace, domain, names = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
    heading = math.radians(45.0)
    ticks = 0
    with Ros2Swarm(namespace, names, domain_id=domain) as swarm:
        while (tick := swarm.wait_tick(timeout=60.0 if ticks == 0 else 5.0)) is not None:
            for v in tick.observations:
                swarm.send_setpoint(v, tick.stamp, Setpoint.MODE_AUTO, 1.3, heading)
            ticks += 1
    return 0 if ticks > 0 else 1


if __name__ == "__main__":
    sys.exit(main())
