"""cdpowder.force_set_repair: a barrier's force set moved onto the balance (physics.md §11.3).

An attained value of the admissible interval (cdpowder.stress_bounds) needs an admissible force
set: one that balances each sphere within its range, a few 1e-7 wide. Clp's barrier without
crossover ends a sign-fixed program 1e-7 to 1e-6 off a handful of those ranges, on one
program in four of the paper's (0, 0) packings, and HiGHS then took 25–35 s to solve it again
(docs/lab/2026-12-02-bounds-by-their-duals.md).

onto_balance moves the answer by the least step, weighted by each unknown's room, that brings
each balance row off its range back to the range's centre and leaves every other balance row
where it is. The step moves the normal forces, the polygons' weights (each disc mode follows
its weights, Σ_k λ_k ρ u_k) and the torsion couples, each by a weight equal to its room: how far
it may move, with all the others moving as far, while its bounds and thresholds hold.

  * a weight λ_k ≥ 0 by λ_k, and by s / (2K), s = cap (R_n + F_c) − Σ_k λ_k its polygon's slack;
  * R_n by its distance to its bounds, by s / (2 cap) for each polygon it scales, and by
    t / (2 τ) for its torsion interval |T_n| ≤ τ (R_n + F_c) of slack t;
  * T_n by t / 2.

Each constraint then holds if no unknown moves past its room (the halves add up to the slack).
The least step may still move one past it; the answer is checked after the repair as before
(cdpowder.clp), and one the repair does not bring onto the ranges goes on as a refused one.
"""
import numpy as np
import scipy.sparse
import scipy.sparse.linalg


def onto_balance(program, x, scale, row_lower, row_upper, lower, upper):
    """x, a force set on its polygons of radius × scale (Program.onto_polygons), moved onto the
    balance ranges row_lower ≤ B x ≤ row_upper (the program's first rows) as the module says;
    x itself where no balance row is off its range. lower, upper: the unknowns' bounds the
    answer must keep (R_n's are the first m)."""
    m, k, rows = program.m, program.facets, program.balance.shape[0]
    value = program.balance @ x[:6 * m]
    off = (value < row_lower[:rows]) | (value > row_upper[:rows])
    if not off.any():
        return x
    target = np.where(off, program.rhs - value, 0.0)
    p = program.packing
    cohesion = p.cohesion[program.free]
    normal = x[:m]
    rho, angles = program.vertices(scale)
    room_normal = np.minimum(normal - lower[:m], upper[:m] - normal)
    # the unknowns the step moves, after R_n: each disc mode's weights, then the torsion couples
    maps = [(np.arange(m), np.arange(m), np.ones(m))]  # (unknown, step variable, coefficient)
    rooms = [None]  # R_n's, set once every threshold has limited it
    modes = []  # (first unknown, contacts, first column, first step variable)
    column, variable = 6 * m, m
    for first, cap, idx in program.disc_modes:
        q = len(idx)
        if q == 0:
            continue
        weights = x[column:column + k * q].reshape(k, q)
        slack = np.maximum(cap[idx] * (normal[idx] + cohesion[idx]) - weights.sum(axis=0), 0.0)
        room_normal[idx] = np.minimum(room_normal[idx], slack / (2 * cap[idx]))
        rooms.append(np.minimum(weights, slack / (2 * k)).reshape(-1))
        corner, contact = np.meshgrid(np.arange(k), np.arange(q), indexing="ij")
        step_variable = (variable + corner * q + contact).reshape(-1)
        for part, along in ((0, np.cos(angles)), (1, np.sin(angles))):
            maps.append(((first + part) * m + idx[contact].reshape(-1), step_variable,
                         rho * along[corner].reshape(-1)))
        modes.append((first, idx, column, variable))
        column += k * q
        variable += k * q
    twist = scale * p.twist_cap[program.free]
    turning = np.flatnonzero(twist > 0)
    torsion_variable = variable
    if len(turning):
        torsion = x[5 * m + turning]
        slack = np.maximum(twist[turning] * (normal[turning] + cohesion[turning]) - np.abs(torsion),
                           0.0)
        room_normal[turning] = np.minimum(room_normal[turning], slack / (2 * twist[turning]))
        rooms.append(slack / 2)
        maps.append((5 * m + turning, variable + np.arange(len(turning)), np.ones(len(turning))))
        variable += len(turning)
    rooms[0] = np.maximum(room_normal, 0.0)
    room = np.concatenate(rooms)
    unknown, step_variable, coefficient = (np.concatenate(part) for part in zip(*maps))
    to_unknowns = scipy.sparse.csr_matrix((coefficient, (unknown, step_variable)),
                                          shape=(6 * m, variable))
    # the least Σ (Δ_j / room_j)² with B J Δ = target: Δ = W² (B J)ᵀ (B J W² (B J)ᵀ)⁻¹ target;
    # a row no unknown with room reaches gets a regularised 0 and stays off (the check says so)
    scaled = (program.balance @ to_unknowns @ scipy.sparse.diags(room)).tocsr()
    normal_matrix = (scaled @ scaled.T).tocsc()
    regular = 1e-14 * max(float(normal_matrix.diagonal().max(initial=0.0)), np.finfo(float).tiny)
    normal_matrix = normal_matrix + scipy.sparse.identity(rows, format="csc") * regular
    step = room * (scaled.T @ scipy.sparse.linalg.spsolve(normal_matrix, target))
    moved = np.array(x, float)
    moved[:m] += step[:m]
    for first, idx, column, first_variable in modes:
        q = len(idx)
        moved[column:column + k * q] += step[first_variable:first_variable + k * q]
        weights = moved[column:column + k * q].reshape(k, q)
        moved[first * m + idx] = rho * (np.cos(angles) @ weights)
        moved[(first + 1) * m + idx] = rho * (np.sin(angles) @ weights)
    if len(turning):
        moved[5 * m + turning] += step[torsion_variable:torsion_variable + len(turning)]
    return moved
