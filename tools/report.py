#!/usr/bin/python3
"""Turns a `cdpowder sweep` folder into the figures and tables of the paper's comparison.

    tools/report.py SWEEP_DIR [--out DIR] [--all-runs] [--seeds LIST] [--packing RUN_FOLDER]

Reads SWEEP_DIR/results.csv (one row per run) and writes into DIR (default SWEEP_DIR/report):

  fig5_porosity.png/.svg   porosity E against μt for each μn, and against μn for each μt
                           (the paper's Fig. 5), mean ± standard error over seeds
  added_porosity.png/.svg  E1(μt, μn) = E(μt, μn) − E(0, 0) as a map
  additivity.png/.svg      ΔE = E1(μt, μn) − E1(μt, 0) − E1(0, μn) as a map
  packing.png/.svg         one packing before and after compaction (the paper's Fig. 3)
  report.md                the points table, Table 1 beside the paper, the paper's claims
                           with cdpowder's numbers ± error (E0, E(1, 1), the E1 values and
                           their ratio, the ratio along the axes, the additivity residual,
                           saturation along three lines, E(1, 1) against E_init)

Differences between points (E1, ΔE) are paired by seed: runs with the same seed start from
the same deposit, so their difference has a much smaller spread than either porosity.
Only runs that reached the blocked state count, unless --all-runs (for quick looks at
unfinished sweeps; the report then says so). --seeds 1-2 (or 1,2,5) keeps only those seeds:
a sweep that is still running has more seeds at some points than at others, and a report
over the seeds every point has compares like with like. Uses numpy and matplotlib (Debian's
python3-numpy, python3-matplotlib); run with Debian's /usr/bin/python3.
"""
import argparse
import csv
import math
import pathlib
import re
import sys

import matplotlib

matplotlib.use("Agg")
# Same data, same bytes: SVG element ids from a fixed salt and no creation date, so a
# regenerated report changes in git only where its numbers do.
matplotlib.rcParams["svg.hashsalt"] = "cdpowder-report"
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

MU_T = "contact.mu_roll"
MU_N = "contact.mu_twist"
# The paper's Table 1: (μt, μn) → (σzz, σzz+, σzz−) / p
PAPER_TABLE1 = {
    (0.0, 0.0): (1.0, 2.2, -1.2),
    (0.1, 0.1): (1.0, 1.4, -0.4),
    (0.3, 0.3): (1.0, 1.1, -0.1),
    (1.0, 1.0): (1.0, 1.1, -0.1),
    (0.0, 0.3): (1.0, 2.2, -1.2),
    (0.0, 1.0): (1.0, 1.9, -0.9),
    (0.3, 0.0): (1.0, 1.2, -0.2),
    (1.0, 0.0): (1.0, 1.4, -0.4),
}
# The paper's porosities and added porosities E1 = E − E0 (its text, "≈" values)
PAPER_E0 = 0.54
PAPER_E11 = 0.82
PAPER_E1_ROLL = 0.18    # E1(1, 0)
PAPER_E1_TWIST = 0.08   # E1(0, 1)
PAPER_E1_BOTH = 0.28    # E1(1, 1)
# Saturation is judged only along a line with at least this many μ values (the mesh has 8)
SATURATION_MIN_POINTS = 5


def read_csv(path):
    """Rows of a cdpowder CSV as dicts (the '#' provenance lines skipped)."""
    with open(path, newline="") as f:
        lines = [line for line in f if not line.startswith("#")]
    return list(csv.DictReader(lines))


def provenance(path):
    with open(path) as f:
        return [line.rstrip("\n") for line in f if line.startswith("#")]


def num(text):
    """A CSV number; empty cells (non-finite values, or σ/p without a pressure) are NaN."""
    return float(text) if text not in ("", None) else math.nan


class Stat:
    """Mean and standard error of the mean of a sample (NaN entries left out)."""

    def __init__(self, values):
        values = np.asarray(values, dtype=float)
        self.values = values[np.isfinite(values)]
        self.n = len(self.values)
        self.mean = float(self.values.mean()) if self.n else math.nan
        self.sem = float(self.values.std(ddof=1) / math.sqrt(self.n)) if self.n > 1 else math.nan

    def text(self, digits=3):
        if self.n == 0:
            return "–"
        if math.isnan(self.sem):
            return f"{self.mean:.{digits}f} (n = 1)"
        return f"{self.mean:.{digits}f} ± {self.sem:.{digits}f}"


def parameter_columns(rows):
    """The sweep's parameter keys: the columns between 'point' and 'seed'."""
    if not rows:
        return []
    names = list(rows[0].keys())
    return names[names.index("point") + 1:names.index("seed")]


def parse_seeds(text):
    """'1-3,5' → {1, 2, 3, 5}; raises ValueError naming the bad item."""
    seeds = set()
    for item in text.split(","):
        m = re.fullmatch(r"\s*(\d+)\s*(?:-\s*(\d+)\s*)?", item)
        if not m or (m[2] and int(m[2]) < int(m[1])):
            raise ValueError(f"'{item}' is not a seed or a rising range of seeds (1, 1-3)")
        seeds.update(range(int(m[1]), int(m[2] or m[1]) + 1))
    return seeds


def load(sweep_dir, all_runs, seeds=None):
    """runs: (μt, μn) → {seed: row} for the points that change nothing else; variants:
    point name → {seed: row} for points that also change another key (sensitivity).
    seeds: if given, the set of seeds to keep (the others are left out everywhere)."""
    rows = read_csv(sweep_dir / "results.csv")
    if seeds is not None:
        rows = [r for r in rows if int(r["seed"]) in seeds]
    kept = [r for r in rows if all_runs or r["blocked"] == "1"]
    others = [k for k in parameter_columns(rows) if k not in (MU_T, MU_N)]
    runs, variants = {}, {}
    for r in kept:
        if any(r[k] != "" for k in others) or r.get(MU_T, "") == "" or r.get(MU_N, "") == "":
            variants.setdefault(r["point"], {})[int(r["seed"])] = r
            continue
        key = (float(r[MU_T]), float(r[MU_N]))
        runs.setdefault(key, {})[int(r["seed"])] = r
    return rows, kept, runs, variants


def stat_of(runs, point, column):
    rows = runs.get(point, {})
    return Stat([num(r[column]) for r in rows.values()])


def paired(runs, plus, minus, column="porosity"):
    """Σ plus − Σ minus over the seeds every point shares (lists of points)."""
    points = plus + minus
    if any(p not in runs for p in points):
        return Stat([])
    seeds = set.intersection(*(set(runs[p]) for p in points))
    values = []
    for s in sorted(seeds):
        values.append(sum(num(runs[p][s][column]) for p in plus) -
                      sum(num(runs[p][s][column]) for p in minus))
    return Stat(values)


def save(fig, out, name):
    for ext in ("png", "svg"):
        fig.savefig(out / f"{name}.{ext}", dpi=150, bbox_inches="tight",
                    metadata={"Date": None} if ext == "svg" else {"Software": None})
    plt.close(fig)


def plot_fig5(runs, out):
    mu_ts = sorted({p[0] for p in runs})
    mu_ns = sorted({p[1] for p in runs})
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for ax, along, across, label, other in (
        (axes[0], mu_ts, mu_ns, r"$\mu_t$", r"$\mu_n$"),
        (axes[1], mu_ns, mu_ts, r"$\mu_n$", r"$\mu_t$"),
    ):
        for c in across:
            xs, ys, es = [], [], []
            for x in along:
                point = (x, c) if ax is axes[0] else (c, x)
                s = stat_of(runs, point, "porosity")
                if s.n:
                    xs.append(x)
                    ys.append(s.mean)
                    es.append(0.0 if math.isnan(s.sem) else s.sem)
            if xs:
                ax.errorbar(xs, ys, yerr=es, marker="o", capsize=3, label=f"{other} = {c:g}")
        ax.set_xlabel(label)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("porosity E")
    fig.suptitle("Porosity after compaction (mean ± s.e. over seeds)")
    save(fig, out, "fig5_porosity")


def grid_map(runs, values, title, name, out, cmap="viridis", symmetric=False):
    mu_ts = sorted({p[0] for p in runs})
    mu_ns = sorted({p[1] for p in runs})
    data = np.full((len(mu_ns), len(mu_ts)), np.nan)
    for i, n in enumerate(mu_ns):
        for j, t in enumerate(mu_ts):
            s = values(t, n)
            data[i, j] = s.mean if s.n else np.nan
    fig, ax = plt.subplots(figsize=(6, 5))
    kwargs = {}
    if symmetric and np.isfinite(data).any():
        lim = np.nanmax(np.abs(data))
        kwargs = dict(vmin=-lim, vmax=lim)
    im = ax.imshow(data, origin="lower", cmap=cmap, **kwargs)
    ax.set_xticks(range(len(mu_ts)), [f"{t:g}" for t in mu_ts])
    ax.set_yticks(range(len(mu_ns)), [f"{n:g}" for n in mu_ns])
    ax.set_xlabel(r"$\mu_t$ (rolling)")
    ax.set_ylabel(r"$\mu_n$ (torsion)")
    for i in range(len(mu_ns)):
        for j in range(len(mu_ts)):
            if np.isfinite(data[i, j]):
                ax.text(j, i, f"{data[i, j]:.3f}", ha="center", va="center", fontsize=6,
                        color="w")
    fig.colorbar(im, ax=ax)
    ax.set_title(title)
    save(fig, out, name)
    return data


def plot_packing(run_folder, out):
    """Side view (x–z) of the packing before and after compaction, shaded by depth y."""
    before = read_csv(run_folder / "initial_particles.csv")
    after = read_csv(run_folder / "particles.csv")
    top = max(float(r["z"]) + float(r["r"]) for r in before)
    fig, axes = plt.subplots(1, 2, figsize=(8, 8 * top / 60 + 1), sharey=True)
    for ax, rows, title in ((axes[0], before, "deposit"), (axes[1], after, "compacted")):
        ys = np.array([float(r["y"]) for r in rows])
        order = np.argsort(-ys)  # far spheres first, near ones drawn over them
        span = max(ys.max() - ys.min(), 1e-9)
        for k in order:
            r = rows[k]
            shade = 0.25 + 0.6 * (ys[k] - ys.min()) / span
            ax.add_patch(plt.Circle((float(r["x"]), float(r["z"])), float(r["r"]),
                                    color=plt.cm.copper(shade), lw=0))
        ax.set_aspect("equal")
        xs = [float(r["x"]) for r in rows]
        ax.set_xlim(min(xs) - 1.5, max(xs) + 1.5)
        ax.set_ylim(0, top + 1)
        ax.set_title(title)
        ax.set_xlabel("x [R]")
    axes[0].set_ylabel("z [R]")
    save(fig, out, "packing")


def ratio_of(num_stat, den_stat):
    """num/den of two means and its error from their standard errors (NaN where unknown)."""
    if not (num_stat.n and den_stat.n) or den_stat.mean == 0:
        return math.nan, math.nan
    ratio = num_stat.mean / den_stat.mean
    if num_stat.n < 2 or den_stat.n < 2 or num_stat.mean == 0:
        return ratio, math.nan
    return ratio, abs(ratio) * math.sqrt((num_stat.sem / num_stat.mean) ** 2 +
                                         (den_stat.sem / den_stat.mean) ** 2)


def ratios_along_axes(runs):
    """[(μ, E1(μ, 0), E1(0, μ), ratio, error)] for every μ > 0 on both axes."""
    origin = (0.0, 0.0)
    mus = sorted({p[0] for p in runs if p[1] == 0.0 and p[0] > 0} &
                 {p[1] for p in runs if p[0] == 0.0 and p[1] > 0})
    out = []
    for mu in mus:
        roll = paired(runs, [(mu, 0.0)], [origin])
        twist = paired(runs, [(0.0, mu)], [origin])
        out.append((mu, roll, twist) + ratio_of(roll, twist))
    return out


def fmt_row(cells):
    return "| " + " | ".join(cells) + " |"


def saturation(runs, line):
    """The smallest μ from which E1 along `line` (list of (μ, point)) stays within twice the
    combined standard error (at least 0.005) of its value at the largest μ; None if the line
    has fewer than SATURATION_MIN_POINTS values (too coarse to tell)."""
    values = [(mu, paired(runs, [p], [(0.0, 0.0)])) for mu, p in line]
    values = [(mu, s) for mu, s in values if s.n]
    if len(values) < SATURATION_MIN_POINTS:
        return None
    last = values[-1][1]
    found = values[-1][0]
    for mu, s in reversed(values):
        tol = max(0.005, 2 * math.sqrt((0 if math.isnan(s.sem) else s.sem) ** 2 +
                                       (0 if math.isnan(last.sem) else last.sem) ** 2))
        if abs(s.mean - last.mean) <= tol:
            found = mu
        else:
            break
    return found


# Runs whose σzz/p (the stress the packing carries over the applied pressure) is further
# from 1 than this are named in the report: their packing was not in static balance
SIGMA_BALANCE_TOLERANCE = 0.01


def accuracy_section(kept):
    """The accuracy gauges of physics.md §17 over the runs used: largest and median overlap,
    piston imbalance, net force on a sphere and σzz/p − 1, and the runs out of balance."""
    gauges = [("max_overlap", "max overlap [R]"), ("mean_overlap", "mean overlap [R]"),
              ("piston_imbalance", r"piston force imbalance \|ΣR·e_z − F\|/F"),
              ("max_net_force", "largest net force on a sphere [F_coh]")]
    md = ["## Accuracy gauges (physics.md §17)", "",
          fmt_row(["gauge", "median over runs", "largest", "run with the largest"]),
          fmt_row(["---"] * 4)]
    for column, label in gauges:
        values = [(num(r.get(column)), r) for r in kept]
        values = [(v, r) for v, r in values if math.isfinite(v)]
        if not values:
            continue
        worst = max(values, key=lambda x: x[0])
        md.append(fmt_row([label, f"{float(np.median([v for v, _ in values])):.2g}",
                           f"{worst[0]:.2g}", f"`{worst[1]['folder']}`"]))
    off = [(abs(num(r["sigma_zz_over_p"]) - 1.0), r) for r in kept]
    off = sorted(((d, r) for d, r in off if math.isfinite(d) and d > SIGMA_BALANCE_TOLERANCE),
                 key=lambda x: -x[0])
    md.append("")
    if off:
        md.append(f"Runs whose σzz/p is more than {SIGMA_BALANCE_TOLERANCE:g} from 1 (not in "
                  "static balance at the end; their σ± are less accurate than the rest):")
        md.append("")
        for _, r in off:
            force = num(r.get("max_net_force"))
            md.append(f"- `{r['folder']}`: σzz/p = {num(r['sigma_zz_over_p']):.4f}"
                      + (f", largest net force on a sphere {force:.2g} F_coh"
                         if math.isfinite(force) else ""))
    else:
        md.append(f"Every run's σzz/p is within {SIGMA_BALANCE_TOLERANCE:g} of 1.")
    md.append("")
    return md


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("sweep_dir", type=pathlib.Path)
    parser.add_argument("--out", type=pathlib.Path, help="default: SWEEP_DIR/report")
    parser.add_argument("--all-runs", action="store_true",
                        help="also use runs that did not reach the blocked state")
    parser.add_argument("--seeds", metavar="LIST",
                        help="only these seeds, e.g. 1-2 or 1,2,5 (default: all)")
    parser.add_argument("--packing", type=pathlib.Path,
                        help="run folder for the packing figure (default: a (0,0) run)")
    args = parser.parse_args()
    sweep = args.sweep_dir
    if not (sweep / "results.csv").exists():
        sys.exit(f"error: {sweep / 'results.csv'} not found: is {sweep} a sweep folder?")
    try:
        chosen_seeds = parse_seeds(args.seeds) if args.seeds is not None else None
    except ValueError as e:
        sys.exit(f"error: --seeds: {e}")
    out = args.out or sweep / "report"
    out.mkdir(parents=True, exist_ok=True)
    rows, kept, runs, variants = load(sweep, args.all_runs, chosen_seeds)

    md = ["# cdpowder sweep report", ""]
    md += ["Sweep: `" + str(sweep) + "`", "", "```"] + provenance(sweep / "results.csv") + ["```", ""]
    md.append(f"{len(rows)} finished runs, {sum(r['blocked'] == '1' for r in rows)} blocked; "
              f"{'all finished runs used (--all-runs)' if args.all_runs else 'blocked runs used'}. "
              "Errors are standard errors of the mean over seeds; differences between points "
              "are paired by seed (same deposit)."
              + (f" Seeds {args.seeds} only (--seeds)." if chosen_seeds is not None else ""))
    md.append("")
    md += accuracy_section(kept)
    if variants:
        md += ["## Points that change other keys", ""]
        md.append("ΔE and Δσzz+/p are against the point with the same (μt, μn) and nothing "
                  "else changed, paired by seed (– where the sweep has no such point); n counts "
                  "the point's runs, pairs the seeds it shares with that point.")
        md.append("")
        md.append(fmt_row(["point", "E", "n", "ΔE", "pairs", "σzz/p", "σzz+/p", "Δσzz+/p",
                           "σzz−/p", "wall [s]"]))
        md.append(fmt_row(["---"] * 10))
        for name in sorted(variants):
            seeds = variants[name]

            def col(c, seeds=seeds):
                return Stat([num(r[c]) for r in seeds.values()])

            def against_base(c, seeds=seeds):
                first = next(iter(seeds.values()))
                if first.get(MU_T, "") == "" or first.get(MU_N, "") == "":
                    return Stat([])
                base = runs.get((float(first[MU_T]), float(first[MU_N])), {})
                return Stat([num(seeds[k][c]) - num(base[k][c])
                             for k in sorted(set(seeds) & set(base))])
            delta_e = against_base("porosity")
            md.append(fmt_row([f"`{name}`", col("porosity").text(4), str(len(seeds)),
                               delta_e.text(4), str(delta_e.n),
                               col("sigma_zz_over_p").text(3),
                               col("sigma_zz_compressive_over_p").text(2),
                               against_base("sigma_zz_compressive_over_p").text(2),
                               col("sigma_zz_tensile_over_p").text(2),
                               col("wall_seconds").text(0)]))
        md.append("")
    if not runs:
        md.append(f"No points that set only `{MU_T}` and `{MU_N}`: no paper figures.")
        (out / "report.md").write_text("\n".join(md) + "\n")
        print(f"report: {out / 'report.md'}")
        return

    plot_fig5(runs, out)
    origin = (0.0, 0.0)
    have_origin = origin in runs
    md += ["## Porosity (Fig. 5)", "", "![Fig. 5](fig5_porosity.png)", ""]
    md.append(fmt_row(["μt", "μn", "E", "n", "σzz/p", "σzz+/p", "σzz−/p", "sweeps/step",
                       "wall [s]"]))
    md.append(fmt_row(["---"] * 9))
    for p in sorted(runs):
        e = stat_of(runs, p, "porosity")
        steps = stat_of(runs, p, "steps")
        sweeps = stat_of(runs, p, "total_sweeps")
        md.append(fmt_row([f"{p[0]:g}", f"{p[1]:g}", e.text(4), str(e.n),
                           stat_of(runs, p, "sigma_zz_over_p").text(3),
                           stat_of(runs, p, "sigma_zz_compressive_over_p").text(2),
                           stat_of(runs, p, "sigma_zz_tensile_over_p").text(2),
                           f"{sweeps.mean / max(steps.mean, 1):.0f}",
                           stat_of(runs, p, "wall_seconds").text(0)]))
    md.append("")

    if have_origin:
        grid_map(runs, lambda t, n: paired(runs, [(t, n)], [origin]),
                 r"added porosity $E_1 = E - E_0$", "added_porosity", out)
        # ΔE is zero by definition on the axes (t = 0 or n = 0): only off-axis points count
        dE = grid_map(runs, lambda t, n: paired(runs, [(t, n), origin], [(t, 0.0), (0.0, n)])
                      if t > 0 and n > 0 and (t, 0.0) in runs and (0.0, n) in runs
                      else Stat([]),
                      r"additivity residual $\Delta E$", "additivity", out, cmap="RdBu_r",
                      symmetric=True)
        md += ["## Added porosity and additivity", "",
               "![E1](added_porosity.png) ![ΔE](additivity.png)", ""]

    # the paper's claims
    md += ["## The paper's claims", ""]
    md.append(fmt_row(["quantity", "paper", "cdpowder"]))
    md.append(fmt_row(["---"] * 3))
    md.append(fmt_row(["E0 = E(0, 0)", f"≈ {PAPER_E0}", stat_of(runs, origin, "porosity").text(4)]))
    md.append(fmt_row(["E(1, 1)", f"≈ {PAPER_E11}", stat_of(runs, (1.0, 1.0), "porosity").text(4)]))
    e1_roll = paired(runs, [(1.0, 0.0)], [origin])
    e1_twist = paired(runs, [(0.0, 1.0)], [origin])
    e1_both = paired(runs, [(1.0, 1.0)], [origin])
    md.append(fmt_row(["E1(1, 0) (rolling only)", f"≈ {PAPER_E1_ROLL}", e1_roll.text(4)]))
    md.append(fmt_row(["E1(0, 1) (torsion only)", f"≈ {PAPER_E1_TWIST}", e1_twist.text(4)]))
    md.append(fmt_row(["E1(1, 1) (both)", f"≈ {PAPER_E1_BOTH}", e1_both.text(4)]))
    if e1_roll.n and e1_twist.n and e1_twist.mean != 0:
        ratio, err = ratio_of(e1_roll, e1_twist)
        md.append(fmt_row(["E1(1, 0) / E1(0, 1)", "≈ 2",
                           f"{ratio:.2f}" + ("" if math.isnan(err) else f" ± {err:.2f}")]))
    axis_ratios = ratios_along_axes(runs) if have_origin else []
    # the range leaves out ratios whose torsion E1 is not clearly above zero (within twice
    # its standard error, or n = 1 and below 0.005): there the ratio says nothing
    determined = [(mu, r) for mu, _, twist, r, _ in axis_ratios if math.isfinite(r) and
                  twist.mean > (2 * twist.sem if twist.n > 1 else 0.005)]
    if len(determined) >= 2:
        ratios = [r for _, r in determined]
        md.append(fmt_row(["E1(μ, 0) / E1(0, μ) roughly independent of μ", "≈ 2 for every μ",
                           f"{min(ratios):.2f} to {max(ratios):.2f} over μ = "
                           f"{determined[0][0]:g} … {determined[-1][0]:g} (table below)"]))
    if have_origin:
        finite = [(abs(v), i) for i, v in enumerate(dE.flatten()) if np.isfinite(v)]
        md.append(fmt_row(["largest |ΔE| (additivity)", "≲ 0.03",
                           f"{max(finite)[0]:.4f}" if finite
                           else "– (needs (μt, μn), (μt, 0) and (0, μn) off the axes)"]))
        if finite:
            residuals = np.array([v for v in dE.flatten() if np.isfinite(v)])
            md.append(fmt_row(["ΔE over the off-axis points: mean, RMS, positive",
                               "fluctuates around 0, no systematics",
                               f"{residuals.mean():+.4f}, {math.sqrt((residuals ** 2).mean()):.4f}, "
                               f"{int((residuals > 0).sum())} of {len(residuals)}"]))
        mus = sorted({p[0] for p in runs})
        mus_n = sorted({p[1] for p in runs})
        sat_roll = saturation(runs, [(m, (m, 0.0)) for m in mus])
        sat_twist = saturation(runs, [(m, (0.0, m)) for m in mus_n])
        sat_diag = saturation(runs, [(m, (m, m)) for m in mus])
        def saturation_text(found, line_mus):
            if found is None:
                return f"– (needs ≥ {SATURATION_MIN_POINTS} values of μ on the line)"
            if found == max(line_mus):
                return f"not below {found:g} (E1 still changes)"
            return f"{found:g}"
        md.append(fmt_row(["E1 saturates (μn = 0) from μt ≈", "0.4",
                           saturation_text(sat_roll, [m for m in mus if (m, 0.0) in runs])]))
        md.append(fmt_row(["E1 saturates (μt = 0) from μn ≈", "0.4",
                           saturation_text(sat_twist, [m for m in mus_n if (0.0, m) in runs])]))
        md.append(fmt_row(["E1 saturates (μt = μn) from ≈", "0.4",
                           saturation_text(sat_diag, [m for m in mus if (m, m) in runs])]))
    corner = (1.0, 1.0)
    if corner in runs and all(r.get("initial_porosity", "") != "" for r in runs[corner].values()):
        e_init = stat_of(runs, corner, "initial_porosity")
        e_max = stat_of(runs, corner, "porosity")
        md.append(fmt_row(["E(1, 1) below the deposit's porosity E_init", "yes",
                           f"{'yes' if e_max.mean < e_init.mean else 'no'}: "
                           f"{e_max.text(4)} against E_init {e_init.text(4)}"]))
    md.append("")

    if axis_ratios:
        md += ["## Rolling against torsion along the axes", "",
               "The paper: E1(μ, 0) / E1(0, μ) ≈ 2, roughly independent of μ. "
               "Each E1 is paired by seed with E(0, 0).", ""]
        md.append(fmt_row(["μ", "E1(μ, 0)", "E1(0, μ)", "ratio"]))
        md.append(fmt_row(["---"] * 4))
        for mu, roll, twist, ratio, err in axis_ratios:
            md.append(fmt_row([f"{mu:g}", roll.text(4), twist.text(4),
                               "–" if not math.isfinite(ratio) else
                               f"{ratio:.2f}" + ("" if math.isnan(err) else f" ± {err:.2f}")]))
        md.append("")

    # Table 1
    present = [p for p in PAPER_TABLE1 if p in runs]
    if present:
        md += ["## Table 1: σzz and its compressive and tensile parts, / p", ""]
        md.append(fmt_row(["μt", "μn", "paper σzz", "σzz", "paper σzz+", "σzz+",
                           "paper σzz−", "σzz−", "n"]))
        md.append(fmt_row(["---"] * 9))
        for p in present:
            paper = PAPER_TABLE1[p]
            s = [stat_of(runs, p, c) for c in ("sigma_zz_over_p", "sigma_zz_compressive_over_p",
                                              "sigma_zz_tensile_over_p")]
            md.append(fmt_row([f"{p[0]:g}", f"{p[1]:g}", f"{paper[0]}", s[0].text(3),
                               f"{paper[1]}", s[1].text(2), f"{paper[2]}", s[2].text(2),
                               str(s[0].n)]))
        md.append("")

    # The packing figure needs a run's particle files, which stay on the machine that ran it
    # (results/.gitignore): the first run of (0,0) (else of the first point) that has them.
    # Where no run here has them, the figure drawn before is kept, with the run it shows
    # (packing_source.txt), so regenerating a report in a fresh clone does not drop it.
    packing = args.packing
    if packing is None:
        candidates = [p for p in (origin, min(runs)) if p in runs]
        folders = ([sweep / row["folder"] for _, row in sorted(runs[candidates[0]].items())]
                   if candidates else [])
        packing = next((f for f in folders if (f / "initial_particles.csv").exists()), None)
    elif not (packing / "initial_particles.csv").exists():
        print(f"report: warning: {packing} has no particle files; the packing figure is not "
              "redrawn", file=sys.stderr)
    source_file = out / "packing_source.txt"
    if packing is not None and (packing / "initial_particles.csv").exists():
        plot_packing(packing, out)
        source_file.write_text(f"{packing}\n")
    if (out / "packing.png").exists() and source_file.exists():
        md += ["## One packing before and after compaction (Fig. 3)", "",
               f"`{source_file.read_text().strip()}`", "", "![packing](packing.png)", ""]

    (out / "report.md").write_text("\n".join(md) + "\n")
    print(f"report: {out / 'report.md'}")


if __name__ == "__main__":
    main()
