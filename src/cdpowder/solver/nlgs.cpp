// nlgs.cpp — the sweep loop and the stopping rules.
#include "cdpowder/solver/nlgs.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <span>

#include "cdpowder/contact/local_solve.hpp"

namespace cdpowder {

namespace {

/// Sweeps over which the contraction ρ is measured: long enough to average out the
/// sweep-to-sweep noise of a random visiting order.
constexpr int kContractionWindow = 8;
/// ρ is capped here, so the error estimate is at most 1000 × the residual.
constexpr double kMaxContraction = 0.999;

}  // namespace

SweepSums run_sweep(Contacts& contacts, VelocityCache& velocities) {
  SweepSums sums;
  const auto n_pairs = static_cast<ContactIndex>(contacts.pairs.size());
  std::vector<SphereVelocity>& spheres = velocities.spheres;
  for (const ContactIndex k : contacts.visit_order) {
    VisitChange change;
    double normal_force = 0.0;
    double cohesion = 0.0;
    if (k < n_pairs) {
      const PairProblem& p = contacts.pairs[k];
      ContactAction& action = contacts.pair_actions[k];
      change = solve_pair(p, action, spheres[p.a], spheres[p.b]);
      normal_force = action.normal_force;
      cohesion = p.cohesion;
    } else {
      const WallProblem& w = contacts.walls[k - n_pairs];
      ContactAction& action = contacts.wall_actions[k - n_pairs];
      change = solve_wall(w, action, spheres[w.sphere], velocities.piston_velocity);
      normal_force = action.normal_force;
      cohesion = w.cohesion;
    }
    sums.max_change = std::max(sums.max_change, change.change);
    sums.sum_change += change.change;
    sums.sum_magnitude += change.magnitude;
    if (normal_force + cohesion > 0.0) {
      sums.sum_closed_normal += std::abs(normal_force);
      ++sums.closed;
    }
  }
  return sums;
}

SolverStats solve_nlgs(Contacts& contacts, VelocityCache& velocities,
                       const SolverSettings& settings, double reference_force, Rng& rng) {
  std::vector<ContactIndex>& order = contacts.visit_order;
  order.resize(contacts.size());
  std::iota(order.begin(), order.end(), ContactIndex{0});

  SolverStats stats;
  if (contacts.size() == 0) {
    stats.converged = true;
    return stats;
  }
  // residuals of the last kContractionWindow + 1 sweeps, for the contraction estimate
  std::array<double, kContractionWindow + 1> recent{};
  for (int sweep = 1; sweep <= settings.max_sweeps; ++sweep) {
    // a fresh order every sweep, so corrections spread without a preferred direction (§7.1)
    if (settings.visit_order == VisitOrder::RandomEachSweep) {
      shuffle_indices(std::span<ContactIndex>(order), rng);
    }
    const SweepSums sums = run_sweep(contacts, velocities);
    const double mean_closed =
        sums.closed > 0 ? sums.sum_closed_normal / static_cast<double>(sums.closed) : 0.0;
    stats.force_scale = std::max({reference_force, mean_closed, 1e-300});
    stats.sweeps = sweep;
    stats.residual = sums.max_change / stats.force_scale;
    stats.relative_change = sums.sum_magnitude > 0.0 ? sums.sum_change / sums.sum_magnitude : 0.0;
    recent[static_cast<std::size_t>(sweep) % recent.size()] = stats.residual;

    // ρ from the residuals kContractionWindow sweeps apart (fewer in the first sweeps)
    const int window = std::min(kContractionWindow, sweep - 1);
    double rho = kMaxContraction;
    if (window > 0) {
      const double earlier = recent[static_cast<std::size_t>(sweep - window) % recent.size()];
      rho = earlier > 0.0 ? std::pow(stats.residual / earlier, 1.0 / window) : 0.0;
      rho = std::clamp(rho, 0.0, kMaxContraction);
    }
    stats.contraction = rho;
    stats.error_estimate = stats.residual / (1.0 - rho);

    if (sweep < settings.min_sweeps) continue;
    const bool done = settings.stopping_rule == StoppingRule::Residual
                          ? stats.error_estimate <= settings.tolerance
                          : stats.relative_change <= settings.tolerance;
    if (done) {
      stats.converged = true;
      break;
    }
  }
  return stats;
}

}  // namespace cdpowder
