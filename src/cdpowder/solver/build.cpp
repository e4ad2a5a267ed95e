// build.cpp — per-contact constants, cohesion activity, warm start, predicted velocities.
#include "cdpowder/solver/build.hpp"

#include "cdpowder/contact/local_solve.hpp"
#include "cdpowder/core/assert.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace cdpowder {

namespace {

/// Gaps below this count as touching: g_pos = 0 (UK03 eq. 33 with a dead band) [R].
/// Closed contacts that roll or slide open tiny gaps at second order, ≈ (ω Δt)² R per
/// step, because the geometry is frozen within a step (physics.md §3). The closing target
/// g/Δt of such a gap conflicts with the other constraints of a loop of closed, sticking
/// contacts (e.g. two spheres touching each other and the piston): the normal constraints
/// have no exact solution and the NLGS drifts the loop's forces by a constant amount per
/// pass without ever meeting its stopping rule (found in capped compaction steps). Below
/// the dead band the contact is treated as touching. 1e-6 R is three orders below the
/// overlap accuracy target (mean overlap ≤ 1e-3 R, physics.md §17) and four below d_coh.
/// Measured on a 100-sphere compaction at (μ_t, μ_n) = (0, 0): total passes 19.1 M → 9.3 M,
/// capped steps 6823 → 1944, final porosity 0.69915 → 0.69939
/// (docs/lab/2026-11-23-whole-runs-at-paper-scale.md).
constexpr double kTouchingGap = 1e-6;

/// g_pos/Δt: the approach speed that just closes an open gap within the step [R/t0].
double gap_closing_rate(double gap, double dt) {
  return gap > kTouchingGap ? gap / dt : 0.0;
}

/// Cohesion activity of a contact from its start-of-step gap (physics.md §6.2). Exactly
/// touching deposit contacts have |g| ~ 1e-15; `g ≤ d_coh` keeps round-off out of it (§12.11).
bool is_cohesive(const ContactLaw& law, CohesionRule rule, double gap, LastAction last) {
  if (law.cohesion_force <= 0.0) return false;
  switch (rule) {
    case CohesionRule::Graph:
      return gap <= law.cohesion_range;
    case CohesionRule::History:
      // a bond forms at touching, in the sense the contact law uses (the dead band above):
      // with `g ≤ 0` the sign of round-off decided it, and about half of a deposit's exactly
      // touching contacts (|g| ~ 1e-15) started the compaction without cohesion
      return gap <= kTouchingGap || (last.cohesive && gap <= law.cohesion_range);
  }
  return false;
}

/// Warm start: last step's action, with its tangential parts projected onto the new
/// tangent plane (physics.md §7.4), written into `action`. Always inlined: as a call of its own
/// it took ≈ 9 % of the build's time (docs/lab/2026-11-28-build-pairs-and-warm-start-store.md).
[[gnu::always_inline]] inline void warm_start(const ContactAction& last, const Vec3& n,
                                              double cohesion, ContactAction& action) {
  action = last;
  action.tangential_force -= action.tangential_force.dot(n) * n;
  action.rolling_torque -= action.rolling_torque.dot(n) * n;
  // an attraction may only be warm-started where this step's law allows it
  if (action.normal_force < -cohesion) action.normal_force = -cohesion;
}

/// What apply_pair_action and apply_wall_action do with a zero action (every field +0), without
/// the products. Their ΔR = (+0)·n + (+0) and ΔT = (+0) + (+0)·n are +0 in every component (a
/// signed zero plus +0 is +0), as is every product of them with a finite lever or normal,
/// summed with +0, and with Δt/m, Δt/I ≥ 0: body a gets x − (+0), which is x for every x, and
/// the sphere b (or the wall's sphere) gets x + (+0), which is x except that −0 becomes +0; the
/// piston's x − (+0) is x. Adding +0 to the sphere's six components gives those bits without
/// the ≈ 100 instructions of the full update, for every contact that was not in the last step's
/// cache (or every contact, without the warm start).
void apply_zero_action(SphereVelocity& s) {
  s.linear += Vec3(0.0, 0.0, 0.0);
  s.angular += Vec3(0.0, 0.0, 0.0);
}

/// Δt/m and Δt/I of sphere i as the velocity cache holds them (predict_spheres): zero for a
/// fixed sphere, which never moves and absorbs any action.
struct StepResponse {
  double dt_inverse_mass = 0.0;
  double dt_inverse_inertia = 0.0;
};

StepResponse step_response(const Bodies& bodies, BodyIndex i, double dt) {
  if (bodies.fixed[i] != 0) return {};
  return {dt * bodies.inverse_mass[i], dt * bodies.inverse_inertia[i]};
}

/// v* = v + Δt (F_ext/m + g), ω* = ω + Δt T_ext/I of spheres [first, last).
void predict_spheres(const World& world, double dt, std::size_t first, std::size_t last,
                     VelocityCache& velocities) {
  const Bodies& bodies = world.bodies;
  // through a pointer held in a local: the stores into the cache could alias the vectors'
  // own pointers, which would then be reloaded for every sphere
  SphereVelocity* const spheres = velocities.spheres.data();
  for (std::size_t i = first; i < last; ++i) {
    SphereVelocity& s = spheres[i];
    if (bodies.fixed[i] != 0) {
      s = SphereVelocity{};  // fixed: never moves, absorbs any action
      continue;
    }
    const StepResponse response = step_response(bodies, static_cast<BodyIndex>(i), dt);
    s.dt_inverse_mass = response.dt_inverse_mass;
    s.dt_inverse_inertia = response.dt_inverse_inertia;
    s.linear =
        bodies.velocity[i] + s.dt_inverse_mass * bodies.external_force[i] + dt * world.gravity;
    s.angular = bodies.angular_velocity[i] + s.dt_inverse_inertia * bodies.external_torque[i];
  }
}

double predicted_piston_velocity(const World& world, double dt) {
  const Piston& piston = world.walls.piston;
  return piston.enabled
             ? piston.velocity + dt * (-piston.force * piston.inverse_mass() + world.gravity.z())
             : 0.0;
}

/// Whether the step reads last step's actions: for the warm start, or for the history rule.
bool reads_cache(const StepSettings& settings) {
  return settings.solver.warm_start || settings.laws.cohesion_rule == CohesionRule::History;
}

/// Where build_pairs and build_walls take a sphere's Δt/m and Δt/I, and what they do with the
/// warm-start action: on one thread (kApply), from the velocity cache, which predict_spheres
/// has filled, and the action is applied at once; in pieces, from the bodies (the other piece
/// may be predicting the sphere), and the actions are applied by apply_warm_start after.
template <bool kApply>
StepResponse response_of(const World& world, const VelocityCache& velocities, BodyIndex i,
                         double dt) {
  if constexpr (kApply) {
    const SphereVelocity& s = velocities.spheres[i];
    return {s.dt_inverse_mass, s.dt_inverse_inertia};
  } else {
    return step_response(world.bodies, i, dt);
  }
}

/// The constants, cohesion activity and warm-start action of pairs [first, last); with
/// kApply also the action's velocity change (apply_warm_start otherwise).
template <bool kApply>
void build_pairs(const World& world, const StepSettings& settings, const ActionCache& cache,
                 std::size_t first, std::size_t last, Contacts& contacts, VelocityCache& velocities,
                 std::int64_t& kept_bonds) {
  const double dt = settings.solver.dt;
  const ContactLaws& laws = settings.laws;
  const bool lookup = reads_cache(settings);
  std::size_t cursor =
      lookup && first < last ? cache.pair_cursor_at(contact_key(contacts.pairs[first])) : 0;
  for (std::size_t k = first; k < last; ++k) {
    PairProblem& p = contacts.pairs[k];
    const StepResponse a = response_of<kApply>(world, velocities, p.a, dt);
    const StepResponse b = response_of<kApply>(world, velocities, p.b, dt);
    // W blocks of physics.md §5.2, times Δt, with the levers to the common contact point:
    // w_n = 1/m_a + 1/m_b, w_t = w_n + l_a²/I_a + l_b²/I_b, w_r = 1/I_a + 1/I_b
    const double dt_w_n = a.dt_inverse_mass + b.dt_inverse_mass;
    const double dt_w_t = dt_w_n + p.lever_a * p.lever_a * a.dt_inverse_inertia +
                          p.lever_b * p.lever_b * b.dt_inverse_inertia;
    const double dt_w_r = a.dt_inverse_inertia + b.dt_inverse_inertia;
    p.inv_dt_w_n = 1.0 / dt_w_n;
    p.inv_dt_w_t = 1.0 / dt_w_t;
    p.inv_dt_w_r = 1.0 / dt_w_r;
    p.gap_rate = gap_closing_rate(p.gap, dt);
    p.mu = laws.spheres.mu;
    p.roll_cap = laws.spheres.mu_roll * p.r_eff;
    p.twist_cap = laws.spheres.mu_twist * p.r_eff;
    const LastAction last_step = lookup ? cache.find_pair(cursor, contact_key(p)) : LastAction{};
    const bool cohesive = is_cohesive(laws.spheres, laws.cohesion_rule, p.gap, last_step);
    p.cohesion = cohesive ? laws.spheres.cohesion_force : 0.0;
    contacts.pair_cohesive[k] = cohesive ? 1 : 0;
    kept_bonds += cohesive && last_step.cohesive ? 1 : 0;
    ContactAction& action = contacts.pair_actions[k];
    if (settings.solver.warm_start && last_step) {
      warm_start(*last_step.action, p.normal, p.cohesion, action);
      if constexpr (kApply) {
        apply_pair_delta(p, action_force(action, p.normal), action_torque(action, p.normal),
                         velocities.spheres[p.a], velocities.spheres[p.b]);
      }
    } else {
      action = ContactAction{};
      if constexpr (kApply) apply_zero_action(velocities.spheres[p.b]);
    }
  }
}

/// build_pairs for wall contacts [first, last).
template <bool kApply>
void build_walls(const World& world, const StepSettings& settings, const ActionCache& cache,
                 std::size_t first, std::size_t last, Contacts& contacts, VelocityCache& velocities,
                 std::int64_t& kept_bonds) {
  const double dt = settings.solver.dt;
  const ContactLaws& laws = settings.laws;
  const bool lookup = reads_cache(settings);
  std::size_t cursor =
      lookup && first < last ? cache.wall_cursor_at(contact_key(contacts.walls[first])) : 0;
  const double piston_response =
      world.walls.piston.enabled ? dt * world.walls.piston.inverse_mass() : 0.0;
  for (std::size_t k = first; k < last; ++k) {
    WallProblem& w = contacts.walls[k];
    const StepResponse s = response_of<kApply>(world, velocities, w.sphere, dt);
    w.wall_response = w.wall == WallKind::Piston ? piston_response : 0.0;
    w.wall_moves = w.wall == WallKind::Piston ? 1.0 : 0.0;
    // the wall is immobile tangentially and does not rotate; the piston moves along n
    const double dt_w_n = s.dt_inverse_mass + w.wall_response;
    const double dt_w_t = s.dt_inverse_mass + w.radius * w.radius * s.dt_inverse_inertia;
    const double dt_w_r = s.dt_inverse_inertia;
    w.inv_dt_w_n = dt_w_n > 0.0 ? 1.0 / dt_w_n : 0.0;
    w.inv_dt_w_t = dt_w_t > 0.0 ? 1.0 / dt_w_t : 0.0;
    w.inv_dt_w_r = dt_w_r > 0.0 ? 1.0 / dt_w_r : 0.0;
    w.gap_rate = gap_closing_rate(w.gap, dt);
    const double r_eff = laws.wall_r_eff_factor * w.radius;
    w.mu = laws.walls.mu;
    w.roll_cap = laws.walls.mu_roll * r_eff;
    w.twist_cap = laws.walls.mu_twist * r_eff;
    const LastAction last_step = lookup ? cache.find_wall(cursor, contact_key(w)) : LastAction{};
    const bool cohesive = is_cohesive(laws.walls, laws.cohesion_rule, w.gap, last_step);
    w.cohesion = cohesive ? laws.walls.cohesion_force : 0.0;
    contacts.wall_cohesive[k] = cohesive ? 1 : 0;
    kept_bonds += cohesive && last_step.cohesive ? 1 : 0;
    ContactAction& action = contacts.wall_actions[k];
    if (settings.solver.warm_start && last_step) {
      warm_start(*last_step.action, w.normal, w.cohesion, action);
      if constexpr (kApply) apply_wall_action(w, action, velocities);
    } else {
      action = ContactAction{};
      if constexpr (kApply) apply_zero_action(velocities.spheres[w.sphere]);
    }
  }
}

/// The build's cut into pieces by sphere owner: piece p owns spheres [first_sphere[p],
/// first_sphere[p + 1]) and the pairs whose sphere a it owns, [first_pair[p], first_pair[p + 1])
/// (pairs are sorted by a, and b > a): about as many pairs each.
struct OwnerCut {
  std::uint32_t pieces = 0;
  std::array<BodyIndex, kMaxPieces + 1> first_sphere{};
  std::array<std::size_t, kMaxPieces + 1> first_pair{};

  /// The piece that owns sphere i: how many of first_sphere[1 … pieces − 1] are ≤ i.
  [[nodiscard]] std::uint32_t owner(BodyIndex i) const {
    const auto* const begin = first_sphere.begin() + 1;
    return static_cast<std::uint32_t>(std::upper_bound(begin, first_sphere.begin() + pieces, i) -
                                      begin);
  }
};

/// Cuts at the first sphere a of `pieces` near-equal ranges of the pairs (at the end where a
/// range is empty), so that the pieces' pairs are near-equal too.
OwnerCut owner_cut(const Contacts& contacts, std::size_t sphere_count, std::uint32_t pieces) {
  OwnerCut cut;
  cut.pieces = pieces;
  const std::vector<PairProblem>& pairs = contacts.pairs;
  const auto all = static_cast<BodyIndex>(sphere_count);
  for (std::uint32_t k = 1; k < pieces; ++k) {
    const std::size_t first = piece_of(pairs.size(), pieces, k).first;
    cut.first_sphere[k] = first < pairs.size() ? pairs[first].a : all;
  }
  cut.first_sphere[pieces] = all;
  for (std::uint32_t k = 1; k < pieces; ++k) {
    const BodyIndex s = cut.first_sphere[k];
    cut.first_pair[k] = static_cast<std::size_t>(
        std::partition_point(pairs.begin(), pairs.end(),
                             [s](const PairProblem& p) { return p.a < s; }) -
        pairs.begin());
  }
  cut.first_pair[pieces] = pairs.size();
  return cut;
}

/// Piece p's pairs whose sphere b a later piece owns, grouped by that piece and in pair order
/// within a group: scratch.crossing[p], group d at [scratch.group_starts[p][d],
/// scratch.group_starts[p][d + 1]). A counting sort on the piece's own thread: one scan of the
/// piece's pairs finds the crossing ones and their owners (one binary search each), the
/// placing reads only those.
void group_crossing_pairs(const Contacts& contacts, const OwnerCut& cut, std::uint32_t p,
                          BuildScratch& scratch) {
  static_assert(kMaxPieces <= 256, "a piece's number is kept in one byte");
  const std::vector<PairProblem>& pairs = contacts.pairs;
  const BodyIndex end = cut.first_sphere[p + 1];
  std::vector<std::uint32_t>& found = scratch.found[p];
  std::vector<std::uint8_t>& found_owner = scratch.found_owner[p];
  found.clear();
  found_owner.clear();
  std::array<std::uint32_t, kMaxPieces + 1> next{};
  for (std::size_t k = cut.first_pair[p]; k < cut.first_pair[p + 1]; ++k) {
    if (pairs[k].b < end) continue;
    const std::uint32_t owner = cut.owner(pairs[k].b);
    ++next[owner];
    found.push_back(static_cast<std::uint32_t>(k));
    found_owner.push_back(static_cast<std::uint8_t>(owner));
  }
  std::array<std::uint32_t, kMaxPieces + 1>& starts = scratch.group_starts[p];
  starts[0] = 0;
  for (std::uint32_t d = 0; d < cut.pieces; ++d) {
    starts[d + 1] = starts[d] + next[d];
    next[d] = starts[d];
  }
  std::vector<std::uint32_t>& crossing = scratch.crossing[p];
  crossing.resize(found.size());
  for (std::size_t f = 0; f < found.size(); ++f) crossing[next[found_owner[f]]++] = found[f];
}

/// What a warm-start action changes (§5.3): the force ΔR, the torque ΔT and n × ΔR.
struct PairDelta {
  Vec3 force;
  Vec3 torque;
  Vec3 n_cross_force;
};

PairDelta pair_delta(const PairProblem& p, const ContactAction& action) {
  PairDelta d{action_force(action, p.normal), action_torque(action, p.normal), Vec3::Zero()};
  d.n_cross_force = p.normal.cross(d.force);
  return d;
}

/// The walls of one kind whose sphere is in [first, last): a range, since walls are sorted by
/// (kind, sphere).
IndexRange walls_of(const std::vector<WallProblem>& walls, WallKind kind, BodyIndex first,
                    BodyIndex last) {
  const auto position = [&](BodyIndex i) {
    const std::uint64_t key = wall_key(kind, i);
    return static_cast<std::size_t>(
        std::partition_point(walls.begin(), walls.end(),
                             [key](const WallProblem& w) { return contact_key(w) < key; }) -
        walls.begin());
  };
  return {position(first), position(last)};
}

/// The velocity changes of the warm-start actions (§5.3) on the spheres that piece d owns:
/// every contact's change in contact order (pairs, then walls), so each sphere gets its changes
/// in the order of a pass over all contacts. Its pairs come from earlier pieces' crossing
/// groups (all before its own pairs, in pair order) and from its own pairs. A contact without a
/// warm start has a zero action, whose change adds +0 (local_solve_test, ZeroAction).
void apply_warm_start(const Contacts& contacts, const OwnerCut& cut, const BuildScratch& scratch,
                      std::uint32_t d, VelocityCache& velocities) {
  SphereVelocity* const spheres = velocities.spheres.data();
  for (std::uint32_t c = 0; c < d; ++c) {
    const std::vector<std::uint32_t>& crossing = scratch.crossing[c];
    for (std::uint32_t g = scratch.group_starts[c][d]; g < scratch.group_starts[c][d + 1]; ++g) {
      const PairProblem& p = contacts.pairs[crossing[g]];
      const PairDelta delta = pair_delta(p, contacts.pair_actions[crossing[g]]);
      apply_pair_delta_to_b(p, delta.force, delta.torque, delta.n_cross_force, spheres[p.b]);
    }
  }
  const BodyIndex end = cut.first_sphere[d + 1];
  for (std::size_t k = cut.first_pair[d]; k < cut.first_pair[d + 1]; ++k) {
    const PairProblem& p = contacts.pairs[k];
    const PairDelta delta = pair_delta(p, contacts.pair_actions[k]);
    apply_pair_delta_to_a(p, delta.force, delta.torque, delta.n_cross_force, spheres[p.a]);
    if (p.b < end)
      apply_pair_delta_to_b(p, delta.force, delta.torque, delta.n_cross_force, spheres[p.b]);
  }
  for (const WallKind kind : {WallKind::Bottom, WallKind::Piston}) {
    const IndexRange walls = walls_of(contacts.walls, kind, cut.first_sphere[d], end);
    for (std::size_t k = walls.first; k < walls.last; ++k) {
      const WallProblem& w = contacts.walls[k];
      const ContactAction& action = contacts.wall_actions[k];
      apply_wall_delta_to_sphere(w, action_force(action, w.normal), action_torque(action, w.normal),
                                 spheres[w.sphere]);
    }
  }
}

/// The piston's velocity change of the warm-start actions, in wall order.
void apply_warm_start_to_piston(const Contacts& contacts, VelocityCache& velocities) {
  for (std::size_t k = 0; k < contacts.walls.size(); ++k) {
    const WallProblem& w = contacts.walls[k];
    if (w.wall_moves == 0.0) continue;
    const ContactAction& action = contacts.wall_actions[k];
    apply_wall_delta_to_wall(w, action_force(action, w.normal), velocities.piston_velocity);
  }
}

/// How many pieces the build takes: scratch.pieces where set, or one per kChunkIndices pairs
/// (at least two, at most kMaxPieces).
std::uint32_t build_pieces(const BuildScratch& scratch, std::size_t pair_count) {
  if (scratch.pieces != 0) return std::min(scratch.pieces, kMaxPieces);
  return std::max<std::uint32_t>(2, pieces_of(pair_count));
}

/// A piece's count of bonds (run_summed_pieces): integers, so any cut gives the same sum.
struct BondCount {
  std::int64_t bonds = 0;

  void merge(const BondCount& other) { bonds += other.bonds; }
};

/// The bonds formed and broken from the counts of bonds now, in the last step (the cache) and
/// in both (`kept_*`, counted by the build's lookups); without lookups (no warm start, the
/// graph rule) by a merge of the two lists' keys. The flags are counted in pieces on `pieces`.
BondChanges bonds_of_step(const StepSettings& settings, const ActionCache& cache,
                          const Contacts& contacts, std::int64_t kept_pairs,
                          std::int64_t kept_walls, PieceRunner* pieces) {
  if (!(settings.laws.spheres.cohesion_force > 0.0 || settings.laws.walls.cohesion_force > 0.0)) {
    return {};
  }
  if (!reads_cache(settings)) return bond_changes(cache.last(), contacts);
  const auto bonds = [pieces](const std::vector<std::uint8_t>& flags) {
    return run_summed_pieces<BondCount>(
               pieces, flags.size(),
               [&](std::size_t first, std::size_t last, BondCount& c) {
                 const auto begin = flags.begin();
                 c.bonds =
                     std::accumulate(begin + static_cast<std::ptrdiff_t>(first),
                                     begin + static_cast<std::ptrdiff_t>(last), std::int64_t{0});
               })
        .bonds;
  };
  const KeyedContacts& last = cache.last();
  BondChanges c;
  c.pairs_formed = bonds(contacts.pair_cohesive) - kept_pairs;
  c.pairs_broken = bonds(last.pair_cohesive) - kept_pairs;
  c.walls_formed = bonds(contacts.wall_cohesive) - kept_walls;
  c.walls_broken = bonds(last.wall_cohesive) - kept_walls;
  return c;
}

}  // namespace

BondChanges build_local_problems(const World& world, const StepSettings& settings,
                                 const ActionCache& cache, Contacts& contacts,
                                 VelocityCache& velocities, PieceRunner* pieces,
                                 BuildScratch* scratch) {
  const double dt = settings.solver.dt;
  const std::size_t sphere_count = world.bodies.size();
  velocities.spheres.resize(sphere_count);
  velocities.piston_velocity = predicted_piston_velocity(world, dt);
  contacts.pair_actions.resize(contacts.pairs.size());
  contacts.pair_cohesive.resize(contacts.pairs.size());
  contacts.wall_actions.resize(contacts.walls.size());
  contacts.wall_cohesive.resize(contacts.walls.size());

  const std::size_t pair_count = contacts.pairs.size();
  // bonds of the last step that are bonds still, each piece its own count
  std::array<std::int64_t, kMaxPieces> kept_pairs{};
  std::array<std::int64_t, kMaxPieces> kept_walls{};
  if (pieces == nullptr) {
    // one pass: each contact's record, and its warm start applied at once
    predict_spheres(world, dt, 0, sphere_count, velocities);
    build_pairs<true>(world, settings, cache, 0, pair_count, contacts, velocities, kept_pairs[0]);
    build_walls<true>(world, settings, cache, 0, contacts.walls.size(), contacts, velocities,
                      kept_walls[0]);
  } else {
    // two passes of K pieces cut by sphere owner (owner_cut): (1) each piece's share of the
    // predicted velocities and of the walls' records, the records and warm-start actions of
    // its own pairs, and its pairs whose b a later piece owns, grouped by that piece; (2) the
    // warm start's velocity changes, each piece those of its own spheres, and one more piece
    // the piston's
    BuildScratch local;
    BuildScratch& cut_scratch = scratch != nullptr ? *scratch : local;
    const OwnerCut cut = owner_cut(contacts, sphere_count, build_pieces(cut_scratch, pair_count));
    run_pieces(pieces, cut.pieces, [&](std::uint32_t piece) {
      const IndexRange spheres = piece_of(sphere_count, cut.pieces, piece);
      predict_spheres(world, dt, spheres.first, spheres.last, velocities);
      build_pairs<false>(world, settings, cache, cut.first_pair[piece], cut.first_pair[piece + 1],
                         contacts, velocities, kept_pairs[piece]);
      const IndexRange walls = piece_of(contacts.walls.size(), cut.pieces, piece);
      build_walls<false>(world, settings, cache, walls.first, walls.last, contacts, velocities,
                         kept_walls[piece]);
      group_crossing_pairs(contacts, cut, piece, cut_scratch);
    });
    run_pieces(pieces, cut.pieces + 1, [&](std::uint32_t piece) {
      if (piece < cut.pieces) {
        apply_warm_start(contacts, cut, cut_scratch, piece, velocities);
      } else {
        apply_warm_start_to_piston(contacts, velocities);
      }
    });
  }
  // the passes assume finite v*, ω* (debug builds only; one pass over the spheres)
  CDP_ASSERT(std::isfinite(velocities.piston_velocity) &&
                 std::all_of(velocities.spheres.begin(), velocities.spheres.end(),
                             [](const SphereVelocity& s) {
                               return s.linear.allFinite() && s.angular.allFinite();
                             }),
             "non-finite predicted velocity");
  return bonds_of_step(settings, cache, contacts,
                       std::accumulate(kept_pairs.begin(), kept_pairs.end(), std::int64_t{0}),
                       std::accumulate(kept_walls.begin(), kept_walls.end(), std::int64_t{0}),
                       pieces);
}

}  // namespace cdpowder
