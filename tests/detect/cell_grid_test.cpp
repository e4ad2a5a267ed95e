// Tests for src/cdpowder/detect/cell_grid.cpp and detect_contacts.cpp: the grid finds
// exactly the pairs a brute-force minimum-image search finds, also in boxes of one or
// two cells, across the periodic boundaries.
#include "cdpowder/detect/cell_grid.hpp"

#include "cdpowder/core/rng.hpp"

#include <gtest/gtest.h>

#include <set>
#include <utility>

namespace cdpowder {
namespace {

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

void check_against_brute_force(double lx, double ly, double height, int n, double reach) {
  const PeriodicBox box{lx, ly};
  Rng rng = make_rng(3, RngStream::Deposition);
  std::vector<Vec3> x;
  for (int i = 0; i < n; ++i) {
    x.emplace_back(lx * uniform01(rng), ly * uniform01(rng), height * uniform01(rng));
  }
  CellGrid grid;
  grid.rebuild(x, box, reach);
  std::set<std::pair<BodyIndex, BodyIndex>> found;
  int visits = 0;
  grid.for_each_near_pair([&](BodyIndex i, BodyIndex j) {
    ++visits;
    if (box.minimum_image(x[j] - x[i]).norm() < reach) found.insert({i, j});
  });
  const auto expected = brute_force(x, box, reach);
  EXPECT_EQ(found, expected) << "lx=" << lx << " cells " << grid.cells_x();
  EXPECT_GT(expected.size(), 0U);
  // no pair is visited twice
  int distinct = 0;
  grid.for_each_near_pair([&](BodyIndex, BodyIndex) { ++distinct; });
  EXPECT_EQ(visits, distinct);
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
  int visits = 0;
  grid.for_each_near_pair([&](BodyIndex i, BodyIndex j) {
    ++visits;
    EXPECT_LT(i, j);
  });
  EXPECT_EQ(visits, 1);
}

}  // namespace
}  // namespace cdpowder
