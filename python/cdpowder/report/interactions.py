"""Additivity beyond the torques (the paper's open question): does each suppressed mode add
its own porosity whatever the other keys (the Coulomb friction μ, the load F_coh/p) are?

A sweep qualifies when, at two settings of its other keys or more, its runs cover the four
torque corners (μt, μn) ∈ {0, c}² (c > 0). A setting is the values of the other keys; a run
whose point leaves a key at the scene's value is given that value from its summary.json. The
reference setting takes each key at its most frequent value over the runs.

For a setting s and a torque corner m ∈ {(c, 0), (0, c), (c, c)}, paired by seed:
- E1_m(s) = E(s, m) − E(s, 0): the porosity the torques of m add at s;
- ΔE_t(s) = E1_(c,c)(s) − E1_(c,0)(s) − E1_(0,c)(s): the paper's additivity of the torques;
- I_m(s) = E1_m(s) − E1_m(ref): the interaction of the change of setting with m. Additivity
  across the modes, E(s, m) − E(ref, 0) = [E(s, 0) − E(ref, 0)] + E1_m(ref), holds where
  I_m(s) = 0; I is that equation's residual."""
import json
import math

import numpy as np
import pandas as pd

from .data import MU_N, MU_T, Stat, parameter_columns
from .figures import label_panel, ordered_colours, plt, save
from .sections import table

MODES = (("rolling", (1, 0)), ("torsion", (0, 1)), ("both", (1, 1)))
# a residual further than this many standard errors from zero is called a departure
SIGNIFICANT = 2.0
# and further than this in any case: the round-off of sums of porosities (exact data has
# standard errors of 0)
ROUND_OFF = 1e-9


def _scene_value(summary, key, numeric=True):
    """The resolved scene's value of `key`: a number, or (numeric false) a string; NaN
    otherwise."""
    value = summary.get("scene", {})
    for part in key.split("."):
        if not isinstance(value, dict) or part not in value:
            return math.nan
        value = value[part]
    if isinstance(value, bool):
        return math.nan
    if numeric:
        return value if isinstance(value, (int, float)) else math.nan
    return value if isinstance(value, str) else math.nan


def _missing(value):
    return not isinstance(value, str) and math.isnan(value)


def filled_runs(sweep_dir, sweep):
    """sweep.kept with the parameter columns' empty cells filled from each run's resolved scene
    (summary.json "scene"), so a point that leaves a key at the scene's value is placed at that
    value; returns it, the numeric keys and the other (string) keys."""
    runs = sweep.kept.copy()
    columns = parameter_columns(runs)
    keys = [k for k in columns if pd.api.types.is_numeric_dtype(runs[k])]
    labels = [k for k in columns if k not in keys]
    for key in keys:
        runs[key] = runs[key].astype(float)
    for key in labels:
        runs[key] = runs[key].astype(object)
    missing = (runs[keys + labels].isna().any(axis=1) if keys + labels
               else pd.Series(False, index=runs.index))
    for index in runs.index[missing]:
        try:
            summary = json.loads((sweep_dir / runs.at[index, "folder"] / "summary.json")
                                 .read_text())
        except (OSError, ValueError, TypeError):
            continue
        for key in keys + labels:
            if _missing(runs.at[index, key]):
                runs.at[index, key] = _scene_value(summary, key, key in keys)
    return runs, keys, labels


def _text(value):
    return f"{value:g}" if isinstance(value, (int, float)) else str(value)


class Interactions:
    """The torque corners of each setting of a sweep's other keys, paired by seed."""

    def __init__(self, runs, keys, labels=()):
        # the other keys: numbers, then strings (a string key tells settings apart and has no
        # line of its own)
        self.numeric = [k for k in keys if k not in (MU_T, MU_N)]
        self.others = self.numeric + list(labels)
        self.ok = False
        if MU_T not in keys or MU_N not in keys or not self.numeric:
            return
        runs = runs.dropna(subset=[MU_T, MU_N] + self.others)
        nonzero = sorted(set(runs[MU_T][runs[MU_T] > 0]) | set(runs[MU_N][runs[MU_N] > 0]))
        if len(nonzero) != 1:
            return  # one corner value c: the sweep's torque corners are {0, c}²
        self.c = nonzero[0]
        runs = runs.assign(corner=list(zip((runs[MU_T] > 0).astype(int),
                                           (runs[MU_N] > 0).astype(int))),
                           setting=list(zip(*(runs[k] for k in self.others))))
        full = {s for s, g in runs.groupby("setting") if len(set(g["corner"])) == 4}
        if len(full) < 2:
            return
        self.runs = runs[runs["setting"].isin(full)]
        self.settings = sorted(full)
        # the reference: each key at its most frequent value (ties: the smallest)
        self.reference = tuple(
            self.runs[k].value_counts().sort_index(kind="stable").idxmax() for k in self.others)
        self.reference = tuple(float(v) if k in self.numeric else v
                               for k, v in zip(self.others, self.reference))
        self.ok = self.reference in full
        self._by_seed = {}

    def by_seed(self, column):
        """{(setting, corner): column as a Series by seed}."""
        if column not in self._by_seed:
            self._by_seed[column] = {
                key: runs.set_index("seed")[column]
                for key, runs in self.runs.groupby(["setting", "corner"], sort=False)}
        return self._by_seed[column]

    def combination(self, terms, column="porosity"):
        """Σ sign·value over [(sign, setting, corner)], per seed over the seeds every term has,
        as a Stat."""
        series = self.by_seed(column)
        if any((s, m) not in series for _, s, m in terms):
            return Stat([])
        rows = pd.concat([series[(s, m)] for _, s, m in terms], axis=1).dropna()
        total = sum(sign * rows.iloc[:, k] for k, (sign, _, _) in enumerate(terms))
        return Stat(np.asarray(total, dtype=float))

    def value(self, setting, corner, column="porosity"):
        runs = self.runs[(self.runs["setting"] == setting) & (self.runs["corner"] == corner)]
        return Stat(runs[column]) if column in runs else Stat([])

    def added(self, setting, corner):
        return self.combination([(1, setting, corner), (-1, setting, (0, 0))])

    def torque_residual(self, setting):
        return self.combination([(1, setting, (1, 1)), (-1, setting, (1, 0)),
                                 (-1, setting, (0, 1)), (1, setting, (0, 0))])

    def interaction(self, setting, corner):
        ref = self.reference
        return self.combination([(1, setting, corner), (-1, setting, (0, 0)),
                                 (-1, ref, corner), (1, ref, (0, 0))])

    def lines(self):
        """{key: [settings that differ from the reference in that key alone, the reference
        among them, by rising value]}."""
        out = {}
        for i, key in enumerate(self.numeric):
            line = [s for s in self.settings
                    if all(s[j] == self.reference[j] for j in range(len(s)) if j != i)]
            if len(line) > 1:
                out[key] = sorted(line, key=lambda s, i=i: s[i])
        return out

    def departures(self):
        """(residuals over two seeds or more, those beyond SIGNIFICANT standard errors) over
        every interaction and torque residual of the lines."""
        settings = sorted({s for line in self.lines().values() for s in line})
        stats = [self.torque_residual(s) for s in settings]
        stats += [self.interaction(s, m) for s in settings if s != self.reference
                  for _, m in MODES]
        tested = [t for t in stats if t.n > 1]
        return len(tested), sum(abs(t.mean) > max(SIGNIFICANT * t.sem, ROUND_OFF)
                                for t in tested)


def section(sweep_dir, sweep, out):
    """The markdown lines of the section with a figure per key; [] where the sweep does not
    cross the torque corners with another key."""
    runs, keys, labels = filled_runs(sweep_dir, sweep)
    found = Interactions(runs, keys, labels)
    if not found.ok:
        return []
    c = f"{found.c:g}"
    ref = ", ".join(f"`{k}` = {_text(v)}" for k, v in zip(found.others, found.reference))
    md = ["## Additivity beyond the torques", "",
          f"The torque corners (μt, μn) ∈ {{0, {c}}}² at each setting of the other keys. "
          f"Reference: {ref}. Paired by seed: E1 = E − E(0, 0) at the same setting; ΔE_t = "
          f"E1({c}, {c}) − E1({c}, 0) − E1(0, {c}) (the paper's additivity of the torques); "
          "I_m = E1_m − E1_m(reference), the residual of additivity across the modes: "
          "E(setting, m) − E(reference, 0) = [E(setting, 0) − E(reference, 0)] + "
          "E1_m(reference) + I_m.", ""]
    for key, line in found.lines().items():
        i = found.others.index(key)
        rows = []
        for s in line:
            is_ref = s == found.reference
            cells = [f"{s[i]:g}" + (" (ref)" if is_ref else ""),
                     found.value(s, (0, 0)).text(4)]
            cells += [found.added(s, m).text(4) for _, m in MODES]
            cells.append(found.torque_residual(s).text(4))
            cells += ["–" if is_ref else found.interaction(s, m).text(4) for _, m in MODES]
            cells += [found.value(s, m, "sigma_zz_compressive_over_p").text(2)
                      for m in ((0, 0), (1, 1))]
            cells.append(str(found.value(s, (0, 0)).n))
            rows.append(cells)
        figure = draw(found, key, line, out)
        md += [f"### Against `{key}`", "", f"![{key}]({figure}.png)", ""]
        md += table([key, "E(0, 0)", f"E1({c}, 0)", f"E1(0, {c})", f"E1({c}, {c})", "ΔE_t",
                     "I rolling", "I torsion", "I both", "σzz+/p (0, 0)",
                     f"σzz+/p ({c}, {c})", "seeds"], rows) + [""]
    tested, beyond = found.departures()
    md += [f"{beyond} of {tested} residuals (ΔE_t and I) lie more than {SIGNIFICANT:g} standard "
           "errors from zero.", ""]
    return md


def draw(found, key, line, out):
    """(a) E at the four corners, (b) the residuals I_m and ΔE_t, (c) σzz+/p at the four
    corners, each against the key's value (mean ± standard error over seeds)."""
    i = found.others.index(key)
    xs = [s[i] for s in line]
    c = f"{found.c:g}"
    corners = (((0, 0), "(0, 0)"), ((1, 0), f"({c}, 0)"), ((0, 1), f"(0, {c})"),
               ((1, 1), f"({c}, {c})"))
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.6))
    colours = ordered_colours(4)
    for column, ax in (("porosity", axes[0]), ("sigma_zz_compressive_over_p", axes[2])):
        for colour, (m, label) in zip(colours, corners):
            stats = [found.value(s, m, column) for s in line]
            ax.errorbar(xs, [t.mean for t in stats], yerr=[t.error_bar() for t in stats],
                        marker="o", markersize=4, capsize=2.5, color=colour,
                        label=f"(μt, μn) = {label}")
    ax = axes[1]
    ax.axhline(0.0, color="0.5", linewidth=0.8)
    for colour, (name, m) in zip(colours[1:], MODES):
        stats = [Stat([0.0] * 2) if s == found.reference else found.interaction(s, m)
                 for s in line]
        ax.errorbar(xs, [t.mean for t in stats], yerr=[t.error_bar() for t in stats],
                    marker="o", markersize=4, capsize=2.5, color=colour, label=f"I {name}")
    stats = [found.torque_residual(s) for s in line]
    ax.errorbar(xs, [t.mean for t in stats], yerr=[t.error_bar() for t in stats], marker="s",
                markersize=4, capsize=2.5, color="0.3", linestyle="--", label="ΔE_t")
    for ax, label, ylabel in zip(axes, "abc", ("porosity E", "residual (paired)",
                                               r"$\sigma_{zz}^+/p$")):
        ax.set_xlabel(key)
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
        if min(xs) > 0 and max(xs) / min(xs) > 10:
            ax.set_xscale("log")
        label_panel(ax, f"({label})")
        ax.legend(fontsize=7)
    fig.tight_layout()
    name = "additivity_against_" + "".join(ch if ch.isalnum() else "_" for ch in key)
    save(fig, out, name)
    return name
