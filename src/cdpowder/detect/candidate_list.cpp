// candidate_list.cpp — the Verlet list's validity test and its build from the cell grid.
#include "cdpowder/detect/candidate_list.hpp"

#include <algorithm>
#include <cmath>

namespace cdpowder {

bool CandidateList::may_cover(const Bodies& bodies, const PeriodicBox& box, double gap) const {
  return built_gap_ >= 0.0 && anchor_.size() == bodies.size() && box.lx == box_.lx &&
         box.ly == box_.ly && slack(gap) >= 0.0;
}

bool CandidateList::covers_spheres(const Bodies& bodies, const PeriodicBox& box, double gap,
                                   std::size_t first, std::size_t last) const {
  const double slack_sq = slack(gap) * slack(gap);
  for (std::size_t i = first; i < last; ++i) {
    if (box.minimum_image(bodies.position[i] - anchor_[i]).squaredNorm() > slack_sq) return false;
  }
  return true;
}

void CandidateList::rebuild(const Bodies& bodies, const PeriodicBox& box, CellGrid& grid,
                            double gap, double margin) {
  built_gap_ = gap + margin;
  box_ = box;
  anchor_ = bodies.position;
  ++builds_;
  pairs_.clear();
  // Visiting a in index order and sorting each sphere's few partners b gives the list sorted
  // by (a, b) — the order of the warm-start cache — without sorting the whole list.
  grid.rebuild(bodies.position, box, 2.0 * bodies.max_radius() + built_gap_);
  const auto sphere_count = static_cast<BodyIndex>(bodies.size());
  for (BodyIndex a = 0; a < sphere_count; ++a) {
    const std::size_t first = pairs_.size();
    grid.for_each_near(a, [&](BodyIndex b) {
      if (b <= a || (bodies.fixed[a] != 0 && bodies.fixed[b] != 0)) return;
      const double reach = bodies.radius[a] + bodies.radius[b] + built_gap_;
      if (box.minimum_image(bodies.position[b] - bodies.position[a]).squaredNorm() >=
          reach * reach) {
        return;
      }
      pairs_.push_back({a, b});
    });
    std::sort(pairs_.begin() + static_cast<std::ptrdiff_t>(first), pairs_.end(),
              [](const Pair& x, const Pair& y) { return x.b < y.b; });
  }
}

}  // namespace cdpowder
