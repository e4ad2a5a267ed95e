"""cdpowder.stress_bounds: the admissible stress interval of a finished packing (physics.md §11.3).

The forces of a rigid, hyperstatic packing are not unique (physics.md §12.4): for the packing a
run ends on (its geometry, contacts and cohesion states fixed) every set of contact forces and
couples that balances each sphere and the piston and obeys the model's thresholds is as good an
answer as the run's own. This module computes the smallest and largest σ_ij (and its parts σ⁺
and σ⁻ of compressive and tensile contacts, physics.md §11.2) over all of them:

    python3 -m cdpowder.stress_bounds DIR... [--components zz,xx] [--facets 16] [--jobs 2]

reads each DIR's scene.toml, particles.csv, contacts.csv and summary.json and adds the result
to DIR/summary.json under "admissible_stress" (`cdpowder stress-bounds DIR` runs it; a sweep's
folder stands for its blocked runs). In Python, `admissible_stress(DIR)` returns the same dict
without writing.

The programs (physics.md §11.3):

* unknowns per touching contact: the normal force, the tangential force (2), the rolling
  couple (2) and the torsion couple; a contact whose gap exceeds the touching gap keeps the
  run's force, −F_c along n (open);
* balance: each free sphere's 6 equations and the piston's along z, each as well as the run's
  own forces hold it (so the run's forces are admissible);
* thresholds as in physics.md §5.4, the discs replaced by regular polygons of K sides:
  circumscribed ones give bounds no admissible force set passes, inscribed ones force sets that
  are admissible;
* σ⁺ and σ⁻ split the contacts by the sign of their normal force, which no convex program
  expresses: σ⁻ is bounded by each contact's extremes in tension, σ⁺ = σ − σ⁻ by the
  difference, and the attained values fix the signs and search them.

Each quantity is reported as `min`, `max` (the bounds) and `min_attained`, `max_attained`
(values admissible force sets reach, or the run's own), so the true extremes lie in
[min, min_attained] and [max_attained, max]. Units: F_coh/R², as summary.json's "stress". The
linear programs are solved by COIN-OR Clp's barrier (cdpowder.clp) where Debian's
coinor-libclp1 is installed, else by HiGHS (SciPy's `linprog`); `--solver` chooses.
"""
import argparse
import concurrent.futures
import contextlib
import json
import math
import multiprocessing
import numbers
import os
import pathlib
import sys
import time
import tomllib

try:
    import numpy as np
    import scipy.optimize
    import scipy.sparse

    from cdpowder import clp, force_set_repair, tables
except ImportError as missing:  # the command's one message, not a traceback
    sys.exit(f"error: stress-bounds needs NumPy, pandas and SciPy ({missing}); Debian's "
             "python3-numpy, python3-pandas and python3-scipy (tools/install_deps.sh), or "
             "$CDPOWDER_PYTHON naming a Python that has them")

from cdpowder import summary as summaries

FIELD = "admissible_stress"
SOLVER_NAMES = {"clp": "COIN-OR Clp, barrier without crossover",
                "highs": "HiGHS through SciPy's linprog, interior point with crossover"}
TOUCHING_GAP = 1e-6  # kTouchingGap of src/cdpowder/solver/build.cpp [R], physics.md §5.4
AXES = {"x": 0, "y": 1, "z": 2}
# a search goes on while its optimum improves by more than this, relative: ten times the
# solvers' tolerance, so that a barrier's last digits do not keep it going to --rounds
IMPROVEMENT = 1e-6
EXIT_USAGE = 2


class StressBoundsError(Exception):
    """A run folder the bounds cannot be computed for, or a bad argument."""


class Packing:
    """The final packing of a run folder: spheres, contacts, laws and loads, as arrays."""

    def __init__(self, folder):
        folder = pathlib.Path(folder)
        for name in ("scene.toml", "particles.csv", "contacts.csv", "summary.json"):
            if not (folder / name).is_file():
                raise StressBoundsError(f"{folder}: no {name} (a finished run's folder is needed)")
        self.summary = summaries.read_summary(folder / "summary.json")
        run = self.summary.get("run", {})
        if not run.get("blocked"):
            raise StressBoundsError(
                f"{folder}: the run did not end blocked (run.blocked is {run.get('blocked')}), so "
                "its forces do not balance the spheres; the admissible stress is of a packing at rest")
        self.scene = tomllib.loads((folder / "scene.toml").read_text())
        spheres = tables.read_particles(folder / "particles.csv")
        contacts = tables.read_contacts(folder / "contacts.csv")
        self.radius = spheres["r"].to_numpy(float)
        self.fixed = spheres["fixed"].to_numpy(bool)
        system = self.scene.get("system", {})
        gravity = np.asarray(system.get("gravity", [0.0, 0.0, 0.0]), float)
        mass = 4.0 / 3.0 * math.pi * system.get("density", 1.0) * self.radius**3
        self.load_force = spheres[["fx", "fy", "fz"]].to_numpy(float) + mass[:, None] * gravity
        self.load_torque = spheres[["tx", "ty", "tz"]].to_numpy(float)
        self.volume = float(self.summary["packing_volume"])
        piston = self.summary.get("piston", {})
        self.piston_load = float(piston["load"]) if piston.get("enabled") else None
        self._read_contacts(contacts)

    def _read_contacts(self, c):
        self.a = c["a"].to_numpy(np.int64)
        self.b = c["b"].to_numpy(np.int64)
        self.normal = c[["nx", "ny", "nz"]].to_numpy(float)
        self.gap = c["gap"].to_numpy(float)
        self.run_normal = c["normal_force"].to_numpy(float)
        self.run_tangential = c[["tx", "ty", "tz"]].to_numpy(float)
        self.run_rolling = c[["rx", "ry", "rz"]].to_numpy(float)
        self.run_twist = c["twist"].to_numpy(float)
        wall = self.a < 0
        self.wall = wall
        contact = self.scene.get("contact", {})
        walls = contact.get("wall", {})
        rb = self.radius[self.b]
        ra = np.where(wall, np.inf, self.radius[np.where(wall, 0, self.a)])
        cohesion = np.where(wall, walls.get("cohesion_force", 0.0), contact.get("cohesion_force", 0.0))
        self.cohesion = np.where(c["cohesive"].to_numpy(int) == 1, cohesion, 0.0)  # F_c
        self.mu = np.where(wall, walls.get("mu", 0.0), contact.get("mu", 0.0))
        r_eff = np.where(wall, walls.get("r_eff_factor", 1.0) * rb, 1.0 / (1.0 / ra + 1.0 / rb))
        self.roll_cap = np.where(wall, walls.get("mu_roll", 0.0), contact.get("mu_roll", 0.0)) * r_eff
        self.twist_cap = np.where(wall, walls.get("mu_twist", 0.0),
                                  contact.get("mu_twist", 0.0)) * r_eff
        # levers from each centre to the contact point, and the branch vector's length (§4.2, §11.2)
        self.lever_b = np.where(wall, rb, rb + self.gap / 2)
        self.lever_a = np.where(wall, 0.0, ra + self.gap / 2)
        self.branch = np.where(wall, rb + self.gap, self.lever_a + self.lever_b)
        # a tangent basis (e1, e2) with e1 × e2 = n
        helper = np.where(np.abs(self.normal[:, [0]]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
        e1 = np.cross(self.normal, helper)
        self.e1 = e1 / np.linalg.norm(e1, axis=1)[:, None]
        self.e2 = np.cross(self.normal, self.e1)

    def run_actions(self):
        """The run's actions in the program's unknowns, one column each: R_n, R_t·e1, R_t·e2,
        T_t·e1, T_t·e2, T_n."""
        dot = lambda u, v: np.einsum("ij,ij->i", u, v)  # noqa: E731
        return np.column_stack([
            self.run_normal, dot(self.run_tangential, self.e1), dot(self.run_tangential, self.e2),
            dot(self.run_rolling, self.e1), dot(self.run_rolling, self.e2), self.run_twist])


class Program:
    """The balance, the thresholds and the stress of the touching contacts, as sparse rows."""

    def __init__(self, packing, facets, touching_gap=None, force_cap_factor=100.0,
                 time_limit=300.0, solver="auto"):
        p = packing
        self.packing = p
        closed = p.run_normal + p.cohesion > 0.0  # is_closed of contact/local_problem.hpp
        largest_closed_gap = float(p.gap[closed].max()) if closed.any() else 0.0
        self.touching_gap = max(TOUCHING_GAP, largest_closed_gap) if touching_gap is None \
            else touching_gap
        self.free = np.flatnonzero(p.gap <= self.touching_gap)
        self.split = np.flatnonzero(p.cohesion[self.free] > 0)  # may pull: a sign to choose
        self.held = np.flatnonzero(p.gap > self.touching_gap)  # keeps −F_c n: open
        self.facets = facets
        self.time_limit = time_limit  # [s] a linear program
        self.solver = solver_named(solver)  # "clp" or "highs" (_minimise)
        self.stopped = 0  # programs stopped at the time limit
        self.fallbacks = 0  # programs Clp found no answer for, solved again by HiGHS
        self.clp_tries = []  # CPU seconds of Clp's tries that gave an answer (clp.minimise)
        self.solved = 0  # programs solved (an answer or none)
        self.progress = None  # called with what a program was for, after each
        # the disc modes that have a threshold, (first unknown, caps, the contacts' indices):
        # sliding (R_t) and rolling (T_t); a mode without one is held at 0 (bounds())
        self.disc_modes = [(first, cap[self.free], np.flatnonzero(cap[self.free] > 0))
                           for first, cap in ((1, p.mu), (3, p.roll_cap))]
        run = p.run_actions()[self.free]
        self.run_x = run.T.reshape(-1)  # blocks of 6 × m, unknown by unknown
        self.force_cap = force_cap_factor * max(1.0, float(np.abs(p.run_normal).max(initial=0.0)),
                                                float(p.cohesion.max(initial=0.0)))
        self._balance()

    @property
    def m(self):
        return len(self.free)

    def _balance(self):
        """Rows: 6 a free sphere (force, torque), 1 for the piston (z)."""
        p, free, m = self.packing, self.free, self.m
        n, e1, e2 = p.normal[free], p.e1[free], p.e2[free]
        a, b, wall = p.a[free], p.b[free], p.wall[free]
        lb, la = p.lever_b[free], p.lever_a[free]
        sphere_row = np.full(len(p.radius), -1, np.int64)
        movable = np.flatnonzero(~p.fixed)
        sphere_row[movable] = 6 * np.arange(len(movable))
        piston_row = 6 * len(movable)
        rows, cols, vals = [], [], []
        cols_of = [np.arange(m) + k * m for k in range(6)]

        def add(row, col, val):
            keep = (row >= 0) & (val != 0.0)
            rows.append(row[keep])
            cols.append(col[keep])
            vals.append(val[keep])

        # on b: force R_n n + t1 e1 + t2 e2; couple r1 e1 + r2 e2 + T_n n − l_b n × F,
        # n × e1 = e2, n × e2 = −e1; on a: minus the force, −T − l_a n × F (contact/velocity_change.hpp)
        unit = (n, e1, e2)
        for sign, body, lever in ((1.0, b, lb), (-1.0, np.where(wall, -1, a), la)):
            base = np.where(body >= 0, sphere_row[np.maximum(body, 0)], -1)
            for k in range(3):  # force rows
                for u, vec in enumerate(unit):
                    add(np.where(base >= 0, base + k, -1), cols_of[u], sign * vec[:, k])
            for k in range(3):  # torque rows
                row = np.where(base >= 0, base + 3 + k, -1)
                add(row, cols_of[1], -lever * e2[:, k])  # −l n × (t1 e1) = −l t1 e2
                add(row, cols_of[2], lever * e1[:, k])   # −l n × (t2 e2) = +l t2 e1
                for u, vec in ((3, e1), (4, e2), (5, n)):
                    add(row, cols_of[u], sign * vec[:, k])
        rhs = np.zeros(piston_row + 1)
        force = -p.load_force[movable]
        torque = -p.load_torque[movable]
        rhs[:piston_row] = np.column_stack([force, torque]).reshape(-1)
        # the held contacts' fixed forces −F_c n (their couples are zero) go to the right
        for c in self.held:
            fixed_force = -p.cohesion[c] * p.normal[c]
            if p.b[c] >= 0 and not p.fixed[p.b[c]]:
                rhs[sphere_row[p.b[c]]:sphere_row[p.b[c]] + 3] -= fixed_force
            if p.a[c] >= 0 and not p.fixed[p.a[c]]:
                rhs[sphere_row[p.a[c]]:sphere_row[p.a[c]] + 3] += fixed_force
        self.has_piston = p.piston_load is not None and np.any(p.a == -2)
        if self.has_piston:  # Σ over piston contacts of −F_z = the load
            on_piston = np.flatnonzero(a == -2)
            for u, vec in enumerate(unit):
                add(np.full(len(on_piston), piston_row), cols_of[u][on_piston], -vec[on_piston, 2])
            held_piston = self.held[p.a[self.held] == -2]
            rhs[piston_row] = p.piston_load - float(np.sum(p.cohesion[held_piston] *
                                                           p.normal[held_piston, 2]))
            size = piston_row + 1
        else:
            size = piston_row
            rhs = rhs[:size]
        self.balance = scipy.sparse.csr_matrix(
            (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(size, 6 * m))
        self.rhs = rhs
        # each equation holds as well as the run's forces hold it, and no better than to
        # 1e-7 of the largest load (the solver's own tolerance): the run's forces are admissible
        residual = np.abs(self.balance @ self.run_x - rhs)
        floor = 1e-7 * max(1.0, float(np.abs(rhs).max(initial=0.0)))
        self.slack = residual * (1 + 1e-6) + floor
        force_rows = (np.arange(size) % 6 < 3) & (np.arange(size) < piston_row)
        torque_rows = (np.arange(size) % 6 >= 3) & (np.arange(size) < piston_row)
        self.tolerance = {kind: float(self.slack[rows].max(initial=0.0)) for kind, rows in (
            ("force", force_rows), ("torque", torque_rows), ("piston", np.arange(size) >= piston_row))}

    @property
    def width(self):
        """The program's columns: the 6 m unknowns, then K weights a disc mode with a threshold."""
        return 6 * self.m + self.facets * sum(len(idx) for _, _, idx in self.disc_modes)

    def vertices(self, scale):
        """A polygon's vertices ρ u_k per unit of its threshold: ρ = scale / cos(π/K) and the
        angles (2k + 1)π/K of u_k in the tangent basis (thresholds(), onto_polygons())."""
        k = self.facets
        return scale / math.cos(math.pi / k), (2 * np.arange(k) + 1) * math.pi / k

    def thresholds(self, scale):
        """Rows G x ≤ h (with equalities) over the program's columns: each disc a regular polygon
        of K sides (its inradius the threshold × scale), and torsion's interval.

        A polygon is written by its vertices, not its sides: a disc mode x of a contact is
        Σ_k λ_k ρ u_k, with u_k the unit vectors at the angles (2k+1)π/K of the tangent basis,
        ρ = scale / cos(π/K) and weights λ_k ≥ 0 with Σ_k λ_k ≤ cap (R_n + F_c): the polygon
        whose sides are cos θ x1 + sin θ x2 ≤ scale cap (R_n + F_c), θ = 2πk/K. Three rows a mode
        instead of K: the barrier's normal equations shrink from 42 000 rows to 13 000 at the
        paper's (0, 0) packing (docs/lab/2026-12-01-polygons-by-their-vertices.md).
        Returns (G, low, high)."""
        p, free, m, k = self.packing, self.free, self.m, self.facets
        fc = p.cohesion[free]
        rows, cols, vals, low, high = [], [], [], [], []
        count = 0
        column = 6 * m  # the next weight's column
        rho, angles = self.vertices(scale)
        for first, cap, idx in self.disc_modes:
            q = len(idx)
            if q == 0:
                continue
            weights = column + np.arange(k)[:, None] * q + np.arange(q)[None, :]  # k × q
            column += k * q
            for part, along in ((0, np.cos(angles)), (1, np.sin(angles))):  # x_part = Σ λ ρ u
                row = count + np.arange(q)
                rows += [row, np.repeat(row[None, :], k, axis=0).reshape(-1)]
                cols += [(first + part) * m + idx, weights.reshape(-1)]
                vals += [np.ones(q), np.repeat(-rho * along, q)]
                low.append(np.zeros(q))
                high.append(np.zeros(q))
                count += q
            row = count + np.arange(q)  # Σ λ_k − cap R_n ≤ cap F_c
            rows += [row, np.repeat(row[None, :], k, axis=0).reshape(-1)]
            cols += [idx, weights.reshape(-1)]
            vals += [-cap[idx], np.ones(k * q)]
            low.append(np.full(q, -np.inf))
            high.append(cap[idx] * fc[idx])
            count += q
        twist = p.twist_cap[free]
        idx = np.flatnonzero(twist > 0)
        for sign in (1.0, -1.0):  # ±T_n − s μ_n r_eff R_n ≤ s μ_n r_eff F_c
            row = count + np.arange(len(idx))
            rows += [row, row]
            cols += [5 * m + idx, idx]
            vals += [np.full(len(idx), sign), -scale * twist[idx]]
            low.append(np.full(len(idx), -np.inf))
            high.append(scale * twist[idx] * fc[idx])
            count += len(idx)
        matrix = scipy.sparse.csr_matrix(
            (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
            shape=(count, self.width))
        return matrix, np.concatenate(low), np.concatenate(high)

    def bounds(self, scale):
        """Variable bounds: −F_c ≤ R_n ≤ the force cap; a mode without threshold at 0; each other
        mode within the reach of its polygon (radius × scale) at the force cap, ±scale cap
        (force cap + F_c) / cos(π/K) (a vertex's distance from the centre), which the thresholds
        imply (the program is the same): without them an interior-point solver has free
        columns, and Clp's barrier failed on some packings. A polygon's weights (thresholds())
        lie in [0, cap (force cap + F_c)]."""
        p, m, free = self.packing, self.m, self.free
        lower = np.zeros(self.width)
        upper = np.full(self.width, np.inf)
        lower[:m] = -p.cohesion[free]
        upper[:m] = self.force_cap
        reach = scale * (self.force_cap + p.cohesion[free]) / math.cos(math.pi / self.facets)
        for q, cap in ((1, p.mu), (2, p.mu), (3, p.roll_cap), (4, p.roll_cap), (5, p.twist_cap)):
            lower[q * m:(q + 1) * m] = -cap[free] * reach
            upper[q * m:(q + 1) * m] = cap[free] * reach
        column = 6 * m
        for _, cap, idx in self.disc_modes:
            weights = len(idx) * self.facets
            upper[column:column + weights] = np.tile(cap[idx] * (self.force_cap + p.cohesion[free][idx]),
                                                     self.facets)
            column += weights
        return lower, upper

    def onto_polygons(self, x, scale):
        """x moved into the thresholds with polygons of radius × scale, as thresholds() writes
        them: each polygon's weights clipped at 0 and scaled down where their sum passes
        cap (R_n + F_c), each disc mode then set to its weights' point, Σ_k λ_k ρ u_k, and
        torsion clipped into its interval; R_n stays. Clp's barrier meets the rows that tie a
        mode to its weights only to its tolerance: a few 1e-7 on the paper's (0, 0) packings,
        more than the check allows (docs/lab/2026-12-02-clp-answers-repaired.md). Moved onto
        them, the answer is a force set of the polygons to rounding, whose balance the check
        then judges as before."""
        x = np.array(x, float)
        p, m, k = self.packing, self.m, self.facets
        fc = p.cohesion[self.free]
        normal = x[:m]
        rho, angles = self.vertices(scale)
        column = 6 * m
        for first, cap, idx in self.disc_modes:
            q = len(idx)
            if q == 0:
                continue
            weights = np.maximum(x[column:column + k * q].reshape(k, q), 0.0)
            limit = np.maximum(cap[idx] * (normal[idx] + fc[idx]), 0.0)
            total = weights.sum(axis=0)
            over = total > limit
            weights[:, over] *= limit[over] / total[over]
            x[column:column + k * q] = weights.reshape(-1)
            x[first * m + idx] = rho * (np.cos(angles) @ weights)
            x[(first + 1) * m + idx] = rho * (np.sin(angles) @ weights)
            column += k * q
        twist = p.twist_cap[self.free]
        idx = np.flatnonzero(twist > 0)
        limit = scale * twist[idx] * np.maximum(normal[idx] + fc[idx], 0.0)
        x[5 * m + idx] = np.clip(x[5 * m + idx], -limit, limit)
        return x

    def stress_row(self, i, j):
        """σ_ij as a row over the unknowns and the constant of the held contacts (§11.2)."""
        p, free, m = self.packing, self.free, self.m
        scale = p.branch[free] * p.normal[free, j] / p.volume
        row = np.concatenate([scale * p.normal[free, i], scale * p.e1[free, i],
                              scale * p.e2[free, i], np.zeros(3 * m)])
        held = self.held
        constant = float(np.sum(p.branch[held] * p.normal[held, j] * -p.cohesion[held] *
                                p.normal[held, i]) / p.volume)
        return row, constant

    def parts(self, x, i, j):
        """(σ_ij, σ⁺_ij, σ⁻_ij) of the force set x, split as the run splits it (a contact with
        R_n ≥ 0 in σ⁺, physics.md §11.2; the held contacts pull, in σ⁻)."""
        row, constant = self.stress_row(i, j)
        m = self.m
        per_contact = (row.reshape(6, m) * x.reshape(6, m)).sum(axis=0)
        tensile = x[:m] < 0.0
        plus = float(per_contact[~tensile].sum())
        minus = float(per_contact[tensile].sum()) + constant
        return plus + minus, plus, minus

    def constraints(self, scale):
        """(ranges, lower, upper) of _minimise: the balance and the thresholds with polygons of
        radius × scale, and the unknowns' bounds. The balance is the first range."""
        g, g_low, g_high = self.thresholds(scale)
        lower, upper = self.bounds(scale)
        balance = scipy.sparse.hstack([self.balance, scipy.sparse.csr_matrix(
            (self.balance.shape[0], self.width - 6 * self.m))]).tocsr()
        ranges = [(balance, self.rhs - self.slack, self.rhs + self.slack), (g, g_low, g_high)]
        return ranges, lower, upper

    def minus_range(self, i, j, scale):
        """Bounds on σ⁻_ij that hold for every force set: each contact that may pull adds, if
        tensile, its σ_ij contribution w (f n_i + t·e_i), with the normal force f between −F_c
        and 0 and the tangential force t at most μ (f + F_c) × scale, whose extremes are at
        f = −F_c, or at f = 0 with the largest t along the tangent part of e_i; if
        compressive, nothing."""
        p, free = self.packing, self.free[self.split]
        w = p.branch[free] * p.normal[free, j] / p.volume
        fc, n_i = p.cohesion[free], p.normal[free, i]
        pulled = -w * fc * n_i
        sheared = np.abs(w) * scale * p.mu[free] * fc * np.sqrt(np.maximum(0.0, 1.0 - n_i**2))
        _, constant = self.stress_row(i, j)
        low = np.minimum(0.0, np.minimum(pulled, -sheared)).sum()
        high = np.maximum(0.0, np.maximum(pulled, sheared)).sum()
        return float(low) + constant, float(high) + constant


class _Optimum:
    """What _minimise returns: status (0 optimal, 1 stopped at the time limit, 2 neither), fun
    (cost·x) and x, as SciPy's `linprog` does."""

    def __init__(self, status, fun=None, x=None):
        self.status, self.fun, self.x = status, fun, x


def _minimise(program, cost, ranges, lower, upper, scale, force_set=None, what="a program"):
    """min cost·x over lower ≤ x ≤ upper and low ≤ A x ≤ high for each (A, low, high), stopped
    after the program's time limit, by its solver. "clp": COIN-OR Clp's barrier (cdpowder.clp),
    about six times faster at paper scale; "highs": HiGHS's interior-point method with
    crossover, through SciPy's `linprog` (docs/physics.md §11.3); it also decides a program Clp
    finds infeasible, since Clp's barrier without crossover can only say that it found no
    admissible answer. Counts the program's stopped programs and fallbacks. Returns an
    _Optimum. `what` names the program for the program's `progress`.

    `force_set`: (lower, upper) of an admissible force set, for a program whose answer is one
    (an attained value, not a bound). Clp is then given the balance, the first range, as
    equalities at the loads: a subset of ranges a few 1e-7 wide, on which its barrier took the
    paper example's interval at (1, 1) from 285 s to 39 s (with the finite bounds of
    Program.bounds; docs/lab/2026-12-01-stress-bounds-in-a-minute.md). Its answer must keep the
    ranges and these bounds, not the program's: a sign-fixed program's R_n ≥ 0 or ≤ 0 is a
    choice of the search, and a contact that crosses it by the solver's tolerance (up to 1e-6 at
    paper scale) is still admissible, in the part its sign gives it (Program.parts). `scale`:
    the polygons' radius (Program.constraints); Clp's answers are moved onto them
    (Program.onto_polygons) and onto the balance (force_set_repair.onto_balance) before they
    are checked.

    Without `force_set` the optimum is a bound (outer polygons): Clp's is the bound its row
    prices prove (clp.dual_bound), which holds however far its answer misses the narrow
    balance ranges; HiGHS's is its optimum's value."""
    cost = np.concatenate([cost, np.zeros(program.width - len(cost))])
    optimum = _solve(program, cost, ranges, lower, upper, scale, force_set)
    if optimum.x is not None:
        optimum.x = optimum.x[:6 * program.m]  # the unknowns; the polygons' weights stay here
    program.stopped += optimum.status == 1
    program.solved += 1
    if program.progress is not None:
        program.progress(what)
    return optimum


def _solve(program, cost, ranges, lower, upper, scale, force_set):
    """_minimise's program by the program's solver, from Clp to HiGHS when Clp has no answer."""
    time_limit = program.time_limit
    if program.solver == "clp":
        matrix = scipy.sparse.vstack([a for a, _, _ in ranges])
        row_lower = np.concatenate([low for _, low, _ in ranges])
        row_upper = np.concatenate([high for _, _, high in ranges])
        given, admissible, repair = (row_lower, row_upper), None, None
        if force_set is not None:
            given = tuple(np.concatenate([program.rhs, side[len(program.rhs):]]) for side in given)
            admissible = (row_lower, row_upper, *force_set)

            def repair(x):
                return force_set_repair.onto_balance(program, program.onto_polygons(x, scale),
                                                     scale, row_lower, row_upper, *force_set)
        # a bound program's optimum is a bound, proved by the barrier's duals; a force set's
        # program needs an admissible answer, moved onto its polygons and balance and checked
        status, fun, x = clp.minimise(cost, matrix, *given, lower, upper, time_limit,
                                      admissible=admissible, repair=repair,
                                      tries=program.clp_tries, certify=force_set is None)
        if status in (clp.OPTIMAL, clp.STOPPED):
            return _Optimum(0 if status == clp.OPTIMAL else 1, fun, x)
        program.fallbacks += 1  # Clp found no answer it could stand by: HiGHS decides
    blocks, limits = [], []
    for matrix, low, high in ranges:
        for sign, side in ((1.0, high), (-1.0, low)):
            finite = np.flatnonzero(np.isfinite(side))
            if len(finite):
                blocks.append(sign * matrix[finite])
                limits.append(sign * side[finite])
    with _silenced_stdout():
        res = scipy.optimize.linprog(cost, A_ub=scipy.sparse.vstack(blocks).tocsr(),
                                     b_ub=np.concatenate(limits),
                                     bounds=np.column_stack([lower, upper]), method="highs-ipm",
                                     options={"time_limit": float(time_limit)})
    return _Optimum(res.status if res.status in (0, 1) else 2, res.fun, res.x)


def solver_named(name):
    """The solver a name asks for: "auto" is Clp where libClp is found, else HiGHS."""
    if name == "auto":
        return "clp" if clp.available() else "highs"
    if name not in ("clp", "highs"):
        raise StressBoundsError(f"--solver: got '{name}', expected auto, clp or highs")
    if name == "clp" and not clp.available():
        raise StressBoundsError("--solver: clp asked for, but COIN-OR Clp (libClp.so.1, Debian's "
                                "coinor-libclp1) was not found; use --solver highs")
    return name


@contextlib.contextmanager
def _silenced_stdout():
    """HiGHS's C library prints notes of its phases ("Solve 3: Forcing phase 2 …") on file
    descriptor 1 whatever SciPy's `disp` says; they go to /dev/null, so stdout carries results."""
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        with open(os.devnull, "w") as devnull:
            os.dup2(devnull.fileno(), 1)
            yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)


def _total_extreme(program, i, j, sense, scale):
    """The smallest (sense +1) or largest (−1) σ_ij over the force sets with polygons of
    radius × scale: one linear program. Returns (the optimum, the force set), or (None, None)
    when infeasible."""
    row, constant = program.stress_row(i, j)
    ranges, lower, upper = program.constraints(scale)
    # an inner polygon's answer is a force set; an outer one's only bounds
    force_set = (lower, upper) if scale < 1.0 else None
    res = _minimise(program, sense * row, ranges, lower, upper, scale, force_set,
                    "σ reached" if force_set else "bound of σ")
    if res.status != 0:
        return None, None
    return sense * float(res.fun) + constant, res.x


def _signed_extreme(program, i, j, sense, scale, signs):
    """The smallest (sense +1) or largest (−1) σ⁺_ij over the force sets with polygons of
    radius × scale in which each contact with a sign keeps `signs` (1: tensile, R_n ≤ 0; 0:
    compressive, R_n ≥ 0): a linear program whose optimum a force set reaches. Returns (the
    optimum, the force set), or (None, None) when infeasible."""
    m = program.m
    row, _ = program.stress_row(i, j)
    ranges, lower, upper = program.constraints(scale)
    force_set = (lower.copy(), upper.copy())
    tensile = np.zeros(m, bool)
    tensile[program.split[signs > 0.5]] = True
    upper[:m] = np.where(tensile, 0.0, upper[:m])
    lower[:m] = np.where(tensile, lower[:m], 0.0)
    res = _minimise(program, sense * row * np.tile(~tensile, 6), ranges, lower, upper, scale,
                    force_set, "σ⁺ reached")
    if res.status != 0:
        return None, None
    return sense * float(res.fun), res.x


def _search(program, i, j, sense, scale, starts, record, rounds):
    """Force sets with fixed signs that drive σ⁺_ij down (sense +1) or up (−1), each passed to
    `record`: from each start's signs, each round keeps the signs of the last optimum and turns
    over those of its contacts at zero normal force (free to go either way), while that improves
    the best optimum of the search by more than IMPROVEMENT."""
    best = None
    zero = 1e-9 * max(1.0, program.force_cap)
    for signs in starts:
        for _ in range(rounds):
            value, x = _signed_extreme(program, i, j, sense, scale, signs)
            if value is None:
                break
            record(x)
            improved = best is None or sense * value < sense * best - IMPROVEMENT * abs(best)
            if best is None or sense * value < sense * best:
                best = value
            if not improved:
                break
            normal = x[:program.m][program.split]
            signs = np.where(np.abs(normal) <= zero, 1.0 - signs, (normal < 0).astype(float))


def _component(name):
    if len(name) != 2 or name[0] not in AXES or name[1] not in AXES:
        raise StressBoundsError(f"--components: got '{name}', expected two of x, y, z (zz, xx, xz, …)")
    return AXES[name[0]], AXES[name[1]]


def _run_value(summary, i, j, part):
    stress = summary.get("stress", {})
    key = {"total": "sigma", "plus": "sigma_compressive", "minus": "sigma_tensile"}[part]
    return float(stress[key][i][j])


# the Program a forked worker of admissible_stress solves for (set before its pool starts)
_WORKER_PROGRAM = None


def _task(task):
    """One independent piece of admissible_stress: ("total", i, j, sense, scale) is one linear
    program for σ_ij; ("search", i, j, sense, scale, starts, rounds) a whole search for σ⁺_ij.
    Returns (σ's optimum or None, the force sets found, programs, stopped, fallbacks, Clp's
    try times), the counts and times of this task alone."""
    program = _WORKER_PROGRAM
    program.solved = program.stopped = program.fallbacks = 0
    known = len(program.clp_tries)
    found, value = [], None
    if task[0] == "total":
        _, i, j, sense, scale = task
        value, x = _total_extreme(program, i, j, sense, scale)
        found = [] if x is None or scale >= 1.0 else [x]  # an outer polygon's x only bounds
    else:
        _, i, j, sense, scale, starts, rounds = task
        _search(program, i, j, sense, scale, starts, found.append, rounds)
    return value, found, program.solved, program.stopped, program.fallbacks, \
        program.clp_tries[known:]


def _tasks_in(tasks, program, jobs):
    """_task over `tasks` (the answers in their order): on `jobs` processes forked from this
    one, or here when jobs is 1. No task reads another's answer, and the parts of a result are
    extremes (min, max) over the force sets found, so the result is the same for any jobs
    unless a program reaches the time limit (which processes sharing cores reach sooner). A
    worker that dies (a signal, memory) raises BrokenProcessPool here instead of a hang."""
    global _WORKER_PROGRAM
    _WORKER_PROGRAM = program
    try:
        if jobs <= 1 or len(tasks) == 1:
            return [_task(task) for task in tasks]
        sys.stdout.flush()  # what this process has buffered is not the workers' to write again
        sys.stderr.flush()
        with concurrent.futures.ProcessPoolExecutor(
                min(jobs, len(tasks)), mp_context=multiprocessing.get_context("fork")) as pool:
            answers = list(pool.map(_task, tasks))
        # the workers' try times cap later tries (clp.try_cap), also in the next pool's workers
        for answer in answers:
            program.clp_tries.extend(answer[-1])
        return answers
    finally:
        _WORKER_PROGRAM = None


def default_jobs():
    """The processes `cdpowder stress-bounds` uses unless told: its two searches side by side,
    where the process may run on two cores."""
    allowed = os.sched_getaffinity(0) if hasattr(os, "sched_getaffinity") else range(
        os.cpu_count() or 1)
    return max(1, min(2, len(allowed)))


def admissible_stress(folder, components=("zz",), facets=16, force_cap_factor=100.0,
                      progress=None, rounds=8, time_limit=300.0, solver="auto", jobs=1):
    """The admissible interval of σ_ij, σ⁺_ij and σ⁻_ij for each component (module docstring).

    For each quantity and side: the bound (a linear program with the circumscribed polygons and
    each contact's sign relaxed), and the extremes over the admissible force sets found (the
    inscribed polygons, signs fixed and searched from the run's and the bound's; and the run's
    own forces). `progress(text)`, if given, is called after each linear program (in the
    process that solved it); a program stopped at `time_limit` seconds gives nothing (a bound
    stays None, a search start ends). `solver`: "clp", "highs" or "auto" (solver_named).
    `jobs`: processes forked for σ's four programs and then the two searches
    (default_jobs() is what the command uses); the result does not depend on it unless a
    program reaches the time limit. Raises StressBoundsError for a folder that is not a
    blocked run's."""
    if facets < 3:
        raise StressBoundsError(f"--facets: got {facets}, expected an integer ≥ 3")
    if not time_limit > 0:
        raise StressBoundsError(f"--time-limit: got {time_limit}, expected seconds > 0")
    if rounds < 1:
        raise StressBoundsError(f"--rounds: got {rounds}, expected an integer ≥ 1")
    if not force_cap_factor > 1:
        raise StressBoundsError(f"--force-cap: got {force_cap_factor}, expected a number > 1")
    if isinstance(jobs, bool) or not isinstance(jobs, numbers.Integral) or jobs < 1:
        raise StressBoundsError(f"--jobs: got {jobs}, expected an integer ≥ 1")
    jobs = int(jobs)
    solver = solver_named(solver)
    started = time.perf_counter()
    packing = Packing(folder)
    program = Program(packing, facets, force_cap_factor=force_cap_factor, time_limit=time_limit,
                      solver=solver)
    inner = math.cos(math.pi / facets)
    outer = 1.0 / inner
    result = {
        "method": "linear programs: sigma's bounds; sigma-'s from each contact's extremes in "
                  "tension, sigma+'s as their difference; the attained values from force sets "
                  "with the signs fixed and searched",
        "solver": SOLVER_NAMES[solver],
        "facets": facets,
        "rounds": rounds,
        "time_limit": time_limit,
        "threshold_excess": outer - 1.0,
        "touching_gap": program.touching_gap,
        "balance_tolerance": program.tolerance,
        "force_cap": program.force_cap,
        "contacts": {"touching": program.m, "held": len(program.held), "signed": len(program.split)},
    }
    run_signs = (packing.run_normal[program.free][program.split] < 0).astype(float)
    parts = ("total", "plus", "minus")
    totals = {"programs": 0, "stopped": 0, "fallbacks": 0}

    def solved(name, what):
        if progress is not None:
            progress(f"σ_{name}: a linear program ({what}), "
                     f"{time.perf_counter() - started:.0f} s")

    for name in components:
        i, j = _component(name)
        reached = {part: [math.inf, -math.inf] for part in parts}

        def record(x, i=i, j=j, reached=reached):
            for part, value in zip(parts, program.parts(x, i, j)):
                reached[part] = [min(reached[part][0], value), max(reached[part][1], value)]

        def gather(answers):
            for _, found, programs, stopped, fallbacks, _ in answers:
                for x in found:
                    record(x)
                totals["programs"] += programs
                totals["stopped"] += stopped
                totals["fallbacks"] += fallbacks
            return answers

        record(program.run_x)
        program.progress = lambda what, name=name: solved(name, what)
        # σ's reached value (inner polygons) and bound (outer) on each side; the reached ones
        # first: their tries are quick, and their times cap the bound programs' tries (one ran
        # 60 s in a clean-up on a paper packing as its process's first)
        sides = [(sense, scale) for scale in (inner, outer) for sense in (1, -1)]
        answers = gather(_tasks_in([("total", i, j, sense, scale) for sense, scale in sides],
                                   program, jobs))
        bound = {("total", 0): answers[2][0], ("total", 1): answers[3][0]}
        # each start is the sign pattern of a force set (the run's, σ's extremes), and a round
        # turns over only contacts at R_n = 0, so a search's programs are feasible over the
        # balance's ranges (Clp, solving them at the loads, may not find them so; HiGHS then
        # decides). (All
        # compressive, once a start too, is no force set's at paper scale, and there both
        # solvers spent minutes on it without an answer.)
        starts = [run_signs] + [(found[0][:program.m][program.split] < 0).astype(float)
                                for (_, found, *_), (_, scale) in zip(answers, sides)
                                if scale == inner and found]
        # σ⁺ = σ − σ⁻ for every force set, and σ⁻ lies within each contact's extremes in tension
        bound["minus", 0], bound["minus", 1] = program.minus_range(i, j, outer)
        known = bound["total", 0] is not None and bound["total", 1] is not None
        bound["plus", 0] = bound["total", 0] - bound["minus", 1] if known else None
        bound["plus", 1] = bound["total", 1] - bound["minus", 0] if known else None
        gather(_tasks_in([("search", i, j, sense, inner, starts, rounds) for sense in (1, -1)],
                         program, jobs))
        for part, suffix in zip(parts, ("", "_plus", "_minus")):
            entry = {"run": _run_value(packing.summary, i, j, part)}
            for side, key in ((0, "min"), (1, "max")):
                attained = reached[part][side]
                # a bound is never inside what a force set reaches: where the solver's
                # tolerance (1e-7 relative) puts it there, the reached value is the bound
                value = bound[part, side]
                entry[key] = None if value is None else (
                    min(value, attained) if side == 0 else max(value, attained))
                entry[f"{key}_attained"] = attained
            result[f"sigma_{name}{suffix}"] = entry
    result["linear_programs"] = totals["programs"]
    result["stopped_programs"] = totals["stopped"]
    result["highs_fallbacks"] = totals["fallbacks"]
    result["jobs"] = jobs
    result["seconds"] = time.perf_counter() - started
    return result


def add_to_summary(folder, result):
    """Writes `result` into folder/summary.json under "admissible_stress", atomically."""
    path = pathlib.Path(folder) / "summary.json"
    data = json.loads(path.read_text())
    data[FIELD] = result
    temporary = path.with_name(f".summary.json.{os.getpid()}.tmp")
    with open(temporary, "w") as out:
        out.write(json.dumps(data, indent=2, sort_keys=True) + "\n")
        out.flush()
        os.fsync(out.fileno())
    os.replace(temporary, path)


def line(result, pressure=None):
    """One line a component part: min … max of the bound, the attained values and the run's."""
    lines = []
    scale = 1.0 / pressure if pressure else 1.0
    unit = "/p" if pressure else " [F_coh/R^2]"
    for key, entry in result.items():
        if not key.startswith("sigma_"):
            continue
        def show(v):
            return "none" if v is None else f"{v * scale:.4g}"
        lines.append(f"{key}{unit}: [{show(entry['min'])}, {show(entry['max'])}] "
                     f"(attained [{show(entry['min_attained'])}, {show(entry['max_attained'])}], "
                     f"the run {show(entry['run'])})")
    return "\n".join(lines)


def run_folders(folders):
    """The run folders named: a sweep's folder (one with results.csv) stands for its finished,
    blocked runs (runs/<point>/seed_<s>, docs/sweeps.md); any other folder for itself."""
    for folder in map(pathlib.Path, folders):
        if not (folder / "results.csv").is_file():
            yield folder
            continue
        for summary in sorted(folder.glob("runs/*/seed_*/summary.json")):
            try:
                blocked = summaries.read_summary(summary).get("run", {}).get("blocked")
            except (OSError, summaries.SummaryError):
                blocked = False
            if blocked:
                yield summary.parent


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="cdpowder stress-bounds",
        description="The admissible stress interval of a finished run's packing (physics.md "
                    "§11.3), added to DIR/summary.json under \"admissible_stress\".")
    parser.add_argument("folders", nargs="+", metavar="DIR",
                        help="a finished, blocked run's folder, or a sweep's (its blocked runs)")
    parser.add_argument("--components", default="zz",
                        help="comma-separated components of σ, e.g. zz,xx (default zz)")
    parser.add_argument("--facets", type=int, default=16,
                        help="sides of the polygons that replace the friction discs (default 16)")
    parser.add_argument("--force-cap", type=float, default=100.0,
                        help="the largest normal force, × the run's largest (default 100)")
    parser.add_argument("--rounds", type=int, default=8,
                        help="rounds of the search over the contacts' signs from each start "
                             "(default 8)")
    parser.add_argument("--time-limit", type=float, default=300.0,
                        help="seconds for each linear program; one stopped there gives nothing "
                             "(default 300)")
    parser.add_argument("--solver", default="auto", choices=("auto", "clp", "highs"),
                        help="the linear programs' solver: COIN-OR Clp's barrier or HiGHS "
                             "(SciPy); auto takes Clp where libClp is found (default auto)")
    parser.add_argument("--jobs", type=int, default=None,
                        help="processes: σ's four programs, then its two searches, side by side; "
                             "the result is the same for any unless a program reaches the time "
                             "limit (default 2 where the process may run on two cores, else 1)")
    parser.add_argument("--no-write", action="store_true", help="print only; leave summary.json")
    args = parser.parse_args(argv)
    components = [c.strip() for c in args.components.split(",") if c.strip()]
    status = 0
    for folder in run_folders(args.folders):
        try:
            result = admissible_stress(folder, components, args.facets, args.force_cap,
                                       rounds=args.rounds, time_limit=args.time_limit,
                                       solver=args.solver,
                                       jobs=default_jobs() if args.jobs is None else args.jobs,
                                       progress=lambda text, f=folder: print(
                                           f"stress-bounds: {f}: {text}", file=sys.stderr,
                                           flush=True))
        except (StressBoundsError, OSError, summaries.SummaryError, KeyError) as error:
            print(f"error: {error}", file=sys.stderr)
            status = EXIT_USAGE
            continue
        if not args.no_write:
            add_to_summary(folder, result)
        piston = summaries.read_summary(pathlib.Path(folder) / "summary.json").get("piston", {})
        stopped, fallbacks = result["stopped_programs"], result["highs_fallbacks"]
        print(f"{folder}: {result['contacts']['touching']} touching contacts, "
              f"{result['linear_programs']} linear programs on {result['jobs']} processes, "
              f"{result['seconds']:.1f} s" + (f", {stopped} linear programs stopped at the time "
                                              "limit" if stopped else "") +
              (f", {fallbacks} solved again by HiGHS" if fallbacks else ""))
        print(line(result, piston.get("applied_pressure")))
    return status


if __name__ == "__main__":
    sys.exit(main())
