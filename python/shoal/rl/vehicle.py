"""`VehicleEnv`: one μAUV² as a Gymnasium environment — reach a depth and a heading.

Task. At reset the vehicle floats at rest at 0.5 m depth, heading north, in a 10 × 10 × 3 m
pool, and draws a target depth (uniform in 0.5 … 2.0 m) and a target heading (uniform in
−π … π). Each step is one control period (0.05 s, `steps_per_action` of them with a larger
value) and is rewarded

    r = −( |target depth − depth reading| / 1 m  +  |heading error| / π )  −  0.01 · |a|² / n_a

(the depth reading and heading are what the vehicle senses: pressure sensor and IMU). An
episode is truncated after `max_steps` steps (400: 20 s); it never terminates early.

Actions (`action=`):
- ``"raw"`` (default): the vehicle's actuators, each in [−1, 1]: the thrusters (top, port,
  starboard; ×100 % of full scale) then the tilt drives (α, β; −1 … 1 maps to −90° … 90°).
  The policy has to learn what the built-in controller does.
- ``"setpoint"``: the built-in controller's auto mode: depth = (a₀ + 1)/2 · pool depth and
  heading = a₁ · π. (A baseline: the controller solves the task.)

Observations (float32, 10 values, each within [−1, 1]): depth error / 1 m, depth rate / 0.5
m/s (from successive readings), cos and sin of the heading error, yaw rate / 2 rad/s, roll
and pitch / (π/2), the two tilt readings / (π/2), target depth / 3 m. Values beyond the
scales are clipped.
"""

from __future__ import annotations

import math
from typing import Any, Optional

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from .. import World

#: The world of the task: one μAUV² (the model's default preset) in a 10 × 10 × 3 m pool.
WORLD = """
name = "vehicle env"
seed = 0
duration = 20.0
dt = 0.01
[pool]
size = [10.0, 10.0, 3.0]
[[vehicles]]
name = "auv"
position = [5.0, 5.0, 0.5]
"""

#: Scales of the observation [m, m/s, rad/s, rad, rad, m].
DEPTH_SCALE, RATE_SCALE, GYRO_SCALE, ANGLE_SCALE, POOL_DEPTH = 1.0, 0.5, 2.0, math.pi / 2, 3.0


class VehicleEnv(gym.Env):
    """Gymnasium environment: one μAUV² must reach a random depth and heading (see the
    module's documentation for the task, the observations and the actions).

    Args:
        action: ``"raw"`` (thrusters and tilt drives) or ``"setpoint"`` (auto-mode depth and
            heading).
        max_steps: steps per episode before truncation.
        steps_per_action: control periods (0.05 s each) per step.
        world: another world (path or TOML text) of one vehicle to use instead.

    Without a seed, `reset` continues the environment's own random stream, which starts
    from seed 0: runs are reproducible unless seeded otherwise.
    """

    metadata = {"render_modes": []}

    def __init__(
        self,
        action: str = "raw",
        max_steps: int = 400,
        steps_per_action: int = 1,
        world: Optional[str] = None,
    ) -> None:
        if action not in ("raw", "setpoint"):
            raise ValueError(f"action = {action!r}: use 'raw' or 'setpoint'")
        if max_steps < 1 or steps_per_action < 1:
            raise ValueError("max_steps and steps_per_action must be ≥ 1")
        self.action_kind = action
        self.max_steps = int(max_steps)
        self.world = World(WORLD if world is None else world, threads=1)
        if len(self.world) != 1:
            raise ValueError(f"VehicleEnv needs a world of one vehicle, not {len(self.world)}")
        self.np_random = np.random.default_rng(0)
        self._steps = self.world.tick_steps * int(steps_per_action)
        self._dt = self._steps * self.world.dt
        counts = self.world.actuator_counts[0]
        self._n_thr, self._n_tilt = int(counts[0]), int(counts[1])
        lim = self.world.limits
        self._thr_max = lim["thruster_max"][0, : self._n_thr]
        self._tilt_lo = lim["tilt_min"][0, : self._n_tilt]
        self._tilt_hi = lim["tilt_max"][0, : self._n_tilt]
        self._depth_max = float(lim["depth_max"])
        n_a = self._n_thr + self._n_tilt if action == "raw" else 2
        self.action_space = spaces.Box(-1.0, 1.0, (n_a,), np.float32)
        self.observation_space = spaces.Box(-1.0, 1.0, (10,), np.float32)
        self._target = np.zeros(2)
        self._prev_depth = 0.0
        self._t = 0

    def _observe(self) -> np.ndarray:
        w = self.world
        depth = float(w.depth_reading[0])
        roll, pitch, yaw = w.imu_euler[0]
        tilts = np.zeros(2)
        tilts[: self._n_tilt] = w.tilt_reading[0, :2]
        e_yaw = self._target[1] - yaw
        obs = np.array(
            [
                (self._target[0] - depth) / DEPTH_SCALE,
                (depth - self._prev_depth) / self._dt / RATE_SCALE,
                math.cos(e_yaw),
                math.sin(e_yaw),
                w.gyro[0, 2] / GYRO_SCALE,
                roll / ANGLE_SCALE,
                pitch / ANGLE_SCALE,
                tilts[0] / ANGLE_SCALE,
                tilts[1] / ANGLE_SCALE,
                self._target[0] / POOL_DEPTH,
            ]
        )
        self._prev_depth = depth
        self._errors = (abs(self._target[0] - depth), abs(math.atan2(math.sin(e_yaw), math.cos(e_yaw))))
        return np.clip(obs, -1.0, 1.0).astype(np.float32)

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        """Starts an episode: a fresh world (seeded from the environment's random stream) and a
        new target. Returns the observation and an info dict with the target."""
        super().reset(seed=seed)
        self.world.reset(int(self.np_random.integers(0, 2**63)))
        self._target = np.array(
            [self.np_random.uniform(0.5, 2.0), self.np_random.uniform(-math.pi, math.pi)]
        )
        self._prev_depth = float(self.world.depth_reading[0])
        self._t = 0
        obs = self._observe()
        return obs, self._info()

    def _info(self) -> dict[str, Any]:
        return {
            "target_depth": float(self._target[0]),
            "target_heading": float(self._target[1]),
            "depth_error": self._errors[0],
            "heading_error": self._errors[1],
        }

    def step(self, action):
        """Applies `action` for one step; returns (observation, reward, terminated, truncated,
        info)."""
        a = np.clip(np.asarray(action, dtype=np.float64).reshape(-1), -1.0, 1.0)
        if a.shape != self.action_space.shape:
            raise ValueError(f"action of shape {a.shape}: expected {self.action_space.shape}")
        w = self.world
        if self.action_kind == "raw":
            thr = a[: self._n_thr] * self._thr_max
            tilt = self._tilt_lo + (a[self._n_thr :] + 1.0) / 2.0 * (self._tilt_hi - self._tilt_lo)
            w.set_actuators(thrusters=thr[None, :], tilts=tilt[None, :], clip=True)
        else:
            w.set_setpoints(depth=(a[0] + 1.0) / 2.0 * self._depth_max, yaw=a[1] * math.pi, clip=True)
        w.step(steps=self._steps)
        self._t += 1
        obs = self._observe()
        e_depth, e_yaw = self._errors
        reward = -(e_depth / DEPTH_SCALE + e_yaw / math.pi) - 0.01 * float(a @ a) / a.size
        truncated = self._t >= self.max_steps
        return obs, float(reward), False, truncated, self._info()
