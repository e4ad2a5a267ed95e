"""The admissible σzz⁺/p of each point (physics.md §11.3), from the runs on which
`cdpowder stress-bounds` was run: a table and a figure, or nothing where no run has it."""
import json
import math

import numpy as np

from .data import Stat
from .figures import plt, save
from .sections import table

# the numbers of each run's summary.json "admissible_stress" the report shows, per σzz⁺
FIELDS = ("run", "min_attained", "max_attained", "min", "max")


def collect(sweep_dir, sweep):
    """{point: {field: [value over seeds]}} of σzz⁺/p, for the runs used that have it."""
    found = {}
    for _, row in sweep.kept.sort_values(["point", "seed"]).iterrows():
        path = sweep_dir / row["folder"] / "summary.json"
        try:
            summary = json.loads(path.read_text())
        except (OSError, ValueError, TypeError):
            continue
        bounds = summary.get("admissible_stress", {}).get("sigma_zz_plus")
        pressure = summary.get("piston", {}).get("applied_pressure")
        if not bounds or not pressure:
            continue
        point = found.setdefault(row["point"], {field: [] for field in FIELDS})
        for field in FIELDS:
            value = bounds.get(field)
            point[field].append(math.nan if value is None else value / pressure)
    return found


def section(sweep_dir, sweep, out):
    """The markdown lines of the section, with its figure; [] when no run has the interval."""
    found = collect(sweep_dir, sweep)
    if not found:
        return []
    rows = []
    for point, values in found.items():
        stats = {field: Stat(values[field]) for field in FIELDS}
        rows.append([f"`{point}`", str(len(values["run"]))] +
                    [stats[field].text(3) for field in FIELDS])
    figure = draw(found, out)
    md = ["## The admissible σzz⁺/p (physics.md §11.3)", "",
          "Each run's packing, its geometry and cohesion states fixed: the σzz⁺/p of the run's "
          "forces, the smallest and largest that admissible force sets reach (`attained`), and "
          "the bounds no admissible force set passes (`cdpowder stress-bounds`). Mean ± "
          "standard error over the seeds that have it.", ""]
    md += table(["point", "seeds", "run", "min attained", "max attained", "bound min",
                 "bound max"], rows)
    return md + ["", f"![admissible]({figure}.png)", ""]


def draw(found, out):
    """Per point: the attained interval (bar), the run's value (dot), means over seeds."""
    fig, ax = plt.subplots(figsize=(max(4.0, 0.6 * len(found) + 2), 3.2))
    for x, (point, values) in enumerate(found.items()):
        low, high, run = (np.nanmean(values[f]) for f in ("min_attained", "max_attained", "run"))
        ax.plot([x, x], [low, high], color="tab:blue", linewidth=6, alpha=0.5,
                label="attained" if x == 0 else None)
        ax.plot(x, run, "o", color="black", label="the run" if x == 0 else None)
    ax.set_xticks(range(len(found)), list(found), rotation=30, ha="right", fontsize=7)
    ax.set_xlim(-0.5, len(found) - 0.5)
    ax.set_ylabel(r"$\sigma^+_{zz}/p$")
    ax.legend(frameon=False)
    save(fig, out, "admissible")
    return "admissible"
