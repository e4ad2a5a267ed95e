"""The sections of report.md, each a list of markdown lines built from a `data.Sweep`."""
import math

import numpy as np

from . import paper
from .data import MU_N, MU_T, Stat

ORIGIN = (0.0, 0.0)
# Saturation is judged only along a line with at least this many μ values (the mesh has 8)
SATURATION_MIN_POINTS = 5
# Runs whose σzz/p (the stress the packing carries over the applied pressure) is further
# from 1 than this are named in the report: their packing was not in static balance
SIGMA_BALANCE_TOLERANCE = 0.01


def fmt_row(cells):
    return "| " + " | ".join(cells) + " |"


def table(header, rows):
    return [fmt_row(header), fmt_row(["---"] * len(header))] + [fmt_row(r) for r in rows]


def header(sweep_dir, provenance, sweep, all_runs, seeds_text):
    rows = sweep.all_rows
    md = ["# cdpowder sweep report", ""]
    md += ["Sweep: `" + str(sweep_dir) + "`", "", "```"] + provenance + ["```", ""]
    md.append(f"{len(rows)} finished runs, {int((rows['blocked'] == 1).sum())} blocked; "
              f"{'all finished runs used (--all-runs)' if all_runs else 'blocked runs used'}. "
              "Errors are standard errors of the mean over seeds; differences between points "
              "are paired by seed (same deposit)."
              + (f" Seeds {seeds_text} only (--seeds)." if seeds_text is not None else ""))
    return md + [""]


def accuracy(sweep):
    """The accuracy gauges of physics.md §17 over the runs used: largest and median overlap,
    piston imbalance, net force on a sphere and σzz/p − 1, and the runs out of balance."""
    gauges = [("max_overlap", "max overlap [R]"), ("mean_overlap", "mean overlap [R]"),
              ("piston_imbalance", r"piston force imbalance \|ΣR·e_z − F\|/F"),
              ("max_net_force", "largest net force on a sphere [F_coh]")]
    kept = sweep.kept
    rows = []
    for column, label in gauges:
        values = kept[column].dropna() if column in kept else kept.iloc[0:0]
        if len(values):
            worst = values.idxmax()
            rows.append([label, f"{float(np.median(values)):.2g}", f"{values[worst]:.2g}",
                         f"`{kept.loc[worst, 'folder']}`"])
    md = ["## Accuracy gauges (physics.md §17)", ""]
    md += table(["gauge", "median over runs", "largest", "run with the largest"], rows) + [""]
    off = (kept["sigma_zz_over_p"] - 1.0).abs()
    off = off[off > SIGMA_BALANCE_TOLERANCE].sort_values(ascending=False, kind="stable")
    if not len(off):
        return md + [f"Every run's σzz/p is within {SIGMA_BALANCE_TOLERANCE:g} of 1.", ""]
    md += [f"Runs whose σzz/p is more than {SIGMA_BALANCE_TOLERANCE:g} from 1 (not in "
           "static balance at the end; their σ± are less accurate than the rest):", ""]
    for index in off.index:
        run = kept.loc[index]
        force = run.get("max_net_force", math.nan)
        md.append(f"- `{run['folder']}`: σzz/p = {run['sigma_zz_over_p']:.4f}"
                  + (f", largest net force on a sphere {force:.2g} F_coh"
                     if math.isfinite(force) else ""))
    return md + [""]


def variants(sweep):
    """Points that change another key, each against the mesh point of its (μt, μn)."""
    if not sweep.variants:
        return []
    rows = []
    for name in sorted(sweep.variants):
        runs = sweep.variants[name]
        first = runs.iloc[0]
        on_mesh = math.isfinite(first.get(MU_T, math.nan)) and \
            math.isfinite(first.get(MU_N, math.nan))
        base = sweep.runs_at((float(first[MU_T]), float(first[MU_N]))) if on_mesh else None

        def against_base(column, runs=runs, base=base):
            return Stat([]) if base is None else sweep.paired_change(runs, base, column)

        delta_e = against_base("porosity")
        rows.append([f"`{name}`", Stat(runs["porosity"]).text(4), str(len(runs)),
                     delta_e.text(4), str(delta_e.n), Stat(runs["sigma_zz_over_p"]).text(3),
                     Stat(runs["sigma_zz_compressive_over_p"]).text(2),
                     against_base("sigma_zz_compressive_over_p").text(2),
                     Stat(runs["sigma_zz_tensile_over_p"]).text(2),
                     Stat(runs["wall_seconds"]).text(0)])
    columns = ["point", "E", "n", "ΔE", "pairs", "σzz/p", "σzz+/p", "Δσzz+/p", "σzz−/p",
               "wall [s]"]
    md = ["## Points that change other keys", ""]
    if all(row[4] == "0" for row in rows):
        # no point has a mesh point to be compared with (a sweep of other keys alone): the
        # tables against each key below pair them with each other
        md += ["n counts the point's runs.", ""]
        keep = [i for i, c in enumerate(columns) if c not in ("ΔE", "pairs", "Δσzz+/p")]
        columns = [columns[i] for i in keep]
        rows = [[row[i] for i in keep] for row in rows]
    else:
        md += ["ΔE and Δσzz+/p are against the point with the same (μt, μn) and nothing "
               "else changed, paired by seed (– where the sweep has no such point); n counts "
               "the point's runs, pairs the seeds it shares with that point.", ""]
    return md + table(columns, rows) + [""]


def points(sweep):
    md = ["## Porosity (Fig. 5)", "", "![Fig. 5](fig5_porosity.png)", "",
          "(a) E against μt for each μn, (b) E against μn for each μt, (c) the added porosity "
          "E1 = E − E0 along the axes and the diagonal, paired by seed; open stars: the "
          "values the paper's text gives (its Fig. 5 is not available as data).", ""]
    rows = []
    for p in sweep.points:
        e = sweep.stat(p, "porosity")
        steps = sweep.stat(p, "steps")
        sweeps = sweep.stat(p, "total_passes")
        rows.append([f"{p[0]:g}", f"{p[1]:g}", e.text(4), str(e.n),
                     sweep.stat(p, "sigma_zz_over_p").text(3),
                     sweep.stat(p, "sigma_zz_compressive_over_p").text(2),
                     sweep.stat(p, "sigma_zz_tensile_over_p").text(2),
                     f"{sweeps.mean / max(steps.mean, 1):.0f}",
                     sweep.stat(p, "wall_seconds").text(0)])
    md += table(["μt", "μn", "E", "n", "σzz/p", "σzz+/p", "σzz−/p", "passes/step", "wall [s]"],
                rows)
    return md + [""]


def ratios_along_axes(sweep):
    """[(μ, E1(μ, 0), E1(0, μ), ratio, error)] for every μ > 0 on both axes."""
    mus = sorted({t for t, n in sweep.points if n == 0.0 and t > 0} &
                 {n for t, n in sweep.points if t == 0.0 and n > 0})
    out = []
    for mu in mus:
        roll, twist = sweep.added((mu, 0.0)), sweep.added((0.0, mu))
        out.append((mu, roll, twist) + sweep.added_ratio((mu, 0.0), (0.0, mu)))
    return out


def saturation(sweep, line):
    """The smallest μ from which E1 along `line` (list of (μ, point)) stays within twice the
    combined standard error (at least 0.005) of its value at the largest μ; None if the line
    has fewer than SATURATION_MIN_POINTS values (too coarse to tell)."""
    values = [(mu, sweep.added(p)) for mu, p in line]
    values = [(mu, s) for mu, s in values if s.n]
    if len(values) < SATURATION_MIN_POINTS:
        return None
    last = values[-1][1]
    found = values[-1][0]
    for mu, s in reversed(values):
        tol = max(0.005, 2 * math.sqrt(s.error_bar() ** 2 + last.error_bar() ** 2))
        if abs(s.mean - last.mean) <= tol:
            found = mu
        else:
            break
    return found


def _saturation_text(found, line_mus):
    if found is None:
        return f"– (needs ≥ {SATURATION_MIN_POINTS} values of μ on the line)"
    if found == max(line_mus):
        return f"not below {found:g} (E1 still changes)"
    return f"{found:g}"


def _ratio_text(ratio, err):
    return f"{ratio:.2f}" + ("" if math.isnan(err) else f" ± {err:.2f}")


def _porosity_claims(sweep):
    e1_roll, e1_twist = sweep.added((1.0, 0.0)), sweep.added((0.0, 1.0))
    rows = [["E0 = E(0, 0)", f"≈ {paper.E0}", sweep.stat(ORIGIN, "porosity").text(4)],
            ["E(1, 1)", f"≈ {paper.E11}", sweep.stat((1.0, 1.0), "porosity").text(4)],
            ["E1(1, 0) (rolling only)", f"≈ {paper.E1_ROLL}", e1_roll.text(4)],
            ["E1(0, 1) (torsion only)", f"≈ {paper.E1_TWIST}", e1_twist.text(4)],
            ["E1(1, 1) (both)", f"≈ {paper.E1_BOTH}", sweep.added((1.0, 1.0)).text(4)]]
    if e1_roll.n and e1_twist.n and e1_twist.mean != 0:
        rows.append(["E1(1, 0) / E1(0, 1)", "≈ 2",
                     _ratio_text(*sweep.added_ratio((1.0, 0.0), (0.0, 1.0)))])
    # the range leaves out ratios whose torsion E1 is not clearly above zero (within twice
    # its standard error, or n = 1 and below 0.005): there the ratio says nothing
    determined = [(mu, r) for mu, _, twist, r, _ in ratios_along_axes(sweep)
                  if math.isfinite(r) and twist.mean > (2 * twist.sem if twist.n > 1 else 0.005)]
    if len(determined) >= 2:
        ratios = [r for _, r in determined]
        rows.append(["E1(μ, 0) / E1(0, μ) roughly independent of μ", "≈ 2 for every μ",
                     f"{min(ratios):.2f} to {max(ratios):.2f} over μ = "
                     f"{determined[0][0]:g} … {determined[-1][0]:g} (table below)"])
    return rows


def _additivity_claims(sweep, residual_map):
    residuals = residual_map[np.isfinite(residual_map)]
    rows = [["largest |ΔE| (additivity)", "≲ 0.03",
             f"{np.abs(residuals).max():.4f}" if residuals.size
             else "– (needs (μt, μn), (μt, 0) and (0, μn) off the axes)"]]
    if residuals.size:
        rows.append(["ΔE over the off-axis points: mean, RMS, positive",
                     "fluctuates around 0, no systematics",
                     f"{residuals.mean():+.4f}, {math.sqrt((residuals ** 2).mean()):.4f}, "
                     f"{int((residuals > 0).sum())} of {residuals.size}"])
    lines = (("E1 saturates (μn = 0) from μt ≈", 0, lambda m: (m, 0.0)),
             ("E1 saturates (μt = 0) from μn ≈", 1, lambda m: (0.0, m)),
             ("E1 saturates (μt = μn) from ≈", 0, lambda m: (m, m)))
    for label, axis, point in lines:
        line = [(m, point(m)) for m in sweep.mus(axis)]
        on_line = [m for m, p in line if p in sweep]
        rows.append([label, f"{paper.SATURATION_MU:g}",
                     _saturation_text(saturation(sweep, line), on_line)])
    return rows


def claims(sweep, residual_map):
    """The paper's claims beside cdpowder's numbers; residual_map: the additivity residual
    ΔE over the mesh (None without E(0, 0))."""
    rows = _porosity_claims(sweep)
    if residual_map is not None:
        rows += _additivity_claims(sweep, residual_map)
    corner = (1.0, 1.0)
    if corner in sweep and sweep.runs_at(corner)["initial_porosity"].notna().all():
        e_init = sweep.stat(corner, "initial_porosity")
        e_max = sweep.stat(corner, "porosity")
        rows.append(["E(1, 1) below the deposit's porosity E_init", "yes",
                     f"{'yes' if e_max.mean < e_init.mean else 'no'}: "
                     f"{e_max.text(4)} against E_init {e_init.text(4)}"])
    return ["## The paper's claims", ""] + table(["quantity", "paper", "cdpowder"], rows) + [""]


def axis_ratios(sweep):
    found = ratios_along_axes(sweep) if ORIGIN in sweep else []
    if not found:
        return []
    md = ["## Rolling against torsion along the axes", "",
          "The paper: E1(μ, 0) / E1(0, μ) ≈ 2, roughly independent of μ. "
          "Each E1 is paired by seed with E(0, 0), and the ratio's error is that of the "
          "ratio of the paired means (the seeds' deposits shared by all three points).", ""]
    rows = [[f"{mu:g}", roll.text(4), twist.text(4),
             "–" if not math.isfinite(ratio) else _ratio_text(ratio, err)]
            for mu, roll, twist, ratio, err in found]
    return md + table(["μ", "E1(μ, 0)", "E1(0, μ)", "ratio"], rows) + [""]


def table1(sweep, with_figure):
    present = [p for p in paper.TABLE1 if p in sweep]
    if not present:
        return []
    md = ["## Table 1: σzz and its compressive and tensile parts, / p", ""]
    if with_figure:
        md += ["![Table 1](table1_stress.png)", ""]
    rows = []
    for p in present:
        stated = paper.TABLE1[p]
        s = [sweep.stat(p, c) for c in ("sigma_zz_over_p", "sigma_zz_compressive_over_p",
                                       "sigma_zz_tensile_over_p")]
        rows.append([f"{p[0]:g}", f"{p[1]:g}", f"{stated[0]}", s[0].text(3), f"{stated[1]}",
                     s[1].text(2), f"{stated[2]}", s[2].text(2), str(s[0].n)])
    md += table(["μt", "μn", "paper σzz", "σzz", "paper σzz+", "σzz+", "paper σzz−", "σzz−",
                 "n"], rows)
    return md + [""]


def against_keys(sweep, figure_names):
    """For every swept numeric key: its figure, and a table of E, σzz/p, σzz+/p, σzz−/p per
    value and group of the other keys (mean ± standard error over seeds)."""
    md = []
    for key, figure in figure_names.items():
        if figure is None:
            continue
        md += [f"## Against `{key}`", "", f"![{key}]({figure}.png)", "",
               f"ΔE and Δσzz+/p: against the smallest `{key}` of the same other keys, paired "
               "by seed (the same deposit); pairs counts the seeds both have.", ""]
        rows = []
        for group, by_value in sweep.against(key).items():
            first = next(iter(by_value.values()))
            for value, runs in by_value.items():
                change = sweep.paired_change(runs, first, "porosity")
                stress_change = sweep.paired_change(runs, first, "sigma_zz_compressive_over_p")
                is_first = runs is first
                rows.append([group or "–", f"{value:g}", Stat(runs["porosity"]).text(4),
                             str(len(runs)), "–" if is_first else change.text(4),
                             "–" if is_first else str(change.n),
                             Stat(runs["sigma_zz_over_p"]).text(3),
                             Stat(runs["sigma_zz_compressive_over_p"]).text(2),
                             "–" if is_first else stress_change.text(2),
                             Stat(runs["sigma_zz_tensile_over_p"]).text(2)])
        md += table(["other keys", key, "E", "n", "ΔE", "pairs", "σzz/p", "σzz+/p", "Δσzz+/p",
                     "σzz−/p"], rows) + [""]
    return md
