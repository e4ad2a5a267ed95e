// slabs.cpp — the cut at the median mid-height of the contacts (slabs.hpp).
#include "cdpowder/solver/nlgs/slabs.hpp"

#include <algorithm>
#include <cstddef>

namespace cdpowder {

void cut_into_slabs(const std::vector<Vec3>& positions, const Contacts& contacts,
                    std::vector<std::uint8_t>& slab, std::vector<double>& scratch) {
  const std::vector<PairProblem>& pairs = contacts.pairs;
  slab.clear();
  if (pairs.size() < kMinPairsToCut) return;
  // z is not periodic (the box is periodic in x and y only), so mid-heights are plain means
  scratch.resize(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    scratch[k] = 0.5 * (positions[pairs[k].a].z() + positions[pairs[k].b].z());
  }
  // pairs below the cut p0 so that p0 + w_b·bottom = (P − p0) + w_p·piston
  double walls_above = 0.0;  // the piston contacts' visits less the bottom-wall contacts'
  for (const WallProblem& w : contacts.walls) {
    walls_above += w.wall == WallKind::Piston ? kPistonVisitCost : -kBottomWallVisitCost;
  }
  const double below = 0.5 * (static_cast<double>(pairs.size()) + walls_above);
  const auto rank =
      static_cast<std::ptrdiff_t>(std::clamp(below, 0.0, static_cast<double>(pairs.size() - 1)));
  const auto at = scratch.begin() + rank;
  std::nth_element(scratch.begin(), at, scratch.end());
  const double cut = *at;
  slab.resize(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) {
    slab[i] = positions[i].z() >= cut ? 1 : 0;
  }
}

}  // namespace cdpowder
