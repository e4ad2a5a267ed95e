"""`cdpowder stress-bounds` (python/cdpowder/stress_bounds.py, physics.md §11.3): the admissible
stress interval of a finished packing. Run by ctest (python_module_test); needs CDPOWDER_EXE
and CDPOWDER_SOURCE_DIR in the environment."""
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import scipy.optimize
import scipy.sparse

from cdpowder import clp, force_set_repair, stress_bounds

SOURCE = Path(os.environ["CDPOWDER_SOURCE_DIR"])
QUICK = SOURCE / "examples/quick/scene.toml"
ENVIRONMENT = {**os.environ, "CDPOWDER_PYTHON": sys.executable}

# one sphere between the bottom and the piston: its normal forces are the load, and its
# tangential forces a self-stress of the two wall contacts held by the rolling couples
COLUMN = """
[system]
lx = 5.0
ly = 5.0
[particles]
file = "column.csv"
[contact]
mu = 0.3
mu_roll = 0.2
mu_twist = 0.1
[piston]
enabled = true
pressure = 0.01
mass = 10.0
[run]
until_blocked = true
max_duration = 500.0
"""


def program(*args, check=True):
    done = subprocess.run([os.environ["CDPOWDER_EXE"], *map(str, args)], capture_output=True,
                          text=True, env=ENVIRONMENT)
    if check:
        assert done.returncode == 0, done.stderr
    return done


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("quick") / "run"
    program("compact", QUICK, "--out", folder, "--quiet")
    return folder


@pytest.fixture(scope="module")
def column_run(tmp_path_factory):
    base = tmp_path_factory.mktemp("column")
    (base / "column.csv").write_text("id,x,y,z,r\n0,2.5,2.5,1.0,1.0\n")
    (base / "column.toml").write_text(COLUMN)
    program("compact", base / "column.toml", "--out", base / "run", "--quiet")
    return base / "run"


def test_the_program_has_the_runs_stress_and_balances_its_forces(quick_run):
    packing = stress_bounds.Packing(quick_run)
    prog = stress_bounds.Program(packing, facets=16)
    sigma = np.array(packing.summary["stress"]["sigma"])
    for i in range(3):
        for j in range(3):
            row, constant = prog.stress_row(i, j)
            assert row @ prog.run_x + constant == pytest.approx(sigma[i, j], rel=1e-9, abs=1e-15)
    # the run's forces balance every sphere and the piston in the program's equations to the
    # run's own accuracy gauges (its largest net force on a sphere, the piston's force
    # imbalance); a wrong sign or lever would leave residuals of the order of the forces
    # (0.1 F_coh)
    residual = np.abs(prog.balance @ prog.run_x - prog.rhs)
    rows = np.arange(len(residual))
    spheres = rows < len(residual) - 1 if prog.has_piston else rows >= 0
    net_force = packing.summary["accuracy"]["max_net_force"]
    assert residual[spheres & (rows % 6 < 3)].max() <= net_force * (1 + 1e-9) + 1e-12
    assert residual[spheres & (rows % 6 >= 3)].max() <= 1e-5
    piston = packing.summary["piston"]
    assert residual[-1] == pytest.approx(piston["force_imbalance"] * piston["load"], rel=1e-6)
    assert residual.max() <= 1e-3
    assert prog.tolerance["force"] <= 1e-3 and prog.tolerance["torque"] <= 1e-5


def test_a_single_sphere_column_has_the_shear_interval_of_its_couples(column_run):
    # |R_t| ≤ min(μ, μ_t) (F + F_coh) (sliding, and the rolling couples that balance the pair
    # of tangential forces: 2 R |R_t| ≤ 2 μ_t R S); σ_xz = 2 R R_t,x / V
    facets = 16
    result = stress_bounds.admissible_stress(column_run, components=["xz", "zz"], facets=facets)
    summary = json.loads((column_run / "summary.json").read_text())
    load = summary["piston"]["load"]
    exact = 2 * 1.0 * min(0.3, 0.2) * (load + 1.0) / summary["packing_volume"]
    shear = result["sigma_xz"]
    # a bound is the one its duals prove, within clp.DUAL_GAP of the optimum (relative)
    assert exact <= shear["max"] <= exact / math.cos(math.pi / facets) * (1 + clp.DUAL_GAP)
    assert exact * math.cos(math.pi / facets) * (1 - 1e-6) <= shear["max_attained"] <= exact
    assert shear["min"] == pytest.approx(-shear["max"], rel=2 * clp.DUAL_GAP)
    # the normal forces are the load: σ_zz and its compressive part are p, the tension none
    pressure = summary["piston"]["applied_pressure"]
    for side in ("min_attained", "max_attained"):
        assert result["sigma_zz"][side] == pytest.approx(pressure, rel=1e-5)
    for side in ("min", "max"):
        assert result["sigma_zz"][side] == pytest.approx(pressure, rel=clp.DUAL_GAP)
    assert result["sigma_zz_plus"]["min_attained"] == pytest.approx(pressure, rel=1e-5)
    assert result["sigma_zz_plus"]["max_attained"] == pytest.approx(pressure, rel=1e-5)


def test_the_command_adds_an_interval_that_holds_the_run(quick_run):
    done = program("stress-bounds", quick_run)
    assert "sigma_zz_plus/p" in done.stdout
    result = json.loads((quick_run / "summary.json").read_text())["admissible_stress"]
    for key in ("sigma_zz", "sigma_zz_plus", "sigma_zz_minus"):
        entry = result[key]
        assert entry["min"] <= entry["min_attained"] <= entry["run"], key
        assert entry["run"] <= entry["max_attained"] <= entry["max"], key
    # σ_zz is the load for every balanced force set (physics.md §11.2)
    pressure = json.loads((quick_run / "summary.json").read_text())["piston"]["applied_pressure"]
    assert result["sigma_zz"]["min"] == pytest.approx(pressure, rel=1e-3)
    assert result["sigma_zz"]["max"] == pytest.approx(pressure, rel=1e-3)
    assert result["facets"] == 16 and result["contacts"]["touching"] > 0


@pytest.mark.skipif(not clp.available(), reason="COIN-OR Clp (coinor-libclp1) is not installed")
def test_clp_answers_programs_with_fixed_columns():
    # min x0 + 2 x1 + 3 x2 over 1 ≤ x0 + x1 + x2 ≤ 4, x1 − x2 ≥ −5, x2 ≥ 0, with x2 fixed at 0.5
    # and x0, x1 ≥ 0: the optimum x = (0.5, 0, 0.5), cost 2; the fixed column's part goes to the
    # rows' bounds and the answer holds it
    matrix = np.array([[1.0, 1.0, 1.0], [0.0, 1.0, -1.0]])
    status, cost, x = clp.minimise([1.0, 2.0, 3.0], matrix, [1.0, -5.0], [4.0, np.inf],
                                   [0.0, 0.0, 0.5], [np.inf, np.inf, 0.5], 10.0)
    assert status == clp.OPTIMAL
    assert x == pytest.approx([0.5, 0.0, 0.5], abs=1e-7) and cost == pytest.approx(2.0, abs=1e-7)
    # a row that only fixed columns touch must hold by itself: x2 = 0.5 against x2 ≥ 1
    status, _, x = clp.minimise([1.0, 2.0, 3.0], np.vstack([matrix, [0.0, 0.0, 1.0]]),
                                [1.0, -5.0, 1.0], [4.0, np.inf, np.inf], [0.0, 0.0, 0.5],
                                [np.inf, np.inf, 0.5], 10.0)
    assert status == clp.INFEASIBLE and x is None
    # every column fixed, and rows that only fixed columns touch: answered without Clp
    status, cost, x = clp.minimise([1.0, 2.0, 3.0], matrix, [0.0, -5.0], [4.0, np.inf],
                                   [0.5] * 3, [0.5] * 3, 10.0)
    assert status == clp.OPTIMAL and cost == pytest.approx(3.0) and list(x) == [0.5] * 3
    status, cost, x = clp.minimise([1.0, 2.0, 3.0], np.array([[0.0, 0.0, 1.0]]), [0.0], [1.0],
                                   [0.0, 0.0, 0.5], [1.0, np.inf, 0.5], 10.0)
    assert status == clp.OPTIMAL and cost == pytest.approx(1.5) and list(x) == [0.0, 0.0, 0.5]


@pytest.mark.skipif(not clp.available(), reason="COIN-OR Clp (coinor-libclp1) is not installed")
def test_clp_checks_an_answer_against_what_is_admissible():
    # min x0 over x0 + x1 = 1, 0 ≤ x ≤ 1: x = (0, 1). Checked against wider rows and bounds it
    # stands; against bounds that x1 = 1 leaves it is refused (a sign-fixed program's answer
    # is judged by the admissible bounds, not the search's)
    matrix = np.array([[1.0, 1.0]])
    program = ([1.0, 0.0], matrix, [1.0], [1.0], [0.0, 0.0], [1.0, 1.0], 10.0)
    status, cost, x = clp.minimise(*program, admissible=([0.99], [1.01], [-1.0, -1.0], [2.0, 2.0]))
    assert status == clp.OPTIMAL and x == pytest.approx([0.0, 1.0], abs=1e-7)
    status, _, x = clp.minimise(*program, admissible=([0.99], [1.01], [-1.0, -1.0], [2.0, 0.5]))
    assert status == clp.INFEASIBLE and x is None


@pytest.mark.skipif(not clp.available(), reason="COIN-OR Clp (coinor-libclp1) is not installed")
def test_clp_stopped_at_the_time_limit_is_stopped():
    # a time limit reached is STOPPED (a program that gives nothing), not DIFFICULT (which
    # stress_bounds hands to HiGHS); with time enough the same program is solved
    rng = np.random.default_rng(1)
    n = 400
    matrix = scipy.sparse.random(n, n, density=0.05, random_state=2) + scipy.sparse.eye(n)
    program = (rng.uniform(-1.0, 1.0, n), matrix, -np.ones(n), np.ones(n), np.full(n, -5.0),
               np.full(n, 5.0))
    assert clp.minimise(*program, 1e-9)[0] == clp.STOPPED
    assert clp.minimise(*program, 60.0)[0] == clp.OPTIMAL


@pytest.mark.parametrize("facets", [5, 6, 16])
def test_the_unknowns_bounds_hold_every_polygon_at_the_force_cap(quick_run, facets):
    # Program.bounds(scale) must not cut the polygons (radius × scale) the thresholds allow at
    # the largest normal force, for any number of sides: each vertex lies within the bounds
    program = stress_bounds.Program(stress_bounds.Packing(quick_run), facets)
    p, m, free = program.packing, program.m, program.free
    half = math.pi / facets
    for scale in (math.cos(half), 1.0 / math.cos(half)):
        lower, upper = program.bounds(scale)
        for first, cap in ((1, p.mu[free]), (3, p.roll_cap[free])):
            radius = scale * cap * (program.force_cap + p.cohesion[free]) / math.cos(half)
            for k in range(facets):  # vertex between facets k and k + 1
                angle = 2 * math.pi * k / facets + half
                for q, coordinate in ((first, math.cos(angle)), (first + 1, math.sin(angle))):
                    value = radius * coordinate
                    column = slice(q * m, (q + 1) * m)
                    assert np.all(value <= upper[column] * (1 + 1e-12) + 1e-300), (scale, q, k)
                    assert np.all(value >= lower[column] * (1 + 1e-12) - 1e-300), (scale, q, k)


@pytest.mark.parametrize("facets", [5, 16])
def test_a_polygon_by_its_vertices_has_the_sides_of_the_threshold(quick_run, facets):
    # Program.thresholds writes each disc by K weighted vertices: the mode is reached along the
    # normal of each side θ = 2πk/K as far as scale × cap (R_n + F_c), and no further, and a
    # vertex lies at that over cos(π/K): the polygon of the sides cos θ x1 + sin θ x2 ≤ scale
    # cap (R_n + F_c). Checked on one contact's sliding mode, R_n at the run's value, by linprog.
    program = stress_bounds.Program(stress_bounds.Packing(quick_run), facets)
    p, m = program.packing, program.m
    c = int(np.flatnonzero(p.mu[program.free] > 0)[0])
    radius = p.mu[program.free][c] * (program.run_x[c] + p.cohesion[program.free][c])
    half = math.pi / facets
    for scale in (math.cos(half), 1.0):
        g, low, high = program.thresholds(scale)
        lower, upper = program.bounds(scale)
        lower[:m] = upper[:m] = program.run_x[:m]  # the normal forces held
        equal, below = low == high, np.isfinite(high) & (low != high)

        def farthest(angle):  # the largest reach of the sliding mode along the angle
            cost = np.zeros(program.width)
            cost[m + c], cost[2 * m + c] = -math.cos(angle), -math.sin(angle)
            res = scipy.optimize.linprog(cost, A_ub=g[below], b_ub=high[below], A_eq=g[equal],
                                         b_eq=high[equal], bounds=np.column_stack([lower, upper]),
                                         method="highs")
            assert res.status == 0
            return -res.fun

        for k in range(facets):
            assert farthest(2 * half * k) == pytest.approx(scale * radius, rel=1e-9)
        assert farthest(half) == pytest.approx(scale * radius / math.cos(half), rel=1e-9)


@pytest.mark.skipif(not clp.available(), reason="COIN-OR Clp (coinor-libclp1) is not installed")
def test_clp_tries_the_next_barrier_setting_when_an_answer_is_refused(monkeypatch):
    # min x0 over x0 + x1 = 1, 0 ≤ x ≤ 1: x = (0, 1). A first setting whose answer leaves the
    # row is refused and the next one is asked; where every setting's is refused, the program
    # has no answer (stress_bounds then asks HiGHS)
    asked = []
    solve = clp._minimise_free

    def first_one_wrong(*args, **options):
        asked.append(args[-1])
        status, cost, x, prices = solve(*args, **options)
        return (status, cost, x + 0.5, prices) if len(asked) == 1 else (status, cost, x, prices)

    monkeypatch.setattr(clp, "_minimise_free", first_one_wrong)
    program = ([1.0, 0.0], np.array([[1.0, 1.0]]), [1.0], [1.0], [0.0, 0.0], [1.0, 2.0], 10.0)
    status, _, x = clp.minimise(*program)
    assert asked == [barrier for barrier, _ in clp.BARRIERS[:2]]
    assert status == clp.OPTIMAL and x == pytest.approx([0.0, 1.0], abs=1e-7)
    monkeypatch.setattr(clp, "_minimise_free",
                        lambda *args, **options: (clp.OPTIMAL, 0.0, np.array([0.5, 0.0]), None))
    assert clp.minimise(*program)[0] == clp.INFEASIBLE


@pytest.mark.skipif(not clp.available(), reason="COIN-OR Clp (coinor-libclp1) is not installed")
def test_clp_checks_the_repaired_answer(monkeypatch):
    # min x0 over x0 + x1 = 1, 0 ≤ x ≤ 1: an answer that leaves the row is refused, unless a
    # repair moves it back onto the row; the value returned is the repaired answer's
    program = ([1.0, 0.0], np.array([[1.0, 1.0]]), [1.0], [1.0], [0.0, 0.0], [1.0, 1.0], 10.0)
    off = np.array([0.25, 0.75 + 1e-5])
    monkeypatch.setattr(clp, "_minimise_free", lambda *args, **options: (clp.OPTIMAL, 0.25, off, None))
    assert clp.minimise(*program)[0] == clp.INFEASIBLE
    status, value, x = clp.minimise(*program, repair=lambda x: np.array([x[0], 1.0 - x[0]]))
    assert status == clp.OPTIMAL and x == pytest.approx([0.25, 0.75], abs=1e-15)
    assert value == 0.25


@pytest.mark.skipif(not clp.available(), reason="COIN-OR Clp (coinor-libclp1) is not installed")
def test_a_try_past_its_cap_goes_on_to_the_next_setting(monkeypatch):
    # after tries that gave answers, a try is capped at TRY_FACTOR times their median (TRY_FLOOR
    # at least); a try stopped at its cap (a clean-up that runs long) goes on to the next
    # setting, not to the end of the program, and the try that answers is added to the times
    assert clp.try_cap([]) is None and clp.try_cap(None) is None
    assert clp.try_cap([0.1, 0.2, 9.0]) == clp.TRY_FLOOR
    assert clp.try_cap([2.0, 3.0, 100.0]) == pytest.approx(clp.TRY_FACTOR * 3.0)
    asked = []
    solve = clp._minimise_free

    def first_one_capped(*args, **options):
        asked.append(args[-2:])
        return (clp.STOPPED, None, None, None) if len(asked) == 1 else solve(*args, **options)

    monkeypatch.setattr(clp, "_minimise_free", first_one_capped)
    monkeypatch.setattr(clp, "HARD_CAP", False)  # `asked` is this process's
    program = ([1.0, 0.0], np.array([[1.0, 1.0]]), [1.0], [1.0], [0.0, 0.0], [1.0, 2.0], 100.0)
    tries = [0.01]
    status, _, x = clp.minimise(*program, tries=tries)
    assert [barrier for _, barrier in asked] == [barrier for barrier, _ in clp.BARRIERS[:2]]
    assert [seconds for seconds, _ in asked] == [clp.TRY_FLOOR, clp.TRY_FLOOR]
    assert status == clp.OPTIMAL and x == pytest.approx([0.0, 1.0], abs=1e-7)
    assert len(tries) == 2
    # without earlier tries there is no cap: a stop is the program's time limit
    asked.clear()
    assert clp.minimise(*program, tries=[])[0] == clp.STOPPED
    assert asked[0][0] == pytest.approx(100.0, abs=1.0)


@pytest.mark.skipif(not clp.available(), reason="COIN-OR Clp (coinor-libclp1) is not installed")
def test_a_capped_try_that_does_not_end_is_killed(monkeypatch):
    # Clp reads its time limit only between simplex iterations: a capped try runs in a child
    # that is killed at its cap (here one that waits, at the wall clock's limit), and the next
    # setting answers
    solve = clp._minimise_free

    def first_one_hangs(*args, **options):
        if args[-1] == clp.BARRIERS[0][0] and options["tolerance"] == clp.BARRIERS[0][1]:
            time.sleep(60)
        return solve(*args, **options)

    monkeypatch.setattr(clp, "_minimise_free", first_one_hangs)
    monkeypatch.setattr(clp, "TRY_FLOOR", 0.5)  # a try's CPU limit 1 s, its wall clock 3 s
    monkeypatch.setattr(clp, "HARD_GRACE", 0.5)
    program = ([1.0, 0.0], np.array([[1.0, 1.0]]), [1.0], [1.0], [0.0, 0.0], [1.0, 2.0], 100.0)
    tries = [0.01]
    started = time.monotonic()
    status, _, x = clp.minimise(*program, tries=tries)
    assert time.monotonic() - started < 10.0
    assert status == clp.OPTIMAL and x == pytest.approx([0.0, 1.0], abs=1e-7)
    assert len(tries) == 2


@pytest.mark.parametrize("scale", [math.cos(math.pi / 16), 1.0])
def test_an_answer_off_its_polygons_is_moved_onto_them(quick_run, scale):
    # An interior-point answer meets the rows that tie a mode to its polygon's weights only to
    # the solver's tolerance. Program.onto_polygons writes each mode as its weights' point,
    # scales weights whose sum passes cap (R_n + F_c) down to it, and clips torsion: every
    # threshold row then holds to rounding, R_n stays, and a mode within its polygon keeps
    # its weights
    program = stress_bounds.Program(stress_bounds.Packing(quick_run), 16)
    m, k = program.m, program.facets
    g, low, high = program.thresholds(scale)
    ranges, lower, upper = program.constraints(scale)
    res = stress_bounds._solve(program, np.zeros(program.width), ranges, lower, upper, scale,
                               (lower, upper))  # a force set's program: its answer is repaired
    assert res.status == 0
    rng = np.random.default_rng(3)
    x = res.x  # the unknowns and the polygons' weights, moved onto the polygons
    inside = program.onto_polygons(x, scale)
    assert inside == pytest.approx(x, abs=1e-12)
    off = x.copy()
    off[m:3 * m] += rng.uniform(-3e-7, 3e-7, 2 * m)  # the ties left, by the barrier's size
    column = 6 * m + k * len(program.disc_modes[0][2])
    off[6 * m:column] *= 1 + 1e-6  # some polygons' weights past their threshold
    off[5 * m:6 * m] += 1e-6  # torsion past its interval where it has one
    ties = low == high
    assert clp._violation(g @ off, low, high) > clp.FEASIBILITY
    fixed = program.onto_polygons(off, scale)
    assert np.abs((g @ fixed)[ties]).max() <= 1e-12
    assert clp._violation(g @ fixed, low, high) <= 1e-12
    assert np.array_equal(fixed[:m], off[:m])


def test_an_answer_off_the_balance_is_moved_onto_it(quick_run):
    # Clp's barrier ends some sign-fixed programs 1e-7 to 1e-6 off a few balance ranges.
    # force_set_repair.onto_balance moves the answer by the least room-weighted step onto them:
    # the rows off their range go to its centre, the others stay, and the polygons, the torsion
    # intervals and the unknowns' bounds still hold
    program = stress_bounds.Program(stress_bounds.Packing(quick_run), 16)
    scale = math.cos(math.pi / 16)
    ranges, lower, upper = program.constraints(scale)
    (balance, b_low, b_high), (g, g_low, g_high) = ranges
    res = stress_bounds._solve(program, np.zeros(program.width), ranges, lower, upper, scale,
                               (lower, upper))
    assert res.status == 0
    x = program.onto_polygons(res.x, scale)
    assert force_set_repair.onto_balance(program, x, scale, b_low, b_high, lower, upper) is x
    m = program.m
    rng = np.random.default_rng(7)
    off = x.copy()
    pushed = rng.choice(m, 5, replace=False)
    off[pushed] += 3e-6 * program.force_cap / 100  # five normal forces: their spheres off
    off = program.onto_polygons(off, scale)
    value = balance @ off
    assert clp._violation(value, b_low, b_high) > clp.FEASIBILITY
    moved = force_set_repair.onto_balance(program, off, scale, b_low, b_high, lower, upper)
    value = balance @ moved
    assert clp._violation(value, b_low, b_high) <= 1e-12
    was_off = (balance @ off < b_low) | (balance @ off > b_high)
    assert value[was_off] == pytest.approx(program.rhs[was_off], abs=1e-12)
    assert value[~was_off] == pytest.approx((balance @ off)[~was_off], abs=1e-12)
    assert clp._violation(g @ moved, g_low, g_high) <= 1e-12
    assert clp._violation(moved, lower, upper) <= 1e-12


@pytest.mark.skipif(not clp.available(), reason="COIN-OR Clp (coinor-libclp1) is not installed")
def test_both_solvers_agree(quick_run):
    # Clp's barrier and HiGHS solve the same programs: σ's bounds agree to the solvers'
    # tolerance (1e-7 of the load in each equation, about 2e-6 of σ_zz on this packing), and each
    # one's attained values hold the run's
    one = stress_bounds.admissible_stress(quick_run, solver="clp")
    highs = stress_bounds.admissible_stress(quick_run, solver="highs")
    assert one["solver"].startswith("COIN-OR Clp") and highs["solver"].startswith("HiGHS")
    for key in ("sigma_zz", "sigma_zz_plus", "sigma_zz_minus"):
        for result in (one, highs):
            entry = result[key]
            assert entry["min"] <= entry["min_attained"] <= entry["run"] <= \
                entry["max_attained"] <= entry["max"], key
    for side in ("min", "max"):
        assert one["sigma_zz"][side] == pytest.approx(highs["sigma_zz"][side], rel=1e-5)
    assert one["stopped_programs"] == 0 and highs["stopped_programs"] == 0


def test_the_interval_does_not_depend_on_the_jobs(quick_run):
    # σ's four programs and the two searches run side by side on forked processes; each search
    # is sequential, and the result keeps extremes over the force sets found, so one process and
    # two give the same numbers and the same count of programs
    one = stress_bounds.admissible_stress(quick_run, jobs=1)
    two = stress_bounds.admissible_stress(quick_run, jobs=2)
    assert (one["jobs"], two["jobs"]) == (1, 2)
    for key in ("sigma_zz", "sigma_zz_plus", "sigma_zz_minus", "linear_programs",
                "highs_fallbacks", "stopped_programs"):
        assert one[key] == two[key], key
    assert one["linear_programs"] >= 6  # σ's four, then at least one a search


def test_a_sweep_asks_for_the_interval_of_every_run(tmp_path):
    sweep = tmp_path / "sweep.toml"
    sweep.write_text(f'scene = "{QUICK}"\nseeds = [1]\n[grid]\n"contact.mu_roll" = [1.0]\n')
    done = program("sweep", sweep, "--out", tmp_path / "out", "--quiet", "--stress-bounds")
    assert "sigma_zz_plus/p" in done.stdout
    [summary] = (tmp_path / "out" / "runs").glob("*/seed_1/summary.json")
    entry = json.loads(summary.read_text())["admissible_stress"]["sigma_zz_plus"]
    assert entry["min_attained"] <= entry["run"] <= entry["max_attained"]


def test_mistakes_are_named(quick_run, tmp_path):
    done = program("stress-bounds", tmp_path / "none", check=False)
    assert done.returncode == 2 and "no scene.toml" in done.stderr
    done = program("stress-bounds", quick_run, "--components", "zq", check=False)
    assert done.returncode == 2 and "--components: got 'zq'" in done.stderr
    done = program("stress-bounds", quick_run, "--facets", "2", check=False)
    assert done.returncode == 2 and "--facets: got 2" in done.stderr
    done = program("stress-bounds", quick_run, "--jobs", "0", check=False)
    assert done.returncode == 2 and "--jobs: got 0" in done.stderr
    done = program("stress-bounds", quick_run, "--solver", "glpk", check=False)
    assert done.returncode == 2 and "--solver: invalid choice: 'glpk'" in done.stderr
    # a run that did not block: its forces balance nothing
    short = tmp_path / "short"
    program("compact", QUICK, "--out", short, "--quiet", "--set", "run.max_duration=1.0",
            check=False)
    before = (short / "summary.json").read_text()
    done = program("stress-bounds", short, check=False)
    assert done.returncode == 2 and "did not end blocked" in done.stderr
    assert (short / "summary.json").read_text() == before


def test_solves_from_rest_lie_inside_the_interval(tmp_path):
    # The quick packing at (0, 0), solved again from zero forces with four visiting orders at a
    # tight tolerance: each is a balanced force set of the same packing (σ_zz/p = 1), so its
    # σzz⁺ lies between the bounds; it differs from the run's own (the path the forces took)
    # while every re-solve stays inside the interval the attained force sets span.
    import pickle

    import cdpowder
    scene = cdpowder.Scene.from_toml(str(QUICK), {"contact.mu_roll": 0.0, "contact.mu_twist": 0.0})
    folder = tmp_path / "run"
    world = cdpowder.compact(scene, out=str(folder)).world
    pressure = scene["piston.pressure"]
    interval = stress_bounds.admissible_stress(folder)["sigma_zz_plus"]
    resolved = []
    for kernel, order, depth in (("coloured", "random_each_step", 5), ("scalar", "fixed", 5),
                                 ("scalar", "random_each_pass", 0), ("coloured", "fixed", 0)):
        again = scene.with_overrides({
            "solver.warm_start": False, "solver.tolerance": 1e-8, "solver.max_passes": 200000,
            "solver.kinematic_tolerance": 0.0, "solver.kernel": kernel,
            "solver.visit_order": order, "solver.acceleration_depth": depth,
            "run.duration": scene["solver.dt"], "run.until_blocked": False})
        step = cdpowder.simulate(again, world=pickle.loads(pickle.dumps(world))).world
        stress = step.stress()
        assert stress["sigma"][2][2] == pytest.approx(pressure, rel=1e-4)
        assert step.last_step.max_net_force < 1e-4
        resolved.append(stress["sigma_plus"][2][2])
    for value in resolved:
        assert interval["min"] <= value <= interval["max"]
        assert interval["min_attained"] <= value <= interval["max_attained"]
    # the path dependence the interval measures: a solve from rest ends far from the run's
    assert max(abs(value - interval["run"]) for value in resolved) > 0.1 * interval["run"]
