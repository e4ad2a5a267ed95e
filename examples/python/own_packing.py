#!/usr/bin/python3
"""A packing built in Python, compacted by the piston: does the deposit's structure set the
porosity after compaction? The command line starts from a ballistic deposit or a particles
CSV; here the spheres come from NumPy. A random loose packing (random sequential addition:
spheres placed at random where they overlap nothing, below the top of the ballistic deposit of
the same scene, so about as porous) and that ballistic deposit are compacted at the same
pressure. The deposit's spheres hang together in cohesive chains and keep much of their
porosity; the loose packing's touch nothing and rearrange until they do: with the quick
example, E = 0.913 → 0.910 against 0.912 → 0.760.
With the quick example (100 spheres) it takes a few seconds; pass a scene file to use another:
    PYTHONPATH=build/release/python examples/python/own_packing.py [SCENE.toml]"""
import sys
import tomllib
from pathlib import Path

import numpy as np

import cdpowder


def random_loose_packing(n, lx, ly, height, rng, radius=1.0):
    """n spheres of `radius`, centres uniform in the cell below `height`, none overlapping
    another (minimum image in x and y) or the bottom wall."""
    centres = np.empty((0, 3))
    cell = np.array([lx, ly])
    while len(centres) < n:
        trial = rng.uniform([0.0, 0.0, radius], [lx, ly, height - radius])
        d = centres - trial
        d[:, :2] -= cell * np.round(d[:, :2] / cell)
        if len(centres) == 0 or (d * d).sum(axis=1).min() >= (2 * radius) ** 2:
            centres = np.vstack([centres, trial])
    return centres


path = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parents[1] / "quick/scene.toml"
scene = cdpowder.Scene.from_toml(path)
resolved = tomllib.loads(scene.toml)
system, pressure = resolved["system"], resolved["piston"]["pressure"]
deposit = cdpowder.deposit(scene)
top = float((deposit.positions[:, 2] + deposit.radii).max())
rng = np.random.default_rng(1)
loose = cdpowder.World.from_arrays(
    scene, random_loose_packing(len(deposit), system["lx"], system["ly"], top, rng),
    np.ones(len(deposit)))
for name, world in (("ballistic deposit", deposit), ("random loose packing", loose)):
    before = world.porosity
    result = cdpowder.compact(scene, world=world)
    print(f"{name}: E = {before:.4f} before, {result.porosity:.4f} after compaction "
          f"(blocked = {result.blocked}, sigma_zz/p = {result.sigma[2, 2] / pressure:.4f})")
