#!/usr/bin/python3
"""tools/campaign_status.py on two synthetic sweep folders that share one run (a reused run
is stored in both): it must count the shared run once in the campaign's totals, leave out
interrupted runs, and total paper-size and smaller runs apart."""
import json
import pathlib
import subprocess
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
TOOL = ROOT / "tools" / "campaign_status.py"


def write_run(folder, point, seed, scene, wall, interrupted=False):
    run = folder / "runs" / point / f"seed_{seed}"
    run.mkdir(parents=True)
    (run / "summary.json").write_text(json.dumps({
        "scene_toml": scene,
        "run": {"interrupted": interrupted, "blocked": not interrupted, "wall_seconds": wall}}))


class CampaignStatus(unittest.TestCase):
    def test_shared_runs_count_once(self):
        with tempfile.TemporaryDirectory() as tmp:
            a, b = pathlib.Path(tmp, "table1"), pathlib.Path(tmp, "fig5")
            for folder in (a, b):
                folder.mkdir()
                (folder / "results.csv").write_text("point,seed\n")
            paper = "[deposition]\nspheres = 1015\nseed = {}\n"
            write_run(a, "p", 1, paper.format(1), 3600.0)
            write_run(a, "p", 2, paper.format(2), 1800.0)
            write_run(b, "p", 1, paper.format(1), 3600.0)          # reused from table1
            write_run(b, "q", 1, paper.format(3), 100.0, interrupted=True)
            write_run(b, "r", 1, "[deposition]\nspheres = 100\n", 60.0)
            out = subprocess.run([sys.executable, str(TOOL), str(a), str(b)],
                                 capture_output=True, text=True, check=True).stdout
        self.assertIn(f"| `{a}` | 2 | 2 | – | 1.5 h |", out)
        self.assertIn(f"| `{b}` | 2 | 2 | – | 1.0 h |", out)
        self.assertIn("Distinct runs, paper size (1 015 spheres): 2, summed wall time 1.5 h "
                      "(45.0 min per run).", out)
        self.assertIn("Distinct runs, smaller: 1, summed wall time 0.0 h (1.0 min per run).", out)


if __name__ == "__main__":
    unittest.main()
