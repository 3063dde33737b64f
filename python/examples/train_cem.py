#!/usr/bin/env python3
"""Learns to steer one μAUV² to a depth and heading with its raw actuators, by the cross-entropy
method (CEM, a simple evolution strategy) on `shoal.rl.VehicleEnv`, in numpy only (no torch, no
GPU): under a minute on two cores.

The policy is linear, a = tanh(W·obs + b) (5 actuators × 10 observations + 5 = 55 numbers).
Each generation samples `POPULATION` policies from a Gaussian, scores each by its mean return
over the same `EPISODES` fresh random targets, and refits the Gaussian to the best `ELITE`.
The learning curve — the mean policy's return on `EVAL` fixed targets it never trains on,
next to the built-in controller's (auto mode given the target) — is written to
learning_curve.png and .svg, the policy to policy.npy.

    python/examples/train_cem.py [OUT_DIR] [--generations N]

Deterministic: the same arguments give the same curve.
"""

import argparse
import math
from pathlib import Path

import numpy as np

import shoal
from shoal.rl import VehicleEnv

POPULATION, ELITE, EPISODES = 24, 6, 4
#: Seeds of the evaluation targets.
EVAL = range(10_000, 10_008)


def rollout(env, params, seed):
    """Return of one episode of the linear policy `params` from the environment's `seed`."""
    n_a, n_o = env.action_space.shape[0], env.observation_space.shape[0]
    w, b = params[: n_a * n_o].reshape(n_a, n_o), params[n_a * n_o :]
    obs, _ = env.reset(seed=int(seed))
    total, done = 0.0, False
    while not done:
        obs, r, terminated, truncated, _ = env.step(np.tanh(w @ obs + b))
        total, done = total + r, terminated or truncated
    return total


def controller_return(seed, max_steps):
    """Return of the built-in controller (auto mode, setpoints = the target) on `seed`."""
    env = VehicleEnv(action="setpoint", max_steps=max_steps)
    _, info = env.reset(seed=int(seed))
    a = np.array([info["target_depth"] / 1.5 - 1.0, info["target_heading"] / math.pi])
    total, done = 0.0, False
    while not done:
        _, r, terminated, truncated, _ = env.step(a)
        total, done = total + r, terminated or truncated
    return total


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out", nargs="?", default="out/train_cem", help="output folder")
    ap.add_argument("--generations", type=int, default=40)
    ap.add_argument("--steps", type=int, default=200, help="steps per episode (0.05 s each)")
    args = ap.parse_args()
    env = VehicleEnv(action="raw", max_steps=args.steps)
    n = env.action_space.shape[0] * (env.observation_space.shape[0] + 1)
    rng = np.random.default_rng(1)
    mean, std = np.zeros(n), np.full(n, 0.5)
    reference = np.mean([controller_return(s, args.steps) for s in EVAL])
    curve = []
    for g in range(args.generations):
        seeds = rng.integers(0, 2**31, EPISODES)
        pop = mean + std * rng.standard_normal((POPULATION, n))
        score = np.array([np.mean([rollout(env, p, s) for s in seeds]) for p in pop])
        elite = pop[np.argsort(score)[-ELITE:]]
        mean, std = elite.mean(axis=0), elite.std(axis=0) + 0.02
        held_out = np.mean([rollout(env, mean, s) for s in EVAL])
        curve.append((g + 1, held_out, reference))
        print(f"generation {g + 1:3d}: population mean {score.mean():7.1f}, best {score.max():7.1f}; "
              f"mean policy on the held-out targets {held_out:7.1f} "
              f"(built-in controller {reference:.1f})", flush=True)
    c = np.array(curve)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    np.save(out / "policy.npy", mean)
    files = shoal.plot(
        out / "learning_curve",
        [("CEM mean policy", c[:, 0], c[:, 1]), ("built-in controller", c[:, 0], c[:, 2], True)],
        title="CEM on VehicleEnv (raw actuators): reach depth and heading",
        x_label="generation", y_label=f"mean return, {len(EVAL)} held-out targets ({args.steps} steps)")
    print("wrote", ", ".join(str(f) for f in files))


if __name__ == "__main__":
    main()
