#!/usr/bin/python3
"""A compaction stepped from Python, reading the forces as it goes: every 50 steps the piston's
height, the largest normal contact force and the largest net force on a sphere (its contacts'
sum: how far from balance the packing is), until the packing blocks or the scene's
run.max_duration ends it. The steps are those of `cdpowder compact` on the scene, bit for bit.
    PYTHONPATH=build/release/python examples/python/step_loop.py [SCENE.toml]"""
import sys
from pathlib import Path

import numpy as np

import cdpowder

path = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parents[1] / "quick/scene.toml"
world = cdpowder.deposit(cdpowder.Scene.from_toml(path))
while True:
    before = world.step_count
    result = world.run(steps=50)  # fewer steps once the packing blocks
    normal = world.contacts()["normal_force"]
    net = np.linalg.norm(world.forces(), axis=1)
    print(f"t = {world.time:7.2f} t0  Z_P = {world.piston_height:6.3f} R  largest normal force "
          f"{normal.max():.3f} F_coh  largest net force {net.max():.1e} F_coh")
    if world.step_count - before < 50:
        break
print(f"blocked = {result.blocked}, E = {world.porosity:.4f}, "
      f"sigma_zz = {world.stress()['sigma'][2, 2]:.3e} F_coh/R²")
