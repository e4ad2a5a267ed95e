"""One packing before and after compaction (the paper's Fig. 3), seen from the side (x–z).

Spheres are shaded by depth y (the far ones darker and drawn first); the bottom wall, the
periodic cell's side boundaries x = 0 and x = L_x and the piston are drawn where the run's
summary.json gives them: the piston where it started (the scene's `piston.height`, else the
deposit's top plus `piston.start_gap`) and where it came to rest.
"""
import json

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from .figures import label_panel, save

PISTON_DRAWN_THICKNESS = 1.0  # R: the piston is a plane; a band makes it visible
WALL_COLOUR = "0.45"


def _read_particles(path):
    return pd.read_csv(path, comment="#")


class RunGeometry:
    """What the run's summary.json tells about the picture (None for what it lacks): the
    piston's height at the start and at the end [R], the cell length L_x [R], and the
    porosity before and after."""

    def __init__(self, run_folder, top_of_deposit):
        try:
            summary = json.loads((run_folder / "summary.json").read_text())
        except (OSError, ValueError):
            summary = {}
        scene = summary.get("scene") or {}
        piston = scene.get("piston") or {}
        self.cell = (scene.get("system") or {}).get("lx")
        self.porosity = (summary.get("initial_porosity"), summary.get("porosity"))
        self.piston = (None, None)
        if (summary.get("piston") or {}).get("enabled"):
            start = piston.get("height")
            if start is None and piston.get("start_gap") is not None:
                start = top_of_deposit + piston["start_gap"]
            self.piston = (start, summary["piston"].get("height"))


def _draw_spheres(ax, spheres, depth_range):
    far_first = spheres.sort_values("y", ascending=False)
    low, span = depth_range
    for x, y, z, r in far_first[["x", "y", "z", "r"]].itertuples(index=False):
        shade = 0.25 + 0.6 * (y - low) / span
        ax.add_patch(plt.Circle((x, z), r, color=plt.cm.copper(shade), lw=0))


def _draw_walls(ax, piston_height, cell, x_range):
    left, right = x_range
    ax.axhspan(-PISTON_DRAWN_THICKNESS, 0.0, color=WALL_COLOUR, lw=0)
    if cell is not None:
        for x in (0.0, cell):
            ax.axvline(x, color="black", linestyle="--", linewidth=0.8)
    if piston_height is not None:
        ax.add_patch(plt.Rectangle((left, piston_height), right - left,
                                   PISTON_DRAWN_THICKNESS, color=WALL_COLOUR, lw=0))
        ax.text((left + right) / 2, piston_height + PISTON_DRAWN_THICKNESS, "piston",
                ha="center", va="bottom", fontsize=8)


def plot_packing(run_folder, out):
    """packing.{png,svg,pdf} from a run folder with initial_particles.csv and particles.csv."""
    before = _read_particles(run_folder / "initial_particles.csv")
    after = _read_particles(run_folder / "particles.csv")
    top = float((before["z"] + before["r"]).max())
    run = RunGeometry(run_folder, top)
    ceiling = max(top, run.piston[0] or 0.0) + 2 * PISTON_DRAWN_THICKNESS + 1
    both = pd.concat([before, after])
    depth_range = (float(both["y"].min()), max(float(np.ptp(both["y"])), 1e-9))
    left = min(0.0, float((both["x"] - both["r"]).min())) - 1
    right = max(run.cell or 0.0, float((both["x"] + both["r"]).max())) + 1
    fig, axes = plt.subplots(1, 2, figsize=(8, 8 * ceiling / 60 + 1), sharey=True)
    panels = zip(axes, (before, after), run.piston, ("deposit", "compacted"), run.porosity)
    for k, (ax, spheres, piston, title, porosity) in enumerate(panels):
        _draw_spheres(ax, spheres, depth_range)
        _draw_walls(ax, piston, run.cell, (left, right))
        ax.set_aspect("equal")
        ax.set_xlim(left, right)
        ax.set_ylim(-PISTON_DRAWN_THICKNESS, ceiling)
        ax.set_title(title + (f", E = {porosity:.3f}" if porosity is not None else ""))
        ax.set_xlabel("x [R]")
        label_panel(ax, "(" + "ab"[k] + ")")
    axes[0].set_ylabel("z [R]")
    axes[0].annotate("shade: depth y (darker is further back); dashed: the periodic cell; "
                     "grey: bottom wall and piston", (0.0, 0.0), xycoords="axes fraction",
                     xytext=(0, -34), textcoords="offset points", fontsize=7, va="top")
    save(fig, out, "packing")
