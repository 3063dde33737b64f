"""`shoal.rl`: SwarmEnv passes PettingZoo's parallel API and seed tests and VehicleEnv
Gymnasium's environment checker, with every warning they give an error; both are
deterministic for a seed (the same observations and rewards, bit for bit), and their worlds
do what the tasks say (beacons are heard, the controller reaches the target)."""

import math

import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from pettingzoo.test import parallel_api_test, parallel_seed_test

from shoal.rl import SwarmEnv, VehicleEnv

#: The checkers report many problems only as warnings: here each one fails the test.
checker = pytest.mark.filterwarnings("error")


@checker
@pytest.mark.parametrize("task, action", [("aggregate", "setpoint"), ("contact", "raw"),
                                          ("cover", "setpoint")])
def test_swarm_env_passes_the_parallel_api_and_seed_tests(task, action):
    parallel_api_test(SwarmEnv(task=task, action=action, n_vehicles=5), num_cycles=200)
    parallel_seed_test(lambda: SwarmEnv(task=task, action=action, n_vehicles=5), num_cycles=50)


@checker
@pytest.mark.parametrize("action", ["raw", "setpoint"])
def test_vehicle_env_passes_the_environment_checker(action):
    check_env(VehicleEnv(action=action), skip_render_check=True)


def rollout(env, seed, steps):
    obs, _ = env.reset(seed=seed)
    rng = np.random.default_rng(0)
    out = [np.stack([obs[a] for a in env.possible_agents])]
    rewards = []
    for _ in range(steps):
        act = {a: rng.uniform(-1, 1, 3).astype(np.float32) for a in env.agents}
        obs, r, _, _, info = env.step(act)
        out.append(np.stack([obs[a] for a in env.possible_agents]))
        rewards.append([r[a] for a in env.possible_agents])
    return np.array(out), np.array(rewards), env.world.digest


def test_swarm_env_is_deterministic_and_vehicles_hear_each_others_beacons():
    a = rollout(SwarmEnv(task="contact"), 5, 100)
    b = rollout(SwarmEnv(task="contact"), 5, 100)
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])
    assert a[2] == b[2]
    assert rollout(SwarmEnv(task="contact"), 6, 100)[2] != a[2]
    # Who hears whom is the medium's physics: after 5 s, a vehicle has heard (in the last
    # second) nearly every vehicle within 2 m (the reliable range) and none beyond 4.5 m
    # (more than the cut-off range in pool water).
    env = SwarmEnv(task="contact")
    obs, _ = env.reset(seed=5)
    for _ in range(100):
        obs, r, _, _, _ = env.step({a: np.zeros(3, np.float32) for a in env.agents})
    heard = np.array([obs[a][8] * 8 for a in env.possible_agents])
    np.testing.assert_allclose([r[a] for a in env.possible_agents], heard / 7)
    p = env.world.position
    d = np.linalg.norm(p[:, None] - p[None], axis=-1)
    near, reach = (d < 2.0).sum(axis=1) - 1, (d < 4.5).sum(axis=1) - 1
    assert (heard <= reach).all() and heard.sum() >= 0.8 * near.sum() > 0, (heard, near, reach)


def vehicle_rollout(env, steps, seed=None):
    """Observations (steps + 1, 10) and rewards (steps,) of `steps` random actions (drawn
    from a fixed stream) after `env.reset(seed=seed)`."""
    obs, _ = env.reset(seed=seed)
    rng = np.random.default_rng(0)
    out, rewards = [obs], []
    for _ in range(steps):
        obs, r, _, _, _ = env.step(rng.uniform(-1, 1, env.action_space.shape).astype(np.float32))
        out.append(obs)
        rewards.append(r)
    return np.array(out), np.array(rewards)


def test_vehicle_env_is_reproducible_without_a_seed_and_needs_one_vehicle():
    # Unseeded, and with the same seed: the same observations and rewards, bit for bit (the
    # sensors are noisy, so this holds only when the world's seed is reproduced too).
    for seed in (None, 4):
        a = vehicle_rollout(VehicleEnv(), 40, seed)
        b = vehicle_rollout(VehicleEnv(), 40, seed)
        np.testing.assert_array_equal(a[0], b[0])
        np.testing.assert_array_equal(a[1], b[1])
    # Another seed gives another episode (so the comparison above can fail).
    c = vehicle_rollout(VehicleEnv(), 40, 5)
    assert not np.array_equal(a[0], c[0])
    with pytest.raises(ValueError, match="one vehicle"):
        VehicleEnv(world="seed = 1\n[[vehicles]]\ncount = 2\n"
                   "grid = { origin = [2.0, 2.0, 1.0], spacing = [1.0, 0.0], columns = 2 }\n")


def test_swarm_env_rewards_follow_the_tasks():
    env = SwarmEnv(task="aggregate")
    env.reset(seed=1)
    _, r, _, _, _ = env.step({a: np.zeros(3, np.float32) for a in env.agents})
    p = env.world.position
    d = np.linalg.norm(p - p.mean(axis=0), axis=1) / np.linalg.norm([20.0, 20.0, 3.0])
    np.testing.assert_allclose([r[a] for a in env.possible_agents], -d)
    env = SwarmEnv(task="cover")
    env.reset(seed=1)
    _, r, _, _, _ = env.step({a: np.zeros(3, np.float32) for a in env.agents})
    values = set(r.values())
    assert len(values) == 1 and 0.0 < values.pop() < 0.5, "a cluster covers part of the pool"


def test_vehicle_env_setpoint_action_reaches_the_target():
    env = VehicleEnv(action="setpoint", max_steps=1200)  # 60 s
    _, info = env.reset(seed=3)
    a = np.array([info["target_depth"] / 1.5 - 1.0, info["target_heading"] / math.pi])
    for _ in range(1200):
        _, r, terminated, truncated, info = env.step(a)
    assert truncated and not terminated
    assert info["depth_error"] < 0.03 and info["heading_error"] < math.radians(3), info
    assert r > -0.05
