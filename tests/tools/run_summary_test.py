#!/usr/bin/python3
"""tools/run_summary.py: schema 0 and 1 read, newer schemas and broken files refused, and
every summary committed under results/ reads."""
import json
import pathlib
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import run_summary  # noqa: E402


class RunSummary(unittest.TestCase):
    def test_a_file_without_the_key_is_schema_zero(self):
        s = run_summary.parse_summary(json.dumps({"porosity": 0.6, "run": {"steps": 3}}))
        self.assertEqual(s["schema"], 0)
        self.assertEqual(s["porosity"], 0.6)

    def test_the_current_schema_reads(self):
        s = run_summary.parse_summary(json.dumps({"schema": run_summary.SCHEMA, "porosity": 0.6}))
        self.assertEqual(s["schema"], run_summary.SCHEMA)

    def test_a_newer_schema_is_refused_with_the_reason(self):
        with self.assertRaisesRegex(run_summary.SummaryError, "newer cdpowder"):
            run_summary.parse_summary(json.dumps({"schema": run_summary.SCHEMA + 1}))

    def test_broken_files_are_refused(self):
        with self.assertRaisesRegex(run_summary.SummaryError, "not JSON"):
            run_summary.parse_summary("{ broken")
        with self.assertRaisesRegex(run_summary.SummaryError, "not a JSON object"):
            run_summary.parse_summary("[1, 2]")
        with tempfile.TemporaryDirectory() as tmp, self.assertRaises(OSError):
            run_summary.read_summary(pathlib.Path(tmp) / "summary.json")

    def test_the_schema_matches_the_program(self):
        header = (ROOT / "src/cdpowder/run/run_summary.hpp").read_text()
        self.assertIn(f"inline constexpr int kRunSummarySchema = {run_summary.SCHEMA};", header)

    def test_every_committed_summary_reads(self):
        paths = sorted((ROOT / "results").glob("*/runs/*/seed_*/summary.json"))
        self.assertGreaterEqual(len(paths), 313)
        for path in paths:
            s = run_summary.read_summary(path)
            self.assertLessEqual(s["schema"], run_summary.SCHEMA, path)
            self.assertIn("scene_toml", s, path)


if __name__ == "__main__":
    unittest.main()
