"""cdpowder.clp: linear programs by COIN-OR Clp's interior-point method, through its C interface.

The admissible stress interval (cdpowder.stress_bounds, physics.md §11.3) solves linear
programs of 10⁴–10⁵ rows whose balance rows are ranges a few 1e-7 wide. HiGHS 1.2 (SciPy 1.10's
`linprog`) takes 20–80 s for one at paper scale (1 015 spheres, (0, 0)); Clp's barrier, without
presolve (which fixes those narrow ranges as equalities and then stalls) and without crossover
(the optimum's value and an admissible force set are what the bounds need, not a vertex),
takes 1–3 s (docs/lab/2026-11-30-stress-bounds-on-clp.md,
docs/lab/2026-12-01-polygons-by-their-vertices.md).

Debian's `coinor-libclp1` provides libClp.so.1; `available()` says whether it was found.

    status, objective, x = minimise(cost, matrix, row_lower, row_upper, lower, upper, seconds)

minimises cost·x over lower ≤ x ≤ upper and row_lower ≤ matrix x ≤ row_upper (±inf for a side
without bound). Status 0: optimal; 1: primal infeasible; 2: dual infeasible; 3: stopped at the
time limit; 4: stopped on difficulties or at MAX_ITERATIONS (Clp_status's codes, but for the
cap). Without crossover Clp may call an infeasible program optimal, so an answer that leaves a
bound by more than FEASIBILITY (relative to 1 + |bound|) is reported infeasible.

    status, bound, x = minimise(..., certify=True)

asks for a lower bound on the minimum instead of an answer: the value any dual vector proves
(weak duality, with the rounding of its own sums allowed for; Neumaier and Shcherbina, Math.
Program. 99 (2004) 283), from Clp's row prices. It holds whatever the barrier's primal answer
misses, and is taken once it lies within DUAL_GAP of the answer's value (or, after the last
try, the best within LOOSE_DUAL_GAP).
"""
import ctypes
import ctypes.util
import math
import os
import pickle
import resource
import select
import signal
import time

import numpy as np
import scipy.sparse

_COIN_DBL_MAX = np.finfo(float).max
_BARRIER_NO_CROSSOVER = 4  # ClpSolve::useBarrierNoCross
_PRESOLVE_OFF = 1  # ClpSolve::presolveOff
OPTIMAL, INFEASIBLE, UNBOUNDED, STOPPED, DIFFICULT = range(5)
FEASIBILITY = 1e-7  # the largest relative excess over a bound an answer may have
# A certified bound is taken when it lies within this of the barrier's value (relative): on the
# paper's (0, 0) packings the bound of the setting 96 lies 1e-8 to 5e-5 below it, the
# regularised setting 128's up to 2e-3 (docs/lab/2026-12-02-bounds-by-their-duals.md)
DUAL_GAP = 1e-4
# Where no try's bound lies within DUAL_GAP, the best one within this is taken after the last
# try (HiGHS would take 30–60 s for the program): a bound all the same, up to 1e-3 looser
LOOSE_DUAL_GAP = 1e-2
# Clp's default primal tolerance (1e-7, on its scaled program) leaves answers 3–4e-7 outside the
# narrow balance ranges of a sign-fixed program at paper scale; 1e-8 keeps most within 5e-8.
PRIMAL_TOLERANCE = 1e-8
# When its barrier ends short of the optimum, Clp cleans up with the primal simplex, which on these
# programs can run for minutes (a (0, 0) packing: more than 3 min on a bound program). Capped
# here; a program stopped by the cap has no answer, and cdpowder.stress_bounds hands it to HiGHS.
# At least 1 000: below that, Clp 1.17's initialSolve takes the value as the barrier's own cap
# and lifts the simplex's to 10⁷.
MAX_ITERATIONS = 1000
# The barrier's tries, (setting, primal tolerance) in turn (the setting: ClpSolve's special
# option 4, -1 for Clp's own), until one gives an answer that passes the check: Clp's barrier
# ends short of an admissible answer on one program in five at paper scale, and each try on
# other ones; a second try costs about one more barrier, HiGHS (the last resort) ten
# (docs/lab/2026-12-01-polygons-by-their-vertices.md). 96: the regularisation δ = 1e-5
# ("aggressive gamma" 3); 128: γ = δ = 1e-3 (4). On the paper's (0, 0) packings the tolerances
# 1e-8 and Clp's 1e-7 end different programs in a clean-up: the second try answers most of
# those the first does not (a force set's balance then met by stress_bounds' repair, a bound
# proved by its duals; docs/lab/2026-12-02-bounds-by-their-duals.md).
BARRIERS = ((96, PRIMAL_TOLERANCE), (96, 1e-7), (128, PRIMAL_TOLERANCE), (-1, PRIMAL_TOLERANCE))
# A setting whose clean-up runs long is stopped for the next one: after the first admissible
# answers, each try is capped at TRY_FACTOR times the median time of the tries that gave one,
# and at TRY_FLOOR seconds at least (stress_bounds.Program keeps the times; `tries`).
TRY_FACTOR = 4.0
TRY_FLOOR = 5.0
# A capped try runs in a forked child, killed at its cap (Clp's own limit is not read in a
# clean-up's values pass): at HARD_GRACE CPU seconds past it, or at HARD_WALL_FACTOR times
# that on the wall clock (a child that waits)
HARD_CAP = True
HARD_GRACE = 1.0
HARD_WALL_FACTOR = 3.0

_library = None


def _load():
    """libClp with the prototypes of the functions used here, or None when it is missing."""
    global _library
    if _library is not None:
        return _library or None
    name = ctypes.util.find_library("Clp")
    try:
        lib = ctypes.CDLL(name or "libClp.so.1")
    except OSError:
        _library = False
        return None
    model, solve = ctypes.c_void_p, ctypes.c_void_p
    doubles, ints = ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_int)
    prototypes = {
        "Clp_newModel": (model, []),
        "Clp_deleteModel": (None, [model]),
        "ClpSolve_new": (solve, []),
        "ClpSolve_delete": (None, [solve]),
        "ClpSolve_setSolveType": (None, [solve, ctypes.c_int, ctypes.c_int]),
        "ClpSolve_setPresolveType": (None, [solve, ctypes.c_int, ctypes.c_int]),
        "ClpSolve_setSpecialOption": (None, [solve, ctypes.c_int, ctypes.c_int, ctypes.c_int]),
        "Clp_setLogLevel": (None, [model, ctypes.c_int]),
        "Clp_setMaximumSeconds": (None, [model, ctypes.c_double]),
        "Clp_setPrimalTolerance": (None, [model, ctypes.c_double]),
        "Clp_setMaximumIterations": (None, [model, ctypes.c_int]),
        "Clp_numberIterations": (ctypes.c_int, [model]),
        "Clp_loadProblem": (None, [model, ctypes.c_int, ctypes.c_int, ints, ints, doubles,
                                   doubles, doubles, doubles, doubles, doubles]),
        "Clp_initialSolveWithOptions": (ctypes.c_int, [model, solve]),
        "Clp_status": (ctypes.c_int, [model]),
        "Clp_getObjValue": (ctypes.c_double, [model]),
        "Clp_getColSolution": (doubles, [model]),
        "Clp_getRowPrice": (doubles, [model]),
    }
    for function, (result, arguments) in prototypes.items():
        getattr(lib, function).restype = result
        getattr(lib, function).argtypes = arguments
    _library = lib
    return lib


def available():
    """Whether libClp can be loaded."""
    return _load() is not None


def _pointer(array, kind):
    return array.ctypes.data_as(ctypes.POINTER(kind))


def _finite_or_max(values):
    """Clp's infinity is COIN_DBL_MAX, not inf."""
    values = np.asarray(values, float)
    return np.ascontiguousarray(np.clip(values, -_COIN_DBL_MAX, _COIN_DBL_MAX))


def _violation(values, low, high):
    """The largest excess of values over [low, high], relative to 1 + |bound|."""
    low, high = np.asarray(low, float), np.asarray(high, float)
    low_finite, high_finite = np.isfinite(low), np.isfinite(high)
    low, high = np.where(low_finite, low, 0.0), np.where(high_finite, high, 0.0)
    below = np.where(low_finite, (low - values) / (1.0 + np.abs(low)), 0.0)
    above = np.where(high_finite, (values - high) / (1.0 + np.abs(high)), 0.0)
    return float(max(0.0, below.max(initial=0.0), above.max(initial=0.0)))


def minimise(cost, matrix, row_lower, row_upper, lower, upper, seconds, admissible=None,
             repair=None, tries=None, certify=False):
    """Returns (status, cost·x, x) of min cost·x (module docstring); x is None unless optimal.
    `admissible`: (row_lower, row_upper, lower, upper) the answer is checked against, if not
    the program's own (a program solved with narrower rows or bounds than an answer must keep).
    `repair`: a function of an answer x that returns it moved onto rows the caller knows how to
    meet exactly (rows that tie one column to others, say); the check then judges the repaired
    answer, and cost·x is its value.
    `tries`: a list of the CPU seconds of earlier tries that gave an admissible answer (the
    caller's, over its programs); each try of this call that gives one is appended, and once it
    holds any, each try is capped at try_cap(tries) seconds: a try stopped there goes on to the
    next setting, as one that ends short does.

    `certify`: returns (OPTIMAL, a lower bound on the minimum, the barrier's x) instead, the
    bound proved by Clp's row prices (dual_bound), once one lies within DUAL_GAP of the value
    of its barrier's x (which is not checked: the bound holds whatever x misses), or after the
    last try the best one within LOOSE_DUAL_GAP; `admissible` and `repair` are then not used.

    The barrier runs with each of BARRIERS' tries in turn until one's answer passes the check
    (or its bound, to certify); the last one's status is returned when none does. Clp's time
    limit, `seconds`, covers them all.

    Columns fixed by their bounds (lower = upper) are taken out before Clp sees the program,
    their part moved to the rows' bounds: a barrier without presolve keeps such a column as a
    box of zero width. Rows left empty by that must hold 0 (else the program is infeasible)
    and are taken out too."""
    matrix = scipy.sparse.csc_matrix(matrix)
    cost, lower, upper = (np.asarray(a, float) for a in (cost, lower, upper))
    row_lower, row_upper = np.asarray(row_lower, float), np.asarray(row_upper, float)
    fixed = lower == upper
    free = np.flatnonzero(~fixed)
    constant = matrix[:, fixed] @ lower[fixed]
    reduced = matrix[:, free].tocsr()
    used = np.diff(reduced.indptr) > 0
    # without crossover Clp can call an infeasible program optimal: each answer is checked,
    # against the program as given (the rows only fixed columns touch, each row's own bounds)
    # or against `admissible`
    check = admissible or (row_lower, row_upper, lower, upper)
    if not (used.any() and len(free)):  # no row left on a free column: each at its cheaper bound
        status, x_free = _bounds_only(cost[free], lower[free], upper[free])
        return _checked(status, x_free, cost, matrix, lower, free, check, repair)
    spent = 0.0  # CPU seconds of this call's tries: Clp's time limit is in CPU seconds
    answer = (DIFFICULT, None, None)
    loose = (DIFFICULT, None, None)  # the best bound within LOOSE_DUAL_GAP (certify)
    program = (cost[free], reduced[used], row_lower[used] - constant[used],
               row_upper[used] - constant[used], lower[free], upper[free])
    for barrier, tolerance in BARRIERS:
        left = seconds - spent
        if left <= 0:
            return loose if loose[0] == OPTIMAL else (STOPPED, None, None)
        cap = try_cap(tries)
        capped = cap is not None and cap < left
        status, x_free, prices, used_seconds = _try(program, cap if capped else left, barrier,
                                                    tolerance, capped and HARD_CAP)
        spent += used_seconds
        if status == STOPPED and capped:
            continue  # the try's cap, not the program's limit: the next setting
        if status in (STOPPED, INFEASIBLE, UNBOUNDED):
            # a bound already proved holds whatever a later try says (a barrier without
            # crossover cannot prove infeasibility)
            return loose if loose[0] == OPTIMAL else (status, None, None)
        if certify:
            answer, gap = _certified(status, x_free, prices, program,
                                     float(cost[fixed] @ lower[fixed]), lower, free)
            tight = gap <= DUAL_GAP
            if gap <= LOOSE_DUAL_GAP and (loose[1] is None or answer[1] > loose[1]):
                loose = answer  # every proved bound holds: the largest is the best
            answer = loose if tight else (DIFFICULT, None, None)
        else:
            answer = _checked(status, x_free, cost, matrix, lower, free, check, repair)
        if answer[0] == OPTIMAL:
            if tries is not None:
                tries.append(used_seconds)
            return answer
    return loose if certify and loose[0] == OPTIMAL else answer


def _try(program, seconds, barrier, tolerance, hard):
    """(status, x, row prices, CPU seconds) of one barrier on the reduced program. Where `hard`,
    in a forked child whose CPU time the kernel limits to `seconds` (and HARD_GRACE), STOPPED
    when it is killed there: Clp reads its own time limit only between the simplex's
    iterations, and a clean-up ran 30–60 s past a cap of 5 s on the paper's (0, 0) packings
    (docs/lab/2026-12-02-bounds-by-their-duals.md). A child that does not answer within
    HARD_WALL_FACTOR times that on the wall clock (one that waits, not computes) is killed too."""
    if not hard:
        started = time.process_time()
        status, _, x, prices = _minimise_free(*program, seconds, barrier, tolerance=tolerance)
        return status, x, prices, time.process_time() - started
    limit = seconds + HARD_GRACE
    answer = _in_child(_try, (program, seconds, barrier, tolerance, False), limit,
                       HARD_WALL_FACTOR * limit)
    if answer is None:
        return STOPPED, None, None, seconds
    return answer


def _in_child(function, arguments, cpu_seconds, wall_seconds):
    """function(*arguments) in a forked child, its answer pickled back through a pipe; None when
    the child is killed at its CPU limit (SIGXCPU past `cpu_seconds`, rounded up to a whole
    second) or at `wall_seconds` on the wall clock, or dies without an answer. An exception in
    the child is raised here. The child shares the parent's memory copy-on-write: nothing is
    sent to it."""
    read, write = os.pipe()
    try:
        pid = os.fork()
    except OSError:
        os.close(read)
        os.close(write)
        raise
    if pid == 0:  # the child: answer, and leave without running the parent's exit handlers
        status = 1
        try:
            os.close(read)
            soft = math.ceil(cpu_seconds)
            resource.setrlimit(resource.RLIMIT_CPU, (soft, soft + 1))
            try:
                message = ("answer", function(*arguments))
            except Exception as error:  # noqa: BLE001 (raised again in the parent)
                message = ("error", error)
            with os.fdopen(write, "wb") as pipe:
                try:
                    pickle.dump(message, pipe, protocol=pickle.HIGHEST_PROTOCOL)
                except (pickle.PicklingError, TypeError, AttributeError):
                    pickle.dump(("error", RuntimeError(repr(message[1]))), pipe)
            status = 0
        finally:
            os._exit(status)
    os.close(write)
    deadline = time.monotonic() + wall_seconds
    chunks, ended = [], False
    try:
        while True:
            left = deadline - time.monotonic()
            if left <= 0 or not select.select([read], [], [], left)[0]:
                return None
            chunk = os.read(read, 1 << 20)
            if not chunk:
                ended = True
                break
            chunks.append(chunk)
    finally:
        os.close(read)
        if not ended:  # past the wall clock, or this process interrupted: the child goes too
            os.kill(pid, signal.SIGKILL)
        os.waitpid(pid, 0)
    try:
        kind, value = pickle.loads(b"".join(chunks))
    except (pickle.UnpicklingError, EOFError, ValueError):
        return None  # killed while it wrote
    if kind == "error":
        raise value
    return value


def try_cap(tries):
    """The CPU seconds a try may take after `tries` (minimise), or None without any."""
    if not tries:
        return None
    return max(TRY_FLOOR, TRY_FACTOR * float(np.median(tries)))


def _checked(status, x_free, cost, matrix, lower, free, check, repair=None):
    """(status, cost·x, x) of an answer on the free columns, repaired where a `repair` is given,
    INFEASIBLE where it leaves `check`."""
    if x_free is None:
        return status, None, None
    x = lower.copy()
    x[free] = x_free
    if repair is not None:
        x = repair(x)
    if _violation(matrix @ x, check[0], check[1]) > FEASIBILITY or \
            _violation(x, check[2], check[3]) > FEASIBILITY:
        return INFEASIBLE, None, None
    return OPTIMAL, float(cost @ x), x


def dual_bound(prices, cost, matrix, row_lower, row_upper, lower, upper):
    """The lower bound on min cost·x over lower ≤ x ≤ upper, row_lower ≤ matrix x ≤ row_upper that
    the row prices y prove, whatever y is (weak duality): for every such x,
    cost·x = y·(matrix x) + d·x with d = cost − matrixᵀ y, and each term is at least its value
    at the bound its sign picks. A price whose row has no bound on that side counts as 0. The
    bound is lowered by a bound on the rounding of these sums in double precision (Higham,
    Accuracy and Stability of Numerical Algorithms, §3.1: n u Σ|terms| for a sum of n terms),
    so it holds as computed. −inf where a column whose reduced cost is not 0 to rounding has no
    bound on a side it may take."""
    matrix = scipy.sparse.csc_matrix(matrix)
    y = np.array(prices, float)
    y[(y > 0) & ~np.isfinite(row_lower)] = 0.0
    y[(y < 0) & ~np.isfinite(row_upper)] = 0.0
    reduced = cost - matrix.T @ y
    # the reduced costs' own rounding: each is a sum of 1 + (its column's entries) products;
    # a column whose reduced cost may have either sign is charged at its farther bound
    unit = np.finfo(float).eps
    sums = 1 + np.diff(matrix.indptr)
    reduced_error = sums * unit * (np.abs(cost) + abs(matrix).T @ np.abs(y))
    side = np.where(reduced > 0, lower, upper)
    moving = reduced != 0
    farther = np.maximum(np.abs(lower), np.abs(upper))
    if not np.all(np.isfinite(side[moving])) or \
            not np.all(np.isfinite(farther[reduced_error > 0])):
        return -math.inf
    # a price left is not 0 only where its side is finite; a reduced cost, where its side is
    row_terms = y * np.where(y != 0, np.where(y > 0, row_lower, row_upper), 0.0)
    column_terms = reduced * np.where(moving, side, 0.0)
    error = float(reduced_error[reduced_error > 0] @ farther[reduced_error > 0]) + \
        (len(row_terms) + len(column_terms)) * unit * float(np.abs(row_terms).sum() +
                                                           np.abs(column_terms).sum())
    return math.fsum(row_terms) + math.fsum(column_terms) - error


def _certified(status, x_free, prices, program, fixed_cost, lower, free):
    """((OPTIMAL, the bound the prices prove, x), the bound's gap below x's value, relative) of
    an answer; ((DIFFICULT, None, None), inf) without one or a finite bound."""
    if status != OPTIMAL or x_free is None:
        return (DIFFICULT, None, None), math.inf
    bound = dual_bound(prices, *program)
    value = float(program[0] @ x_free)
    if not math.isfinite(bound):
        return (DIFFICULT, None, None), math.inf
    # relative to the objective's terms at x as well, so that an optimum near 0 (terms that
    # cancel) is judged on their size
    size = max(abs(value), abs(bound), float(np.abs(program[0] * x_free).sum()),
               np.finfo(float).tiny)
    gap = max(0.0, value - bound) / size
    x = lower.copy()
    x[free] = x_free
    return (OPTIMAL, bound + fixed_cost, x), gap


def _bounds_only(cost, lower, upper):
    """(status, x) of min cost·x over lower ≤ x ≤ upper alone."""
    # a column the cost does not weigh: the point of its bounds nearest 0
    x = np.where(cost > 0, lower, np.where(cost < 0, upper, np.clip(0.0, lower, upper)))
    if not np.all(np.isfinite(x)):
        return UNBOUNDED, None
    return OPTIMAL, x


def _minimise_free(cost, matrix, row_lower, row_upper, lower, upper, seconds, barrier,
                   tolerance=PRIMAL_TOLERANCE):
    """(status, cost·x, x, row prices) of Clp's barrier on a program handed as it is; minimise()
    checks x."""
    lib = _load()
    if lib is None:
        raise OSError("COIN-OR Clp (libClp.so.1, Debian's coinor-libclp1) was not found")
    columns = scipy.sparse.csc_matrix(matrix)
    columns.sort_indices()
    rows, width = columns.shape
    start = np.ascontiguousarray(columns.indptr, np.int32)
    index = np.ascontiguousarray(columns.indices, np.int32)
    value = np.ascontiguousarray(columns.data, float)
    arrays = [_finite_or_max(a) for a in (lower, upper, cost, row_lower, row_upper)]
    model = lib.Clp_newModel()
    options = lib.ClpSolve_new()
    try:
        lib.Clp_setLogLevel(model, 0)
        lib.Clp_setMaximumSeconds(model, float(seconds))
        lib.Clp_setPrimalTolerance(model, tolerance)
        lib.Clp_setMaximumIterations(model, MAX_ITERATIONS)
        lib.Clp_loadProblem(model, width, rows, _pointer(start, ctypes.c_int),
                            _pointer(index, ctypes.c_int), _pointer(value, ctypes.c_double),
                            *(_pointer(a, ctypes.c_double) for a in arrays))
        lib.ClpSolve_setSolveType(options, _BARRIER_NO_CROSSOVER, -1)
        lib.ClpSolve_setPresolveType(options, _PRESOLVE_OFF, -1)
        if barrier >= 0:
            lib.ClpSolve_setSpecialOption(options, 4, barrier, -1)
        started = time.process_time()  # Clp's time limit is in CPU seconds
        lib.Clp_initialSolveWithOptions(model, options)
        status = lib.Clp_status(model)
        if status == STOPPED and (lib.Clp_numberIterations(model) >= MAX_ITERATIONS or
                                  time.process_time() - started < seconds):
            status = DIFFICULT  # not the time limit: the clean-up's cap or the barrier's own
        if status != OPTIMAL:
            return status, None, None, None
        x = np.ctypeslib.as_array(lib.Clp_getColSolution(model), shape=(width,)).copy()
        prices = np.ctypeslib.as_array(lib.Clp_getRowPrice(model), shape=(rows,)).copy()
        return status, float(lib.Clp_getObjValue(model)), x, prices
    finally:
        lib.ClpSolve_delete(options)
        lib.Clp_deleteModel(model)
