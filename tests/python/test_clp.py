"""cdpowder.clp (python/cdpowder/clp.py): COIN-OR Clp's barrier through its C interface, on linear
programs whose answers are known. Run by ctest (python_module_test)."""
import time

import numpy as np
import pytest
import scipy.sparse

from cdpowder import clp

pytestmark = pytest.mark.skipif(not clp.available(),
                                reason="COIN-OR Clp (Debian's coinor-libclp1) is not installed")


def test_a_small_program_has_its_known_optimum():
    # max x + y over x + 2y ≤ 4, 3x + y ≤ 6, x, y ≥ 0: the vertex (8/5, 6/5), value 14/5
    matrix = scipy.sparse.csr_matrix([[1.0, 2.0], [3.0, 1.0]])
    status, value, x = clp.minimise([-1.0, -1.0], matrix, [-np.inf, -np.inf], [4.0, 6.0],
                                    [0.0, 0.0], [np.inf, np.inf], 60)
    assert status == clp.OPTIMAL
    assert value == pytest.approx(-14 / 5, rel=1e-7)
    assert x == pytest.approx([8 / 5, 6 / 5], rel=1e-6)


def test_ranged_rows_and_free_columns_are_kept():
    # min x − y with 1 ≤ x + y ≤ 1 + 1e-7 (a narrow range, as the balance rows are), x free,
    # −2 ≤ y ≤ 3: y at 3, x = 1 − 3, value −5
    matrix = scipy.sparse.csr_matrix([[1.0, 1.0]])
    status, value, x = clp.minimise([1.0, -1.0], matrix, [1.0], [1.0 + 1e-7], [-np.inf, -2.0],
                                    [np.inf, 3.0], 60)
    assert status == clp.OPTIMAL
    assert value == pytest.approx(-5.0, abs=1e-6)
    assert x[1] == pytest.approx(3.0, abs=1e-6)
    assert 1.0 - 1e-9 <= x.sum() <= 1.0 + 1e-7 + 1e-9


def test_an_infeasible_program_says_so():
    # x ≥ 2 and x ≤ 1
    matrix = scipy.sparse.csr_matrix([[1.0]])
    status, value, x = clp.minimise([1.0], matrix, [2.0], [np.inf], [-np.inf], [1.0], 60)
    assert status == clp.INFEASIBLE
    assert value is None and x is None


def test_a_dual_bound_holds_for_any_prices_and_is_the_optimum_at_the_optimal_ones():
    # min −x − y over x + 2y ≤ 4, 3x + y ≤ 6, 0 ≤ x, y ≤ 10: optimum −14/5 at the prices
    # (−2/5, −1/5) (weak duality: no prices prove a bound above it)
    matrix = scipy.sparse.csr_matrix([[1.0, 2.0], [3.0, 1.0]])
    program = ([-1.0, -1.0], matrix, np.array([-np.inf, -np.inf]), np.array([4.0, 6.0]),
               np.zeros(2), np.full(2, 10.0))
    assert clp.dual_bound([-0.4, -0.2], *program) == pytest.approx(-14 / 5, abs=1e-12)
    assert clp.dual_bound([-0.4, -0.2], *program) <= -14 / 5
    rng = np.random.default_rng(5)
    for prices in rng.normal(size=(200, 2)):  # a price of the wrong sign counts as 0
        assert clp.dual_bound(prices, *program) <= -14 / 5
    # a column whose reduced cost asks for a bound it does not have proves nothing
    assert clp.dual_bound([0.0, 0.0], *program[:5], np.array([np.inf, 10.0])) == -np.inf


def test_a_certified_minimum_is_a_bound_close_to_the_optimum():
    # certify: the value is the bound Clp's row prices prove, below the optimum and within
    # DUAL_GAP of it; the answer x is the barrier's
    matrix = scipy.sparse.csr_matrix([[1.0, 2.0], [3.0, 1.0]])
    status, bound, x = clp.minimise([-1.0, -1.0], matrix, [-np.inf, -np.inf], [4.0, 6.0],
                                    [0.0, 0.0], [10.0, 10.0], 60, certify=True)
    assert status == clp.OPTIMAL
    assert -14 / 5 * (1 + clp.DUAL_GAP) <= bound <= -14 / 5
    assert x == pytest.approx([8 / 5, 6 / 5], rel=1e-6)


def test_a_loose_certified_bound_is_the_last_resort(monkeypatch):
    # min x0 over x0 + x1 = 1, 0.5 ≤ x0 ≤ 1, 0 ≤ x1 ≤ 1: optimum 0.5. Prices 0.001 prove 0.4995
    # (a gap of 1e-3, past DUAL_GAP): every try is asked, then that bound is taken; prices 0.5
    # prove 0.25 (past LOOSE_DUAL_GAP): no bound, HiGHS decides
    program = ([1.0, 0.0], np.array([[1.0, 1.0]]), [1.0], [1.0], [0.5, 0.0], [1.0, 1.0], 10.0)
    asked = []
    for price, expected in ((0.001, 0.4995), (0.5, None)):
        asked.clear()

        def answer(*args, price=price, **options):
            asked.append(args[-1])
            return clp.OPTIMAL, 0.5, np.array([0.5, 0.5]), np.array([price])

        monkeypatch.setattr(clp, "_minimise_free", answer)
        status, bound, _ = clp.minimise(*program, certify=True)
        assert len(asked) == len(clp.BARRIERS)
        if expected is None:
            assert status == clp.DIFFICULT and bound is None
        else:
            assert status == clp.OPTIMAL and bound == pytest.approx(expected, abs=1e-12)


def test_a_loose_bound_holds_when_a_later_try_stops(monkeypatch):
    # a bound proved by one try is returned when a later try stops (not at a cap of its own)
    program = ([1.0, 0.0], np.array([[1.0, 1.0]]), [1.0], [1.0], [0.5, 0.0], [1.0, 1.0], 10.0)
    answers = iter([(clp.OPTIMAL, 0.5, np.array([0.5, 0.5]), np.array([0.001])),
                    (clp.STOPPED, None, None, None)])
    monkeypatch.setattr(clp, "_minimise_free", lambda *args, **options: next(answers))
    status, bound, _ = clp.minimise(*program, certify=True)
    assert status == clp.OPTIMAL and bound == pytest.approx(0.4995, abs=1e-12)


def test_a_child_is_killed_at_its_cpu_limit_and_its_errors_are_raised():
    # _in_child: a child that computes past its CPU limit is killed by the kernel (SIGXCPU),
    # whatever the wall clock allows; an exception in the child is raised in the parent
    def spin():
        while True:
            pass

    def fail():
        raise ValueError("the child's own")

    started = time.monotonic()
    assert clp._in_child(spin, (), 0.5, 60.0) is None
    assert time.monotonic() - started < 30.0
    with pytest.raises(ValueError, match="the child's own"):
        clp._in_child(fail, (), 5.0, 60.0)
    assert clp._in_child(sum, ([1, 2, 3],), 5.0, 60.0) == 6
