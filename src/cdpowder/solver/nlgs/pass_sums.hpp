// pass_sums.hpp — what a pass reports to the stopping rules, shared by the scalar pass
// (nlgs.cpp) and the coloured one (coloured_pass.cpp). The scalar visit both use is in
// visit_contact.hpp, which only the solver's sources include (it brings the contact kernels).
#pragma once

#include <algorithm>
#include <cstddef>

namespace cdpowder {

/// One pass's largest change and sums.
struct PassSums {
  double max_change_sq = 0.0;  ///< largest squared correction of a visit [F_coh²]
  double sum_change_sq = 0.0;
  double sum_closed_normal = 0.0;
  std::size_t closed = 0;

  /// Adds the sums of the next part of a pass (coloured_pass.hpp): adding a part that
  /// visited nothing leaves the bits (the sums are ≥ +0).
  void add_part(const PassSums& part) {
    max_change_sq = std::max(max_change_sq, part.max_change_sq);
    sum_change_sq += part.sum_change_sq;
    sum_closed_normal += part.sum_closed_normal;
    closed += part.closed;
  }
};

}  // namespace cdpowder
