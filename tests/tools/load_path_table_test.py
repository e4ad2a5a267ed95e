#!/usr/bin/python3
"""tools/load_path_table.py on a synthetic loading path and fresh compactions of the same
deposits: the path's E after each stage and its difference from the fresh run of the same seed
at the stage's pressure, left out where no fresh run has that pressure or changes another key."""
import json
import os
import pathlib
import subprocess
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
TOOL = ROOT / "tools" / "load_path_table.py"
P0 = 0.0025
CORNER = "contact.mu_roll=0.0,contact.mu_twist=0.0"


def write_path(folder):
    """Two seeds of one corner, stages at p0/4, p0 and back to p0/4."""
    folder.mkdir(parents=True)
    rows = []
    for seed, offset in ((1, 0.0), (2, 0.01)):
        run = folder / "runs" / CORNER / f"seed_{seed}"
        run.mkdir(parents=True)
        stages = [{"pressure_over_p": f, "porosity": e + offset}
                  for f, e in ((0.25, 0.70), (1.0, 0.70), (0.25, 0.60))]
        (run / "protocol.json").write_text(json.dumps({
            "scene": f"[piston]\nmass = 1000.0\npressure = {P0}\n", "returned": {"stages": stages}}))
        rows.append(f'"{CORNER}",0.0,0.0,{seed},0.6,1,"runs/{CORNER}/seed_{seed}"')
    (folder / "results.csv").write_text(
        "# a provenance line\npoint,contact.mu_roll,contact.mu_twist,seed,porosity,blocked,folder\n"
        + "\n".join(rows) + "\n")


def write_fresh(folder):
    """Fresh compactions at p0/4 and p0 of seeds 1 and 2, and a point of another key (left out)."""
    folder.mkdir(parents=True)
    rows = []
    for seed, offset in ((1, 0.0), (2, 0.01)):
        rows.append(f'"p",,0.0,0.0,{P0 / 4},{seed},{0.70 + offset},1,runs/a/seed_{seed}')
        rows.append(f'"p",,0.0,0.0,{P0},{seed},{0.65 + offset + 0.002 * seed},1,runs/b/seed_{seed}')
        rows.append(f'"d",0.001,0.0,0.0,{P0},{seed},0.1,1,runs/c/seed_{seed}')
    (folder / "results.csv").write_text(
        "# a provenance line\npoint,contact.cohesion_range,contact.mu_roll,contact.mu_twist,"
        "piston.pressure,seed,porosity,blocked,folder\n" + "\n".join(rows) + "\n")


class LoadPathTable(unittest.TestCase):
    def test_the_path_is_paired_with_the_fresh_runs_of_its_seeds(self):
        with tempfile.TemporaryDirectory() as scratch:
            scratch = pathlib.Path(scratch)
            write_path(scratch / "path")
            write_fresh(scratch / "fresh")
            done = subprocess.run(
                [sys.executable, str(TOOL), str(scratch / "path"), str(scratch / "fresh")],
                capture_output=True, text=True, env={**os.environ, "PYTHONPATH": str(ROOT / "python")})
            self.assertEqual(done.returncode, 0, done.stderr)
            lines = done.stdout.splitlines()
            self.assertIn("| 1 | 0.25 | 0.7050 ± 0.0050 | 0.000 ± 0.000 | 2 |", lines)
            # path − fresh at p0: 0.70 − 0.652 and 0.71 − 0.664
            self.assertIn("| 2 | 1 | 0.7050 ± 0.0050 | 0.047 ± 0.001 | 2 |", lines)
            self.assertIn("| 3 (unloaded) | 0.25 | 0.6050 ± 0.0050 | -0.100 ± 0.000 | 2 |", lines)


if __name__ == "__main__":
    unittest.main()
