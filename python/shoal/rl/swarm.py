"""`SwarmEnv`: a swarm of μAUV² with optical modems as a PettingZoo ``ParallelEnv``, one agent
per vehicle.

World. `n_vehicles` μAUV² (default 8) start at rest at random places in the middle of a
`pool` = (length, width, depth) m pool (default 20 × 20 × 3 m), 1.0 … 1.5 m deep, with random
headings; each carries a ring of four modems (front, right, back, left). Every vehicle
beacons every `beacon_period` s (0.5) on all its modems: a 9-byte frame with its heading and
depth reading (float32). The beacons' phases are random and each period is jittered by ±10 %,
because a modem is half-duplex — deaf while it transmits — so vehicles that always transmit
at the same instant never hear each other.

Observations (float32, 15 values in [−1, 1], only what the vehicle can sense): depth reading
/ pool depth; cos and sin of its IMU heading; yaw rate / 1 rad/s; then from the beacons it
received in the last `memory` s (1.0): per modem (front, right, back, left) the strongest
received power, as (log₁₀ P [W] + 9) / 3 (0 = nothing heard, 1 = 1 µW); the number of
vehicles heard / 8; the mean cos and sin of their headings relative to its own; their mean
depth minus its own / 1 m.

Actions (`action=`), each in [−1, 1]:
- ``"setpoint"`` (default, 3 values): turn — heading setpoint = IMU heading + a₀ · π/4;
  surge force (a₁ + 1)/2 · `surge_max` N (0.05); depth setpoint from 0.3 m (a₂ = −1) to the
  pool depth − 0.3 m (a₂ = 1); the built-in controller in auto mode follows them.
- ``"raw"`` (5 values): thrusters ×100 %, then tilt drives −90° … 90°.

Tasks (`task=`): every agent's reward per step, each minus `touch_penalty` (0.1) while its
hull touches a wall, the floor or another obstacle:
- ``"aggregate"``: −(distance to the swarm's centroid) / (pool diagonal) — gather.
- ``"contact"``: (vehicles heard in the last `memory` s) / (n − 1) — keep optical contact.
- ``"cover"``: the same for all: the fraction of a 2 m grid over the pool's floor within
  `cover_radius` m (3) horizontally of some vehicle — spread out and cover the area.

Agents never terminate; all are truncated after `max_cycles` steps (600: 30 s). Each step is
one control period (0.05 s).
"""

from __future__ import annotations

import functools
import math
from typing import Any, Optional

import numpy as np
from gymnasium import spaces
from pettingzoo import ParallelEnv

from .. import World

#: A ring of four modems (front, right, back, left) on the μAUV² hull [m].
RING = (
    ("front", (0.125, 0.0, 0.0), (1.0, 0.0, 0.0)),
    ("right", (0.0, 0.078, 0.0), (0.0, 1.0, 0.0)),
    ("back", (-0.125, 0.0, 0.0), (-1.0, 0.0, 0.0)),
    ("left", (0.0, -0.078, 0.0), (0.0, -1.0, 0.0)),
)
#: Beacon: tag, heading [rad] and depth reading [m] as little-endian float32.
BEACON_TAG = 0xB5
BEACON_DTYPE = np.dtype([("tag", "u1"), ("heading", "<f4"), ("depth", "<f4")])
TASKS = ("aggregate", "contact", "cover")


def swarm_world(n_vehicles: int, pool: tuple[float, float, float]) -> str:
    """The TOML text of the swarm world: `n_vehicles` μAUV² with a modem ring, placed at
    random (the world seed decides) in the middle third of a `pool` [m]."""
    lx, ly, lz = pool
    lines = [
        'name = "swarm env"',
        "seed = 0",
        "duration = 30.0",
        "dt = 0.01",
        "[pool]",
        f"size = [{lx}, {ly}, {lz}]",
        "[water]",
        'attenuation = "pool"',
        "[[vehicles]]",
        'name = "v"',
        f"count = {n_vehicles}",
        f"random = {{ min = [{lx / 3}, {ly / 3}, 1.0], max = [{2 * lx / 3}, {2 * ly / 3}, 1.5],"
        " random_heading = true }",
    ]
    for name, pos, d in RING:
        lines += [
            "[[vehicles.model.modems]]",
            f'name = "{name}"',
            f"position = [{pos[0]}, {pos[1]}, {pos[2]}]",
            f"direction = [{d[0]}, {d[1]}, {d[2]}]",
        ]
    return "\n".join(lines) + "\n"


class SwarmEnv(ParallelEnv):
    """PettingZoo parallel environment over a shoal world: one agent per vehicle, observing
    its own sensors and the beacons it receives (see the module's documentation for the
    world, observations, actions and tasks).

    Args:
        task: ``"aggregate"``, ``"contact"`` or ``"cover"``.
        n_vehicles: vehicles (agents), ≥ 2.
        action: ``"setpoint"`` or ``"raw"``.
        pool: pool length, width, depth [m].
        max_cycles: steps per episode before truncation.
        beacon_period: time between a vehicle's beacons [s].
        memory: how long a heard beacon counts [s].
        surge_max: largest surge force of the setpoint action [N].
        cover_radius: horizontal radius a vehicle covers in the ``"cover"`` task [m].
        touch_penalty: reward subtracted per step while a hull touches something.
        threads: working threads of the world.

    Without a seed, `reset` continues the environment's own random stream, which starts
    from seed 0: runs are reproducible unless seeded otherwise.
    """

    metadata = {"name": "shoal_swarm_v0", "render_modes": [], "is_parallelizable": True}

    def __init__(
        self,
        task: str = "aggregate",
        n_vehicles: int = 8,
        action: str = "setpoint",
        pool: tuple[float, float, float] = (20.0, 20.0, 3.0),
        max_cycles: int = 600,
        beacon_period: float = 0.5,
        memory: float = 1.0,
        surge_max: float = 0.05,
        cover_radius: float = 3.0,
        touch_penalty: float = 0.1,
        threads: int = 1,
    ) -> None:
        if task not in TASKS:
            raise ValueError(f"task = {task!r}: use one of {TASKS}")
        if action not in ("setpoint", "raw"):
            raise ValueError(f"action = {action!r}: use 'setpoint' or 'raw'")
        if n_vehicles < 2:
            raise ValueError("n_vehicles must be ≥ 2 (a swarm)")
        self.task, self.action_kind = task, action
        self.max_cycles = int(max_cycles)
        self.beacon_period, self.memory = float(beacon_period), float(memory)
        self.surge_max, self.cover_radius = float(surge_max), float(cover_radius)
        self.touch_penalty = float(touch_penalty)
        self.world = World(swarm_world(n_vehicles, pool), threads=threads)
        self.n = n_vehicles
        self.possible_agents = list(self.world.names)
        self.agents = []
        self._pool = np.asarray(pool, dtype=np.float64)
        lim = self.world.limits
        counts = self.world.actuator_counts[0]
        self._n_thr, self._n_tilt = int(counts[0]), int(counts[1])
        self._thr_max = lim["thruster_max"][:, : self._n_thr]
        self._tilt_lo = lim["tilt_min"][:, : self._n_tilt]
        self._tilt_hi = lim["tilt_max"][:, : self._n_tilt]
        n_a = 3 if action == "setpoint" else self._n_thr + self._n_tilt
        self._action_space = spaces.Box(-1.0, 1.0, (n_a,), np.float32)
        self._observation_space = spaces.Box(-1.0, 1.0, (15,), np.float32)
        #: The space of `state()`.
        self.state_space = spaces.Box(-1.0, 1.0, (5 * n_vehicles,), np.float32)
        gx = np.arange(1.0, pool[0], 2.0)
        gy = np.arange(1.0, pool[1], 2.0)
        self._cells = np.stack(np.meshgrid(gx, gy), -1).reshape(-1, 2)
        self.rng = np.random.default_rng(0)
        self._reset_memory()

    @functools.lru_cache(maxsize=None)
    def observation_space(self, agent: str) -> spaces.Box:
        """The observation space of `agent` (the same for every agent)."""
        return self._observation_space

    @functools.lru_cache(maxsize=None)
    def action_space(self, agent: str) -> spaces.Box:
        """The action space of `agent` (the same for every agent)."""
        return self._action_space

    def _reset_memory(self) -> None:
        n = self.n
        #: Per receiver and sender: last time heard [s], its modem, power [W], heading, depth.
        self._heard_t = np.full((n, n), -np.inf)
        self._heard_modem = np.zeros((n, n), dtype=np.int64)
        self._heard_power = np.zeros((n, n))
        self._heard_heading = np.zeros((n, n))
        self._heard_depth = np.zeros((n, n))
        self._next_beacon = np.zeros(n)
        self._cycle = 0

    def reset(self, seed: Optional[int] = None, options: Optional[dict] = None):
        """Starts an episode (a fresh world from `seed`, or from the environment's random
        stream); returns the observations and infos of all agents."""
        if seed is not None:
            self.rng = np.random.default_rng(seed)
        self.world.reset(int(self.rng.integers(0, 2**63)))
        self.agents = list(self.possible_agents)
        self._reset_memory()
        self._next_beacon = self.rng.uniform(0.0, self.beacon_period, self.n)
        # Hold depth and heading until the first action.
        self.world.set_setpoints(
            depth=self.world.depth_reading, yaw=self.world.imu_euler[:, 2], clip=True
        )
        obs = self._observe()
        return obs, {a: {} for a in self.agents}

    def _beacon(self) -> None:
        """Queues the beacons due within the coming step, each at its own instant."""
        w = self.world
        t, step = w.time, w.control_dt
        due = np.flatnonzero(self._next_beacon < t + step)
        if due.size == 0:
            return
        frames = np.zeros(due.size, BEACON_DTYPE)
        frames["tag"] = BEACON_TAG
        frames["heading"] = w.imu_euler[due, 2]
        frames["depth"] = w.depth_reading[due]
        delay = np.clip(self._next_beacon[due] - t, 0.0, step)
        w.send(due, frames.view(np.uint8).reshape(due.size, -1), delay=delay)
        jitter = self.rng.uniform(0.9, 1.1, due.size)
        self._next_beacon[due] = np.maximum(self._next_beacon[due], t) + self.beacon_period * jitter

    def _remember(self) -> None:
        """Files the beacons received in the last step."""
        rx = self.world.received
        ok = (rx["length"] == BEACON_DTYPE.itemsize) & (rx["payload"][:, 0] == BEACON_TAG)
        if not ok.any():
            return
        b = rx["payload"][ok, : BEACON_DTYPE.itemsize].copy().view(BEACON_DTYPE).reshape(-1)
        i, j = rx["vehicle"][ok], rx["sender"][ok]
        self._heard_t[i, j] = rx["t"][ok]
        self._heard_modem[i, j] = rx["modem"][ok]
        self._heard_power[i, j] = rx["power"][ok]
        self._heard_heading[i, j] = b["heading"]
        self._heard_depth[i, j] = b["depth"]

    def _observe(self) -> dict[str, np.ndarray]:
        w = self.world
        depth = w.depth_reading
        yaw = w.imu_euler[:, 2]
        fresh = self._heard_t > w.time - self.memory
        n_heard = fresh.sum(axis=1)
        obs = np.zeros((self.n, 15))
        obs[:, 0] = depth / self._pool[2]
        obs[:, 1], obs[:, 2] = np.cos(yaw), np.sin(yaw)
        obs[:, 3] = w.gyro[:, 2]
        power = np.log10(np.maximum(self._heard_power, 1e-12))
        level = np.where(fresh, np.clip((power + 9.0) / 3.0, 0.0, 1.0), 0.0)
        for m in range(4):
            obs[:, 4 + m] = np.where(self._heard_modem == m, level, 0.0).max(axis=1)
        obs[:, 8] = n_heard / 8.0
        rel = self._heard_heading - yaw[:, None]
        with np.errstate(invalid="ignore", divide="ignore"):
            k = np.maximum(n_heard, 1)
            obs[:, 9] = np.where(fresh, np.cos(rel), 0.0).sum(axis=1) / k
            obs[:, 10] = np.where(fresh, np.sin(rel), 0.0).sum(axis=1) / k
            obs[:, 11] = np.where(fresh, self._heard_depth - depth[:, None], 0.0).sum(axis=1) / k
        obs = np.clip(obs, -1.0, 1.0).astype(np.float32)
        self._n_heard = n_heard
        return {a: obs[i] for i, a in enumerate(self.possible_agents) if a in self.agents}

    def _rewards(self) -> np.ndarray:
        w = self.world
        pos = w.position
        if self.task == "aggregate":
            d = np.linalg.norm(pos - pos.mean(axis=0), axis=1)
            r = -d / float(np.linalg.norm(self._pool))
        elif self.task == "contact":
            r = self._n_heard / (self.n - 1)
        else:
            d2 = ((self._cells[:, None, :] - pos[None, :, :2]) ** 2).sum(axis=-1)
            covered = (d2.min(axis=1) <= self.cover_radius**2).mean()
            r = np.full(self.n, covered)
        return r - self.touch_penalty * w.touching

    def _act(self, actions: dict[str, Any]) -> None:
        live = [i for i, a in enumerate(self.possible_agents) if a in actions]
        if not live:
            return
        ids = np.asarray(live)
        a = np.stack([np.asarray(actions[self.possible_agents[i]], np.float64) for i in live])
        a = np.clip(a, -1.0, 1.0)
        w = self.world
        if self.action_kind == "setpoint":
            yaw = w.imu_euler[ids, 2] + a[:, 0] * (math.pi / 4)
            surge = (a[:, 1] + 1.0) / 2.0 * self.surge_max
            lo, hi = 0.3, self._pool[2] - 0.3
            depth = lo + (a[:, 2] + 1.0) / 2.0 * (hi - lo)
            w.set_setpoints(depth=depth, yaw=yaw, surge=surge, vehicles=ids, clip=True)
        else:
            thr = a[:, : self._n_thr] * self._thr_max[ids]
            lo, hi = self._tilt_lo[ids], self._tilt_hi[ids]
            tilt = lo + (a[:, self._n_thr :] + 1.0) / 2.0 * (hi - lo)
            w.set_actuators(thrusters=thr, tilts=tilt, vehicles=ids, clip=True)

    def step(self, actions: dict[str, Any]):
        """Applies every live agent's action for one control period; returns observations,
        rewards, terminations, truncations and infos of the agents live before the step."""
        self._act(actions)
        self._beacon()
        self.world.step()
        self._remember()
        self._cycle += 1
        live = list(self.agents)
        obs = self._observe()
        r = self._rewards()
        idx = {a: i for i, a in enumerate(self.possible_agents)}
        rewards = {a: float(r[idx[a]]) for a in live}
        done = self._cycle >= self.max_cycles
        terminations = {a: False for a in live}
        truncations = {a: done for a in live}
        infos = {a: {"heard": int(self._n_heard[idx[a]])} for a in live}
        if done:
            self.agents = []
        return obs, rewards, terminations, truncations, infos

    def state(self) -> np.ndarray:
        """The global state for centralised training: every vehicle's position / pool size
        and cos, sin of its true heading, (n, 5) flattened, float32."""
        w = self.world
        yaw = w.euler[:, 2]
        s = np.column_stack([w.position / self._pool, np.cos(yaw), np.sin(yaw)])
        return s.astype(np.float32).reshape(-1)
