"""A loading path's stages (a Python protocol such as examples/paper/load_path.py that returns
{"stages": [{"pressure_over_p", "porosity", "sigma_zz_plus_over_applied", …}, …]} into each
run's protocol.json): per point, E after every stage, its change from the first stage paired
by seed, how many packings moved, and σzz⁺ over the stage's applied pressure; a figure of E
along the path. Nothing where no run has such a record."""
import json

import numpy as np

from .data import Stat
from .figures import ordered_colours, plt, save
from .sections import table

# a packing "moved" in a stage when its porosity changed by more than this from the first stage
MOVED = 1e-4


def collect(sweep_dir, sweep):
    """{point: [stages of each seed's run, in seed order]} for the runs used whose protocol.json
    has stages, every run of a point with the same pressures."""
    found = {}
    for _, row in sweep.kept.sort_values(["point", "seed"]).iterrows():
        path = sweep_dir / row["folder"] / "protocol.json"
        try:
            stages = json.loads(path.read_text())["returned"]["stages"]
            pressures = [float(s["pressure_over_p"]) for s in stages]
            if not all(isinstance(s["porosity"], (int, float)) for s in stages):
                continue
        except (OSError, ValueError, TypeError, KeyError):
            continue
        runs = found.setdefault(row["point"], [])
        if runs and [float(s["pressure_over_p"]) for s in runs[0]] != pressures:
            continue  # another path: not averaged with this one
        runs.append(stages)
    return found


def section(sweep_dir, sweep, out):
    found = collect(sweep_dir, sweep)
    if not found:
        return []
    md = ["## Loading path", "",
          "Each run's packing loaded stage by stage (its protocol.json): E after each stage, "
          "ΔE from the first stage paired by seed, the packings whose porosity changed by more "
          f"than {MOVED:g} from the first stage, and σzz⁺ over the stage's applied pressure. "
          "Mean ± standard error over seeds.", ""]
    for point, runs in found.items():
        rows = []
        first = np.array([r[0]["porosity"] for r in runs], dtype=float)
        for k, stage in enumerate(runs[0]):
            porosity = np.array([r[k]["porosity"] for r in runs], dtype=float)
            change = porosity - first
            stress = [r[k].get("sigma_zz_plus_over_applied", float("nan")) for r in runs]
            rows.append([str(k + 1), f"{float(stage['pressure_over_p']):g}",
                         Stat(porosity).text(4), "–" if k == 0 else Stat(change).text(4),
                         f"{int(np.sum(np.abs(change) > MOVED))} of {len(runs)}",
                         Stat(stress).text(2)])
        md += [f"`{point}`, {len(runs)} seeds:", ""]
        md += table(["stage", "p / p0", "E", "ΔE from stage 1", "moved", "σzz⁺ / applied"],
                    rows) + [""]
    draw(found, out)
    return md + ["![loading path](load_path.png)", ""]


def draw(found, out):
    """E against the applied pressure along the path, one curve per point (mean ± standard
    error over seeds); the stages after the rising ones (an unloading) dashed."""
    fig, ax = plt.subplots(figsize=(5.5, 3.8))
    for colour, (point, runs) in zip(ordered_colours(len(found)), found.items()):
        xs = [float(s["pressure_over_p"]) for s in runs[0]]
        stats = [Stat([r[k]["porosity"] for r in runs]) for k in range(len(xs))]
        ys = [s.mean for s in stats]
        bars = [s.error_bar() for s in stats]
        # the loading: pressures rising from the first stage; after it, each stage its own
        rising = 1
        while rising < len(xs) and xs[rising] > xs[rising - 1]:
            rising += 1
        ax.errorbar(xs[:rising], ys[:rising], yerr=bars[:rising], marker="o", markersize=4,
                    capsize=2.5, color=colour, label=point)
        if rising < len(xs):
            ax.plot(xs[rising - 1:], ys[rising - 1:], linestyle="--", color=colour, marker="s",
                    markersize=4)
    ax.set_xscale("log")
    ax.set_xlabel("applied pressure / p0")
    ax.set_ylabel("porosity E")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    save(fig, out, "load_path")
