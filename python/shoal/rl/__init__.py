"""Reinforcement-learning environments over a shoal world (needs ``pip install "shoal[rl]"``:
PettingZoo and Gymnasium).

- :class:`SwarmEnv` — a PettingZoo ``ParallelEnv``, one agent per vehicle of a swarm with
  optical modems; tasks ``"aggregate"``, ``"contact"`` (keep optical contact) and
  ``"cover"`` (cover the pool's area);
- :class:`VehicleEnv` — a Gymnasium ``Env``: one μAUV² reaches a depth and a heading, with
  raw actuators or the built-in controller's setpoints.

Both are deterministic for a seed. See each class for its task, observations and actions.
``gymnasium.make("shoal/Vehicle-v0")`` makes a ``VehicleEnv`` too.
"""

import gymnasium

from .swarm import SwarmEnv
from .vehicle import VehicleEnv

if "shoal/Vehicle-v0" not in gymnasium.registry:
    gymnasium.register(id="shoal/Vehicle-v0", entry_point="shoal.rl.vehicle:VehicleEnv")

__all__ = ["SwarmEnv", "VehicleEnv"]
