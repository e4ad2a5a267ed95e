"""cdpowder.clp (python/cdpowder/clp.py): COIN-OR Clp's barrier through its C interface, on linear
programs whose answers are known. Run by ctest (python_module_test)."""
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
