#!/usr/bin/python3
"""How far the paper's sweeps have come: runs finished, distinct runs, and wall time.

    tools/campaign_status.py [RESULTS_DIR ...]      (default: every sweep folder in results/)

A run that a sweep reused from another (`--reuse`) is stored in both folders; it is counted
once, by its resolved scene (summary.json's scene_toml), so the total wall time is the
computing the whole campaign cost. Runs with 1 015 spheres (the paper's size) and the
rest (the quick studies) are totalled apart. Uses only the standard library.
"""
import argparse
import csv
import pathlib
import sys

from run_summary import SummaryError, read_summary


def finished_runs(folder):
    """(scene_toml, wall_seconds, blocked) of every finished, uninterrupted run."""
    runs = []
    for summary in sorted(folder.glob("runs/*/seed_*/summary.json")):
        try:
            s = read_summary(summary)
        except (OSError, SummaryError):
            continue
        run = s.get("run", {})
        if run.get("interrupted", True):
            continue
        runs.append((s.get("scene_toml", str(summary)), float(run.get("wall_seconds", 0.0)),
                     bool(run.get("blocked", False))))
    return runs


def planned_points(folder):
    """The sweep's points (rows of its points.csv), or None without one. The runs still to
    do are in `cdpowder sweep SWEEP.toml --out FOLDER --dry-run`."""
    path = folder / "points.csv"
    if not path.exists():
        return None
    with open(path, newline="") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return len(rows)


# how a resolved scene of the paper's size reads (scene_writer: [deposition] spheres = ...)
PAPER_SIZE = "spheres = 1015"


def hours(seconds):
    return f"{seconds / 3600:.1f} h"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folders", nargs="*", type=pathlib.Path)
    args = parser.parse_args()
    folders = args.folders or sorted(p.parent for p in pathlib.Path("results").glob("**/results.csv"))
    if not folders:
        sys.exit("error: no sweep folders (folders with results.csv) given or found in results/")
    seen = {}  # scene → (wall seconds, paper size)
    print("| sweep | finished runs | blocked | points | summed wall time |")
    print("| --- | --- | --- | --- | --- |")
    for folder in folders:
        runs = finished_runs(folder)
        points = planned_points(folder)
        for scene, wall, _ in runs:
            seen.setdefault(scene, (wall, PAPER_SIZE in scene))
        print(f"| `{folder}` | {len(runs)} | {sum(b for _, _, b in runs)} | "
              f"{'–' if points is None else points} | {hours(sum(w for _, w, _ in runs))} |")
    print()
    for label, paper in (("paper size (1 015 spheres)", True), ("smaller", False)):
        walls = [w for w, p in seen.values() if p == paper]
        if walls:
            print(f"Distinct runs, {label}: {len(walls)}, summed wall time {hours(sum(walls))} "
                  f"({sum(walls) / len(walls) / 60:.1f} min per run).")


if __name__ == "__main__":
    main()
