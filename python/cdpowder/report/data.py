"""A sweep's results.csv as pandas tables, and the statistics the report is made of.

A run's row (one per run, docs/sweeps.md) holds its point, the point's parameter values, the
seed and every measured number; empty cells (non-finite values, σ/p without a pressure) are
NaN. The report's points are the (μt, μn) mesh: runs that set only `contact.mu_roll` and
`contact.mu_twist`. Runs that also set another key are variants (a sensitivity study) and are
compared with the mesh point of the same (μt, μn).

Differences between points are paired by seed: runs with the same seed start from the same
deposit, so their difference has a much smaller spread than either porosity.
"""
import io
import math
import re

import numpy as np
import pandas as pd

MU_T = "contact.mu_roll"
MU_N = "contact.mu_twist"


def read_results(path):
    """(table, provenance): the runs of a cdpowder CSV as a DataFrame, and its '#' lines."""
    with open(path, newline="") as f:
        lines = f.readlines()
    provenance = [line.rstrip("\n") for line in lines if line.startswith("#")]
    body = "".join(line for line in lines if not line.startswith("#"))
    # names stay text; "" is NaN only in the numeric columns (pandas' default)
    table = pd.read_csv(io.StringIO(body), dtype={"point": str, "folder": str})
    # tables written before the NLGS pass was called a pass (CHANGELOG.md)
    table = table.rename(columns={"total_sweeps": "total_passes"})
    return table, provenance


def parameter_columns(table):
    """The sweep's parameter keys: the columns between 'point' and 'seed'."""
    names = list(table.columns)
    if "point" not in names or "seed" not in names:
        return []
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

    def error_bar(self):
        """The standard error, 0 where one run gives none (a bar of no length)."""
        return 0.0 if math.isnan(self.sem) else self.sem


def paired_ratio(num, den):
    """mean(num)/mean(den) of two samples paired by seed (arrays of one length, the same seed
    at each place) and its standard error. The error is the ratio estimator's, from the
    per-seed residuals num_s − R den_s, so what the two share (the deposit, E(0, 0)) cancels:
    treating them as independent overstated it tenfold at μ = 0.05. (NaN, NaN) without data or
    with mean(den) = 0; NaN error for one seed."""
    num, den = np.asarray(num, dtype=float), np.asarray(den, dtype=float)
    both = np.isfinite(num) & np.isfinite(den)
    num, den = num[both], den[both]
    if len(num) == 0 or den.mean() == 0:
        return math.nan, math.nan
    ratio = float(num.mean() / den.mean())
    if len(num) < 2:
        return ratio, math.nan
    residuals = num - ratio * den
    return ratio, float(residuals.std(ddof=1) / math.sqrt(len(num)) / abs(den.mean()))


class Sweep:
    """The runs a report uses: `all_rows` (every finished run), `kept` (the blocked ones, or
    all with all_runs), `mesh` (kept runs of the (μt, μn) mesh, with float columns mu_t and
    mu_n) and `variants` (the other kept runs, by point name)."""

    def __init__(self, table, all_runs=False, seeds=None):
        if seeds is not None:
            table = table[table["seed"].isin(seeds)]
        self.all_rows = table
        self.kept = table if all_runs else table[table["blocked"] == 1]
        others = [k for k in parameter_columns(table) if k not in (MU_T, MU_N)]
        on_mesh = pd.Series(True, index=self.kept.index)
        for key in others:
            on_mesh &= self.kept[key].isna()
        for key in (MU_T, MU_N):
            on_mesh &= self.kept[key].notna() if key in self.kept else False
        # a sweep of other keys (piston.pressure, …) has no mesh: every point is a variant
        self.mesh = self.kept[on_mesh].assign(
            mu_t=lambda t: t[MU_T].astype(float) if MU_T in t else np.nan,
            mu_n=lambda t: t[MU_N].astype(float) if MU_N in t else np.nan)
        self.keys = parameter_columns(table)
        self.variants = {name: runs for name, runs in self.kept[~on_mesh].groupby("point")}
        self.points = sorted(set(zip(self.mesh["mu_t"], self.mesh["mu_n"])))
        self._by_seed = {}

    def __contains__(self, point):
        return point in self.points

    def runs_at(self, point):
        t, n = point
        return self.mesh[(self.mesh["mu_t"] == t) & (self.mesh["mu_n"] == n)]

    def stat(self, point, column):
        return Stat(self.runs_at(point)[column]) if column in self.mesh else Stat([])

    def by_seed(self, column):
        """column as a seed × (μt, μn) table (NaN where a point lacks the seed); made once per
        column, since every paired difference reads it."""
        if column not in self._by_seed:
            self._by_seed[column] = self.mesh.set_index(["seed", "mu_t", "mu_n"])[column] \
                .unstack(["mu_t", "mu_n"])
        return self._by_seed[column]

    def paired_values(self, plus, minus, column="porosity"):
        """Σ plus − Σ minus per seed, over the seeds every point shares (lists of points), as
        a Series by seed; empty when a point is missing or no seed is shared."""
        if any(p not in self for p in plus + minus):
            return pd.Series(dtype=float)
        wide = self.by_seed(column)
        shared = wide[list(plus + minus)].notna().all(axis=1)
        rows = wide[shared]
        if not len(rows):
            return pd.Series(dtype=float)
        # the sums in the order the points are given, then their difference, per seed
        return sum(rows[p] for p in plus) - sum(rows[p] for p in minus)

    def paired(self, plus, minus, column="porosity"):
        """Σ plus − Σ minus over the seeds every point shares (lists of points), as a Stat."""
        return Stat(np.asarray(self.paired_values(plus, minus, column), dtype=float))

    def added(self, point):
        """E1(point) = E(point) − E(0, 0), paired by seed."""
        return self.paired([point], [(0.0, 0.0)])

    def added_ratio(self, num, den):
        """E1(num) / E1(den) and its error, paired by seed: over the seeds all three points
        (num, den and (0, 0)) share (paired_ratio)."""
        origin = (0.0, 0.0)
        e1_num, e1_den = self.paired_values([num], [origin]).align(
            self.paired_values([den], [origin]))
        return paired_ratio(e1_num, e1_den)

    def against(self, key):
        """The kept runs grouped for a plot against `key`: {group: {value: Stat of the runs'
        rows}}, a group being the values of the sweep's other keys (as text; "" for none).
        Only numeric keys with two values or more."""
        if key not in self.kept or self.kept[key].dropna().nunique() < 2:
            return {}
        values = pd.to_numeric(self.kept[key], errors="coerce")
        if values.isna().any():
            return {}
        others = [k for k in self.keys if k != key]
        groups = {}
        for _, row in self.kept.assign(_value=values).iterrows():
            group = ", ".join(f"{k}={row[k]:g}" if isinstance(row[k], float) else f"{k}={row[k]}"
                              for k in others if pd.notna(row[k]))
            groups.setdefault(group, {}).setdefault(row["_value"], []).append(row)
        return {g: {v: pd.DataFrame(rows) for v, rows in sorted(by_value.items())}
                for g, by_value in sorted(groups.items())}

    @staticmethod
    def paired_change(runs, first, column):
        """runs[column] − first[column] over the seeds both have (DataFrames of runs, with a
        seed column), seed by seed in rising order."""
        a, b = runs.set_index("seed")[column], first.set_index("seed")[column]
        shared = sorted(set(a.index) & set(b.index))
        return Stat([a.loc[s] - b.loc[s] for s in shared])

    def mus(self, axis):
        """The values of μt (axis 0) or μn (axis 1) on the mesh, rising."""
        return sorted({p[axis] for p in self.points})
