// Tests for src/cdpowder/detect/cell_grid.cpp: the grid finds exactly the pairs a
// brute-force minimum-image search finds, each once, also in boxes of one or two cells,
// across the periodic boundaries. detect_contacts_test.cpp tests the production path.
#include "cdpowder/detect/cell_grid.hpp"

#include "cdpowder/core/rng.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <map>
#include <set>
#include <utility>

namespace cdpowder {
namespace {

/// visit(j) for every sphere j of the runs near_runs gives for sphere i (i itself included).
template <typename Visitor>
void for_each_near(const CellGrid& grid, BodyIndex i, Visitor&& visit) {
  std::array<CellGrid::Run, CellGrid::kMaxRuns> runs{};
  const int count = grid.near_runs(i, runs);
  for (int r = 0; r < count; ++r) {
    for (std::uint32_t t = runs[r].first; t < runs[r].last; ++t) visit(grid.sorted()[t]);
  }
}

std::set<std::pair<BodyIndex, BodyIndex>> brute_force(const std::vector<Vec3>& x,
                                                      const PeriodicBox& box, double reach) {
  std::set<std::pair<BodyIndex, BodyIndex>> pairs;
  for (BodyIndex i = 0; i < x.size(); ++i) {
    for (BodyIndex j = i + 1; j < x.size(); ++j) {
      if (box.minimum_image(x[j] - x[i]).norm() < reach) pairs.insert({i, j});
    }
  }
  return pairs;
}

/// The grid of `x` finds exactly the pairs within `reach` a brute-force search finds, each
/// once (as the candidate list takes them: the neighbours j > i of every sphere i); returns
/// the grid.
CellGrid check_grid(const std::vector<Vec3>& x, const PeriodicBox& box, double reach) {
  const double lx = box.lx;
  CellGrid grid;
  grid.rebuild(x, box, reach);
  std::set<std::pair<BodyIndex, BodyIndex>> found;
  std::map<std::pair<BodyIndex, BodyIndex>, int> visits;  // every visited pair, near or not
  for (BodyIndex i = 0; i < x.size(); ++i) {
    for_each_near(grid, i, [&](BodyIndex j) {
      if (j <= i) return;
      ++visits[{i, j}];
      if (box.minimum_image(x[j] - x[i]).norm() < reach) found.insert({i, j});
    });
  }
  const auto expected = brute_force(x, box, reach);
  EXPECT_EQ(found, expected) << "lx=" << lx << " cells " << grid.cells_x();
  EXPECT_GT(expected.size(), 0U);
  // no pair is visited twice
  for (const auto& [pair, count] : visits) {
    EXPECT_EQ(count, 1) << "pair (" << pair.first << ", " << pair.second << "), cells "
                        << grid.cells_x() << "×" << grid.cells_y() << "×" << grid.cells_z();
  }
  // near_runs, which the candidate list walks: every neighbour of i once, i itself included
  for (BodyIndex i = 0; i < x.size(); ++i) {
    std::map<BodyIndex, int> near;
    for_each_near(grid, i, [&](BodyIndex j) { ++near[j]; });
    EXPECT_EQ(near.count(i), 1U);
    for (const auto& [j, count] : near) EXPECT_EQ(count, 1) << "sphere " << i << ", near " << j;
    for (const auto& [a, b] : expected) {
      if (a == i) {
        EXPECT_EQ(near.count(b), 1U) << "sphere " << i << " misses " << b;
      }
    }
  }
  return grid;
}

void check_against_brute_force(double lx, double ly, double height, int n, double reach) {
  Rng rng = make_rng(3, RngStream::Deposition);
  std::vector<Vec3> x;
  x.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    x.emplace_back(lx * uniform01(rng), ly * uniform01(rng), height * uniform01(rng));
  }
  check_grid(x, PeriodicBox{lx, ly}, reach);
}

// Memory O(N): 200 spheres in a cell 10^9 R wide once asked for ~10^10 cells and threw
// std::bad_alloc. The cells grow instead, and still find every pair.
TEST(CellGrid, AVastBoxGetsLargerCellsNotMoreMemory) {
  // 100 pairs 1.5 R apart, scattered over a cell 10^9 R wide
  const PeriodicBox box{1e9, 30.0};
  Rng rng = make_rng(5, RngStream::Deposition);
  std::vector<Vec3> x;
  for (int i = 0; i < 100; ++i) {
    const Vec3 p(1e9 * uniform01(rng), 30.0 * uniform01(rng), 0.0);
    Vec3 partner = p + Vec3(1.5, 0.0, 0.0);
    box.wrap(partner);
    x.push_back(p);
    x.push_back(partner);
  }
  const CellGrid grid = check_grid(x, box, 2.5);  // the grown cells find every pair, once
  const double cells = static_cast<double>(grid.cells_x()) * grid.cells_y() * grid.cells_z();
  EXPECT_LE(cells, 64.0 * 200);  // max(4096, 64 per sphere) for 200 spheres
  EXPECT_GT(grid.cells_x(), 1);
}

TEST(CellGrid, FindsAllPairsOfARandomGas) {
  check_against_brute_force(25.0, 20.0, 30.0, 600, 2.1);
}

TEST(CellGrid, FindsAllPairsWithOneCellAlongX) {
  check_against_brute_force(4.5, 12.0, 10.0, 80, 2.2);
}

TEST(CellGrid, FindsAllPairsWithTwoCellsAlongEachAxis) {
  check_against_brute_force(4.5, 4.5, 10.0, 60, 2.2);
}

TEST(CellGrid, VisitsEachPairOnceWhenCellsWrap) {
  const PeriodicBox box{4.5, 4.5};
  const std::vector<Vec3> x = {Vec3(0.1, 0.1, 0.0),
                               Vec3(4.4, 4.4, 0.0)};  // touching through the corner
  CellGrid grid;
  grid.rebuild(x, box, 2.2);
  int visits = 0;  // of the pair, from either sphere
  for (BodyIndex i = 0; i < x.size(); ++i) {
    for_each_near(grid, i, [&](BodyIndex j) { visits += j != i ? 1 : 0; });
  }
  EXPECT_EQ(visits, 2);  // 0 sees 1 and 1 sees 0, each once through the wrapped corner
}

}  // namespace
}  // namespace cdpowder
