"""One exported cdpowder contact problem as a Siconos 3-D friction-contact problem.

The problem comes from `contact_problem export` (bench/contact_problem.cpp): the contact
records of one step exactly as the engine's kernels see them (docs/physics.md §5.2, §5.4).
Only the (mu_roll, mu_twist) = (0, 0) corner maps: there every couple is zero, and each
contact carries a force R = R_n n + R_t with

    S = R_n + F_c >= 0,  V_n + g_pos/dt >= 0,  S (V_n + g_pos/dt) = 0     (§5.4 step 1)
    |R_t| <= mu S, and R_t opposes V_t when |R_t| = mu S, V_t = 0 else   (§5.4 step 2)

which is Signorini-Coulomb on the shifted force S. So, in the local frame (n, t1, t2)
of each contact and in the engine's units (forces [F_coh], velocities [R/t0]):

    r = (S, R_t.t1, R_t.t2)                      Siconos' reaction
    u = (V_n + g_pos/dt, V.t1, V.t2) = W r + q   Siconos' local velocity
    W = H (dt M^-1) H^T                          Delassus matrix, velocity per force
    q = H x_free + g_pos/dt e_n - W F_c e_n      free velocity, gap term, cohesion shift

where x = (v_i, omega_i per sphere; V_P of the piston) and H maps x to the relative
velocities of the contact points (§5.1): for a pair along a direction e,
e.V = e.(v_b - v_a) + |l_a| omega_a.(e x n) + |l_b| omega_b.(e x n); at a wall,
e.V = e.v_s + R omega_s.(e x n) - (e.e_z) V_P for the piston. The cone condition of
Siconos (r in K_mu, u + mu|u_t| e_n in K_mu*) is exactly the pair of laws above. An open
contact within the cohesion range (F_c > 0, S = 0) keeps R_n = -F_c and zero friction, as
the engine's open branch does.

W and q are divided by s = mean diagonal of W before they are handed to Siconos. The
solution set does not change (the cone conditions are invariant under u -> u/s), and
Siconos' natural-map error r - P_K(r - u), which adds forces to velocities, then adds
forces to forces of the size dt w (one contact's response).
"""
import json

import numpy as np
import scipy.sparse as sp


def load_json(path):
    with open(path) as f:
        return json.load(f)


def tangent_frames(normals):
    """Unit t1, t2 with (n, t1, t2) right-handed, from the axis least aligned with n."""
    axis = np.zeros_like(normals)
    axis[np.arange(len(normals)), np.argmin(np.abs(normals), axis=1)] = 1.0
    t1 = np.cross(normals, axis)
    t1 /= np.linalg.norm(t1, axis=1)[:, None]
    t2 = np.cross(normals, t1)
    return t1, t2


class Fc3dMapping:
    """W, q, mu of one step, and the conversions between engine actions and reactions."""

    def __init__(self, problem):
        if any(np.any(np.asarray(problem[kind][cap]) > 0.0)
               for kind in ("pairs", "walls") for cap in ("roll_cap", "twist_cap")):
            raise ValueError("rolling or twisting thresholds: only the (0,0) corner maps")
        pairs, walls = problem["pairs"], problem["walls"]
        free = problem["free_velocities"]
        n_pairs, n_walls = len(pairs["a"]), len(walls["sphere"])
        n_spheres = len(free["linear"])
        self.n_pairs, self.n_contacts = n_pairs, n_pairs + n_walls
        self.normals = np.array(pairs["normal"] + walls["normal"], dtype=float).reshape(-1, 3)
        self.t1, self.t2 = tangent_frames(self.normals)
        self.cohesion = np.array(pairs["cohesion"] + walls["cohesion"], dtype=float)
        self.mu = np.array(pairs["mu"] + walls["mu"], dtype=float)
        gap_rate = np.array(pairs["gap_rate"] + walls["gap_rate"], dtype=float)

        # H: rows 3k + (0 normal, 1 t1, 2 t2); columns 6i + (0..2 v, 3..5 omega), 6N piston
        rows, cols, vals = [], [], []

        piston_col = 6 * n_spheres
        k_pair = np.arange(n_pairs)
        k_wall = n_pairs + np.arange(n_walls)
        a = np.array(pairs["a"], dtype=np.int64)
        b = np.array(pairs["b"], dtype=np.int64)
        lever_a = np.array(pairs["lever_a"], dtype=float)[:, None]
        lever_b = np.array(pairs["lever_b"], dtype=float)[:, None]
        s = np.array(walls["sphere"], dtype=np.int64)
        radius = np.array(walls["radius"], dtype=float)[:, None]
        moves = np.array(walls["wall_moves"], dtype=float)
        for d, e_all in enumerate((self.normals, self.t1, self.t2)):
            e, n = e_all[:n_pairs], self.normals[:n_pairs]
            e_x_n = np.cross(e, n)
            for j in range(3):
                rows += [3 * k_pair + d] * 4
                cols += [6 * b + j, 6 * a + j, 6 * a + 3 + j, 6 * b + 3 + j]
                vals += [e[:, j], -e[:, j], lever_a[:, 0] * e_x_n[:, j], lever_b[:, 0] * e_x_n[:, j]]
            e, n = e_all[n_pairs:], self.normals[n_pairs:]
            e_x_n = np.cross(e, n)
            for j in range(3):
                rows += [3 * k_wall + d] * 2
                cols += [6 * s + j, 6 * s + 3 + j]
                vals += [e[:, j], radius[:, 0] * e_x_n[:, j]]
            rows.append(3 * k_wall + d)
            cols.append(np.full(n_walls, piston_col))
            vals.append(-moves * e[:, 2])
        H = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                          shape=(3 * self.n_contacts, piston_col + 1))
        H.eliminate_zeros()

        # dt M^-1 and x_free; dt/M_P is the piston contacts' wall_response
        dt_inv_m = np.array(free["dt_inverse_mass"], dtype=float)
        dt_inv_i = np.array(free["dt_inverse_inertia"], dtype=float)
        response = np.array(walls["wall_response"], dtype=float)
        dt_inv_piston = response.max() if n_walls else 0.0
        minv = np.column_stack([dt_inv_m] * 3 + [dt_inv_i] * 3).ravel()
        minv = np.append(minv, dt_inv_piston)
        x_free = np.concatenate([np.array(free["linear"], dtype=float),
                                 np.array(free["angular"], dtype=float)], axis=1).ravel()
        x_free = np.append(x_free, free["piston"])

        self.H, self.minv, self.x_free = H, minv, x_free
        self.W = (H @ sp.diags(minv) @ H.T).tocsc()
        shift = np.zeros(3 * self.n_contacts)
        shift[0::3] = self.cohesion
        self.q = H @ x_free - self.W @ shift
        self.q[0::3] += gap_rate
        self.scale = self.W.diagonal().mean()

    def siconos_data(self):
        """(W/s, q/s, mu) for Siconos: W as scipy csc with 64-bit indices."""
        W = (self.W / self.scale).tocsc()
        W.indices = W.indices.astype(np.int64)
        W.indptr = W.indptr.astype(np.int64)
        return W, self.q / self.scale, self.mu

    def reactions_from_actions(self, actions):
        """Engine actions {"normal_force", "tangential_force"} -> r = (S, R_t.t1, R_t.t2)."""
        normal = np.asarray(actions["normal_force"], dtype=float)
        tangential = np.asarray(actions["tangential_force"], dtype=float).reshape(-1, 3)
        r = np.empty(3 * self.n_contacts)
        r[0::3] = normal + self.cohesion
        r[1::3] = np.einsum("ij,ij->i", tangential, self.t1)
        r[2::3] = np.einsum("ij,ij->i", tangential, self.t2)
        return r

    def actions_from_reactions(self, r):
        """r -> engine actions (R_n = S - F_c, R_t = r_t1 t1 + r_t2 t2; no couples)."""
        tangential = r[1::3, None] * self.t1 + r[2::3, None] * self.t2
        return {"normal_force": (r[0::3] - self.cohesion).tolist(),
                "tangential_force": tangential.tolist()}

    def local_velocities(self, r):
        """u = W r + q in the engine's units [R/t0]."""
        return self.W @ r + self.q
