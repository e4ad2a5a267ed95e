#!/usr/bin/python3
"""Compaction in pressure steps, recording E(p): one deposit pressed by the piston at p, until
it blocks, then at 2p, 4p, ... each step continuing the packing the last one left. The
command line compacts at one pressure; here the same packing carries a loading history.
Writes pressure_steps.csv (p, E, sigma_zz/p) in the working folder. With the quick example
(100 spheres) it takes a few seconds; pass a scene file to use another:
    PYTHONPATH=build/release/python examples/python/pressure_steps.py [SCENE.toml]"""
import csv
import sys
from pathlib import Path

import cdpowder

path = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parents[1] / "quick/scene.toml"
base = cdpowder.Scene.from_toml(path)
p0 = base["piston.pressure"]  # a value of the resolved scene
world = cdpowder.deposit(base)
rows = []
for k in range(6):
    p = p0 * 2**k
    result = cdpowder.compact(base.with_overrides({"piston.pressure": p}), world=world)
    world = result.world  # the next pressure presses this packing
    rows.append((p, result.porosity, result.sigma[2, 2] / p))
    print(f"p = {p:.5f} F_coh/R²: E = {result.porosity:.5f}, sigma_zz/p = {rows[-1][2]:.4f}, "
          f"blocked = {result.blocked}")
with open("pressure_steps.csv", "w", newline="") as f:
    writer = csv.writer(f)
    writer.writerow(["pressure", "porosity", "sigma_zz_over_pressure"])
    writer.writerows(rows)
