#!/usr/bin/python3
"""tools/report.py on synthetic sweeps whose answers are known by construction.

The porosity of every run is E = E0 + s·0.01 + E1(μt, μn) with a seed offset s·0.01 (the
same deposit for every point of a seed) and an exactly additive, saturating
E1 = 0.2 min(μt/0.4, 1) + 0.1 min(μn/0.4, 1). Paired by seed, the report must then find
E1(1, 0) = 0.2, E1(0, 1) = 0.1, their ratio 2, no additivity residual, and saturation from
μ = 0.4 on both lines; on a three-point line it must decline to judge saturation.
"""
import csv
import json
import pathlib
import subprocess
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
REPORT = ROOT / "tools" / "report.py"
COLUMNS = ["point", "contact.mu_roll", "contact.mu_twist", "seed", "porosity", "initial_porosity",
           "sigma_zz_over_p", "sigma_zz_compressive_over_p", "sigma_zz_tensile_over_p",
           "steps", "total_passes", "wall_seconds", "blocked", "folder"]
E0 = 0.6
E_INIT = 0.95


def added(mu_t, mu_n):
    return 0.2 * min(mu_t / 0.4, 1.0) + 0.1 * min(mu_n / 0.4, 1.0)


def write_sweep(folder, points, seeds=3, blocked=lambda p, s: True, sigma=lambda p, s: 1.0,
                e_init=E_INIT):
    folder.mkdir(parents=True, exist_ok=True)
    with open(folder / "results.csv", "w", newline="") as f:
        f.write("# synthetic sweep for the report test\n")
        w = csv.writer(f)
        w.writerow(COLUMNS)
        for mu_t, mu_n in points:
            name = f"contact.mu_roll={mu_t},contact.mu_twist={mu_n}"
            for s in range(1, seeds + 1):
                w.writerow([name, mu_t, mu_n, s, E0 + 0.01 * s + added(mu_t, mu_n), e_init,
                            sigma((mu_t, mu_n), s), 2.0 - mu_t, -1.0 + mu_t, 1000, 50000, 10.0,
                            int(blocked((mu_t, mu_n), s)), f"runs/{name}/seed_{s}"])


def run_report(folder, *options, vector=False):
    """report.md of a report on `folder`; the SVG and PDF figures only where a test reads
    them (vector=True): they take most of a report's time."""
    options = options if vector else (*options, "--png-only")
    out = subprocess.run([sys.executable, str(REPORT), str(folder), *options],
                         capture_output=True, text=True, check=True)
    assert "report:" in out.stdout
    return (folder / "report" / "report.md").read_text()


def claim(report, quantity):
    """The cdpowder cell of a row of the paper's-claims table."""
    for line in report.splitlines():
        if line.startswith(f"| {quantity} |"):
            return line.strip("| ").split(" | ")[-1]
    raise AssertionError(f"no row {quantity!r} in the report")


class ReportOnKnownSweeps(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = pathlib.Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def test_full_mesh_gives_the_constructed_claims(self):
        mus = [0.0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.6, 1.0]
        write_sweep(self.dir, [(t, n) for t in mus for n in mus])
        report = run_report(self.dir, vector=True)
        self.assertEqual(claim(report, "E0 = E(0, 0)"), "0.6200 ± 0.0058")
        self.assertEqual(claim(report, "E1(1, 0) (rolling only)"), "0.2000 ± 0.0000")
        self.assertEqual(claim(report, "E1(0, 1) (torsion only)"), "0.1000 ± 0.0000")
        self.assertEqual(claim(report, "E1(1, 1) (both)"), "0.3000 ± 0.0000")
        self.assertEqual(claim(report, "E1(1, 0) / E1(0, 1)"), "2.00 ± 0.00")
        self.assertEqual(claim(report, "largest |ΔE| (additivity)"), "0.0000")
        self.assertEqual(claim(report, "E1 saturates (μn = 0) from μt ≈"), "0.4")
        self.assertEqual(claim(report, "E1 saturates (μt = 0) from μn ≈"), "0.4")
        self.assertEqual(claim(report, "E1 saturates (μt = μn) from ≈"), "0.4")
        self.assertEqual(claim(report, "E1(μ, 0) / E1(0, μ) roughly independent of μ"),
                         "2.00 to 2.00 over μ = 0.05 … 1 (table below)")
        mean, rms, _ = claim(report, "ΔE over the off-axis points: mean, RMS, positive").split(", ")
        self.assertAlmostEqual(float(mean), 0.0)
        self.assertAlmostEqual(float(rms), 0.0)
        self.assertEqual(claim(report, "E(1, 1) below the deposit's porosity E_init"),
                         "yes: 0.9200 ± 0.0058 against E_init 0.9500 ± 0.0000")
        self.assertIn("| 0.4 | 0.2000 ± 0.0000 | 0.1000 ± 0.0000 | 2.00 ± 0.00 |", report)
        for figure in ("fig5_porosity", "added_porosity", "additivity", "table1_stress"):
            for ext in ("png", "svg", "pdf"):
                self.assertTrue((self.dir / "report" / f"{figure}.{ext}").stat().st_size > 0)
        # the vector files keep their text: Fig. 5's panel labels, the paper's values
        fig5 = (self.dir / "report" / "fig5_porosity.svg").read_text()
        for text in ("(a)", "(b)", "(c)", "paper (text)", "paper: saturates"):
            self.assertIn(text, fig5)
        self.assertTrue((self.dir / "report" / "fig5_porosity.pdf").read_bytes()
                        .startswith(b"%PDF"))

    def test_coarse_lines_do_not_claim_saturation(self):
        # the paper's Table 1 points: three values of μ on each line
        write_sweep(self.dir, [(0.0, 0.0), (0.1, 0.1), (0.3, 0.3), (1.0, 1.0), (0.0, 0.3),
                               (0.0, 1.0), (0.3, 0.0), (1.0, 0.0)])
        report = run_report(self.dir, vector=True)
        self.assertTrue(claim(report, "E1 saturates (μn = 0) from μt ≈").startswith("– (needs"))
        self.assertIn("| 0 | 0 | 1.0 | 1.000 ± 0.000 | 2.2 | 2.00 ± 0.00 | -1.2 | -1.00 ± 0.00 | 3 |",
                      report)
        # Table 1 as a figure: cdpowder's and the paper's values of both parts, each point
        self.assertIn("![Table 1](table1_stress.png)", report)
        svg = (self.dir / "report" / "table1_stress.svg").read_text()
        for text in ("(compressive), cdpowder", "(compressive), paper", "(tensile), paper",
                     "(0.1, 0.1)", "(1, 0)"):
            self.assertIn(text, svg)

    def test_unsaturated_line_is_said_so(self):
        mus = [0.0, 0.2, 0.4, 0.6, 1.0]
        # a deposit denser than the compacted corner: E(1, 1) = 0.92 above E_init = 0.9
        write_sweep(self.dir, [(t, n) for t in mus for n in mus], e_init=0.9)
        rows = (self.dir / "results.csv").read_text().splitlines()
        # raise E(1, 0) by 0.05 for every seed: rolling still adds porosity between 0.6 and 1
        bumped = []
        for row in rows:
            if row.startswith('"contact.mu_roll=1.0,contact.mu_twist=0.0"'):
                cells = next(csv.reader([row]))
                cells[4] = str(float(cells[4]) + 0.05)
                row = ",".join(f'"{c}"' if "," in c else c for c in cells)
            bumped.append(row)
        (self.dir / "results.csv").write_text("\n".join(bumped) + "\n")
        report = run_report(self.dir)
        self.assertEqual(claim(report, "E1 saturates (μn = 0) from μt ≈"),
                         "not below 1 (E1 still changes)")
        # rolling's E1(1, 0) = 0.25 against torsion's 0.1: the ratio now grows with μ, and
        # the additivity residual is −0.05 at every μt = 1 point (4 of the 16 off-axis ones)
        self.assertEqual(claim(report, "E1(μ, 0) / E1(0, μ) roughly independent of μ"),
                         "2.00 to 2.50 over μ = 0.2 … 1 (table below)")
        self.assertEqual(claim(report, "ΔE over the off-axis points: mean, RMS, positive"),
                         "-0.0125, 0.0250, 0 of 16")
        # the torsion axis is untouched: it still saturates from 0.4
        self.assertEqual(claim(report, "E1 saturates (μt = 0) from μn ≈"), "0.4")
        self.assertEqual(claim(report, "E(1, 1) below the deposit's porosity E_init"),
                         "no: 0.9200 ± 0.0058 against E_init 0.9000 ± 0.0000")

    def test_unblocked_runs_are_left_out(self):
        write_sweep(self.dir, [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)],
                    blocked=lambda p, s: not (p == (1.0, 0.0) and s == 3))
        report = run_report(self.dir)
        self.assertIn("9 finished runs, 8 blocked", report)
        self.assertEqual(claim(report, "E1(1, 0) (rolling only)"), "0.2000 ± 0.0000")

    def test_runs_out_of_static_balance_are_named(self):
        write_sweep(self.dir, [(0.0, 0.0), (1.0, 1.0)],
                    sigma=lambda p, s: 1.05 if (p, s) == ((1.0, 1.0), 2) else 1.0 + 1e-4)
        report = run_report(self.dir)
        named = [line for line in report.splitlines() if line.startswith("- `runs/")]
        self.assertEqual(named, ["- `runs/contact.mu_roll=1.0,contact.mu_twist=1.0/seed_2`: "
                                 "σzz/p = 1.0500"])

    def test_packing_figure_survives_a_clone_without_particle_files(self):
        # particle files stay on the machine that ran (results/.gitignore): the figure is
        # drawn from the first (0,0) run that has them, and kept, with the run it shows,
        # when the report is regenerated where none has them
        write_sweep(self.dir, [(0.0, 0.0), (1.0, 1.0)])
        run = self.dir / "runs" / "contact.mu_roll=0.0,contact.mu_twist=0.0" / "seed_2"
        run.mkdir(parents=True)
        for name, top in (("initial_particles.csv", 9.0), ("particles.csv", 3.0)):
            (run / name).write_text("id,x,y,z,r\n0,1,1,1,1\n1,2,1,%g,1\n" % top)
        (run / "summary.json").write_text(json.dumps({
            "initial_porosity": 0.9, "porosity": 0.6,
            "piston": {"enabled": True, "height": 4.5},
            "scene": {"system": {"lx": 5.0}, "piston": {"start_gap": 2.0}}}))
        self.assertIn(f"`{run}`", run_report(self.dir, vector=True))
        # drawn with the piston and each packing's porosity from the run's summary
        svg = (self.dir / "report" / "packing.svg").read_text()
        for text in ("piston", "deposit, E = 0.900", "compacted, E = 0.600", "(a)", "(b)"):
            self.assertIn(text, svg)
        for name in ("initial_particles.csv", "particles.csv"):
            (run / name).unlink()
        report = run_report(self.dir)
        self.assertIn("## One packing before and after compaction (Fig. 3)", report)
        self.assertIn(f"`{run}`", report)
        self.assertTrue((self.dir / "report" / "packing.png").exists())

    def test_variant_is_paired_with_its_base_point_over_shared_seeds(self):
        # a sensitivity point (one more key) with 3 seeds, its base point with seeds 1 and 2
        # only: ΔE is the constructed +0.05 over the 2 shared seeds, n counts all 3 runs
        self.dir.mkdir(parents=True, exist_ok=True)
        columns = COLUMNS[:3] + ["contact.cohesion_range"] + COLUMNS[3:]
        with open(self.dir / "results.csv", "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(columns)
            for name, d_coh, offset, seeds in (
                    ("contact.mu_roll=0.0,contact.mu_twist=0.0", "", 0.0, (1, 2)),
                    ("contact.mu_roll=0.0,contact.mu_twist=0.0,contact.cohesion_range=0.05",
                     0.05, 0.05, (1, 2, 3))):
                for s in seeds:
                    w.writerow([name, 0.0, 0.0, d_coh, s, E0 + 0.01 * s + offset, E_INIT, 1.0,
                                2.0, -1.0, 1000, 50000, 10.0, 1, f"runs/{name}/seed_{s}"])
        report = run_report(self.dir)
        row = next(line for line in report.splitlines()
                   if line.startswith("| `contact.mu_roll=0.0,contact.mu_twist=0.0,contact."))
        cells = row.strip("| ").split(" | ")
        self.assertEqual(cells[2], "3")                 # n: the variant's runs
        self.assertEqual(cells[3], "0.0500 ± 0.0000")   # ΔE against the base point
        self.assertEqual(cells[4], "2")                 # pairs: the seeds both have

    def test_seeds_option_keeps_only_the_chosen_seeds(self):
        # seed s adds 0.01 s to every porosity: E0 over seeds 1-2 is 0.615 ± 0.005, over
        # seeds 1-3 0.620 ± 0.0058; E1 is seed-independent either way
        write_sweep(self.dir, [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)])
        self.assertEqual(claim(run_report(self.dir), "E0 = E(0, 0)"), "0.6200 ± 0.0058")
        report = run_report(self.dir, "--seeds", "1-2")
        self.assertIn("Seeds 1-2 only (--seeds).", report)
        self.assertIn("8 finished runs", report)
        self.assertEqual(claim(report, "E0 = E(0, 0)"), "0.6150 ± 0.0050")
        self.assertEqual(claim(report, "E1(1, 0) (rolling only)"), "0.2000 ± 0.0000")
        self.assertEqual(claim(run_report(self.dir, "--seeds", "1,3"), "E0 = E(0, 0)"),
                         "0.6200 ± 0.0100")

    def test_bad_seeds_option_is_named_and_writes_nothing(self):
        # each bad list, and the item of it the error must name
        write_sweep(self.dir, [(0.0, 0.0)])
        for bad, item in (("2-1", "'2-1'"), ("x", "'x'"), ("1,,2", "''"), ("1,3-", "'3-'")):
            out = subprocess.run([sys.executable, str(REPORT), str(self.dir), "--seeds", bad],
                                 capture_output=True, text=True)
            self.assertNotEqual(out.returncode, 0, bad)
            self.assertIn(f"--seeds: {item} is not a seed", out.stderr)
            self.assertFalse((self.dir / "report").exists(), bad)

    def test_regenerated_report_is_byte_identical(self):
        write_sweep(self.dir, [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)])
        folder = self.dir / "report"
        run_report(self.dir, vector=True)
        first = {f.name: f.read_bytes() for f in folder.iterdir()}
        run_report(self.dir, vector=True)
        second = {f.name: f.read_bytes() for f in folder.iterdir()}
        self.assertEqual(sorted(first), sorted(second))
        self.assertIn("fig5_porosity.pdf", first)
        for name in first:
            self.assertEqual(first[name], second[name], name)

    def test_a_sweep_of_another_key_is_reported_against_it(self):
        # a pressure sweep: no (μt, μn) columns, no paper figures, E against the key
        folder = self.dir / "pressure"
        folder.mkdir()
        with open(folder / "results.csv", "w", newline="") as f:
            f.write("# synthetic pressure sweep\n")
            w = csv.writer(f)
            w.writerow(["point", "piston.pressure", "seed", "porosity", "initial_porosity",
                        "sigma_zz_over_p", "sigma_zz_compressive_over_p",
                        "sigma_zz_tensile_over_p", "steps", "total_passes", "wall_seconds",
                        "blocked", "folder"])
            for p, e in ((0.001, 0.8), (0.004, 0.75), (0.016, 0.7)):
                for s in (1, 2):
                    w.writerow([f"piston.pressure={p}", p, s, e + 0.01 * s, 0.9, 1.0, 1.4, -0.4,
                                100, 1000, 1.0, 1, f"runs/p{p}/seed_{s}"])
        report = run_report(folder)
        self.assertIn("## Against `piston.pressure`", report)
        # ΔE against the smallest pressure, paired by seed: the seed offset cancels
        self.assertIn("| – | 0.004 | 0.7650 ± 0.0050 | 2 | -0.0500 ± 0.0000 | 2 |", report)
        self.assertIn("| – | 0.001 | 0.8150 ± 0.0050 | 2 | – | – |", report)
        self.assertTrue((folder / "report" / "against_piston_pressure.png").exists())

    def test_the_admissible_stress_of_the_runs_that_have_it_is_drawn(self):
        write_sweep(self.dir, [(0.0, 0.0), (1.0, 1.0)], seeds=2)
        self.assertNotIn("admissible", run_report(self.dir))
        # `cdpowder stress-bounds` wrote its interval into two runs' summaries (physics.md
        # §11.3); the others have none and are left out of the means
        for seed, low in ((1, 1.5), (2, 2.5)):
            folder = self.dir / "runs" / "contact.mu_roll=0.0,contact.mu_twist=0.0" / f"seed_{seed}"
            folder.mkdir(parents=True)
            p = 0.0025
            interval = {"run": 3 * p, "min_attained": low * p, "max_attained": 6 * p,
                        "min": -p, "max": None}
            (folder / "summary.json").write_text(json.dumps({
                "piston": {"applied_pressure": p},
                "admissible_stress": {"sigma_zz_plus": interval}}))
        report = run_report(self.dir)
        self.assertIn("## The admissible σzz⁺/p", report)
        self.assertIn("| `contact.mu_roll=0.0,contact.mu_twist=0.0` | 2 | 3.000 ± 0.000 | "
                      "2.000 ± 0.500 | 6.000 ± 0.000 | -1.000 ± 0.000 | – |", report)
        self.assertNotIn("contact.mu_roll=1.0,contact.mu_twist=1.0` | ", report.split(
            "## The admissible")[1])
        self.assertTrue((self.dir / "report" / "admissible.png").stat().st_size > 0)

    def test_the_energy_budget_of_the_runs_that_have_one_is_tabled_as_fractions_of_the_work(self):
        write_sweep(self.dir, [(0.0, 0.0), (1.0, 1.0)], seeds=3)
        self.assertNotIn("energy budget", run_report(self.dir))
        # two runs with a complete budget (physics.md §17): W = 100 + 0; one with an incomplete
        # one (a format-1 checkpoint) is left out
        for seed, broken, complete in ((1, 100, True), (2, 300, True), (3, 0, False)):
            folder = self.dir / "runs" / "contact.mu_roll=0.0,contact.mu_twist=0.0" / f"seed_{seed}"
            folder.mkdir(parents=True, exist_ok=True)
            (folder / "summary.json").write_text(json.dumps({"porosity": 0.6, "energy": {
                "complete": complete, "piston_work": 100.0, "gravity_work": 0.0,
                "bonds_formed": 1000, "bonds_broken": broken, "breaking_work": 0.01 * broken,
                "cohesive_start": -10.0, "cohesive_end": -15.0, "dissipated": 105.0}}))
        report = run_report(self.dir)
        self.assertIn("## Where the piston's work goes", report)
        # breaking work 1 and 3 of W = 100; −ΔU_coh = 5; dissipated 105
        self.assertIn("| `contact.mu_roll=0.0,contact.mu_twist=0.0` | 2 | 0.600 ± 0.000 | 100 ± 0 | "
                      "1000 ± 0 | 200 ± 100 | 0.020 ± 0.010 | 0.050 ± 0.000 | 1.050 ± 0.000 |",
                      report)
        self.assertTrue((self.dir / "report" / "energy_budget.png").stat().st_size > 0)

    def test_additivity_across_the_modes_against_other_keys(self):
        # the torque corners crossed with μ (the grid) and with the pressure (points that
        # leave μ at the scene's 0.3, read from their summary.json). E is additive in every
        # mode except rolling at μ = 0.1, which adds 0.02 less: I rolling = -0.02 there alone
        folder = self.dir / "modes"
        folder.mkdir()
        e1 = {(0, 0): 0.0, (1, 0): 0.2, (0, 1): 0.1, (1, 1): 0.3}
        with open(folder / "results.csv", "w", newline="") as f:
            f.write("# synthetic additivity sweep\n")
            w = csv.writer(f)
            w.writerow(["point", "contact.mu", "contact.mu_roll", "contact.mu_twist",
                        "piston.pressure"] + COLUMNS[3:])
            settings = [(mu, "") for mu in (0.1, 0.3, 1.0)] + [("", 0.01)]
            for mu, pressure in settings:
                for (t, n), added_e in e1.items():
                    name = f"mu={mu},p={pressure},t={t},n={n}"
                    for s in (1, 2, 3):
                        e = 0.6 + 0.01 * s + added_e + (0.05 if pressure else 0.0) \
                            + (0.1 * float(mu) if mu != "" else 0.03)
                        if mu == 0.1 and (t, n) in ((1, 0), (1, 1)):
                            e -= 0.02
                        run = f"runs/{name}/seed_{s}"
                        w.writerow([name, mu, t, n, pressure, s, e, 0.95, 1.0, 2.0 - t, -1.0 + t,
                                    1000, 50000, 10.0, 1, run])
                        (folder / run).mkdir(parents=True)
                        (folder / run / "summary.json").write_text(json.dumps(
                            {"scene": {"contact": {"mu": 0.3}, "piston": {"pressure": 0.0025}}}))
        report = run_report(folder)
        self.assertIn("## Additivity beyond the torques", report)
        self.assertIn("Reference: `contact.mu` = 0.3, `piston.pressure` = 0.0025.", report)
        self.assertIn("### Against `contact.mu`", report)
        self.assertIn("### Against `piston.pressure`", report)
        rows = [line for line in report.splitlines() if line.startswith("| 0.1 |")]
        self.assertEqual(len(rows), 1)
        cells = rows[0].strip("| ").split(" | ")
        # E1 rolling, and I rolling, I torsion, I both at μ = 0.1; the torques stay additive
        # among themselves (ΔE_t = 0: rolling adds 0.02 less alone and with torsion)
        self.assertEqual(cells[2], "0.1800 ± 0.0000")
        self.assertEqual(cells[6:9], ["-0.0200 ± 0.0000", "0.0000 ± 0.0000",
                                      "-0.0200 ± 0.0000"])
        self.assertAlmostEqual(float(cells[5].split()[0]), 0.0)
        self.assertIn("| 0.3 (ref) | 0.6500 ± 0.0058 |", report)
        # the pressure's change adds 0.05 to E0 and nothing to the torques
        row = [line for line in report.splitlines() if line.startswith("| 0.01 |")][0]
        self.assertEqual(row.strip("| ").split(" | ")[1:5], [
            "0.7000 ± 0.0058", "0.2000 ± 0.0000", "0.1000 ± 0.0000", "0.3000 ± 0.0000"])
        self.assertIn("2 of 13 residuals (ΔE_t and I) lie more than 2 standard errors from "
                      "zero", report)
        self.assertTrue((folder / "report" / "additivity_against_contact_mu.png").exists())

    def test_a_string_key_tells_settings_apart_without_a_line_of_its_own(self):
        # capture radius 2 and 3 (numbers) and, at 3, the other capture rule (a string that
        # points leave at the scene's "centre_distance"): three settings, not two with twice the
        # seeds each
        folder = self.dir / "labels"
        folder.mkdir()
        with open(folder / "results.csv", "w", newline="") as f:
            f.write("# synthetic sweep with a string key\n")
            w = csv.writer(f)
            w.writerow(["point", "contact.mu_roll", "contact.mu_twist",
                        "deposition.capture_radius", "deposition.capture_rule"] + COLUMNS[3:])
            for radius, rule, shift in ((2.0, "", -0.05), (3.0, "", 0.0),
                                        (3.0, "surface_gap", 0.02)):
                for t, n in ((0, 0), (1, 0), (0, 1), (1, 1)):
                    name = f"r={radius},rule={rule},t={t},n={n}"
                    for s in (1, 2):
                        e = 0.6 + 0.01 * s + 0.2 * t + 0.1 * n + shift
                        run = f"runs/{name}/seed_{s}"
                        w.writerow([name, t, n, radius if radius != 3.0 else "", rule, s, e,
                                    0.95, 1.0, 2.0, -1.0, 1000, 50000, 10.0, 1, run])
                        (folder / run).mkdir(parents=True)
                        (folder / run / "summary.json").write_text(json.dumps(
                            {"scene": {"deposition": {"capture_radius": 3.0,
                                                      "capture_rule": "centre_distance"}}}))
        report = run_report(folder)
        self.assertIn("Reference: `deposition.capture_radius` = 3, `deposition.capture_rule` = "
                      "centre_distance.", report)
        self.assertIn("### Against `deposition.capture_radius`", report)
        self.assertNotIn("### Against `deposition.capture_rule`", report)
        self.assertIn("| 3 (ref) | 0.6150 ± 0.0050 |", report)

    def test_a_loading_paths_stages_are_tabulated_and_paired(self):
        # a Python protocol's runs (protocol.json "stages"): the packing of seed s has
        # E = 0.8 + 0.01 s and keeps it to the second stage; the third takes 0.05 off
        write_sweep(self.dir, [(0.0, 0.0)], seeds=2)
        self.assertNotIn("## Loading path", run_report(self.dir))
        for seed in (1, 2):
            folder = self.dir / "runs" / "contact.mu_roll=0.0,contact.mu_twist=0.0" / f"seed_{seed}"
            folder.mkdir(parents=True)
            base = 0.8 + 0.01 * seed
            stages = [{"pressure_over_p": f, "porosity": e, "sigma_zz_plus_over_applied": 2.0}
                      for f, e in ((0.25, base), (1.0, base), (4.0, base - 0.05),
                                   (0.25, base - 0.05))]
            (folder / "protocol.json").write_text(json.dumps({"returned": {"stages": stages}}))
        report = run_report(self.dir)
        self.assertIn("## Loading path", report)
        self.assertIn("| 2 | 1 | 0.8150 ± 0.0050 | 0.0000 ± 0.0000 | 0 of 2 | 2.00 ± 0.00 |",
                      report)
        self.assertIn("| 3 | 4 | 0.7650 ± 0.0050 | -0.0500 ± 0.0000 | 2 of 2 | 2.00 ± 0.00 |",
                      report)
        self.assertTrue((self.dir / "report" / "load_path.png").exists())

    def test_a_ratio_of_added_porosities_is_paired_by_seed(self):
        # E1(μ, 0) = 2 E1(0, μ) seed by seed, E1 varying from seed to seed: the paired ratio
        # is 2 with no error, where independent errors would give a large one
        sys.path.insert(0, str(ROOT / "python"))
        from cdpowder.report.data import paired_ratio
        twist = [0.05, 0.10, 0.15, 0.20]
        ratio, error = paired_ratio([2 * t for t in twist], twist)
        self.assertAlmostEqual(ratio, 2.0)
        self.assertAlmostEqual(error, 0.0)
        ratio, error = paired_ratio([0.2, 0.3], [0.1, 0.1])
        self.assertAlmostEqual(ratio, 2.5)
        self.assertAlmostEqual(error, 0.5)  # residuals ±0.05: sd 0.0707 / √2 / 0.1
        self.assertTrue(all(map(lambda v: v != v, paired_ratio([], []))))


if __name__ == "__main__":
    unittest.main()
