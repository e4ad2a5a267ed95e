#!/usr/bin/python3
"""tools/accuracy_gate.py: its statistics and verdict on synthetic summaries whose answers are
known by construction, its arguments, and the whole command on a stand-in program (a short
script that writes a summary.json from its --set values), so the simulator never runs."""
import json
import math
import os
import pathlib
import stat
import subprocess
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
TOOL = ROOT / "tools" / "accuracy_gate.py"
sys.path.insert(0, str(TOOL.parent))
import accuracy_gate as gate  # noqa: E402

SEEDS = list(range(1, 11))


def summary(porosity=0.7, sigma_plus=3.0, sigma_minus=-2.0, sigma=1.0, mean_overlap=1e-8,
            opening=0.01, piston=1e-5, net_force=1e-6, force_balance=1e-2, blocked=True,
            radius=1.0, load=1.0, drop=()):
    """A summary.json as the program writes it (the fields the gate reads)."""
    s = {"porosity": porosity,
         "stress": {"sigma_zz_over_pressure": sigma,
                    "sigma_zz_compressive_over_pressure": sigma_plus,
                    "sigma_zz_tensile_over_pressure": sigma_minus},
         "accuracy": {"mean_overlap": mean_overlap, "max_cohesive_opening_per_range": opening,
                      "max_net_force": net_force},
         "piston": {"force_imbalance": piston, "applied_force": load},
         "scene": {"run": {"blocked": {"force_balance": force_balance}},
                   "deposition": {"radius_min": radius}},
         "run": {"blocked": blocked, "interrupted": False, "wall_seconds": 1.0}}
    for path in drop:
        *parents, last = path.split(".")
        node = s
        for p in parents:
            node = node[p]
        del node[last]
    return s


# Seed-to-seed spread of the deposit (the same on both sides of a pair) and a small
# compaction noise with zero mean over the ten seeds, alternating in sign.
def deposit(s):
    return 0.01 * s


def noise(s):
    return 1e-4 * (-1) ** s


def runs(**by_seed):
    """{seed: run_values} with every keyword a function of the seed (or a constant)."""
    return {s: gate.run_values(summary(**{k: (v(s) if callable(v) else v)
                                          for k, v in by_seed.items()})) for s in SEEDS}


def check(result, prefix):
    found = [c for c in result["checks"] if c["check"].startswith(prefix)]
    assert len(found) == 1, (prefix, result["checks"])
    return found[0]


C = "(c) every candidate σzz/p within 0.01 of 1"
D = "(d) every run blocked, candidate gauges within the contract"


def failed(result):
    return [c["check"] for c in result["checks"] if not c["pass"]]


class Statistics(unittest.TestCase):
    def test_mean_and_standard_error_of_the_mean(self):
        s = gate.Sample([1.0, 2.0, 3.0, 4.0])
        self.assertEqual(s.mean, 2.5)
        self.assertAlmostEqual(s.sd, math.sqrt(5.0 / 3.0))           # n − 1 in the variance
        self.assertAlmostEqual(s.se, math.sqrt(5.0 / 3.0) / 2.0)
        self.assertEqual((s.min, s.max), (1.0, 4.0))

    def test_within_two_standard_errors(self):
        self.assertTrue(gate.Sample([0.0, 0.0, 0.0]).within(2.0))    # identical runs
        self.assertFalse(gate.Sample([1.0, 1.0, 1.0]).within(2.0))   # a shift without spread
        self.assertFalse(gate.Sample([0.5]).within(2.0))             # one pair: no error
        # mean 1, se 0.5: 1 is within 2.01 se and outside 1.99 se
        self.assertTrue(gate.Sample([0.5, 1.5]).within(2.01))
        self.assertFalse(gate.Sample([0.5, 1.5]).within(1.99))

    def test_differences_are_paired_by_seed(self):
        # the deposit's spread (0.01 per seed) is 100 times the compaction noise; paired,
        # only the noise and the shift remain
        base = runs(porosity=lambda s: 0.7 + deposit(s))
        cand = runs(porosity=lambda s: 0.7 + deposit(s) + 1e-3 + noise(s))
        r = gate.evaluate_point(base, cand, SEEDS)
        e = r["stats"]["porosity"]
        self.assertAlmostEqual(e["mean"], 1e-3)
        self.assertAlmostEqual(e["sd"], 1e-4 * math.sqrt(10 / 9))
        self.assertAlmostEqual(e["se"], 1e-4 / 3)
        self.assertEqual(r["n"], 10)


class Verdict(unittest.TestCase):
    def test_identical_runs_pass(self):
        base = runs(porosity=lambda s: 0.7 + deposit(s))
        r = gate.evaluate_point(base, base, SEEDS)
        self.assertEqual(r["verdict"], "PASS", failed(r))
        self.assertEqual(r["stats"]["porosity"]["mean"], 0.0)

    def test_noise_with_zero_mean_passes(self):
        base = runs(porosity=lambda s: 0.7 + deposit(s), sigma_plus=lambda s: 3.0 + deposit(s))
        cand = runs(porosity=lambda s: 0.7 + deposit(s) + noise(s),
                    sigma_plus=lambda s: 3.0 + deposit(s) + 100 * noise(s),
                    sigma_minus=lambda s: -2.0 - 100 * noise(s))
        r = gate.evaluate_point(base, cand, SEEDS)
        self.assertEqual(r["verdict"], "PASS", failed(r))

    def test_porosity_shift_beyond_two_standard_errors_fails(self):
        base = runs(porosity=lambda s: 0.7 + deposit(s))
        se = 1e-4 / 3    # of the alternating noise over ten seeds
        # shifts of 1.9 and 2.1 standard errors, both far below 0.005
        for shift, failures in ((1.9 * se, []), (2.1 * se, ["(a) mean ΔE within 2 se"])):
            cand = runs(porosity=lambda s, shift=shift: 0.7 + deposit(s) + shift + noise(s))
            r = gate.evaluate_point(base, cand, SEEDS)
            self.assertAlmostEqual(r["stats"]["porosity"]["se"], se)
            self.assertEqual(failed(r), failures)

    def test_porosity_shift_of_half_a_percent_fails_even_when_noisy(self):
        base = runs(porosity=lambda s: 0.7 + deposit(s))
        # mean 0.0055 within 2 se (se ≈ 0.0033) but not below 0.005; 0.0045 passes
        for shift, verdict in ((0.0055, "FAIL"), (0.0045, "PASS")):
            cand = runs(porosity=lambda s, shift=shift: 0.7 + deposit(s) + shift + 100 * noise(s))
            r = gate.evaluate_point(base, cand, SEEDS)
            self.assertTrue(check(r, "(a) mean ΔE within").get("pass"))
            self.assertEqual(r["verdict"], verdict, (shift, failed(r)))

    def test_stress_split_shift_fails(self):
        # a shift of 0.1 p against a spread of 0.01 p, in σzz+ and in σzz− separately
        shifted = lambda level: (lambda s: level + 0.1 + 100 * noise(s))  # noqa: E731
        r = gate.evaluate_point(runs(), runs(sigma_plus=shifted(3.0)), SEEDS)
        self.assertEqual(failed(r), ["(b) mean Δσzz+/p within 2 se"])
        r = gate.evaluate_point(runs(), runs(sigma_minus=shifted(-2.0)), SEEDS)
        self.assertEqual(failed(r), ["(b) mean Δσzz−/p within 2 se"])

    def test_sigma_off_balance_fails_and_names_the_run(self):
        # 0.95× and 1.05× the tolerance of 0.01
        cand = runs(sigma=lambda s: 1.0105 if s == 4 else 0.9905)
        r = gate.evaluate_point(runs(), cand, SEEDS)
        self.assertEqual(failed(r), [C])
        self.assertIn("candidate seed 4: σzz/p = 1.0105", check(r, "(c)")["detail"])
        self.assertNotIn("seed 3", check(r, "(c)")["detail"])

    def test_each_gauge_just_below_passes_and_just_above_fails(self):
        limits = {"mean_overlap": (1e-3, "mean overlap"),
                  "opening": (0.1, "largest cohesive opening per step"),
                  "piston": (1e-2, "piston force imbalance"),
                  "net_force": (1e-2, "largest net force on a sphere")}
        for key, (limit, text) in limits.items():
            ok = gate.evaluate_point(runs(), runs(**{key: 0.95 * limit}), SEEDS)
            self.assertEqual(ok["verdict"], "PASS", (key, failed(ok)))
            bad = gate.evaluate_point(runs(), runs(**{key: lambda s, lim=limit: 1.05 * lim
                                                      if s == 7 else 0.0}), SEEDS)
            self.assertEqual(failed(bad), [D])
            self.assertIn(f"candidate seed 7: {text}", check(bad, "(d)")["detail"])

    def test_force_gauges_use_the_scenes_force_balance(self):
        r = gate.evaluate_point(runs(force_balance=1e-3), runs(force_balance=1e-3, piston=2e-3),
                                SEEDS)
        self.assertIn("force_balance 0.001", check(r, "(d)")["detail"])

    def test_net_force_is_bounded_by_force_balance_times_the_load(self):
        # physics.md §17: the largest net force [F_coh] ≤ force_balance × F; the paper's
        # piston carries F = 1.5625 F_coh, the quick scene's 0.5625
        for load in (1.5625, 0.5625):
            limit = 1e-2 * load
            ok = gate.evaluate_point(runs(load=load), runs(load=load, net_force=0.99 * limit),
                                     SEEDS)
            self.assertEqual(ok["verdict"], "PASS", (load, failed(ok)))
            bad = gate.evaluate_point(runs(load=load), runs(load=load, net_force=1.01 * limit),
                                      SEEDS)
            self.assertEqual(failed(bad), [D], load)
            self.assertIn(f"force_balance × F = 0.01 × {load:g}", check(bad, "(d)")["detail"])

    def test_overlap_is_in_units_of_the_radius(self):
        r = gate.evaluate_point(runs(radius=2.0), runs(radius=2.0, mean_overlap=1.9e-3), SEEDS)
        self.assertEqual(r["verdict"], "PASS", failed(r))

    def test_a_base_run_out_of_contract_alone_passes_and_is_listed(self):
        r = gate.evaluate_point(runs(opening=lambda s: 0.2 if s == 1 else 0.01,
                                     sigma=lambda s: 1.02 if s == 2 else 1.0), runs(), SEEDS)
        self.assertEqual(r["verdict"], "PASS", failed(r))
        self.assertEqual(r["inherited"], [])
        self.assertIn("runs out (base 1 of 10, candidate 0 of 10): base seed 1: largest "
                      "cohesive opening per step 0.2 d_coh > 0.1", check(r, "(d)")["detail"])
        self.assertIn("runs out (base 1 of 10, candidate 0 of 10): base seed 2: σzz/p = 1.0200",
                      check(r, "(c)")["detail"])

    def test_candidate_out_on_a_gauge_the_base_is_within_fails(self):
        # the base is out on the opening, the candidate on the overlap: nothing to inherit
        base = runs(opening=lambda s: 0.2 if s == 1 else 0.01)
        cand = runs(opening=lambda s: 0.2 if s == 1 else 0.01,
                    mean_overlap=lambda s: 2e-3 if s == 3 else 1e-8)
        r = gate.evaluate_point(base, cand, SEEDS)
        self.assertEqual(failed(r), [D])
        self.assertEqual(r["inherited"], ["opening"])
        detail = check(r, "(d)")["detail"]
        self.assertIn("not inherited (every base run is within the contract): mean overlap [R]: "
                      "candidate worst 0.002", detail)
        self.assertIn("candidate seed 3: mean overlap 0.002 > 0.001 R", detail)

    def test_candidate_sigma_off_balance_fails_even_when_the_base_is_off_too(self):
        r = gate.evaluate_point(runs(sigma=1.03), runs(sigma=1.02), SEEDS)
        self.assertEqual(failed(r), [C])

    def test_gauge_the_base_violates_is_inherited_up_to_its_worst_times_the_margin(self):
        limits = {"mean_overlap": (1e-3, "overlap", "mean overlap [R]"),
                  "opening": (0.1, "opening", "largest cohesive opening per step"),
                  "piston": (1e-2, "piston", "piston force imbalance"),
                  "net_force": (1e-2, "net force", "largest net force on a sphere")}
        margin = 1.0 + gate.INHERITED_MARGIN
        self.assertEqual(margin, 1.1)
        for key, (limit, gauge, label) in limits.items():
            worst = 1.65 * limit                                   # base seed 9, as measured
            base = runs(**{key: lambda s, lim=limit, w=worst: w if s == 9 else 0.5 * lim})
            # the candidate out in more runs than the base, its worst at the base's × 1.1
            # (passes), and × 1.11 (fails)
            for factor, verdict in ((0.96, f"PASS (inherited: {gauge})"),
                                    (margin, f"PASS (inherited: {gauge})"),
                                    (1.11, "FAIL")):
                cand = runs(**{key: lambda s, lim=limit, w=worst * factor:
                               w if s == 4 else 1.2 * lim})
                r = gate.evaluate_point(base, cand, SEEDS)
                self.assertEqual(r["verdict"], verdict, (key, factor, failed(r)))
                detail = check(r, "(d)")["detail"]
                self.assertIn("runs out (base 1 of 10, candidate 10 of 10)", detail)
                if verdict == "FAIL":
                    self.assertEqual(failed(r), [D])
                    self.assertEqual(r["inherited"], [])
                    self.assertIn(f"worse than the base (its worst × 1.1): {label}: base worst "
                                  f"{worst:.4g}, candidate worst {worst * factor:.4g} > "
                                  f"{worst * margin:.4g}", detail)
                else:
                    self.assertEqual(r["inherited"], [gauge])
                    self.assertIn(f"inherited from the base (not worse than its worst × 1.1): "
                                  f"{label}: base worst {worst:.4g}", detail)

    def test_inherited_opening_as_on_the_quick_scene(self):
        base = runs(opening=lambda s: {1: 0.1145, 3: 0.1436, 9: 0.165}.get(s, 0.08))
        cand = runs(opening=lambda s: {1: 0.1141, 3: 0.158, 10: 0.1275}.get(s, 0.08))
        r = gate.evaluate_point(base, cand, SEEDS)
        self.assertEqual(r["verdict"], "PASS (inherited: opening)", failed(r))
        md = "\n".join(gate.tables([{**r, "point": [0.0, 0.0]}]))
        self.assertIn("| **PASS (inherited: opening)** |", md)
        self.assertIn("  - inherited from the base (not worse than its worst × 1.1): largest "
                      "cohesive opening per step: base worst 0.165, candidate worst 0.158", md)
        self.assertIn("(0, 0) (d) every run blocked, candidate gauges within the contract: runs "
                      "out (base 3 of 10, candidate 3 of 10)", md)
        self.assertIn("Every check passed at every point.", md)

    def test_a_candidate_gauge_that_is_not_a_number_is_not_inherited(self):
        r = gate.evaluate_point(runs(opening=0.2), runs(opening=lambda s: math.nan if s == 2
                                                        else 0.15), SEEDS)
        self.assertEqual(failed(r), [D])

    def test_unblocked_runs_fail_even_when_the_base_is_unblocked_too(self):
        r = gate.evaluate_point(runs(blocked=lambda s: s != 2), runs(blocked=lambda s: s != 2),
                                SEEDS)
        self.assertEqual(failed(r), [D])
        self.assertIn("base seed 2: not blocked", check(r, "(d)")["detail"])
        self.assertIn("candidate seed 2: not blocked", check(r, "(d)")["detail"])

    def test_unblocked_run_fails(self):
        r = gate.evaluate_point(runs(), runs(blocked=lambda s: s != 2), SEEDS)
        self.assertIn("candidate seed 2: not blocked", check(r, "(d)")["detail"])

    def test_missing_field_fails_and_is_named(self):
        base = runs()
        base[5] = gate.run_values(summary(drop=("accuracy.max_cohesive_opening_per_range",)))
        r = gate.evaluate_point(base, runs(), SEEDS)
        self.assertIn("base seed 5: summary.json has no accuracy.max_cohesive_opening_per_range",
                      check(r, "(d)")["detail"])

    def test_missing_run_fails_and_pairs_the_rest(self):
        cand = runs()
        del cand[3]
        r = gate.evaluate_point(runs(), cand, SEEDS)
        self.assertEqual(failed(r), ["runs"])
        self.assertIn("candidate seed 3", check(r, "runs")["detail"])
        self.assertEqual(r["n"], 9)


class Arguments(unittest.TestCase):
    def test_seeds(self):
        self.assertEqual(gate.parse_seeds("1-3,7"), [1, 2, 3, 7])
        for bad in ("3-1", "a", "1,,2", "-1"):
            with self.assertRaises(gate.BadArgument):
                gate.parse_seeds(bad)
        with self.assertRaisesRegex(gate.BadArgument, "at least 2"):
            gate.parse_seeds("4")

    def test_points(self):
        self.assertEqual(gate.parse_point("0.3,1"), (0.3, 1.0))
        for bad in ("1", "1,2,3", "-1,0", "a,b", "nan,0"):
            with self.assertRaisesRegex(gate.BadArgument, "--points"):
                gate.parse_point(bad)

    def test_overrides_and_seed_placeholders(self):
        self.assertEqual(gate.parse_set("solver.seed={seed+1000}", "--candidate-set"),
                         ("solver.seed", "{seed+1000}"))
        for bad in ("solver.seed", "seed=1", "solver.seed=", "solver.seed={seed*2}"):
            with self.assertRaises(gate.BadArgument):
                gate.parse_set(bad, "--set")
        with self.assertRaisesRegex(gate.BadArgument, "--points"):
            gate.parse_set("contact.mu_roll=1", "--set")
        o = gate.overrides_for((0.0, 1.0), 7, [("solver.seed", "3"), ("x.y", "{seed-2}")],
                               [("solver.seed", "{seed+1000}")])
        self.assertEqual(o, {"deposition.seed": "7", "solver.seed": "1007",
                             "contact.mu_roll": "0.0", "contact.mu_twist": "1.0", "x.y": "5"})


# A stand-in for cdpowder: `compact SCENE --out DIR --quiet --set k=v …` writes a summary.json
# whose porosity is 0.7 + 0.01 × deposition.seed + 0.1 × mu_roll + test.shift and largest
# cohesive opening per step test.opening (default 0.01); it rejects the
# key bad.key with exit status 2, as cdpowder rejects an unknown key, and counts its runs.
FAKE = r'''
import json, os, pathlib, sys
if sys.argv[1:] == ["--version"]:
    print("0.0.0 (commit fake)"); sys.exit(0)
args = sys.argv[2:]
out = pathlib.Path(args[args.index("--out") + 1])
sets = dict(args[i + 1].split("=", 1) for i, a in enumerate(args) if a == "--set")
with open(os.environ["FAKE_CALLS"], "a") as f:
    f.write(" ".join(args) + "\n")
if "bad.key" in sets:
    print("error: --set: bad.key: unknown key", file=sys.stderr); sys.exit(2)
E = 0.7 + 0.01 * int(sets["deposition.seed"]) + 0.1 * float(sets["contact.mu_roll"]) \
    + float(sets.get("test.shift", 0))
out.mkdir(parents=True, exist_ok=True)
(out / "summary.json").write_text(json.dumps({
    "porosity": E,
    "stress": {"sigma_zz_over_pressure": 1.0, "sigma_zz_compressive_over_pressure": 2.0,
               "sigma_zz_tensile_over_pressure": -1.0},
    "accuracy": {"mean_overlap": 1e-9,
                 "max_cohesive_opening_per_range": float(sets.get("test.opening", 0.01)),
                 "max_net_force": 1e-6},
    "piston": {"force_imbalance": 1e-5, "applied_force": 1.0},
    "scene": {"run": {"blocked": {"force_balance": 0.01}}, "deposition": {"radius_min": 1.0},
              "solver": {"seed": int(sets["solver.seed"])}},
    "run": {"blocked": True, "interrupted": False, "wall_seconds": 0.0}}))
'''


class Command(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = pathlib.Path(self.tmp.name)
        self.fake = self.dir / "fake_cdpowder"
        self.fake.write_text(f"#!{sys.executable}\n" + FAKE)
        self.fake.chmod(self.fake.stat().st_mode | stat.S_IXUSR)
        self.calls = self.dir / "calls.txt"
        self.calls.touch()
        self.scene = self.dir / "scene.toml"
        self.scene.write_text("[deposition]\nspheres = 10\n")

    def tearDown(self):
        self.tmp.cleanup()

    def gate(self, out, *extra, binary=None):
        binary = str(binary or self.fake)
        return subprocess.run(
            [sys.executable, str(TOOL), "--base", binary, "--candidate", binary,
             "--scene", str(self.scene), "--seeds", "1-3", "--points", "0,0", "1,0",
             "--out", str(out), "--jobs", "2", *extra],
            capture_output=True, text=True, env={**os.environ, "FAKE_CALLS": str(self.calls)})

    def ncalls(self):
        return len(self.calls.read_text().splitlines())

    def test_pass_resume_and_seed_placeholder(self):
        out = self.dir / "gate"
        r = self.gate(out, "--candidate-set", "solver.seed={seed+1000}")
        self.assertEqual(r.returncode, 0, r.stderr + r.stdout)
        self.assertEqual(self.ncalls(), 12)                    # 2 points × 3 seeds × 2 sides
        g = json.loads((out / "gate.json").read_text())
        self.assertEqual(g["verdict"], "PASS")
        self.assertEqual([p["n"] for p in g["points"]], [3, 3])
        cand = out / "candidate" / "contact.mu_roll=1,contact.mu_twist=0" / "seed2"
        self.assertEqual(json.loads((cand / "summary.json").read_text())["scene"]["solver"]["seed"],
                         1002)
        self.assertIn("**PASS**", (out / "gate.md").read_text())
        self.assertIn("seeds 1-3 (3)", (out / "gate.md").read_text())
        # the same command again runs only a run that was interrupted; another candidate
        # setting reruns that side only
        s = json.loads((cand / "summary.json").read_text())
        s["run"]["interrupted"] = True
        (cand / "summary.json").write_text(json.dumps(s))
        self.assertEqual(self.gate(out, "--candidate-set", "solver.seed={seed+1000}").returncode, 0)
        self.assertEqual(self.ncalls(), 13)
        self.assertEqual(self.gate(out, "--candidate-set", "solver.seed={seed+2000}").returncode, 0)
        self.assertEqual(self.ncalls(), 19)
        # a new folder with --reuse takes the base runs from the first one
        r = self.gate(self.dir / "gate2", "--reuse", str(out), "--candidate-set", "test.shift=0")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(self.ncalls(), 25)

    def test_base_runs_of_an_earlier_sweep(self):
        # a sweep's layout: runs/<point, numbers as the sweep file wrote them>/seed_<s>/
        sweep = self.dir / "sweep"
        # the fake candidate's numbers at (0, 0); 0.01 above them at (1, 0)
        for point, shift in (("contact.mu_roll=0.0,contact.mu_twist=0.0", 0.0),
                             ("contact.mu_roll=1.0,contact.mu_twist=0.0", 0.11)):
            for seed in (1, 2, 3):
                run = sweep / "runs" / point / f"seed_{seed}"
                run.mkdir(parents=True)
                (run / "summary.json").write_text(json.dumps(summary(
                    porosity=0.7 + 0.01 * seed + shift, sigma_plus=2.0, sigma_minus=-1.0)))
        out = self.dir / "gate"
        r = subprocess.run(
            [sys.executable, str(TOOL), "--base-runs", str(sweep), "--candidate", str(self.fake),
             "--scene", str(self.scene), "--seeds", "1-3", "--points", "0,0", "1,0",
             "--out", str(out), "--jobs", "2"],
            capture_output=True, text=True, env={**os.environ, "FAKE_CALLS": str(self.calls)})
        self.assertEqual(self.ncalls(), 6)                     # the candidate side only
        g = json.loads((out / "gate.json").read_text())
        base = [run["folder"] for run in g["runs"] if run["side"] == "base"]
        self.assertIn(str(sweep / "runs" / "contact.mu_roll=1.0,contact.mu_twist=0.0" / "seed_2"),
                      base)
        self.assertEqual(g["programs"]["base"]["binary"], f"runs of {sweep}")
        self.assertEqual([p["verdict"].split()[0] for p in g["points"]], ["PASS", "FAIL"], r.stdout)
        # a seed the sweep lacks is named, and nothing runs
        r = subprocess.run(
            [sys.executable, str(TOOL), "--base-runs", str(sweep), "--candidate", str(self.fake),
             "--scene", str(self.scene), "--seeds", "1-4", "--points", "0,0",
             "--out", str(out), "--jobs", "2"],
            capture_output=True, text=True, env={**os.environ, "FAKE_CALLS": str(self.calls)})
        self.assertEqual(r.returncode, 2)
        self.assertIn("1 base runs missing or unfinished", r.stderr)
        self.assertIn("seed_4", r.stderr)
        self.assertEqual(self.ncalls(), 6)
        # two sweeps against each other (a rerun of a table): nothing runs, no scene needed
        r = subprocess.run(
            [sys.executable, str(TOOL), "--base-runs", str(sweep), "--candidate-runs", str(sweep),
             "--seeds", "1-3", "--points", "0,0", "1,0", "--out", str(self.dir / "two")],
            capture_output=True, text=True, env={**os.environ, "FAKE_CALLS": str(self.calls)})
        self.assertEqual(r.returncode, 0, r.stderr + r.stdout)
        self.assertEqual(self.ncalls(), 6)
        g = json.loads((self.dir / "two" / "gate.json").read_text())
        self.assertEqual([p["n"] for p in g["points"]], [3, 3])

    def test_base_and_base_runs_exclude_each_other(self):
        r = subprocess.run(
            [sys.executable, str(TOOL), "--base", str(self.fake), "--base-runs", str(self.dir),
             "--candidate", str(self.fake), "--scene", str(self.scene), "--seeds", "1-3",
             "--points", "0,0", "--out", str(self.dir / "g")], capture_output=True, text=True)
        self.assertEqual(r.returncode, 2)
        self.assertIn("exactly one of --base PROGRAM and --base-runs SWEEP_DIR", r.stderr)

    def test_shifted_candidate_fails(self):
        r = self.gate(self.dir / "gate", "--candidate-set", "test.shift=0.01")
        self.assertEqual(r.returncode, 1, r.stderr)
        self.assertIn("|mean ΔE| = 1.00e-02", r.stdout)
        self.assertIn("**FAIL**", r.stdout)

    def test_inherited_opening_passes_and_is_named_in_the_report(self):
        out = self.dir / "gate"
        r = self.gate(out, "--base-set", "test.opening=0.15", "--candidate-set",
                      "test.opening=0.16")
        self.assertEqual(r.returncode, 0, r.stderr + r.stdout)
        g = json.loads((out / "gate.json").read_text())
        self.assertEqual(g["verdict"], "PASS")
        self.assertEqual([p["verdict"] for p in g["points"]], ["PASS (inherited: opening)"] * 2)
        self.assertEqual([p["inherited"] for p in g["points"]], [["opening"]] * 2)
        md = (out / "gate.md").read_text()
        self.assertIn("**PASS** (inherited from the base: (0, 0): opening; (1, 0): opening)", md)
        self.assertIn("| **PASS (inherited: opening)** |", md)
        self.assertIn("inherited from the base (not worse than its worst × 1.1): largest cohesive "
                      "opening per step: base worst 0.15, candidate worst 0.16", md)
        # worse than the base's worst × 1.1: fails (only the candidate side runs again)
        r = self.gate(out, "--base-set", "test.opening=0.15", "--candidate-set",
                      "test.opening=0.1666")
        self.assertEqual(r.returncode, 1, r.stderr + r.stdout)
        self.assertIn("worse than the base (its worst × 1.1): largest cohesive opening per step: "
                      "base worst 0.15, candidate worst 0.1666 > 0.165", r.stdout)
        self.assertEqual(self.ncalls(), 18)

    def test_bad_arguments_exit_2_with_the_argument_named(self):
        cases = [(("--jobs", "0"), "--jobs: got '0'"),
                 (("--seeds", "5"), "--seeds: '5' gives 1 seed"),
                 (("--set", "contact.mu_twist=1"), "--set: 'contact.mu_twist=1' sets"),
                 (("--set", "bad.key=1"), "rejected the scene or an override")]
        for extra, message in cases:
            r = self.gate(self.dir / "bad", *extra)
            self.assertEqual(r.returncode, 2, (extra, r.stderr))
            self.assertIn(message, r.stderr)
        # a run rejected with exit status 2 starts no more runs: at most one per job
        self.assertLessEqual(self.ncalls(), 2)
        r = self.gate(self.dir / "bad", binary=self.dir / "missing")
        self.assertEqual(r.returncode, 2)
        self.assertIn(f"--base: '{self.dir / 'missing'}' is not an executable file", r.stderr)


if __name__ == "__main__":
    unittest.main()
