#!/usr/bin/python3
"""tools/compare_points.py on synthetic points.csv files with known answers."""
import pathlib
import subprocess
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
TOOL = ROOT / "tools" / "compare_points.py"
sys.path.insert(0, str(TOOL.parent))
import compare_points as tool  # noqa: E402

HEADER = ("point,contact.mu_roll,runs,n,porosity_mean,porosity_sem,"
          "sigma_zz_compressive_over_p_mean,sigma_zz_compressive_over_p_sem,"
          "sigma_zz_tensile_over_p_mean,sigma_zz_tensile_over_p_sem\n")


def write(folder, rows, n=10):
    folder.mkdir(parents=True)
    text = "# a provenance line\n" + HEADER
    for name, (e, e_sem, plus, plus_sem, minus, minus_sem) in rows.items():
        text += f'"{name}",0.0,10,{n},{e},{e_sem},{plus},{plus_sem},{minus},{minus_sem}\n'
    (folder / "points.csv").write_text(text)
    return folder


class ComparePoints(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = pathlib.Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def run_tool(self, a, b):
        return subprocess.run([sys.executable, str(TOOL), str(a), str(b)], capture_output=True,
                              text=True)

    def test_just_within_two_errors_agrees_and_just_beyond_does_not(self):
        # errors 0.003 and 0.004 combine to 0.005: two errors are 0.010
        base = {"p": (0.70, 0.003, 2.0, 0.3, -1.0, 0.3)}
        a = write(self.dir / "a", base)
        b = write(self.dir / "b", {"p": (0.7099, 0.004, 2.0, 0.4, -1.0, 0.4)})
        c = write(self.dir / "c", {"p": (0.7101, 0.004, 2.0, 0.4, -1.0, 0.4)})
        self.assertEqual(self.run_tool(a, b).returncode, 0)
        done = self.run_tool(a, c)
        self.assertEqual(done.returncode, 1)
        self.assertIn("| p | E | 0.7000 | 0.7101 | +0.0101 ± 0.0050 | **no** |", done.stdout)
        self.assertIn("2 of 3 agree", done.stdout)

    def test_points_are_matched_by_name_and_extra_ones_ignored(self):
        a = write(self.dir / "a", {"p": (0.7, 0.01, 2, 0.1, -1, 0.1),
                                   "q": (0.8, 0.01, 1, 0.1, 0, 0.1)})
        b = write(self.dir / "b", {"q": (0.8, 0.01, 1, 0.1, 0, 0.1)})
        rows = tool.compare(tool.read_points(a), tool.read_points(b))
        self.assertEqual({r[0] for r in rows}, {"q"})

    def test_bad_input_is_named(self):
        a = write(self.dir / "a", {"p": (0.7, 0.01, 2, 0.1, -1, 0.1)})
        self.assertEqual(self.run_tool(a, self.dir / "missing").returncode, 2)
        b = write(self.dir / "b", {"p": (0.7, 0.01, 2, 0.1, -1, 0.1)}, n=1)
        done = self.run_tool(a, b)
        self.assertEqual(done.returncode, 2)
        self.assertIn("fewer than two blocked runs", done.stderr)


if __name__ == "__main__":
    unittest.main()
