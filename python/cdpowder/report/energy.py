"""Where the piston's work goes (physics.md §17, "The energy budget"): each point's porosity
beside its runs' energy budget from summary.json `energy`, as fractions of the piston's work,
a table and a figure; nothing where no run has a complete budget."""
import json

import numpy as np

from .data import Stat
from .figures import plt, save
from .sections import table

# (column, summary.json energy → value) for each run; W is the work of the piston and gravity
COLUMNS = (
    ("E", lambda s, e, w: s.get("porosity")),
    ("W [F_coh R]", lambda s, e, w: w),
    ("bonds formed", lambda s, e, w: e["bonds_formed"]),
    ("bonds broken", lambda s, e, w: e["bonds_broken"]),
    ("breaking work / W", lambda s, e, w: e["breaking_work"] / w),
    ("−ΔU_coh / W", lambda s, e, w: -(e["cohesive_end"] - e["cohesive_start"]) / w),
    ("dissipated / W", lambda s, e, w: e["dissipated"] / w),
)


def collect(sweep_dir, sweep):
    """{point: {column: [value over seeds]}} for the runs used whose budget is complete."""
    found = {}
    for _, row in sweep.kept.sort_values(["point", "seed"]).iterrows():
        try:
            summary = json.loads((sweep_dir / row["folder"] / "summary.json").read_text())
        except (OSError, ValueError, TypeError):
            continue
        energy = summary.get("energy") or {}
        if not energy.get("complete"):
            continue
        work = energy["piston_work"] + energy["gravity_work"]
        if not work > 0:
            continue
        point = found.setdefault(row["point"], {name: [] for name, _ in COLUMNS})
        for name, value in COLUMNS:
            point[name].append(value(summary, energy, work))
    return found


def section(sweep_dir, sweep, out):
    """The markdown lines of the section, with its figure; [] when no run has a budget."""
    found = collect(sweep_dir, sweep)
    if not found:
        return []
    rows = [[f"`{point}`", str(len(values["E"]))] +
            [Stat(values[name]).text(0 if name.startswith("bonds") or name.startswith("W")
                                     else 3) for name, _ in COLUMNS]
            for point, values in found.items()]
    md = ["## Where the piston's work goes (physics.md §17, \"The energy budget\")", "",
          "W is the work of the piston's applied force and of gravity over the run; the "
          "cohesive bonds the steps formed and broke; the work that breaking them took "
          "(F_coh d_coh each); the energy the bonds' attraction gave back, net (−ΔU_coh); and "
          "what the contacts dissipated, W − ΔK − ΔU_coh. Mean ± standard error over the "
          "seeds whose budget is complete.", ""]
    md += table(["point", "seeds"] + [name for name, _ in COLUMNS], rows)
    return md + ["", f"![energy budget]({draw(found, out)}.png)", ""]


def draw(found, out):
    """Per point: the breaking work, the net cohesive energy given back and the dissipation as
    fractions of W (means over seeds), with the porosity on a second axis."""
    fig, ax = plt.subplots(figsize=(max(4.5, 0.7 * len(found) + 2), 3.4))
    x = np.arange(len(found))
    for offset, (name, colour) in zip((-0.25, 0.0, 0.25), (
            ("breaking work / W", "tab:red"), ("−ΔU_coh / W", "tab:green"),
            ("dissipated / W", "tab:blue"))):
        stats = [Stat(values[name]) for values in found.values()]
        ax.bar(x + offset, [s.mean for s in stats], width=0.25, color=colour, label=name,
               yerr=[s.error_bar() for s in stats])
    ax.set_ylabel("fraction of W")
    ax.set_xticks(x, list(found), rotation=30, ha="right", fontsize=7)
    porosity = ax.twinx()
    porosity.plot(x, [Stat(values["E"]).mean for values in found.values()], "ko", label="E")
    porosity.set_ylabel("porosity E")
    ax.legend(frameon=False, fontsize=7, loc="upper left")
    save(fig, out, "energy_budget")
    return "energy_budget"
