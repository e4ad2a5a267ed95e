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


def short(point):
    """A point's name on an axis: its keys without their section, one a line."""
    return "\n".join(part.split("=")[0].split(".")[-1] + "=" + part.split("=", 1)[1]
                     if "=" in part else part for part in point.split(","))


def draw(found, out):
    """Per point, means over seeds with their standard errors: (a) the bonds broken in a run,
    with the porosity on a second axis; (b) the breaking work, the cohesive energy given back
    and the dissipation as fractions of W, on a log scale (the breaking work is a hundredth of
    the rest)."""
    x = np.arange(len(found))
    labels = [short(point) for point in found]
    fig, (bonds, shares) = plt.subplots(1, 2, figsize=(max(8.0, 1.6 * len(found) + 2), 3.8))
    broken = [Stat(values["bonds broken"]) for values in found.values()]
    # a log scale has no 0: a point with no bond broken (or no share) has no bar
    bonds.bar(x, [s.mean if s.mean > 0 else np.nan for s in broken],
              yerr=[s.error_bar() for s in broken],
              color="tab:red", label="bonds broken")
    bonds.set_yscale("log")
    bonds.set_ylabel("bonds broken in a run")
    bonds.set_title("(a)", loc="left")
    porosity = bonds.twinx()
    porosity.errorbar(x, [Stat(values["E"]).mean for values in found.values()],
                      yerr=[Stat(values["E"]).error_bar() for values in found.values()],
                      fmt="ko", label="E")
    porosity.set_ylabel("porosity E")
    for offset, (name, colour) in zip((-0.27, 0.0, 0.27), (
            ("breaking work / W", "tab:red"), ("−ΔU_coh / W", "tab:green"),
            ("dissipated / W", "tab:blue"))):
        stats = [Stat(values[name]) for values in found.values()]
        shares.bar(x + offset, [s.mean if s.mean > 0 else np.nan for s in stats], width=0.27,
                   color=colour,
                   label=name)
    shares.set_yscale("log")
    shares.set_ylabel("fraction of W")
    shares.set_title("(b)", loc="left")
    shares.legend(frameon=False, fontsize=7)
    for ax in (bonds, shares):
        ax.set_xticks(x, labels, fontsize=6, rotation=30, ha="right")
    fig.tight_layout()
    save(fig, out, "energy_budget")
    return "energy_budget"
