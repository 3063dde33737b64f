"""What a world file says about its ROS 2 bridge: the vehicles driven over ROS 2, their names,
the DDS domain, the namespace and what the conversions need.

The vehicle names come from shoal's own loader (:class:`shoal.World`, the compiled extension),
so they are exactly the run's (``trajectories.csv``'s ``vehicle`` column); the ``[ros2]``,
``[agents]`` and ``[water]`` settings are read from the TOML with their documented defaults.
"""

import sys
from dataclasses import dataclass
from pathlib import Path
from typing import List, Union

from . import enu

__all__ = ["ROS2_AGENT", "Ros2World"]

#: The agent name that puts a vehicle group under the ROS 2 bridge.
ROS2_AGENT = "ros2"


def _toml(path: Path) -> dict:
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover (Python < 3.11)
        try:
            import tomli as tomllib
        except ImportError:
            raise ImportError("reading a world file needs Python ≥ 3.11 or `pip install tomli`")
    with open(path, "rb") as f:
        return tomllib.load(f)


@dataclass
class Ros2World:
    """The ROS 2 side of a world file."""

    #: DDS domain (``[ros2] domain_id``, default 0).
    domain_id: int
    #: Namespace of the vehicles' topics (``[ros2] namespace``, default ``shoal``).
    namespace: str
    #: Names of the vehicles with ``agent = "ros2"``, in the world's order.
    vehicles: List[str]
    #: Water density (``[water] density``, default 1000) [kg/m³].
    density: float
    #: ``[agents] grant_position``: the world publishes ``odom`` and ``/tf``.
    odometry: bool

    @classmethod
    def load(cls, path: Union[str, Path]) -> "Ros2World":
        """Reads the world file `path` (loaded by :class:`shoal.World` for the vehicle names;
        raises its ``WorldError`` for a world shoal cannot load)."""
        import shoal

        spec = _toml(Path(path))
        groups = spec.get("vehicles", [])
        w = shoal.World(str(path))
        vehicles = [
            name for name, g in zip(w.names, w.groups)
            if groups[int(g)].get("agent") == ROS2_AGENT
        ]
        ros2 = spec.get("ros2", {})
        return cls(
            domain_id=int(ros2.get("domain_id", 0)),
            namespace=str(ros2.get("namespace", "shoal")),
            vehicles=vehicles,
            density=float(spec.get("water", {}).get("density", enu.WATER_DENSITY)),
            odometry=bool(spec.get("agents", {}).get("grant_position", False)),
        )
