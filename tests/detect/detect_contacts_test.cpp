// Tests for src/cdpowder/detect/detect_contacts.cpp, the production broad phase
// (CellGrid::near_runs): on random packings of mixed radii, across the periodic x/y
// boundaries and in boxes of one, two or three cells per axis, the candidates are exactly
// those of a brute-force O(N²) minimum-image search with the same cutoff, each pair once,
// in the key order the warm-start merge of ActionCache relies on (physics.md §4.3, §7.4);
// the pairs' geometry, formed in lanes, has the bits of the scalar formulas on every
// instruction set (also for coincident centres and at exactly half a cell apart); and
// PeriodicBox::wrap, whose shortcut for positions in the cell keeps the formula's bits.
#include "cdpowder/detect/detect_contacts.hpp"

#include "cdpowder/contact/action_cache.hpp"
#include "cdpowder/core/lanes.hpp"
#include "cdpowder/core/rng.hpp"
#include "cdpowder/solver/nlgs/tile_threads.hpp"
#include "cdpowder/solver/settings.hpp"
#include "support/backward_runner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <vector>

namespace cdpowder {
namespace {

/// The brute force repeats detect_contacts' formulas, so the two differ by round-off in the
/// last bits at most (a different evaluation order of the same sum) [R].
constexpr double kRoundOff = 1e-12;

struct Packing {
  double lx = 10.0;      ///< L_x [R]
  double ly = 10.0;      ///< L_y [R]
  double height = 10.0;  ///< spheres' centres in [0, height), the piston at height [R]
  int spheres = 100;
  double min_radius = 0.5;  ///< radii uniform in [min_radius, max_radius] [R]
  double max_radius = 1.0;
  double max_speed = 1.0;  ///< velocities uniform in a cube of this half-width [R/t0]
  std::uint64_t seed = 1;
};

/// Random spheres, overlaps allowed (the broad phase must not care). Every fifth sphere sits
/// within 0.05 R of a periodic x or y boundary, on either side, some centres outside the box
/// (detect_contacts wraps them); every seventh is fixed.
World make_world(const Packing& p) {
  Rng rng = make_rng(p.seed, RngStream::Deposition);
  World world;
  world.box = PeriodicBox{p.lx, p.ly};
  world.walls.bottom.enabled = true;
  world.walls.piston.enabled = true;
  world.walls.piston.height = p.height;
  world.walls.piston.velocity = -0.1;
  for (int i = 0; i < p.spheres; ++i) {
    Vec3 centre(p.lx * uniform01(rng), p.ly * uniform01(rng), p.height * uniform01(rng));
    if (i % 5 == 0) {
      const double offset = 0.1 * uniform01(rng) - 0.05;  // in [−0.05, 0.05) R
      if (i % 10 == 0) {
        centre.x() = offset;
      } else {
        centre.y() = p.ly + offset;
      }
    }
    const double radius = p.min_radius + (p.max_radius - p.min_radius) * uniform01(rng);
    const BodyIndex b = world.bodies.add_sphere(centre, radius, 1.0, i % 7 == 3);
    if (world.bodies.fixed[b] == 0) {
      world.bodies.velocity[b] =
          p.max_speed *
          Vec3(2.0 * uniform01(rng) - 1.0, 2.0 * uniform01(rng) - 1.0, 2.0 * uniform01(rng) - 1.0);
      world.bodies.angular_velocity[b] = Vec3(0.0, 0.0, p.max_speed * uniform01(rng));
    }
  }
  return world;
}

/// Calls visit(a, b, d) for every pair a < b, in (a, b) order, except pairs of two fixed
/// spheres, d the minimum image of x_b − x_a.
template <typename Visit>
void for_each_pair(const World& world, const Visit& visit) {
  const Bodies& bodies = world.bodies;
  const auto n = static_cast<BodyIndex>(bodies.size());
  for (BodyIndex a = 0; a < n; ++a) {
    for (BodyIndex b = a + 1; b < n; ++b) {
      if (bodies.fixed[a] != 0 && bodies.fixed[b] != 0) continue;
      visit(a, b, world.box.minimum_image(bodies.position[b] - bodies.position[a]));
    }
  }
}

/// Every pair a < b whose minimum-image centre distance is below R_a + R_b + cutoff, except
/// pairs of two fixed spheres, keyed by pair_key.
std::map<std::uint64_t, PairProblem> brute_force_pairs(const World& world, double cutoff) {
  const Bodies& bodies = world.bodies;
  std::map<std::uint64_t, PairProblem> pairs;
  for_each_pair(world, [&](BodyIndex a, BodyIndex b, const Vec3& d) {
    const double reach = bodies.radius[a] + bodies.radius[b] + cutoff;
    if (d.norm() >= reach) return;
    PairProblem p;
    p.a = a;
    p.b = b;
    p.normal = d.normalized();
    p.gap = d.norm() - bodies.radius[a] - bodies.radius[b];
    pairs[pair_key(a, b)] = p;
  });
  return pairs;
}

/// Bottom-wall candidates of free spheres, then piston candidates of all spheres, each in
/// sphere order: (wall kind, sphere) ascending.
std::vector<WallProblem> brute_force_walls(const World& world, double cutoff) {
  const Bodies& bodies = world.bodies;
  std::vector<WallProblem> walls;
  for (BodyIndex i = 0; i < bodies.size(); ++i) {
    const double gap = bodies.position[i].z() - bodies.radius[i];
    if (gap < cutoff && bodies.fixed[i] == 0) {
      walls.push_back({.sphere = i, .wall = WallKind::Bottom, .gap = gap});
    }
  }
  for (BodyIndex i = 0; i < bodies.size(); ++i) {
    const double gap = world.walls.piston.height - bodies.position[i].z() - bodies.radius[i];
    if (gap < cutoff) walls.push_back({.sphere = i, .wall = WallKind::Piston, .gap = gap});
  }
  return walls;
}

struct Checked {
  CellGrid grid;  ///< so callers can check the cell counts they aimed at
  std::size_t pairs = 0;
  std::size_t walls = 0;
};

/// Runs detect_contacts on the packing and checks it against the brute force.
Checked check_against_brute_force(const Packing& packing) {
  World world = make_world(packing);
  // no candidate-list margin: the cells are sized by the candidate gap alone, so the tests
  // below control how many cells an axis has (the margin is tested in candidate_list_test)
  StepSettings settings;
  settings.solver.verlet_margin = 0.0;
  CellGrid grid;
  Contacts contacts;
  detect_contacts(world, settings.detection(), grid, contacts);
  // detect_contacts wraps the positions and changes nothing the cutoff depends on
  const double cutoff = candidate_gap(world, settings.detection());
  const std::string where = "packing seed " + std::to_string(packing.seed) + ", cells " +
                            std::to_string(grid.cells_x()) + "×" + std::to_string(grid.cells_y()) +
                            "×" + std::to_string(grid.cells_z());

  // pairs: strictly ascending keys (so each pair once, a < b), the brute force's set
  for (std::size_t k = 0; k < contacts.pairs.size(); ++k) {
    const PairProblem& p = contacts.pairs[k];
    EXPECT_LT(p.a, p.b) << where;
    if (k > 0) {
      const PairProblem& q = contacts.pairs[k - 1];
      EXPECT_LT(pair_key(q.a, q.b), pair_key(p.a, p.b)) << where << ", pair " << k;
    }
  }
  const auto expected = brute_force_pairs(world, cutoff);
  EXPECT_EQ(contacts.pairs.size(), expected.size()) << where;
  std::size_t matched = 0;
  for (const PairProblem& p : contacts.pairs) {
    const auto it = expected.find(pair_key(p.a, p.b));
    if (it == expected.end()) {
      ADD_FAILURE() << where << ": pair (" << p.a << ", " << p.b << ") is not a candidate";
      continue;
    }
    ++matched;
    const PairProblem& e = it->second;
    EXPECT_NEAR(p.gap, e.gap, kRoundOff) << where;
    EXPECT_NEAR((p.normal - e.normal).norm(), 0.0, kRoundOff) << where;
    // levers to the middle of the gap (physics.md §4.2)
    EXPECT_EQ(p.lever_a, world.bodies.radius[p.a] + 0.5 * p.gap);
    EXPECT_EQ(p.lever_b, world.bodies.radius[p.b] + 0.5 * p.gap);
    EXPECT_EQ(p.r_eff, effective_radius(world.bodies.radius[p.a], world.bodies.radius[p.b]));
  }
  EXPECT_EQ(matched, expected.size()) << where;

  // walls: the same list in the same order, (wall kind, sphere) strictly ascending
  const auto expected_walls = brute_force_walls(world, cutoff);
  EXPECT_EQ(contacts.walls.size(), expected_walls.size()) << where;
  for (std::size_t k = 0; k < std::min(contacts.walls.size(), expected_walls.size()); ++k) {
    const WallProblem& w = contacts.walls[k];
    const WallProblem& e = expected_walls[k];
    EXPECT_EQ(wall_key(w.wall, w.sphere), wall_key(e.wall, e.sphere)) << where << ", wall " << k;
    EXPECT_EQ(w.gap, e.gap) << where;
    EXPECT_EQ(w.normal, Vec3(0.0, 0.0, w.wall == WallKind::Bottom ? 1.0 : -1.0)) << where;
    if (k > 0) {
      const WallProblem& v = contacts.walls[k - 1];
      EXPECT_LT(wall_key(v.wall, v.sphere), wall_key(w.wall, w.sphere)) << where;
    }
  }
  return {grid, expected.size(), expected_walls.size()};
}

TEST(DetectContacts, MatchesBruteForceOnRandomPackingsOfSeveralSizes) {
  for (const int n : {2, 10, 60, 300, 1200}) {
    std::size_t pairs = 0;
    std::size_t walls = 0;
    for (const std::uint64_t seed : {1U, 2U, 3U}) {
      // a solid fraction of ≈ 0.15 whatever n
      const double side = std::cbrt(12.0 * n);
      const Checked checked = check_against_brute_force({.lx = side,
                                                         .ly = 0.8 * side,
                                                         .height = side,
                                                         .spheres = n,
                                                         .min_radius = 0.3,
                                                         .max_radius = 1.0,
                                                         .seed = seed});
      pairs += checked.pairs;
      walls += checked.walls;
    }
    if (n >= 60) {  // dense enough to test something
      EXPECT_GT(pairs, 0U) << n << " spheres";
      EXPECT_GT(walls, 0U) << n << " spheres";
    }
  }
}

TEST(DetectContacts, MatchesBruteForceWithOneTwoOrThreeCellsPerAxis) {
  // cell edge = 2 max R + cutoff ≈ 2.06 R at these speeds, so L = 2.5, 4.5, 6.5 give
  // 1, 2 and 3 cells: neighbour offsets ±1 wrap onto the same cell below three
  for (const int cells_x : {1, 2, 3}) {
    for (const int cells_y : {1, 2, 3}) {
      for (const std::uint64_t seed : {4U, 5U}) {
        const Packing packing{.lx = 0.5 + 2.0 * cells_x,
                              .ly = 0.5 + 2.0 * cells_y,
                              .height = 8.0,
                              .spheres = 12 * cells_x * cells_y,
                              .min_radius = 0.5,
                              .max_radius = 1.0,
                              .max_speed = 0.5,
                              .seed = seed};
        const Checked checked = check_against_brute_force(packing);
        EXPECT_EQ(checked.grid.cells_x(), cells_x);
        EXPECT_EQ(checked.grid.cells_y(), cells_y);
        EXPECT_GT(checked.pairs, 0U);
      }
    }
  }
}

TEST(DetectContacts, FastSpheresWidenTheCutoffAndTheCells) {
  // 2 v_max Δt = 2 × 20 × 0.01 = 0.4 R dominates d_coh: a larger cutoff, larger cells
  const Checked checked = check_against_brute_force({.lx = 12.0,
                                                     .ly = 9.0,
                                                     .height = 10.0,
                                                     .spheres = 200,
                                                     .min_radius = 0.4,
                                                     .max_radius = 1.2,
                                                     .max_speed = 20.0,
                                                     .seed = 6});
  EXPECT_GT(checked.pairs, 0U);
}

TEST(DetectContacts, FindsPairsAcrossEveryPeriodicBoundary) {
  // pairs of unit spheres touching through the x boundary, the y boundary and the corner,
  // each pair at its own height so that only partners meet
  World world;
  world.box = PeriodicBox{10.0, 10.0};
  const double corner = 10.0 - std::sqrt(2.0) + 0.5;
  for (const Vec3& centre : {Vec3(0.5, 5.0, 2.0), Vec3(8.5, 5.0, 2.0),  // across x: d = −2 e_x
                             Vec3(5.0, 0.5, 6.0), Vec3(5.0, 8.5, 6.0),  // across y: d = −2 e_y
                             Vec3(0.5, 0.5, 10.0), Vec3(corner, corner, 10.0)}) {
    world.bodies.add_sphere(centre, 1.0, 1.0);
  }
  const StepSettings settings;
  CellGrid grid;
  Contacts contacts;
  detect_contacts(world, settings.detection(), grid, contacts);
  std::vector<std::uint64_t> keys;
  keys.reserve(contacts.pairs.size());
  for (const PairProblem& p : contacts.pairs) keys.push_back(pair_key(p.a, p.b));
  ASSERT_EQ(keys, (std::vector<std::uint64_t>{pair_key(0, 1), pair_key(2, 3), pair_key(4, 5)}));
  for (const PairProblem& p : contacts.pairs) EXPECT_NEAR(p.gap, 0.0, kRoundOff);
  const std::array<Vec3, 3> expected_normals = {Vec3(-1.0, 0.0, 0.0), Vec3(0.0, -1.0, 0.0),
                                                Vec3(-1.0, -1.0, 0.0).normalized()};
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR((contacts.pairs[k].normal - expected_normals[k]).norm(), 0.0, kRoundOff);
  }
}

/// Whether two pair or wall records hold the same bits in every field (neither has padding).
template <typename Problem>
bool same_bits(const Problem& x, const Problem& y) {
  return std::memcmp(&x, &y, sizeof(Problem)) == 0;
}

/// The geometry detect_contacts gives a pair, one scalar expression at a time (find_pairs in
/// detect_contacts.cpp): the reference the lanes must match bit for bit. Pairs in (a, b) order,
/// none of two fixed spheres.
std::vector<PairProblem> scalar_pairs(const World& world, double cutoff) {
  const Bodies& bodies = world.bodies;
  std::vector<PairProblem> pairs;
  for_each_pair(world, [&](BodyIndex a, BodyIndex b, const Vec3& d) {
    const double reach = bodies.radius[a] + bodies.radius[b] + cutoff;
    const double distance_squared = d.squaredNorm();
    if (distance_squared >= reach * reach) return;
    const double distance = std::sqrt(distance_squared);
    PairProblem p;
    p.a = a;
    p.b = b;
    p.normal = distance > 0.0 ? Vec3(d / distance) : Vec3::UnitZ();
    p.gap = distance - bodies.radius[a] - bodies.radius[b];
    p.lever_a = bodies.radius[a] + 0.5 * p.gap;
    p.lever_b = bodies.radius[b] + 0.5 * p.gap;
    p.r_eff = effective_radius(bodies.radius[a], bodies.radius[b]);
    pairs.push_back(p);
  });
  return pairs;
}

TEST(DetectContacts, PairsFormedInLanesHaveTheScalarFormulasBitsOnEveryInstructionSet) {
  for (const lanes::Isa isa : {lanes::Isa::Sse2, lanes::Isa::Avx2}) {
    if (!lanes::allow_isa(isa)) continue;  // no AVX2 here
    // lists of every length modulo the lanes (1 … 40 pairs and more), so that the last block
    // of lanes is full, partial or absent; pairs across the boundaries (make_world)
    for (const int n : {2, 3, 5, 9, 17, 40, 150}) {
      for (const std::uint64_t seed : {1U, 2U}) {
        SCOPED_TRACE(::testing::Message()
                     << n << " spheres, seed " << seed << ", avx2 " << (isa == lanes::Isa::Avx2));
        const double side = std::cbrt(6.0 * n);
        World world = make_world({.lx = side,
                                  .ly = side,
                                  .height = side,
                                  .spheres = n,
                                  .min_radius = 0.3,
                                  .max_radius = 1.0,
                                  .seed = seed});
        if (n == 9) {
          // coincident centres: the normal e_z
          world.bodies.position[4] = world.bodies.position[3];
        }
        StepSettings settings;
        CellGrid grid;
        Contacts contacts;
        detect_contacts(world, settings.detection(), grid, contacts);
        const auto expected = scalar_pairs(world, candidate_gap(world, settings.detection()));
        ASSERT_EQ(contacts.pairs.size(), expected.size());
        for (std::size_t k = 0; k < expected.size(); ++k) {
          EXPECT_TRUE(same_bits(contacts.pairs[k], expected[k]))
              << "pair " << k << " (" << expected[k].a << ", " << expected[k].b << ")";
        }
      }
    }
  }
  lanes::allow_isa(lanes::Isa::Avx512);
}

TEST(DetectContacts, PairsHalfACellApartTakeTheirOwnImageInLanes) {
  // a 4 R cell and unit spheres: the only candidates are four touching pairs, two of them
  // exactly L/2 = 2 R apart along x or y (the minimum image's boundary case, |d| ≤ L/2), all
  // four in one block of lanes on AVX2 and in two on SSE2
  const std::array<Vec3, 5> centres = {Vec3(1.0, 1.0, 1.0), Vec3(3.0, 1.0, 1.0),
                                       Vec3(1.0, 1.0, 3.0), Vec3(1.0, 3.0, 3.0),
                                       Vec3(1.0, 1.0, 5.0)};
  for (const lanes::Isa isa : {lanes::Isa::Sse2, lanes::Isa::Avx2}) {
    if (!lanes::allow_isa(isa)) continue;  // no AVX2 here
    SCOPED_TRACE(::testing::Message() << "avx2 " << (isa == lanes::Isa::Avx2));
    World world;
    world.box = PeriodicBox{4.0, 4.0};
    for (const Vec3& centre : centres) world.bodies.add_sphere(centre, 1.0, 1.0);
    const StepSettings settings;
    CellGrid grid;
    Contacts contacts;
    detect_contacts(world, settings.detection(), grid, contacts);
    const auto expected = scalar_pairs(world, candidate_gap(world, settings.detection()));
    std::vector<std::uint64_t> keys;
    keys.reserve(expected.size());
    for (const PairProblem& p : expected) keys.push_back(pair_key(p.a, p.b));
    ASSERT_EQ(keys, (std::vector<std::uint64_t>{pair_key(0, 1), pair_key(0, 2), pair_key(2, 3),
                                                pair_key(2, 4)}));
    ASSERT_EQ(contacts.pairs.size(), expected.size());
    for (std::size_t k = 0; k < expected.size(); ++k) {
      EXPECT_TRUE(same_bits(contacts.pairs[k], expected[k])) << "pair " << k;
    }
    // the two at L/2 keep the sign of their separation: n = +e_x, +e_y
    EXPECT_EQ(contacts.pairs[0].normal, Vec3(1.0, 0.0, 0.0));
    EXPECT_EQ(contacts.pairs[2].normal, Vec3(0.0, 1.0, 0.0));
  }
  lanes::allow_isa(lanes::Isa::Avx512);
}

/// PeriodicBox::wrap without its shortcut for positions already in the cell.
double wrapped_by_formula(double x, double length) {
  x -= length * std::floor(x / length);
  return x >= length || x < 0.0 ? 0.0 : x;
}

// 10 000 spheres (a candidate list of more than three chunks, so more than three pieces):
// detection in pieces, on two threads and backwards, gives the contacts of one piece, bit for
// bit, over steps of free flight that reuse the list and rebuild it, also where only the last
// pieces of the spheres moved past the list's cover.
TEST(DetectContacts, InPiecesOfALongListGivesTheContactsOfOnePiece) {
  Packing p;
  p.lx = p.ly = 40.0;
  p.height = 12.0;
  p.spheres = 10000;
  p.max_speed = 0.5;
  World whole = make_world(p);
  World by_threads = whole;
  World backwards = whole;
  StepSettings settings;
  settings.solver.verlet_margin = 0.1;
  const DetectionSettings detection = settings.detection();
  TileThreads two(2);
  BackwardRunner backward;
  std::array<CellGrid, 3> grids;
  std::array<CandidateList, 3> lists;
  std::array<Contacts, 3> contacts;
  std::array<DetectionScratch, 2> scratch;
  for (int step = 0; step < 12; ++step) {
    detect_contacts(whole, detection, grids[0], contacts[0], &lists[0]);
    detect_contacts(by_threads, detection, grids[1], contacts[1], &lists[1], &two, &scratch[0]);
    detect_contacts(backwards, detection, grids[2], contacts[2], &lists[2], &backward, &scratch[1]);
    ASSERT_GT(lists[0].pairs().size(), 3 * kChunkIndices);
    for (std::size_t k = 1; k < 3; ++k) {
      ASSERT_EQ(contacts[k].pairs.size(), contacts[0].pairs.size()) << "step " << step;
      for (std::size_t c = 0; c < contacts[0].pairs.size(); ++c) {
        ASSERT_TRUE(same_bits(contacts[k].pairs[c], contacts[0].pairs[c])) << "pair " << c;
      }
      ASSERT_EQ(contacts[k].walls.size(), contacts[0].walls.size()) << "step " << step;
      for (std::size_t w = 0; w < contacts[0].walls.size(); ++w) {
        ASSERT_TRUE(same_bits(contacts[k].walls[w], contacts[0].walls[w])) << "wall " << w;
      }
    }
    // free flight of every sphere, or on odd steps of the last fifth alone, farther: then
    // only the last pieces' cover check fails
    for (World* world : {&whole, &by_threads, &backwards}) {
      const std::size_t n = world->bodies.size();
      for (std::size_t i = step % 2 == 1 ? n - n / 5 : 0; i < n; ++i) {
        world->bodies.position[i] += (step % 2 == 1 ? 0.3 : 0.05) * world->bodies.velocity[i];
      }
    }
  }
  EXPECT_GT(lists[1].builds(), 1);
  EXPECT_EQ(lists[1].builds(), lists[0].builds());
  EXPECT_FALSE(contacts[0].walls.empty());
}

TEST(PeriodicBox, WrapGivesTheFormulasBitsWithAndWithoutItsShortcut) {
  // cell lengths just above, at and just below powers of two, and the paper's
  for (const double length :
       {25.0, 16.0, std::nextafter(16.0, 32.0), std::nextafter(16.0, 0.0), 1.0, 3.0, 0.1}) {
    const double below = std::nextafter(length, 0.0);
    for (const double x : {0.0, -0.0, 4.9e-324, below, length, -4.9e-324, -below, -length,
                           0.5 * length, 2.5 * length, -1e-17, std::nextafter(2.0 * length, 0.0)}) {
      PeriodicBox box;
      box.lx = box.ly = length;
      const double expected = wrapped_by_formula(x, length);
      const double inside = 0.5 * length;
      // x and y each with the other coordinate in the cell, so the shortcut sees them alone
      for (const int axis : {0, 1}) {
        Vec3 p(inside, inside, 1.0);
        p[axis] = x;
        box.wrap(p);
        EXPECT_EQ(std::bit_cast<std::uint64_t>(p[axis]), std::bit_cast<std::uint64_t>(expected))
            << "x = " << x << ", L = " << length << ", axis " << axis;
        // and a wrapped position is its own image
        const double once = p[axis];
        box.wrap(p);
        EXPECT_EQ(std::bit_cast<std::uint64_t>(p[axis]), std::bit_cast<std::uint64_t>(once));
      }
    }
  }
}

/// PeriodicBox::minimum_image without its shortcut for separations already their own image.
double minimum_image_by_formula(double d, double length) {
  return d - length * std::nearbyint(d / length);
}

TEST(PeriodicBox, MinimumImageGivesTheFormulasBitsWithAndWithoutItsShortcut) {
  for (const double length :
       {25.0, 16.0, std::nextafter(16.0, 32.0), std::nextafter(16.0, 0.0), 1.0, 3.0, 0.1}) {
    const double half = 0.5 * length;
    std::vector<double> separations = {0.0,
                                       -0.0,
                                       4.9e-324,
                                       -4.9e-324,
                                       1e-17,
                                       -1e-17,
                                       half,
                                       -half,
                                       std::nextafter(half, 0.0),
                                       std::nextafter(half, length),
                                       std::nextafter(-half, 0.0),
                                       std::nextafter(-half, -length),
                                       1.5 * length,
                                       -1.5 * length,
                                       std::nextafter(length, 0.0),
                                       -std::nextafter(length, 0.0),
                                       0.3 * length,
                                       -0.7 * length};
    for (const double d : separations) {
      PeriodicBox box;
      box.lx = box.ly = length;
      const Vec3 image = box.minimum_image(Vec3(d, d, d));
      const double expected = minimum_image_by_formula(d, length);
      for (const int axis : {0, 1}) {
        EXPECT_EQ(std::bit_cast<std::uint64_t>(image[axis]), std::bit_cast<std::uint64_t>(expected))
            << "d = " << d << ", L = " << length << ", axis " << axis;
      }
      EXPECT_EQ(std::bit_cast<std::uint64_t>(image.z()), std::bit_cast<std::uint64_t>(d));
    }
  }
}

}  // namespace
}  // namespace cdpowder
