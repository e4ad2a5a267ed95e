// candidate_list.cpp — the Verlet list's validity test and its build from the cell grid.
#include "cdpowder/detect/candidate_list.hpp"

#include "cdpowder/core/pieces.hpp"
#include "cdpowder/detect/sphere_scan.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace cdpowder {

bool CandidateList::may_cover(const Bodies& bodies, const PeriodicBox& box, double gap) const {
  return built_gap_ >= 0.0 && anchor_.size() == bodies.size() && box.lx == box_.lx &&
         box.ly == box_.ly && slack(gap) >= 0.0;
}

bool CandidateList::covers_spheres(const Bodies& bodies, const PeriodicBox& box, double gap,
                                   std::size_t first, std::size_t last) const {
  const double slack_sq = slack(gap) * slack(gap);
  return all_within(bodies.position.data(), anchor_.data(), box, slack_sq, first, last);
}

namespace {

/// Appends to `out` the listed pairs (a, b) of the spheres a in [first, last), in a's order
/// and each a's partners sorted: the list's entries of those spheres, in the list's order.
void list_pairs_of(const Bodies& bodies, const PeriodicBox& box, const CellGrid& grid,
                   double built_gap, BodyIndex first, BodyIndex last,
                   std::vector<BodyIndex>& partners, std::vector<CandidateList::Pair>& out) {
  const std::vector<BodyIndex>& near = grid.sorted();
  const std::vector<Vec3>& near_position = grid.sorted_positions();
  std::array<CellGrid::Run, CellGrid::kMaxRuns> runs{};
  // Visiting a in index order and sorting each sphere's few partners b gives the list sorted
  // by (a, b), the order of the warm-start cache, without sorting the whole list.
  for (BodyIndex a = first; a < last; ++a) {
    const int run_count = grid.near_runs(a, runs);
    std::size_t near_count = 0;
    for (int r = 0; r < run_count; ++r) near_count += runs[r].last - runs[r].first;
    if (partners.size() < near_count) partners.resize(near_count);
    const Vec3& position_a = bodies.position[a];
    const double radius_a = bodies.radius[a];
    const std::size_t free_a = bodies.fixed[a] == 0 ? 1 : 0;
    // every neighbour written, the kept ones counted: no branch on the tests, which go
    // either way about as often (b > a for half of them)
    std::size_t kept = 0;
    for (int r = 0; r < run_count; ++r) {
      for (std::uint32_t t = runs[r].first; t < runs[r].last; ++t) {
        const BodyIndex b = near[t];
        const double reach = radius_a + bodies.radius[b] + built_gap;
        const double distance_squared =
            box.minimum_image(near_position[t] - position_a).squaredNorm();
        // listed: b > a, not both fixed, and within reach (0 or 1 each, and-ed as integers);
        // a pair is passed over where d² ≥ reach², so a NaN distance is listed, as find_pairs
        // keeps it (a non-finite step is then caught by its checks, not lost here)
        const std::size_t later = b > a ? 1 : 0;
        const std::size_t movable = free_a | (bodies.fixed[b] == 0 ? 1 : 0);
        const std::size_t within = distance_squared >= reach * reach ? 0 : 1;
        partners[kept] = b;
        kept += later & movable & within;
      }
    }
    std::sort(partners.begin(), partners.begin() + static_cast<std::ptrdiff_t>(kept));
    for (std::size_t j = 0; j < kept; ++j) out.push_back({a, partners[j]});
  }
}

}  // namespace

void CandidateList::rebuild(const Bodies& bodies, const PeriodicBox& box, CellGrid& grid,
                            double gap, double margin, PieceRunner* pieces) {
  built_gap_ = gap + margin;
  box_ = box;
  anchor_ = bodies.position;
  ++builds_;
  pairs_.clear();
  grid.rebuild(bodies.position, box, 2.0 * bodies.max_radius() + built_gap_);
  const std::size_t sphere_count = bodies.size();
  const std::size_t per_piece = indices_per_piece(sphere_count);
  const std::size_t piece_count = chunks_of(sphere_count, per_piece);
  if (pieces == nullptr || piece_count <= 1) {
    list_pairs_of(bodies, box, grid, built_gap_, 0, static_cast<BodyIndex>(sphere_count), partners_,
                  pairs_);
    return;
  }
  // each piece of spheres lists its pairs on its own, and the pieces' lists are copied into
  // place side by side: the pairs and their order of one piece, whatever the cut. The pieces'
  // lists keep their room from build to build (a second copy of the list, a few pairs a
  // sphere), so that a build allocates only when the list outgrows every earlier one.
  const auto count = static_cast<std::uint32_t>(piece_count);
  if (piece_pairs_.size() < count) piece_pairs_.resize(count);
  if (piece_partners_.size() < count) piece_partners_.resize(count);
  run_pieces(pieces, count, [&](std::uint32_t piece) {
    const IndexRange spheres = chunk_range(sphere_count, per_piece, piece);
    piece_pairs_[piece].clear();
    list_pairs_of(bodies, box, grid, built_gap_, static_cast<BodyIndex>(spheres.first),
                  static_cast<BodyIndex>(spheres.last), piece_partners_[piece],
                  piece_pairs_[piece]);
  });
  std::array<std::size_t, kMaxPieces + 1> start{};
  for (std::uint32_t piece = 0; piece < count; ++piece) {
    start[piece + 1] = start[piece] + piece_pairs_[piece].size();
  }
  pairs_.resize(start[count]);
  run_pieces(pieces, count, [&](std::uint32_t piece) {
    std::copy(piece_pairs_[piece].begin(), piece_pairs_[piece].end(),
              pairs_.begin() + static_cast<std::ptrdiff_t>(start[piece]));
  });
}

}  // namespace cdpowder
