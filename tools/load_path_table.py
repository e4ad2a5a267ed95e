#!/usr/bin/python3
"""A loading path beside fresh compactions of the same deposits (docs/findings.md §4).

    python3 tools/load_path_table.py PATH_SWEEP FRESH_SWEEP [FRESH_SWEEP ...]

PATH_SWEEP is a sweep of examples/paper/load_path.py (each run's protocol.json holds E after
every stage); each FRESH_SWEEP a sweep whose runs compact the same deposits (the same
deposition seeds) once at some pressure. For each torque corner of PATH_SWEEP and each stage,
prints E along the path and E(path) − E(fresh) at the stage's pressure, paired by seed, as a
markdown table (mean ± standard error over the seeds both have). Needs pandas (Debian's
python3-pandas); run with /usr/bin/python3 and PYTHONPATH=python."""
import json
import math
import pathlib
import sys

import numpy as np

from cdpowder.report.data import Stat, read_results

CORNER = ("contact.mu_roll", "contact.mu_twist")


def fresh_porosities(folders, scene_pressure):
    """{(μt, μn, pressure / p0): {seed: E}} of the blocked runs of `folders` that change
    nothing but the corner and the pressure (the other columns at the scene's values)."""
    fresh = {}
    for folder in folders:
        table, _ = read_results(pathlib.Path(folder) / "results.csv")
        others = [c for c in table.columns if "." in c and c not in CORNER + ("piston.pressure",)]
        for _, row in table[table["blocked"] == 1].iterrows():
            if any(isinstance(row[c], float) and not math.isnan(row[c]) or
                   isinstance(row[c], str) and row[c] for c in others):
                continue  # another point of the study (d_coh, capture radius, mass, …)
            pressure = row.get("piston.pressure", float("nan"))
            ratio = 1.0 if pressure != pressure else pressure / scene_pressure
            key = (float(row[CORNER[0]]), float(row[CORNER[1]]), round(ratio, 6))
            fresh.setdefault(key, {})[int(row["seed"])] = float(row["porosity"])
    return fresh


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    path_sweep = pathlib.Path(sys.argv[1])
    table, _ = read_results(path_sweep / "results.csv")
    runs = {}
    scene_pressure = None
    for _, row in table.iterrows():
        record = json.loads((path_sweep / row["folder"] / "protocol.json").read_text())
        if scene_pressure is None:
            scene_pressure = float(next(line.split("=")[1] for line in record["scene"].splitlines()
                                        if line.startswith("pressure")))
        corner = (float(row[CORNER[0]]), float(row[CORNER[1]]))
        runs.setdefault(corner, {})[int(row["seed"])] = record["returned"]["stages"]
    fresh = fresh_porosities(sys.argv[2:], scene_pressure)
    for corner, by_seed in sorted(runs.items()):
        seeds = sorted(by_seed)
        print(f"(μt, μn) = {corner}, {len(seeds)} seeds\n")
        print("| stage | p / p0 | E along the path | path − fresh | seeds paired |")
        print("| --- | --- | --- | --- | --- |")
        for k, stage in enumerate(by_seed[seeds[0]]):
            ratio = float(stage["pressure_over_p"])
            path = np.array([by_seed[s][k]["porosity"] for s in seeds])
            at = fresh.get((corner[0], corner[1], round(ratio, 6)), {})
            paired = [s for s in seeds if s in at]
            diff = Stat([by_seed[s][k]["porosity"] - at[s] for s in paired])
            last = k == len(by_seed[seeds[0]]) - 1
            print(f"| {k + 1}{' (unloaded)' if last else ''} | {ratio:g} | {Stat(path).text(4)} | "
                  f"{diff.text(3) if paired else '–'} | {len(paired)} |")
        print()


if __name__ == "__main__":
    main()
