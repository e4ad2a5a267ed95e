// coloured_sweep.cpp — batches of independent pair contacts solved side by side
// (coloured_sweep.hpp). The lane arithmetic is solve_pair's, operation for operation
// (Eigen's 3-vector dot products sum left to right, its cross products are the textbook
// formula), with the kernel's two branches computed in every lane and selected: the same
// bits as solve_pair, contact by contact. GCC's generic vectors of 4 doubles are lowered
// to two SSE2 operations each without -march flags; no fused multiply-add
// (-ffp-contract=off), so the results do not depend on the machine.
#include "cdpowder/solver/coloured_sweep.hpp"

#include <algorithm>
#include <cstring>
#include <numeric>
#include <span>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#pragma GCC diagnostic ignored "-Wpsabi"  // no ABI crosses a function boundary here: all inlined

namespace cdpowder {

namespace {

using d4 = double __attribute__((vector_size(32)));

#define CDP_INLINE [[gnu::always_inline]] inline

CDP_INLINE d4 load(const double* p) {
  d4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

CDP_INLINE void store(double* p, d4 v) {
  std::memcpy(p, &v, sizeof v);
}

CDP_INLINE d4 splat(double x) {
  return d4{x, x, x, x};
}

CDP_INLINE d4 vsqrt(d4 x) {
#if defined(__SSE2__)
  __m128d lo;
  __m128d hi;
  std::memcpy(&lo, &x, sizeof lo);
  std::memcpy(&hi, reinterpret_cast<const char*>(&x) + sizeof lo, sizeof hi);
  lo = _mm_sqrt_pd(lo);
  hi = _mm_sqrt_pd(hi);
  d4 r;
  std::memcpy(&r, &lo, sizeof lo);
  std::memcpy(reinterpret_cast<char*>(&r) + sizeof lo, &hi, sizeof hi);
  return r;
#else
  return d4{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
#endif
}

struct V3 {
  d4 x, y, z;
};

CDP_INLINE V3 operator+(const V3& a, const V3& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
CDP_INLINE V3 operator-(const V3& a, const V3& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
CDP_INLINE V3 operator*(d4 s, const V3& a) {
  return {s * a.x, s * a.y, s * a.z};
}
CDP_INLINE V3 operator*(const V3& a, d4 s) {
  return {a.x * s, a.y * s, a.z * s};
}
CDP_INLINE V3 operator-(const V3& a) {
  return {-a.x, -a.y, -a.z};
}
/// Eigen's Vector3d::dot: (x0 y0 + x1 y1) + x2 y2
CDP_INLINE d4 dot(const V3& a, const V3& b) {
  return (a.x * b.x + a.y * b.y) + a.z * b.z;
}
CDP_INLINE V3 cross(const V3& a, const V3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <typename M>
CDP_INLINE d4 select(M mask, d4 a, d4 b) {
  return mask ? a : b;
}
template <typename M>
CDP_INLINE V3 select(M mask, const V3& a, const V3& b) {
  return {mask ? a.x : b.x, mask ? a.y : b.y, mask ? a.z : b.z};
}
/// std::max({a, b, c, d}): the first largest
CDP_INLINE d4 max4(d4 a, d4 b, d4 c, d4 d) {
  d4 m = a;
  m = m < b ? b : m;
  m = m < c ? c : m;
  m = m < d ? d : m;
  return m;
}
/// detail::action_size_sq
CDP_INLINE d4 action_size_sq(d4 R_n, const V3& R_t, const V3& T_t, d4 T_n, d4 inv_r_sq) {
  return max4(R_n * R_n, dot(R_t, R_t), dot(T_t, T_t) * inv_r_sq, T_n * T_n * inv_r_sq);
}
/// clamp_to_disc: the trial itself inside the disc, else trial × (limit/|trial|)
CDP_INLINE V3 clamp_to_disc(const V3& trial, d4 limit) {
  const d4 norm_squared = dot(trial, trial);
  const d4 scale = limit / vsqrt(norm_squared);
  return select(norm_squared <= limit * limit, trial, trial * scale);
}

/// Lane-wise copy of a batch's bodies and actions.
struct Lanes {
  alignas(32) double v[2][8][kBatchLanes];  ///< sphere a, b: v xyz, ω xyz, Δt/m, Δt/I
  alignas(32) double x[8][kBatchLanes];     ///< R_n, R_t xyz, T_t xyz, T_n
};

CDP_INLINE V3 lanes3(const double (*p)[kBatchLanes]) {
  return {load(p[0]), load(p[1]), load(p[2])};
}
CDP_INLINE void store3(double (*p)[kBatchLanes], const V3& v) {
  store(p[0], v.x);
  store(p[1], v.y);
  store(p[2], v.z);
}

/// solve_pair on every lane of a batch; writes the lanes' changes and new normal forces.
CDP_INLINE void solve_batch(const PairBatch& B, SphereVelocity* const* a_ptr,
                            SphereVelocity* const* b_ptr, ContactAction* const* x_ptr,
                            double* change_sq, double* normal_force) {
  Lanes in;
  for (int l = 0; l < kBatchLanes; ++l) {
    const SphereVelocity* s[2] = {a_ptr[l], b_ptr[l]};
    for (int i = 0; i < 2; ++i) {
      for (int c = 0; c < 3; ++c) {
        in.v[i][c][l] = s[i]->linear[c];
        in.v[i][3 + c][l] = s[i]->angular[c];
      }
      in.v[i][6][l] = s[i]->dt_inverse_mass;
      in.v[i][7][l] = s[i]->dt_inverse_inertia;
    }
    const ContactAction& x = *x_ptr[l];
    in.x[0][l] = x.normal_force;
    for (int c = 0; c < 3; ++c) {
      in.x[1 + c][l] = x.tangential_force[c];
      in.x[4 + c][l] = x.rolling_torque[c];
    }
    in.x[7][l] = x.twisting_torque;
  }
  const V3 n{load(B.nx), load(B.ny), load(B.nz)};
  const d4 lever_a = load(B.lever_a);
  const d4 lever_b = load(B.lever_b);
  V3 va = lanes3(&in.v[0][0]);
  V3 wa = lanes3(&in.v[0][3]);
  V3 vb = lanes3(&in.v[1][0]);
  V3 wb = lanes3(&in.v[1][3]);
  const d4 m_a = load(in.v[0][6]);
  const d4 i_a = load(in.v[0][7]);
  const d4 m_b = load(in.v[1][6]);
  const d4 i_b = load(in.v[1][7]);
  const d4 R_n_old = load(in.x[0]);
  const V3 R_t_old = lanes3(&in.x[1]);
  const V3 T_t_old = lanes3(&in.x[4]);
  const d4 T_n_old = load(in.x[7]);
  const d4 cohesion = load(B.cohesion);
  const d4 inv_r_sq = load(B.inv_r_sq);

  // pair_relative_velocity
  const V3 V = (vb - va) - cross(lever_a * wa + lever_b * wb, n);
  const V3 Omega = wb - wa;

  // solve_modes, 1 normal
  const d4 V_n = dot(V, n);
  const d4 R_n_trial = R_n_old - load(B.inv_dt_w_n) * (V_n + load(B.gap_rate));
  const auto open = R_n_trial < -cohesion;
  // the open branch
  const d4 dR_n_open = -cohesion - R_n_old;
  const V3 dR_open = dR_n_open * n - R_t_old;
  const V3 dT_open = -T_t_old - T_n_old * n;
  const d4 change_open = action_size_sq(dR_n_open, R_t_old, T_t_old, T_n_old, inv_r_sq);
  // the closed branch
  const d4 dR_n = R_n_trial - R_n_old;
  const d4 S = R_n_trial + cohesion;
  // 2 sliding
  const V3 V_t = V - V_n * n;
  const V3 R_t = clamp_to_disc(R_t_old - load(B.inv_dt_w_t) * V_t, load(B.mu) * S);
  const V3 dR_t = R_t - R_t_old;
  // 3 rolling, 4 torsion
  const V3 Omega_1 = Omega + load(B.coupling) * cross(n, dR_t);
  const d4 Omega_n = dot(Omega_1, n);
  const V3 Omega_t = Omega_1 - Omega_n * n;
  const d4 inv_dt_w_r = load(B.inv_dt_w_r);
  const d4 roll_cap = load(B.roll_cap);
  const V3 zero{splat(0.0), splat(0.0), splat(0.0)};
  const V3 T_t =
      select(roll_cap > 0.0, clamp_to_disc(T_t_old - inv_dt_w_r * Omega_t, roll_cap * S), zero);
  const d4 T_n_trial = T_n_old - inv_dt_w_r * Omega_n;
  const d4 twist_limit = load(B.twist_cap) * S;
  const d4 minus_limit = -twist_limit;
  const d4 T_n = T_n_trial < minus_limit ? minus_limit
                                          : (twist_limit < T_n_trial ? twist_limit : T_n_trial);
  const V3 dT_t = T_t - T_t_old;
  const d4 dT_n = T_n - T_n_old;
  const V3 dR_closed = dR_n * n + dR_t;
  const V3 dT_closed = dT_t + dT_n * n;
  const d4 change_closed = action_size_sq(dR_n, dR_t, dT_t, dT_n, inv_r_sq);

  const V3 dR = select(open, dR_open, dR_closed);
  const V3 dT = select(open, dT_open, dT_closed);
  store(change_sq, select(open, change_open, change_closed));
  const d4 R_n_new = select(open, -cohesion, R_n_trial);
  store(normal_force, R_n_new);
  Lanes out;
  store(out.x[0], R_n_new);
  store3(&out.x[1], select(open, zero, R_t));
  store3(&out.x[4], select(open, zero, T_t));
  store(out.x[7], select(open, splat(0.0), T_n));

  // apply_pair_delta
  const V3 n_cross_dR = cross(n, dR);
  va = va - m_a * dR;
  vb = vb + m_b * dR;
  wa = wa - i_a * (lever_a * n_cross_dR + dT);
  wb = wb + i_b * (dT - lever_b * n_cross_dR);
  store3(&out.v[0][0], va);
  store3(&out.v[0][3], wa);
  store3(&out.v[1][0], vb);
  store3(&out.v[1][3], wb);
  for (int l = 0; l < kBatchLanes; ++l) {
    SphereVelocity* s[2] = {a_ptr[l], b_ptr[l]};
    for (int i = 0; i < 2; ++i) {
      for (int c = 0; c < 3; ++c) {
        s[i]->linear[c] = out.v[i][c][l];
        s[i]->angular[c] = out.v[i][3 + c][l];
      }
    }
    ContactAction& x = *x_ptr[l];
    x.normal_force = out.x[0][l];
    for (int c = 0; c < 3; ++c) {
      x.tangential_force[c] = out.x[1 + c][l];
      x.rolling_torque[c] = out.x[4 + c][l];
    }
    x.twisting_torque = out.x[7][l];
  }
}

void visit_sequential(ContactIndex k, Contacts& contacts, VelocityCache& velocities,
                      SweepSums& sums) {
  const auto n_pairs = static_cast<ContactIndex>(contacts.pairs.size());
  std::vector<SphereVelocity>& spheres = velocities.spheres;
  if (k < n_pairs) {
    const PairProblem& p = contacts.pairs[k];
    ContactAction& action = contacts.pair_actions[k];
    const VisitChange change = solve_pair(p, action, spheres[p.a], spheres[p.b]);
    add_visit(sums, change, action.normal_force, p.cohesion);
  } else {
    const WallProblem& w = contacts.walls[k - n_pairs];
    ContactAction& action = contacts.wall_actions[k - n_pairs];
    const VisitChange change = solve_wall(w, action, spheres[w.sphere], velocities.piston_velocity);
    add_visit(sums, change, action.normal_force, w.cohesion);
  }
}

}  // namespace

void build_batches(const Contacts& contacts, const VelocityCache& velocities,
                   ColouredSweep& sweep) {
  const PairColouring& colouring = sweep.colouring;
  const std::size_t colours = colouring.colours();
  sweep.batches.clear();
  sweep.colour_batches.assign(colours + 1, 0);
  for (std::size_t c = 0; c < colours; ++c) {
    for (std::uint32_t m = colouring.colour_start[c]; m < colouring.colour_start[c + 1];
         m += kBatchLanes) {
      PairBatch& batch = sweep.batches.emplace_back();
      batch.lanes = std::min<std::uint32_t>(kBatchLanes, colouring.colour_start[c + 1] - m);
      for (std::uint32_t l = 0; l < batch.lanes; ++l) {
        const ContactIndex k = colouring.members[m + l];
        const PairProblem& p = contacts.pairs[k];
        const SphereVelocity& a = velocities.spheres[p.a];
        const SphereVelocity& b = velocities.spheres[p.b];
        batch.pair[l] = k;
        batch.a[l] = p.a;
        batch.b[l] = p.b;
        batch.nx[l] = p.normal.x();
        batch.ny[l] = p.normal.y();
        batch.nz[l] = p.normal.z();
        batch.gap_rate[l] = p.gap_rate;
        batch.lever_a[l] = p.lever_a;
        batch.lever_b[l] = p.lever_b;
        batch.inv_dt_w_n[l] = p.inv_dt_w_n;
        batch.inv_dt_w_t[l] = p.inv_dt_w_t;
        batch.inv_dt_w_r[l] = p.inv_dt_w_r;
        batch.cohesion[l] = p.cohesion;
        batch.mu[l] = p.mu;
        batch.roll_cap[l] = p.roll_cap;
        batch.twist_cap[l] = p.twist_cap;
        const detail::ModeBlock block = pair_mode_block(p, a, b);
        batch.coupling[l] = block.coupling;
        batch.inv_r_sq[l] = block.inv_r_sq;
      }
    }
    sweep.colour_batches[c + 1] = static_cast<std::uint32_t>(sweep.batches.size());
  }
  const auto n_pairs = static_cast<ContactIndex>(contacts.pairs.size());
  sweep.sequential.assign(colouring.overflow.begin(), colouring.overflow.end());
  for (std::size_t w = 0; w < contacts.walls.size(); ++w) {
    sweep.sequential.push_back(n_pairs + static_cast<ContactIndex>(w));
  }
  sweep.group_order.resize(colours + 1);
  std::iota(sweep.group_order.begin(), sweep.group_order.end(), std::uint32_t{0});
}

void prepare_coloured_sweep(const Contacts& contacts, const VelocityCache& velocities,
                            ColouredSweep& sweep) {
  colour_pairs(contacts.pairs, velocities.spheres.size(), kMaxColours, sweep.colouring,
               sweep.masks);
  build_batches(contacts, velocities, sweep);
}

void order_groups(ColouredSweep& sweep, VisitOrder policy, Rng& rng) {
  std::iota(sweep.group_order.begin(), sweep.group_order.end(), std::uint32_t{0});
  if (policy != VisitOrder::Fixed) {
    shuffle_indices(std::span<std::uint32_t>(sweep.group_order), rng);
  }
}

SweepSums run_coloured_sweep(Contacts& contacts, VelocityCache& velocities,
                             const ColouredSweep& sweep) {
  SweepSums sums;
  const std::size_t colours = sweep.colours();
  SphereVelocity spare_sphere;  // unused lanes read and write these
  ContactAction spare_action;
  SphereVelocity* const spheres = velocities.spheres.data();
  ContactAction* const actions = contacts.pair_actions.data();
  for (const std::uint32_t group : sweep.group_order) {
    if (group == colours) {
      for (const ContactIndex k : sweep.sequential) visit_sequential(k, contacts, velocities, sums);
      continue;
    }
    for (std::uint32_t i = sweep.colour_batches[group]; i < sweep.colour_batches[group + 1]; ++i) {
      const PairBatch& batch = sweep.batches[i];
      SphereVelocity* a_ptr[kBatchLanes];
      SphereVelocity* b_ptr[kBatchLanes];
      ContactAction* x_ptr[kBatchLanes];
      for (std::uint32_t l = 0; l < kBatchLanes; ++l) {
        if (l < batch.lanes) {
          a_ptr[l] = spheres + batch.a[l];
          b_ptr[l] = spheres + batch.b[l];
          x_ptr[l] = actions + batch.pair[l];
        } else {
          spare_sphere = SphereVelocity{};
          a_ptr[l] = &spare_sphere;
          b_ptr[l] = &spare_sphere;
          x_ptr[l] = &spare_action;
        }
      }
      alignas(32) double change_sq[kBatchLanes];
      alignas(32) double normal_force[kBatchLanes];
      solve_batch(batch, a_ptr, b_ptr, x_ptr, change_sq, normal_force);
      for (std::uint32_t l = 0; l < batch.lanes; ++l) {
        add_visit(sums, VisitChange{change_sq[l], 0.0}, normal_force[l], batch.cohesion[l]);
      }
    }
  }
  return sums;
}

}  // namespace cdpowder
