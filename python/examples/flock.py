#!/usr/bin/env python3
"""Flocking (Reynolds' boids) of 1,000 μAUV² in numpy: every 0.25 s each vehicle steers towards
the mean heading of its neighbours within 4 m (alignment) and their centre (cohesion), away
from those closer than 0.6 m (separation) and from the pool's walls; the built-in controller
holds 1.5 m depth and the heading, with a 0.03 N push. Prints how aligned the vehicles are
with their neighbours (1: all alike) and the swarm as a whole. Usage: flock.py [WORLD] [SECONDS]"""
import sys

import numpy as np

import shoal

world = shoal.World(sys.argv[1] if len(sys.argv) > 1 else "worlds/flock_1000.toml")
seconds = float(sys.argv[2]) if len(sys.argv) > 2 else 60.0
size = np.array(world.pool_size[:2])
for k in range(round(seconds / 0.25)):
    p, yaw = world.position[:, :2], world.imu_euler[:, 2]
    heading = np.column_stack([np.cos(yaw), np.sin(yaw)])
    d = p[None, :, :] - p[:, None, :]                    # offsets from i to j [m]
    dist = np.hypot(d[..., 0], d[..., 1])
    np.fill_diagonal(dist, np.inf)
    near, close = dist < 4.0, dist < 0.6
    count = np.maximum(near.sum(axis=1), 1)[:, None]
    align = near @ heading / count
    cohere = np.einsum("ij,ijk->ik", near, d) / count
    separate = -np.einsum("ij,ijk->ik", close, d / dist[..., None] ** 2)
    wall = np.clip(5.0 - p, 0, None) - np.clip(p - (size - 5.0), 0, None)
    steer = heading + 5.0 * align + 0.1 * cohere + 0.2 * separate + 0.5 * wall
    world.step({"yaw": np.arctan2(steer[:, 1], steer[:, 0]), "depth": 1.5, "surge": 0.03},
               steps=25)
    if k % 20 == 0:
        local = np.linalg.norm((near @ heading + heading) / (count + 1), axis=1).mean()
        print(f"t = {world.time:5.2f} s: alignment with neighbours {local:.2f}, "
              f"whole swarm {np.linalg.norm(heading.mean(axis=0)):.2f}")
print("digest", world.digest)
