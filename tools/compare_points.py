#!/usr/bin/python3
"""Two sweeps of the same points side by side, point by point: the rerun of a table against
the committed one (docs/lab/2026-11-25-paper-scale-gate.md; issue of the speed work:
"show point by point that E, σzz+ and σzz− agree within their errors").

For each point both sweeps have (matched by the point's name in points.csv) and each quantity
(porosity E, σzz+/p, σzz−/p), the difference of the two means and its error, the root of the
sum of the squared standard errors of the means (the runs of two sweeps are independent
samples; `tools/accuracy_gate.py` is the paired comparison, seed by seed). A quantity AGREES
when |difference| ≤ 2 errors. Prints a markdown table; exit status 0 when every quantity of
every common point agrees, 1 when one does not, 2 on bad input (a folder without points.csv,
no point in common, or a point with fewer than two blocked runs on a side).

Note the multiple comparisons: 8 points × 3 quantities at 2 errors are 24 tests, and at
about 5 % each one or two disagreements are expected of equivalent sweeps by chance alone; a
disagreement is a place to look (more seeds), not a verdict by itself.

usage: compare_points.py BASE_SWEEP_DIR CANDIDATE_SWEEP_DIR
Debian python3, standard library only.
"""
import csv
import math
import pathlib
import sys

QUANTITIES = (("porosity", "E"),
              ("sigma_zz_compressive_over_p", "σzz+/p"),
              ("sigma_zz_tensile_over_p", "σzz−/p"))
N_ERRORS = 2.0


def read_points(folder):
    """{point name: row} of folder/points.csv (comment lines skipped)."""
    path = pathlib.Path(folder) / "points.csv"
    if not path.is_file():
        raise ValueError(f"{folder}: no points.csv (a folder of `cdpowder sweep`?)")
    with open(path, newline="") as f:
        rows = csv.DictReader(line for line in f if not line.startswith("#"))
        return {row["point"]: row for row in rows}


def number(row, key):
    text = row.get(key, "")
    return float(text) if text not in ("", None) else math.nan


def compare(base, candidate):
    """Rows of (point, quantity label, base mean, candidate mean, difference, error,
    agrees) for the points both have, in the base's order."""
    common = [name for name in base if name in candidate]
    if not common:
        raise ValueError("the two sweeps have no point in common")
    rows = []
    for name in common:
        for side, row in (("base", base[name]), ("candidate", candidate[name])):
            if number(row, "n") < 2:
                raise ValueError(f"{side} point {name}: fewer than two blocked runs, no error")
        for key, label in QUANTITIES:
            a, b = number(base[name], key + "_mean"), number(candidate[name], key + "_mean")
            error = math.hypot(number(base[name], key + "_sem"),
                               number(candidate[name], key + "_sem"))
            difference = b - a
            rows.append((name, label, a, b, difference, error,
                         abs(difference) <= N_ERRORS * error))
    return rows


def main(argv):
    if len(argv) != 3:
        print(__doc__.strip().splitlines()[-2], file=sys.stderr)
        return 2
    try:
        rows = compare(read_points(argv[1]), read_points(argv[2]))
    except (ValueError, KeyError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    print(f"| point | quantity | {argv[1]} | {argv[2]} | difference ± error | within 2 errors |")
    print("| --- | --- | --- | --- | --- | --- |")
    for name, label, a, b, difference, error, agrees in rows:
        print(f"| {name} | {label} | {a:.4f} | {b:.4f} | {difference:+.4f} ± {error:.4f} | "
              f"{'yes' if agrees else '**no**'} |")
    disagreeing = sum(1 for row in rows if not row[6])
    print(f"\n{len(rows) - disagreeing} of {len(rows)} agree within {N_ERRORS:g} errors")
    return 0 if disagreeing == 0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
