#!/usr/bin/python3
"""The paper's experiment at (mu_t, mu_n) = (0.3, 0.3): a ballistic deposit of 1 015 cohesive
spheres compacted by the piston until it blocks; prints the porosity and sigma_zz's parts over
the pressure (Table 1's quantities). About 15-20 s. Run from the repository with the module on
the path: PYTHONPATH=build/release/python examples/python/paper_experiment.py"""
from pathlib import Path

import cdpowder

scene = cdpowder.Scene.from_toml(Path(__file__).parents[1] / "paper/scene.toml",
                                 {"contact.mu_roll": 0.3, "contact.mu_twist": 0.3})
pressure = 1.0 / 400.0  # examples/paper/scene.toml: piston.pressure


def progress(world, step):
    print(f"t = {world.time:7.1f} t0  porosity {world.porosity:.4f}  "
          f"piston imbalance {step.piston_imbalance:.2e}")


result = cdpowder.compact(scene, callback=progress, every=2000)
print(f"blocked: {result.blocked}, porosity E = {result.porosity:.5f}")
print(f"sigma_zz/p = {result.sigma[2, 2] / pressure:.4f} = "
      f"{result.sigma_plus[2, 2] / pressure:.4f} (compressive) "
      f"{result.sigma_minus[2, 2] / pressure:+.4f} (tensile)")
