"""shoal: a swarm simulator for tiny AUVs (DFKI μAUV²) with optical modems, in Python.

- :class:`World` — a whole shoal world in this process (the Rust simulator, no shared
  memory): ``reset``, ``step``, ``run``, and every vehicle's state, sensor readings, setpoints,
  received frames and modem counters as numpy arrays over all vehicles at once;
- :mod:`shoal.rl` — a PettingZoo ``ParallelEnv`` (``SwarmEnv``, one agent per vehicle) and a
  Gymnasium env (``VehicleEnv``, one vehicle) for training (``pip install "shoal[rl]"``);
- :mod:`shoal.agent` — agents in a separate process attached to ``shoal run`` over iceoryx2
  shared memory;
- :func:`run` — ``shoal run`` as a function: a world file (or text) → the same output files;
- :func:`read_log` — a measured run (CSV, or a rosbag2 through a mapping) as numpy columns,
  as ``shoal validate`` reads it;
- :func:`validate` — ``shoal validate`` as a function: measured runs (paths or columns of
  numbers) → the effects the model lacks, fitted, with their gain on held-out data
  (:mod:`shoal.validation`).

Units are SI, angles in radians, depth positive down (north-east-down world frame). Errors:
:class:`WorldError` (a world that cannot be loaded), :class:`CommandError` (a bad command,
naming the vehicle and field), :class:`ValidationError` (a validation that cannot run, naming
the setting or the file, line and column; all three are ``ValueError``) and :class:`SimulationError` (a
vehicle's state stopped being finite). See python/README.md.
"""

from ._shoal import (
    MAX_FRAME_DELAY,
    MODES,
    QUANTITIES,
    CommandError,
    SimulationError,
    ValidationError,
    World,
    WorldError,
    __version__,
    plot,
)
from .logs import Log, read_log
from .running import RunResult, run
from .validation import Report, validate

__all__ = [
    "MAX_FRAME_DELAY",
    "MODES",
    "QUANTITIES",
    "CommandError",
    "Log",
    "Report",
    "RunResult",
    "SimulationError",
    "ValidationError",
    "World",
    "WorldError",
    "__version__",
    "plot",
    "read_log",
    "run",
    "validate",
]
