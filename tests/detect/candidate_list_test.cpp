// Tests for src/cdpowder/detect/candidate_list.cpp: a candidate list reused over many steps
// of moving spheres gives every step exactly the contacts of a fresh search, and is rebuilt
// only when a sphere has moved far; a rebuild in pieces gives the list of one piece.
#include "cdpowder/detect/candidate_list.hpp"

#include "cdpowder/core/rng.hpp"
#include "cdpowder/detect/detect_contacts.hpp"
#include "cdpowder/solver/nlgs/tile_threads.hpp"
#include "cdpowder/solver/settings.hpp"
#include "support/backward_runner.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <string>

namespace cdpowder {
namespace {

/// A loose random packing of 200 spheres of radii 0.8–1.2 R in a 12R × 12R cell, with
/// random velocities of up to `speed` R/t0.
World moving_packing(double speed) {
  Rng rng = make_rng(11, RngStream::Deposition);
  World world;
  world.box = PeriodicBox{12.0, 12.0};
  for (int i = 0; i < 200; ++i) {
    const Vec3 centre(12.0 * uniform01(rng), 12.0 * uniform01(rng), 1.0 + 10.0 * uniform01(rng));
    const BodyIndex k = world.bodies.add_sphere(centre, 0.8 + 0.4 * uniform01(rng), 1.0);
    world.bodies.velocity[k] =
        speed * Vec3(uniform01(rng) - 0.5, uniform01(rng) - 0.5, uniform01(rng) - 0.5);
  }
  return world;
}

/// Free flight for one step: r += Δt v.
void drift(World& world, double dt) {
  for (std::size_t i = 0; i < world.bodies.size(); ++i) {
    world.bodies.position[i] += dt * world.bodies.velocity[i];
  }
}

void expect_same_pairs(const Contacts& reused, const Contacts& fresh, const std::string& where) {
  ASSERT_EQ(reused.pairs.size(), fresh.pairs.size()) << where;
  for (std::size_t k = 0; k < fresh.pairs.size(); ++k) {
    const PairProblem& x = reused.pairs[k];
    const PairProblem& y = fresh.pairs[k];
    ASSERT_EQ(x.a, y.a) << where;
    ASSERT_EQ(x.b, y.b) << where;
    // bit for bit: the same arithmetic on the same positions
    EXPECT_EQ(x.gap, y.gap) << where;
    EXPECT_EQ(x.normal, y.normal) << where;
    EXPECT_EQ(x.lever_a, y.lever_a) << where;
  }
}

// 300 steps of free flight across the periodic boundaries, Δt = 0.01: with the list reused
// every step's pairs equal a fresh search's, and the list is rebuilt a few times, not at
// every step.
TEST(CandidateList, AReusedListGivesEveryStepTheContactsOfAFreshSearch) {
  World world = moving_packing(2.0);
  StepSettings settings;
  settings.solver.verlet_margin = 0.1;
  CellGrid grid;
  CellGrid fresh_grid;
  CandidateList list;
  Contacts reused;
  Contacts fresh;
  for (int step = 0; step < 300; ++step) {
    detect_contacts(world, settings.detection(), grid, reused, &list);
    // a list of its own, built now
    detect_contacts(world, settings.detection(), fresh_grid, fresh);
    expect_same_pairs(reused, fresh, "step " + std::to_string(step));
    ASSERT_FALSE(HasFatalFailure());
    drift(world, settings.solver.dt);
  }
  // up to 2·√3/2 R/t0 × 0.01 t0 ≈ 0.017 R a step and a slack of 0.05 R: a rebuild every few
  // steps, far fewer than 300
  EXPECT_GT(list.builds(), 1);
  EXPECT_LT(list.builds(), 150);
}

// Margin 0 rebuilds at every step in which anything moved: the behaviour without reuse.
TEST(CandidateList, MarginZeroRebuildsWheneverASphereMoved) {
  World world = moving_packing(0.5);
  StepSettings settings;
  settings.solver.verlet_margin = 0.0;
  CellGrid grid;
  CandidateList list;
  Contacts contacts;
  for (int step = 0; step < 10; ++step) {
    detect_contacts(world, settings.detection(), grid, contacts, &list);
    drift(world, settings.solver.dt);
  }
  EXPECT_EQ(list.builds(), 10);
}

// A list does not cover a step whose candidate gap grew beyond the built gap, nor another
// cell or sphere count.
TEST(CandidateList, CoversOnlyWhatItWasBuiltFor) {
  World world = moving_packing(0.0);
  CellGrid grid;
  CandidateList list;
  EXPECT_FALSE(list.covers(world.bodies, world.box, 0.05));  // never built
  list.rebuild(world.bodies, world.box, grid, 0.05, 0.1);
  EXPECT_TRUE(list.covers(world.bodies, world.box, 0.05));
  EXPECT_TRUE(list.covers(world.bodies, world.box, 0.15 * (1.0 - 1e-6)));
  EXPECT_FALSE(list.covers(world.bodies, world.box, 0.16));
  EXPECT_FALSE(list.covers(world.bodies, PeriodicBox{12.0, 13.0}, 0.05));
  world.bodies.position[7].x() += 0.049;  // half the slack of 0.1 is 0.05
  EXPECT_TRUE(list.covers(world.bodies, world.box, 0.05));
  world.bodies.position[7].x() += 0.002;
  EXPECT_FALSE(list.covers(world.bodies, world.box, 0.05));
  world.bodies.add_sphere(Vec3(1.0, 1.0, 1.0), 1.0, 1.0);
  EXPECT_FALSE(list.covers(world.bodies, world.box, 0.0));
}

// The list holds exactly the pairs a brute-force search finds (a < b, not both fixed, centre
// distance below R_a + R_b + gap + margin through the periodic boundaries), in (a, b) order:
// in grids of one, two, three (both wrapped neighbours in one row) and many cells along x and
// y, square and not, with every fifth sphere fixed.
TEST(CandidateList, ListsExactlyThePairsABruteForceSearchFinds) {
  struct Box {
    double lx;
    double ly;
    int cells_x;
    int cells_y;
  };

  // cells of edge 2 R_max + gap + margin ≈ 2.45 R
  for (const Box& shape : {Box{3.0, 3.0, 1, 1}, Box{5.0, 5.0, 2, 2}, Box{8.0, 8.0, 3, 3},
                           Box{3.0, 12.0, 1, 4}, Box{12.0, 5.0, 4, 2}, Box{30.0, 30.0, 12, 12}}) {
    SCOPED_TRACE(::testing::Message() << "box " << shape.lx << " × " << shape.ly);
    Rng rng = make_rng(17, RngStream::Deposition);
    Bodies bodies;
    const PeriodicBox box{shape.lx, shape.ly};
    const int n = static_cast<int>(shape.lx * shape.ly);
    for (int i = 0; i < n; ++i) {
      const Vec3 centre(shape.lx * uniform01(rng), shape.ly * uniform01(rng), 8.0 * uniform01(rng));
      bodies.add_sphere(centre, 0.6 + 0.5 * uniform01(rng), 1.0, i % 5 == 0);
    }
    const double gap = 0.05;
    const double margin = 0.2;
    std::vector<CandidateList::Pair> expected;
    for (BodyIndex a = 0; a < bodies.size(); ++a) {
      for (BodyIndex b = a + 1; b < bodies.size(); ++b) {
        if (bodies.fixed[a] != 0 && bodies.fixed[b] != 0) continue;
        const double reach = bodies.radius[a] + bodies.radius[b] + (gap + margin);
        if (box.minimum_image(bodies.position[b] - bodies.position[a]).squaredNorm() <
            reach * reach) {
          expected.push_back({a, b});
        }
      }
    }
    CellGrid grid;
    CandidateList list;
    list.rebuild(bodies, box, grid, gap, margin);
    ASSERT_EQ(grid.cells_x(), shape.cells_x);  // the shapes the test means to cover
    ASSERT_EQ(grid.cells_y(), shape.cells_y);
    ASSERT_EQ(list.pairs().size(), expected.size());
    for (std::size_t k = 0; k < expected.size(); ++k) {
      EXPECT_EQ(list.pairs()[k].a, expected[k].a) << "pair " << k;
      EXPECT_EQ(list.pairs()[k].b, expected[k].b) << "pair " << k;
    }
    EXPECT_GT(expected.size(), 0U);
  }
}

// 10 000 spheres (three pieces of 4 096 spheres): a rebuild in pieces, run backwards or on two
// threads, lists the pairs of a rebuild in one piece, in the same order; again after the
// spheres moved, with the pieces' lists of the first rebuild still held.
TEST(CandidateList, ARebuildInPiecesListsThePairsOfOnePieceInTheirOrder) {
  Rng rng = make_rng(23, RngStream::Deposition);
  Bodies bodies;
  const PeriodicBox box{40.0, 40.0};
  for (int i = 0; i < 10000; ++i) {
    const Vec3 centre(40.0 * uniform01(rng), 40.0 * uniform01(rng), 12.0 * uniform01(rng));
    bodies.add_sphere(centre, 0.6 + 0.5 * uniform01(rng), 1.0, i % 7 == 0);
  }
  ASSERT_GT(chunks_of(bodies.size(), indices_per_piece(bodies.size())), 2U);
  BackwardRunner backward;
  TileThreads two(2);
  std::array<CandidateList, 2> pieced;  // kept from the first build to the second
  for (int build = 0; build < 2; ++build) {
    CellGrid grid;
    CandidateList whole;
    whole.rebuild(bodies, box, grid, 0.05, 0.2);
    for (PieceRunner* runner :
         {static_cast<PieceRunner*>(&backward), static_cast<PieceRunner*>(&two)}) {
      CandidateList& list = pieced[runner == &two ? 1 : 0];
      list.rebuild(bodies, box, grid, 0.05, 0.2, runner);
      ASSERT_EQ(list.pairs().size(), whole.pairs().size()) << "build " << build;
      for (std::size_t k = 0; k < whole.pairs().size(); ++k) {
        ASSERT_EQ(list.pairs()[k].a, whole.pairs()[k].a) << "pair " << k;
        ASSERT_EQ(list.pairs()[k].b, whole.pairs()[k].b) << "pair " << k;
      }
    }
    EXPECT_GT(whole.pairs().size(), 10000U);
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      bodies.position[i] += Vec3(0.3 * uniform01(rng), 0.3 * uniform01(rng), 0.0);
      box.wrap(bodies.position[i]);
    }
  }
}

}  // namespace
}  // namespace cdpowder
