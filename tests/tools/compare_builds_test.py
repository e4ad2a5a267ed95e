#!/usr/bin/python3
"""tools/compare_builds.py on two stand-in programs (never the simulator): both builds run
every point, side by side, with the point's friction and the seed, and the table gives the
ratio of their wall times."""
import json
import pathlib
import stat
import subprocess
import sys
import tempfile
import unittest

TOOL = pathlib.Path(__file__).resolve().parents[2] / "tools" / "compare_builds.py"

# A stand-in for cdpowder: `compact SCENE --out DIR --quiet --set k=v …` writes a summary.json
# whose wall time is WALL (its own constant) and porosity 0.7 + 0.1 × mu_roll + 0.01 × seed;
# it exits with status 3 when mu_twist is 9.
FAKE = r'''
import json, pathlib, sys
args = sys.argv[2:]
out = pathlib.Path(args[args.index("--out") + 1])
sets = dict(args[i + 1].split("=", 1) for i, a in enumerate(args) if a == "--set")
if sets["contact.mu_twist"] == "9":
    print("fault", file=sys.stderr); sys.exit(3)
out.mkdir(parents=True, exist_ok=True)
(out / "summary.json").write_text(json.dumps({
    "porosity": 0.7 + 0.1 * float(sets["contact.mu_roll"]) + 0.01 * int(sets["deposition.seed"]),
    "run": {"steps": 10, "total_passes": 100, "wall_seconds": WALL, "blocked": True,
            "stage_seconds": {"solve_nlgs": WALL / 2}, "seed": sets["solver.seed"]}}))
'''


class CompareBuilds(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = pathlib.Path(self.tmp.name)
        self.builds = {}
        for name, wall in (("before", 6.0), ("after", 2.0)):
            exe = self.dir / name
            exe.write_text(f"#!{sys.executable}\n" + FAKE.replace("WALL", repr(wall)))
            exe.chmod(exe.stat().st_mode | stat.S_IXUSR)
            self.builds[name] = str(exe)

    def tearDown(self):
        self.tmp.cleanup()

    def run_tool(self, *points):
        out = self.dir / "out"
        return out, subprocess.run(
            [sys.executable, str(TOOL), "--before", self.builds["before"], "--after",
             self.builds["after"], "--scene", "scene.toml", "--seed", "3", "--points", *points,
             "--out", str(out)], capture_output=True, text=True)

    def test_every_point_runs_on_both_builds_and_the_ratio_is_printed(self):
        out, done = self.run_tool("0,0", "1,1")
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertIn("| (0,0) | 6.0, 10, 100, 0.73000 | 2.0, 10, 100, 0.73000 | 3.00 |",
                      done.stdout)
        self.assertIn("| (1,1) |", done.stdout)
        rows = json.loads((out / "compare.json").read_text())["rows"]
        self.assertEqual([r["point"] for r in rows], ["0,0", "1,1"])
        self.assertAlmostEqual(rows[1]["after"]["porosity"], 0.83)

    def test_a_failed_run_stops_with_its_status_and_message(self):
        _, done = self.run_tool("0,9")
        self.assertEqual(done.returncode, 1)
        self.assertIn("exited with 3: fault", done.stderr)


if __name__ == "__main__":
    unittest.main()
