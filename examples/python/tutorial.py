#!/usr/bin/python3
"""The tutorial's script (docs/tutorial.md): the paper's question at 100 spheres. Each seed's
deposit is compacted at (mu_t, mu_n) = (0, 0), (1, 0), (0, 1) and (1, 1); the added porosity
E1 = E - E0 of rolling, torsion and both is paired by seed and drawn as tutorial.png, with the
paper's values. About a minute on one core.
    PYTHONPATH=build/release/python examples/python/tutorial.py [SEEDS]"""
import sys
from pathlib import Path

import matplotlib
import numpy as np

import cdpowder

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after the backend)

seeds = int(sys.argv[1]) if len(sys.argv) > 1 else 3
base = cdpowder.Scene.from_toml(Path(__file__).parents[1] / "quick/scene.toml")
points = {"E0": (0, 0), "rolling": (1, 0), "torsion": (0, 1), "both": (1, 1)}
porosity = {name: [] for name in points}
for seed in range(1, seeds + 1):
    # the same deposit (its seed) at each point: the pairs differ by the torques alone
    for name, (mu_t, mu_n) in points.items():
        scene = base.with_overrides({"deposition.seed": seed, "contact.mu_roll": mu_t,
                                     "contact.mu_twist": mu_n})
        result = cdpowder.compact(scene)
        assert result.blocked and abs(result.sigma[2, 2] / scene["piston.pressure"] - 1) < 0.01
        porosity[name].append(result.porosity)
E0 = np.array(porosity["E0"])
rows = []
for name in ("rolling", "torsion", "both"):
    added = np.array(porosity[name]) - E0  # paired by seed
    error = added.std(ddof=1) / np.sqrt(len(added)) if len(added) > 1 else 0.0
    rows.append((name, added.mean(), error))
    print(f"E1 ({name}) = {added.mean():.4f} ± {error:.4f}")
print(f"E0 = {E0.mean():.4f} over {seeds} seeds")

figure, axes = plt.subplots(figsize=(5, 3.5))
x = np.arange(len(rows))
axes.bar(x, [r[1] for r in rows], yerr=[r[2] for r in rows], capsize=4, label="cdpowder, N = 100")
axes.plot(x, [0.18, 0.08, 0.28], "k*", markersize=12, label="the paper, N = 1015")
axes.set_xticks(x, ["rolling (1, 0)", "torsion (0, 1)", "both (1, 1)"])
axes.set_ylabel(r"added porosity $E_1 = E - E_0$")
axes.legend()
figure.tight_layout()
figure.savefig("tutorial.png", dpi=120)
print("figure: tutorial.png")
