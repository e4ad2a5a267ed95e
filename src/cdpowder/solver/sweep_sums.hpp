// sweep_sums.hpp — what a sweep reports to the stopping rules, shared by the scalar sweep
// (nlgs.cpp) and the coloured one (coloured_sweep.cpp).
#pragma once

#include "cdpowder/contact/local_solve.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace cdpowder {

/// One sweep's largest change and sums.
struct SweepSums {
  double max_change_sq = 0.0;  ///< largest squared correction of a visit [F_coh²]
  double sum_change_sq = 0.0;
  double sum_closed_normal = 0.0;
  std::size_t closed = 0;
};

/// Adds one visit; the sums depend on the order of the visits.
inline void add_visit(SweepSums& sums, const VisitChange& change, double normal_force,
                      double cohesion) {
  sums.max_change_sq = std::max(sums.max_change_sq, change.change_sq);
  sums.sum_change_sq += change.change_sq;
  if (normal_force + cohesion > 0.0) {
    sums.sum_closed_normal += std::abs(normal_force);
    ++sums.closed;
  }
}

}  // namespace cdpowder
