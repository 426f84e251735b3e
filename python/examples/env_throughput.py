#!/usr/bin/env python3
"""Steps per second of quadex's learning environment (quadex.env.QuadexEnv)
against FreeMesh-RL's own (rl/boundary_env.py of
design-zeng/ReinforcementLearning4MeshGeneration, MIT), on the same domains,
in one run.

Both read the domain from FreeMesh-RL's file (ui/domains/NAME.json, as its
read_polygon reads it: pixels / 100) and step one episode with a fixed
policy: uniform random actions from each environment's action box (seeded),
until the episode ends (FreeMesh-RL's ends when the domain is meshed or
after 100 failed steps in a row: "gave up") or STEPS steps ("cut"). quadex is also stepped with its
model's own actions (the episode that meshes the domain). Only env.step is
timed.

FreeMesh-RL's code is imported from the checkout given, not copied. Its
modules import packages its environment does not use to step (torch, pycuda,
pygame, stable-baselines3, seaborn, pandas, gym); those that are missing are
replaced by empty stand-ins so the environment can be imported, and numpy 2's
missing np.math is given back as the standard math module.

usage: env_throughput.py FREEMESH_CHECKOUT [NAME ...]   (default: test1 dolphine3)
"""

import importlib
import json
import os
import sys
import time
import types

import numpy as np

STEPS = 2000
SEED = 1


class _Anything(types.ModuleType):
    """A stand-in module: any attribute is another stand-in."""

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        return _Anything(f"{self.__name__}.{name}")

    def __call__(self, *a, **k):
        return _Anything("call")


def stand_ins():
    # numpy 2 dropped np.math, the standard math module under another name
    # (FreeMesh-RL pins numpy 1.16).
    if not hasattr(np, "math"):
        import math

        np.math = math
    for name in ["torch", "pycuda", "pycuda.driver", "pygame", "stable_baselines3",
                 "stable_baselines3.common", "stable_baselines3.common.env_checker",
                 "seaborn", "pandas"]:
        try:
            importlib.import_module(name)
        except ImportError:
            sys.modules[name] = _Anything(name)
    try:
        importlib.import_module("gym")
    except ImportError:
        gym = types.ModuleType("gym")
        spaces = types.ModuleType("gym.spaces")

        class Box:
            def __init__(self, low, high, shape=None, dtype=None):
                self.low, self.high, self.shape = np.asarray(low), np.asarray(high), shape

        spaces.Box = Box
        gym.Env, gym.spaces = object, spaces
        sys.modules["gym"], sys.modules["gym.spaces"] = gym, spaces


def their_run(checkout, name):
    sys.path.insert(0, checkout)
    stand_ins()
    from rl.boundary_env import BoudaryEnv, read_polygon

    env = BoudaryEnv(read_polygon(os.path.join(checkout, "ui", "domains", f"{name}.json")))
    rng = np.random.default_rng(SEED)
    low, high = np.array([-1, -1.5, 0]), np.array([1, 1.5, 1.5])  # its action_space
    env.reset()
    steps, done, elapsed = 0, False, 0.0
    while not done and steps < STEPS:
        a = rng.uniform(low, high)
        t = time.perf_counter()
        _, _, done, info = env.step(a)
        elapsed += time.perf_counter() - t
        steps += 1
    return steps, elapsed, len(env.generated_meshes), "complete" if info.get("is_complete") and done else "gave up" if done else "cut"


def our_run(loops, policy):
    from quadex.env import QuadexEnv

    env = QuadexEnv(loops, max_steps=STEPS)
    rng = np.random.default_rng(SEED)
    env.reset(seed=SEED)
    steps, done, elapsed, quads = 0, False, 0.0, None
    while not done:
        a = env.model_action() if policy == "model" else rng.uniform([0, -0.5, 0], [2, 1.5, 1.5])
        t = time.perf_counter()
        _, _, terminated, truncated, info = env.step(a)
        elapsed += time.perf_counter() - t
        steps += 1
        done = terminated or truncated
    if terminated and "quality" in info:
        quads = info["quality"]["quads"]
    return steps, elapsed, quads, "complete" if terminated else "cut"


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    checkout = os.path.abspath(sys.argv[1])
    names = sys.argv[2:] or ["test1", "dolphine3"]
    print(f"{'domain':<10} {'environment':<28} {'steps':>6} {'seconds':>8} {'steps/s':>9} {'quads':>6} episode")
    for name in names:
        with open(os.path.join(checkout, "ui", "domains", f"{name}.json")) as f:
            pts = np.array(json.loads(f.readline()), dtype=float) / 100.0
        rows = []
        n, s, q, d = their_run(checkout, name)
        rows.append(("FreeMesh-RL, random", n, s, q, d))
        theirs = n / s
        for policy in ("random", "model"):
            n, s, q, d = our_run([pts], policy)
            rows.append((f"quadex, {policy}", n, s, q, d))
        for label, n, s, q, d in rows:
            print(f"{name:<10} {label:<28} {n:>6} {s:>8.3f} {n / s:>9.0f} {q if q is not None else '-':>6} {d}")
        for label, n, s, _, _ in rows[1:]:
            print(f"{name:<10} ratio {label} / FreeMesh-RL: {n / s / theirs:.1f}x")


if __name__ == "__main__":
    main()
