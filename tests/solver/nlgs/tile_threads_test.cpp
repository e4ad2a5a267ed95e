// Tiles on threads (tiles.hpp, tile_solve.hpp, tile_threads.hpp): the grid, the parts of a
// pass, the pieces a team runs, and the bits of one thread against two, three and four: a
// solve, steps and a paper-size step.
#include "cdpowder/solver/nlgs/tile_threads.hpp"

#include "cdpowder/contact/velocity_change.hpp"
#include "cdpowder/core/cpu_budget.hpp"
#include "cdpowder/core/lanes.hpp"
#include "cdpowder/run/state_hash.hpp"
#include "cdpowder/solver/nlgs/kinematic_change.hpp"
#include "cdpowder/solver/nlgs/tiles.hpp"
#include "cdpowder/solver/step.hpp"
#include "support/fixture_hash.hpp"
#include "support/small_packing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace cdpowder::testing {
namespace {

// up to four threads on any machine: the bits are compared, not the times
[[maybe_unused]] const int kOversubscribed = ::setenv(kOversubscribeVariable, "1", 1);

template <typename T>
bool same_bits(const std::vector<T>& x, const std::vector<T>& y) {
  return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(T)) == 0;
}

bool same_bits(double x, double y) {
  return std::bit_cast<std::uint64_t>(x) == std::bit_cast<std::uint64_t>(y);
}

// Every piece runs exactly once per run, on one, two and three threads, run after run.
TEST(TileThreads, RunsEveryPieceOnce) {
  for (const int n : {1, 2, 3}) {
    TileThreads team(n);
    for (std::uint32_t run = 0; run < 2000; ++run) {
      const std::uint32_t pieces = 1 + run % 5;
      std::array<std::atomic<int>, 5> count{};
      run_pieces(&team, pieces, [&](std::uint32_t p) { count[p].fetch_add(1); });
      for (std::uint32_t p = 0; p < 5; ++p) ASSERT_EQ(count[p].load(), p < pieces ? 1 : 0);
    }
  }
}

// Called inside a parallel region of the caller's own (nested regions off, OpenMP's default),
// the team is the caller alone: every piece still runs exactly once.
TEST(TileThreads, ATeamSmallerThanAskedForRunsEveryPiece) {
  TileThreads team(3);
  std::array<std::atomic<int>, 7> count{};
#pragma omp parallel num_threads(2)
  {
#pragma omp single
    run_pieces(&team, 7, [&](std::uint32_t p) { count[p].fetch_add(1); });
  }
  for (const std::atomic<int>& c : count) EXPECT_EQ(c.load(), 1);
}

/// Runs one block of `choice` at `threads_ns` per contact update on the threads and `alone_ns`
/// alone (1000 updates a step); returns whether it ran on the threads.
bool run_block(ThreadChoice& choice, double threads_ns, double alone_ns) {
  const bool threaded = choice.threaded();
  for (std::uint64_t k = 0; k < ThreadChoice::kBlockSteps; ++k) {
    EXPECT_EQ(choice.threaded(), threaded) << "the way changed inside a block";
    choice.record((threaded ? threads_ns : alone_ns) * 1e-9 * 1000, 1000);
  }
  return threaded;
}

/// The blocks among the next `blocks` that run the way `tried` (their indices from 0).
std::vector<std::uint64_t> blocks_run(ThreadChoice& choice, bool tried, std::uint64_t blocks,
                                      double threads_ns, double alone_ns) {
  std::vector<std::uint64_t> out;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    if (run_block(choice, threads_ns, alone_ns) == tried) out.push_back(b);
  }
  return out;
}

// The choice between the threads and the caller alone: the first block on the threads, the
// second alone, then the way whose last block was faster, and now and then a block the other
// way: every kTryEvery-th while the other way loses by less than kClearLoss.
TEST(ThreadChoice, RunsTheFasterWayAndTriesTheOtherNowAndThen) {
  ThreadChoice choice;
  EXPECT_TRUE(run_block(choice, 2.0, 2.2));
  EXPECT_FALSE(run_block(choice, 2.0, 2.2));
  // alone 10 % slower: a try every kTryEvery blocks
  const auto tries = blocks_run(choice, false, 10 * ThreadChoice::kTryEvery, 2.0, 2.2);
  ASSERT_EQ(tries.size(), 10U);
  for (std::size_t k = 1; k < tries.size(); ++k) {
    EXPECT_EQ(tries[k] - tries[k - 1], ThreadChoice::kTryEvery);
  }
  EXPECT_EQ(tries.front(), ThreadChoice::kTryEvery - 1);  // the second block was a try
  EXPECT_EQ(choice.try_every(), ThreadChoice::kTryEvery);
}

// A way that loses clearly is tried at doubling intervals, up to kMaxTryEvery; once it wins
// two tries in a row, it is taken and the interval is kTryEvery again.
TEST(ThreadChoice, TriesAClearLoserLessAndLessOften) {
  ThreadChoice choice;
  EXPECT_TRUE(run_block(choice, 5.0, 2.0));   // the threads 2.5× slower (a slow path)
  EXPECT_FALSE(run_block(choice, 5.0, 2.0));  // a try that wins
  EXPECT_TRUE(run_block(choice, 5.0, 2.0));   // one block of the kept way
  EXPECT_FALSE(run_block(choice, 5.0, 2.0));  // the second try wins: alone is kept
  const auto tries = blocks_run(choice, true, 8 * ThreadChoice::kMaxTryEvery, 5.0, 2.0);
  ASSERT_GE(tries.size(), 5U);
  EXPECT_EQ(tries.front(), ThreadChoice::kTryEvery - 1);
  std::vector<std::uint64_t> gaps;
  for (std::size_t k = 1; k < tries.size(); ++k) gaps.push_back(tries[k] - tries[k - 1]);
  EXPECT_EQ(gaps[0], 2 * ThreadChoice::kTryEvery);
  EXPECT_EQ(gaps[1], 4 * ThreadChoice::kTryEvery);
  for (std::size_t k = 2; k < gaps.size(); ++k) EXPECT_EQ(gaps[k], ThreadChoice::kMaxTryEvery);
  EXPECT_EQ(choice.try_every(), ThreadChoice::kMaxTryEvery);
  // the path turns fast (the threads 1.5× faster): the next try wins, one block alone, the
  // try after it wins too and the threads are kept; alone is tried kTryEvery blocks later,
  // loses clearly, and is tried twice as late after that
  const auto threaded = blocks_run(choice, true, 4 * ThreadChoice::kMaxTryEvery, 2.0, 3.0);
  ASSERT_FALSE(threaded.empty());
  const std::uint64_t found = threaded.front();
  EXPECT_LT(found, ThreadChoice::kMaxTryEvery);
  std::vector<std::uint64_t> alone_after;
  for (std::uint64_t b = found; b < 4 * ThreadChoice::kMaxTryEvery; ++b) {
    if (!std::binary_search(threaded.begin(), threaded.end(), b)) alone_after.push_back(b);
  }
  ASSERT_GE(alone_after.size(), 3U);
  EXPECT_EQ(alone_after[0], found + 1);
  EXPECT_EQ(alone_after[1], found + 2 + ThreadChoice::kTryEvery);
  EXPECT_EQ(alone_after[2], found + 2 + 3 * ThreadChoice::kTryEvery);  // lost clearly: 64 on
}

// The threads turn slow (a busy second core): the block that finds them slower than the last
// block alone brings a try at once, and two tries that win in a row take the choice alone,
// within four blocks.
TEST(ThreadChoice, FollowsTheThreadsTurningSlow) {
  ThreadChoice choice;
  run_block(choice, 2.0, 3.0);
  run_block(choice, 2.0, 3.0);
  for (int b = 0; b < 20; ++b) EXPECT_TRUE(run_block(choice, 2.0, 3.0));
  EXPECT_TRUE(run_block(choice, 5.0, 3.0));   // the block that finds them slow
  EXPECT_FALSE(run_block(choice, 5.0, 3.0));  // a try at once, which wins
  EXPECT_TRUE(run_block(choice, 5.0, 3.0));
  EXPECT_FALSE(run_block(choice, 5.0, 3.0));  // the second try wins: alone is kept
  for (int b = 0; b < 20; ++b) EXPECT_FALSE(run_block(choice, 5.0, 3.0));
}

// One slow block of the threads (a hiccup of the machine) brings one try alone; the try after
// it loses, and the threads stay: a run is not sent to one thread by one block.
TEST(ThreadChoice, OneSlowBlockBringsATryNotASwitch) {
  ThreadChoice choice;
  run_block(choice, 2.0, 3.0);
  run_block(choice, 2.0, 3.0);
  for (int b = 0; b < 20; ++b) EXPECT_TRUE(run_block(choice, 2.0, 3.0));
  EXPECT_TRUE(run_block(choice, 10.0, 3.0));  // the hiccup
  EXPECT_FALSE(run_block(choice, 2.0, 3.0));  // a try, which wins against the hiccup
  EXPECT_TRUE(run_block(choice, 2.0, 3.0));
  EXPECT_FALSE(run_block(choice, 2.0, 3.0));  // the deciding try loses
  const auto alone = blocks_run(choice, false, 2 * ThreadChoice::kTryEvery, 2.0, 3.0);
  ASSERT_FALSE(alone.empty());
  EXPECT_GE(alone.front(), ThreadChoice::kTryEvery - 1);
}

// A choice told to stay on the threads stays there, however slow their blocks.
TEST(ThreadChoice, AlwaysThreadedIgnoresTheTimes) {
  ThreadChoice choice;
  choice.always_threaded();
  for (std::uint64_t k = 0; k < 4 * ThreadChoice::kTryEvery * ThreadChoice::kBlockSteps; ++k) {
    EXPECT_TRUE(choice.threaded());
    choice.record(1.0, 1.0);
  }
}

/// Tiles of 2.83 R: the SmallPacking's 11.3 R cell (too small for the default width) in a
/// 4 × 4 grid, four tiles a phase.
constexpr double kSmallTileWidth = 2.0 * std::numbers::sqrt2;

// The grid: an even count of tiles at least the width wide along each period, or one; the
// default width 12 R_max; the paper's 25 R cell in 2 × 2 tiles.
TEST(Tiles, TheGridIsEvenAndFixedByTheCell) {
  const auto grid = [](double lx, double ly, double width) {
    const TileGrid g = tile_grid(PeriodicBox{lx, ly}, 1.0, width);
    return std::array<std::uint32_t, 2>{g.nx, g.ny};
  };
  EXPECT_EQ(grid(25.0, 25.0, 0.0), (std::array<std::uint32_t, 2>{2, 2}));
  EXPECT_EQ(grid(100.0, 100.0, 0.0), (std::array<std::uint32_t, 2>{8, 8}));
  EXPECT_EQ(grid(15.0, 15.0, 0.0), (std::array<std::uint32_t, 2>{1, 1}));
  EXPECT_EQ(grid(30.0, 72.0, 0.0), (std::array<std::uint32_t, 2>{2, 6}));
  EXPECT_EQ(grid(20.0, 47.9, 0.0), (std::array<std::uint32_t, 2>{1, 2}));
  EXPECT_EQ(grid(25.0, 25.0, 3.0), (std::array<std::uint32_t, 2>{8, 8}));
  EXPECT_EQ(grid(25.0, 5.0, 3.0), (std::array<std::uint32_t, 2>{8, 1}));
}

// Each sphere's rank (the piece of the VTK files it writes) is the rank whose strip of tile rows
// holds it: rows [r ny / P, (r + 1) ny / P), as the ranks solve them; with more ranks than rows
// some have none. 8 rows of 3.125 R in a 25 R cell (width 3).
TEST(Tiles, EachSphereBelongsToTheRankWhoseStripHoldsItsRow) {
  const PeriodicBox box{25.0, 25.0};
  std::vector<Vec3> at;
  at.reserve(9);
  for (int row = 0; row < 8; ++row) at.emplace_back(1.0, 3.125 * row + 1.0, 1.0);
  at.emplace_back(3.0, -1.0, 1.0);  // not wrapped yet: the last row
  EXPECT_EQ(sphere_ranks(at, box, 1.0, 3.0, 1), std::vector<int>(9, 0));
  EXPECT_EQ(sphere_ranks(at, box, 1.0, 3.0, 3), (std::vector<int>{0, 0, 1, 1, 1, 2, 2, 2, 2}));
  EXPECT_EQ(sphere_ranks(at, box, 1.0, 3.0, 16), (std::vector<int>{1, 3, 5, 7, 9, 11, 13, 15, 15}));
  EXPECT_EQ(strip_start(3, 8, 3), 8U);
}

/// The SmallPacking's first step in tiles of kSmallTileWidth.
StepTiles small_tiles(const SmallPacking& packing) {
  StepTiles tiles;
  const World& world = packing.scene.world;
  assign_tiles(world.bodies.position, world.box, world.bodies.max_radius(), kSmallTileWidth,
               packing.scene.work.contacts, tiles);
  return tiles;
}

// The parts of a tiled pass: the four phases' tiles, then the hub; no sphere in two tiles of one
// phase, every piston contact in the split piston's piece of its sphere's tile, every contact
// visited once; too few contacts: no tiles.
TEST(Tiles, ThePhasesTilesShareNoSphere) {
  SmallPacking packing(0.1);
  Contacts contacts = packing.scene.work.contacts;
  const VelocityCache& velocities = packing.scene.work.velocities;
  const StepTiles tiles = small_tiles(packing);
  ASSERT_TRUE(tiles.tiled());
  EXPECT_EQ(tiles.grid.tiles(), 16U);
  EXPECT_EQ(tiles.phase_parts, (std::array<std::uint32_t, kTilePhases + 1>{0, 4, 8, 12, 16}));
  ColouredPass pass;
  prepare_coloured_pass(contacts, velocities, pass, kColourChunk, &tiles);
  ASSERT_TRUE(pass.tiled());
  ASSERT_EQ(pass.parts(), 17U);
  std::vector<std::set<BodyIndex>> spheres(pass.parts());
  std::size_t visits = 0;
  std::size_t piston_contacts = 0;
  const std::size_t colours = pass.colours();
  for (std::size_t p = 0; p < pass.parts(); ++p) {
    for (std::uint32_t i = pass.part_groups[p]; i < pass.part_groups[p + 1]; ++i) {
      const std::uint32_t group = pass.group_order[i];
      if (group >= colours) {
        for (std::uint32_t j = pass.part_sequential[group - colours];
             j < pass.part_sequential[group - colours + 1]; ++j) {
          const ContactIndex k = pass.sequential[j];
          ++visits;
          if (k < contacts.pairs.size()) {
            const PairProblem& pair = pass.pair_record(contacts, k);
            spheres[p].insert({pair.a, pair.b});
            continue;
          }
          const WallProblem& w = contacts.walls[k - contacts.pairs.size()];
          spheres[p].insert(w.sphere);
          EXPECT_NE(w.wall, WallKind::Piston) << "the piston's contacts are split by tile";
        }
        continue;
      }
      for (std::uint32_t b = pass.colour_batches[group]; b < pass.colour_batches[group + 1]; ++b) {
        const BatchPair& pair = pass.batch_pairs[b / 2];
        for (std::uint32_t l = 0; l < pair.lanes[b % 2]; ++l) {
          const std::size_t lane = (b % 2) * kBatchLanes + l;
          spheres[p].insert({pair.a_row[lane] / kRecordDoubles, pair.b_row[lane] / kRecordDoubles});
          ++visits;
        }
      }
    }
  }
  // the piston's contacts, tile by tile in tile order (split_piston.hpp)
  const SplitPiston& split = pass.split_piston;
  ASSERT_TRUE(split.active());
  std::uint32_t last_tile = 0;
  for (std::uint32_t piece = 0; piece < split.pieces(); ++piece) {
    const std::uint32_t tile =
        tiles.sphere_part[contacts.walls[split.walls[split.piece_start[piece]]].sphere];
    if (piece > 0) {
      EXPECT_GT(tile, last_tile);
    }
    last_tile = tile;
    for (std::uint32_t j = split.piece_start[piece]; j < split.piece_start[piece + 1]; ++j) {
      const WallProblem& w = contacts.walls[split.walls[j]];
      EXPECT_EQ(w.wall, WallKind::Piston);
      EXPECT_EQ(tiles.sphere_part[w.sphere], tile);
      ++visits;
      ++piston_contacts;
    }
  }
  EXPECT_EQ(visits, contacts.size());
  EXPECT_GT(piston_contacts, 0U);
  std::size_t tiles_with_contacts = 0;
  for (std::size_t phase = 0; phase < kTilePhases; ++phase) {
    for (std::uint32_t p = tiles.phase_parts[phase]; p < tiles.phase_parts[phase + 1]; ++p) {
      tiles_with_contacts += spheres[p].empty() ? 0 : 1;
      for (std::uint32_t q = p + 1; q < tiles.phase_parts[phase + 1]; ++q) {
        std::vector<BodyIndex> common;
        std::set_intersection(spheres[p].begin(), spheres[p].end(), spheres[q].begin(),
                              spheres[q].end(), std::back_inserter(common));
        EXPECT_TRUE(common.empty()) << "parts " << p << " and " << q;
      }
    }
  }
  EXPECT_EQ(tiles_with_contacts, 16U);

  Contacts few = contacts;
  few.pairs.resize(kMinPairsToTile - 1);
  StepTiles none;
  const World& world = packing.scene.world;
  assign_tiles(world.bodies.position, world.box, 1.0, kSmallTileWidth, few, none);
  EXPECT_FALSE(none.tiled());
  EXPECT_EQ(none.parts(), 1U);
}

/// Solves the SmallPacking's first step, in tiles, on `threads` threads.
struct TiledSolve {
  Contacts contacts;
  VelocityCache velocities;
  SolverStats stats;
};

/// `piston_velocity`: the piston's free velocity V_P instead of the packing's (a piston that
/// comes down on the spheres); `mixing`: false for no Anderson mixing.
TiledSolve tiled_solve(int threads, lanes::Isa isa, std::optional<double> piston_velocity = {},
                       bool mixing = true) {
  allow_kernel_isa(isa);
  SmallPacking packing(0.1);
  TiledSolve out{packing.scene.work.contacts, packing.scene.work.velocities, {}};
  if (piston_velocity) out.velocities.piston_velocity = *piston_velocity;
  const StepTiles tiles = small_tiles(packing);
  SolverSettings settings = packing.scene.settings.solver;
  settings.threads = threads;
  settings.kinematic_tolerance = 1e-3;  // the kinematic rule's pass too
  settings.min_passes = 40;             // passes and mixings enough to use every piece
  settings.max_passes = 40;
  if (!mixing) settings.acceleration_depth = 0;
  NlgsWorkspace work(5);
  work.thread_choice.always_threaded();
  out.stats = solve_nlgs(out.contacts, out.velocities, settings, 1.0, work, &tiles);
  EXPECT_EQ(out.stats.threaded, threads > 1);
  allow_kernel_isa(lanes::Isa::Avx512);
  return out;
}

// A tiled step's solve (passes, kinematic rule, mixing) on two, three and four threads leaves
// the bits of one thread, with every instruction set.
TEST(TileThreads, ASolveGivesTheBitsOfOneThread) {
  for (const lanes::Isa isa : {lanes::Isa::Sse2, lanes::Isa::Avx2, lanes::Isa::Avx512}) {
    if (!allow_kernel_isa(isa)) continue;  // not on this CPU
    const TiledSolve one = tiled_solve(1, isa);
    EXPECT_EQ(one.stats.passes, 40);
    for (const int n : {2, 3, 4}) {
      const TiledSolve many = tiled_solve(n, isa);
      EXPECT_EQ(many.stats.passes, one.stats.passes);
      EXPECT_TRUE(same_bits(many.stats.residual, one.stats.residual));
      EXPECT_TRUE(same_bits(many.stats.kinematic_error, one.stats.kinematic_error));
      EXPECT_TRUE(same_bits(many.stats.force_scale, one.stats.force_scale));
      EXPECT_TRUE(same_bits(many.contacts.pair_actions, one.contacts.pair_actions));
      EXPECT_TRUE(same_bits(many.contacts.wall_actions, one.contacts.wall_actions));
      EXPECT_TRUE(same_bits(many.velocities.spheres, one.velocities.spheres));
      EXPECT_TRUE(same_bits(many.velocities.piston_velocity, one.velocities.piston_velocity));
    }
  }
}

/// a − b field by field.
ContactAction minus(const ContactAction& a, const ContactAction& b) {
  ContactAction d;
  d.normal_force = a.normal_force - b.normal_force;
  d.tangential_force = a.tangential_force - b.tangential_force;
  d.rolling_torque = a.rolling_torque - b.rolling_torque;
  d.twisting_torque = a.twisting_torque - b.twisting_torque;
  return d;
}

// A tiled step's mixings move the velocity cache by their actions' changes, tile by tile (each
// tile's batched pairs, overflow pairs and walls, the piston's contacts of its spheres
// included) and the piston once by the tiles' changes: after the solve v* is still the start
// plus Δt M⁻¹ Σ (action − its start) over every contact, for the spheres and the piston
// (physics.md §5.3), up to rounding. A piston coming down at 0.5 R/t0, so that its contacts'
// forces change from pass to pass; on one thread and on two.
TEST(TileThreads, ATiledSolveLeavesTheVelocitiesOfItsActions) {
  const SmallPacking packing(0.1);
  const Contacts& before = packing.scene.work.contacts;
  constexpr double kPistonVelocity = -0.5;
  for (const int threads : {1, 2}) {
    SCOPED_TRACE(::testing::Message() << threads << " threads");
    const TiledSolve solved = tiled_solve(threads, lanes::Isa::Avx512, kPistonVelocity);
    VelocityCache expected = packing.scene.work.velocities;
    expected.piston_velocity = kPistonVelocity;
    for (std::size_t k = 0; k < before.pairs.size(); ++k) {
      apply_pair_action(before.pairs[k],
                        minus(solved.contacts.pair_actions[k], before.pair_actions[k]), expected);
    }
    std::size_t piston_contacts = 0;
    for (std::size_t k = 0; k < before.walls.size(); ++k) {
      apply_wall_action(before.walls[k],
                        minus(solved.contacts.wall_actions[k], before.wall_actions[k]), expected);
      piston_contacts += before.walls[k].wall == WallKind::Piston ? 1 : 0;
    }
    ASSERT_GT(piston_contacts, 0U);
    double scale = std::abs(expected.piston_velocity);
    for (const SphereVelocity& s : expected.spheres) {
      scale = std::max({scale, s.linear.norm(), s.angular.norm()});
    }
    ASSERT_GT(scale, 0.0);
    const double tolerance = 1e-10 * scale;
    for (std::size_t i = 0; i < expected.spheres.size(); ++i) {
      EXPECT_LE((solved.velocities.spheres[i].linear - expected.spheres[i].linear).norm(),
                tolerance)
          << "sphere " << i;
      EXPECT_LE((solved.velocities.spheres[i].angular - expected.spheres[i].angular).norm(),
                tolerance)
          << "sphere " << i;
    }
    EXPECT_NEAR(solved.velocities.piston_velocity, expected.piston_velocity, tolerance);
    EXPECT_GT(solved.velocities.piston_velocity, kPistonVelocity);  // the spheres push back
  }
  // the mixings were adopted: without them the actions differ
  const TiledSolve mixed = tiled_solve(1, lanes::Isa::Avx512, kPistonVelocity);
  const TiledSolve unmixed = tiled_solve(1, lanes::Isa::Avx512, kPistonVelocity, false);
  EXPECT_FALSE(same_bits(mixed.contacts.pair_actions, unmixed.contacts.pair_actions));
  EXPECT_FALSE(same_bits(mixed.contacts.wall_actions, unmixed.contacts.wall_actions));
}

// A tiled step takes the spheres in pieces, its tiles' records: here three of 4 097, 3 and
// 5 901 spheres (each starts a block of four of its own), and an empty one. On three threads the
// measure and the snapshot after a mixing have the bits of one thread; the largest change is
// the plain loop's and the RMS speed adds the pieces' sums in piece order.
TEST(KinematicChange, PiecesOnThreadsGiveTheBitsOfOneThread) {
  const double dt = 0.013;
  constexpr std::size_t kSpheres = 10001;
  const std::array<std::uint32_t, 5> piece_start{0, 4097, 4100, 4100, kSpheres};
  VelocityCache cache;
  for (std::size_t i = 0; i < kSpheres; ++i) {
    // a solid sphere of radius r: Δt/m and Δt/I = Δt/(0.4 m r²)
    const double r = 0.7 + 1e-5 * static_cast<double>(i);
    const double mass = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    SphereVelocity s;
    s.dt_inverse_mass = dt / mass;
    s.dt_inverse_inertia = dt / (0.4 * mass * r * r);
    cache.spheres.push_back(s);
  }
  const auto fill = [&](double phase) {
    for (std::size_t i = 0; i < kSpheres; ++i) {
      const double x = phase + 1.7 * static_cast<double>(i);
      cache.spheres[i].linear = Vec3(std::sin(x), std::cos(3 * x), 1e-3 * x);
      cache.spheres[i].angular = Vec3(std::cos(x) / 7, -x, std::sin(5 * x));
    }
  };
  fill(0.3);
  const VelocityCache before = cache;
  TileThreads threads(3);
  KinematicChange alone;
  KinematicChange on_threads;
  KinematicChange handed_out;  // the pieces handed to the threads in another order
  const std::array<std::uint32_t, 4> strips{2, 0, 3, 1};
  alone.begin_step(cache, piece_start, true);
  on_threads.begin_step(cache, piece_start, true);
  handed_out.begin_step(cache, piece_start, true, nullptr, &threads, strips);
  ASSERT_EQ(alone.pieces(), 4U);
  fill(1.1);
  const PassMotion a = alone.after_pass(cache, true);
  const PassMotion b = on_threads.after_pass(cache, true, &threads);
  const PassMotion h = handed_out.after_pass(cache, true, &threads);
  EXPECT_EQ(a.largest_change, b.largest_change);
  EXPECT_EQ(a.rms_surface_speed, b.rms_surface_speed);
  EXPECT_EQ(a.rms_change, b.rms_change);
  EXPECT_EQ(a.largest_change, h.largest_change);
  EXPECT_EQ(a.rms_surface_speed, h.rms_surface_speed);
  EXPECT_EQ(a.rms_change, h.rms_change);
  double largest_sq = 0.0;
  std::array<double, 4> piece_sum{};
  std::array<double, 4> piece_change_sum{};
  for (std::size_t i = 0; i < kSpheres; ++i) {
    const SphereVelocity& v = cache.spheres[i];
    const SphereVelocity& was = before.spheres[i];
    const double r_sq = 2.5 * v.dt_inverse_mass / v.dt_inverse_inertia;
    const double change_sq =
        (v.linear - was.linear).squaredNorm() + r_sq * (v.angular - was.angular).squaredNorm();
    largest_sq = std::max(largest_sq, change_sq);
    const auto piece = static_cast<std::size_t>(
        std::upper_bound(piece_start.begin(), piece_start.end(), i) - piece_start.begin() - 1);
    piece_sum[piece] += v.linear.squaredNorm() + r_sq * v.angular.squaredNorm();
    piece_change_sum[piece] += change_sq;
  }
  EXPECT_EQ(a.largest_change, std::sqrt(largest_sq));
  const double sum_sq = piece_sum[0] + piece_sum[1] + piece_sum[2] + piece_sum[3];
  EXPECT_EQ(a.rms_surface_speed, std::sqrt(sum_sq / static_cast<double>(kSpheres)));
  const double change_sum_sq =
      piece_change_sum[0] + piece_change_sum[1] + piece_change_sum[2] + piece_change_sum[3];
  EXPECT_EQ(a.rms_change, std::sqrt(change_sum_sq / static_cast<double>(kSpheres)));
  // a mixing moves the velocities: the snapshot taken on threads is the one taken alone
  fill(2.9);
  alone.velocities_changed(cache);
  on_threads.velocities_changed(cache, &threads);
  handed_out.velocities_changed(cache, &threads);
  fill(3.4);
  const PassMotion c = alone.after_pass(cache, false);
  const PassMotion d = on_threads.after_pass(cache, false, &threads);
  EXPECT_GT(c.largest_change, 0.0);
  EXPECT_EQ(c.largest_change, d.largest_change);
  EXPECT_EQ(c.largest_change, handed_out.after_pass(cache, false, &threads).largest_change);
}

/// The SmallPacking after a few steps (so that the warm start has actions and the history
/// rule bonds), piston and walls included.
SmallPacking stepped_packing() {
  SmallPacking packing(0.1);
  packing.scene.settings.solver.kinematic_tolerance = 1e-3;
  packing.scene.run(3);
  return packing;
}

// Detection in two pieces (the spheres' and the candidate list's halves side by side, each
// half's pairs counted and then written in place after the first half's) gives the contacts
// of one piece, bit for bit, over steps that reuse the list and steps that rebuild it, with
// the contacts' count going up and down.
TEST(StagesInPieces, DetectionGivesTheContactsOfOnePiece) {
  SmallPacking packing = stepped_packing();
  World one = packing.scene.world;
  World two = one;
  const DetectionSettings settings = packing.scene.settings.detection();
  CellGrid grid_one;
  CellGrid grid_two;
  CandidateList list_one;
  CandidateList list_two;
  Contacts contacts_one;
  Contacts contacts_two;
  DetectionScratch scratch;
  TileThreads threads(2);
  std::size_t last_count = 0;
  bool grew = false;
  bool shrank = false;
  for (int step = 0; step < 40; ++step) {
    detect_contacts(one, settings, grid_one, contacts_one, &list_one);
    detect_contacts(two, settings, grid_two, contacts_two, &list_two, &threads, &scratch);
    grew = grew || (step > 0 && contacts_two.pairs.size() > last_count);
    shrank = shrank || contacts_two.pairs.size() < last_count;
    last_count = contacts_two.pairs.size();
    ASSERT_TRUE(same_bits(contacts_two.pairs, contacts_one.pairs)) << step;
    ASSERT_TRUE(same_bits(contacts_two.walls, contacts_one.walls)) << step;
    ASSERT_TRUE(same_bits(two.bodies.position, one.bodies.position)) << step;  // the wrap
    // a drift across the cell's sides and up to the piston: of every sphere, of the second
    // half of the spheres alone (whose cover check alone then fails), or a slow one of every
    // sphere that the list still covers
    for (World* world : {&one, &two}) {
      const std::size_t n = world->bodies.size();
      const double speed = step % 3 == 2 ? 0.001 : 0.13;
      for (std::size_t i = step % 3 == 1 ? n / 2 : 0; i < n; ++i) {
        world->bodies.position[i] += speed * Vec3(1.0, -0.5, 0.02 * static_cast<double>(i % 3));
      }
    }
  }
  EXPECT_GT(list_two.builds(), 5);  // the search after a failed cover check ran too
  EXPECT_EQ(list_two.builds(), list_one.builds());
  EXPECT_FALSE(contacts_one.walls.empty());
  EXPECT_TRUE(grew);  // records written past the last step's, and fewer than its
  EXPECT_TRUE(shrank);
}

// Building the local problems in K pieces cut by sphere owner (predicted velocities and records
// a share each, then the warm start's velocity changes, each piece those of its own spheres,
// some from earlier pieces' pairs) gives the bits of one piece, on two threads or three, for K
// from two to kMaxPieces.
TEST(StagesInPieces, BuildGivesTheProblemsOfOnePiece) {
  struct Cut {
    bool warm_start;
    std::uint32_t pieces;
    int threads;
  };

  for (const Cut cut : {Cut{true, 0, 2}, Cut{false, 0, 2}, Cut{true, 3, 3}, Cut{true, 7, 2},
                        Cut{false, 7, 3}, Cut{true, kMaxPieces, 3}}) {
    const bool warm_start = cut.warm_start;
    SCOPED_TRACE(::testing::Message() << "warm start " << warm_start << ", pieces " << cut.pieces
                                      << ", threads " << cut.threads);
    SmallPacking packing = stepped_packing();
    TinyScene& scene = packing.scene;
    scene.settings.solver.warm_start = warm_start;
    // begin_step's first half by hand: the last step's contacts into the cache, then detection
    take_last_step(scene.work);
    detect_contacts(scene.world, scene.settings.detection(), scene.work.grid, scene.work.contacts);
    ASSERT_GT(carried_pairs(scene.work.action_cache.last()).size(), 100U);
    Contacts contacts_one = scene.work.contacts;
    Contacts contacts_two = scene.work.contacts;
    ActionCache cache_one = scene.work.action_cache;
    ActionCache cache_two = scene.work.action_cache;
    VelocityCache velocities_one;
    VelocityCache velocities_two;
    TileThreads threads(cut.threads);
    BuildScratch scratch;
    scratch.pieces = cut.pieces;
    const BondChanges bonds_one =
        build_local_problems(scene.world, scene.settings, cache_one, contacts_one, velocities_one);
    const BondChanges bonds_two = build_local_problems(
        scene.world, scene.settings, cache_two, contacts_two, velocities_two, &threads, &scratch);
    // most pieces but the last (whose pairs' spheres b no later piece owns) have pairs whose
    // b a later piece owns: changes that cross between pieces
    const std::uint32_t crossing_pieces = (cut.pieces == 0 ? 2 : cut.pieces) - 1;
    EXPECT_GT(std::count_if(scratch.crossing.begin(), scratch.crossing.begin() + crossing_pieces,
                            [](const std::vector<std::uint32_t>& c) { return !c.empty(); }),
              crossing_pieces / 2);
    EXPECT_TRUE(same_bits(contacts_two.pairs, contacts_one.pairs));
    EXPECT_TRUE(same_bits(contacts_two.pair_actions, contacts_one.pair_actions));
    EXPECT_TRUE(same_bits(contacts_two.pair_cohesive, contacts_one.pair_cohesive));
    EXPECT_TRUE(same_bits(contacts_two.walls, contacts_one.walls));
    EXPECT_TRUE(same_bits(contacts_two.wall_actions, contacts_one.wall_actions));
    EXPECT_TRUE(same_bits(contacts_two.wall_cohesive, contacts_one.wall_cohesive));
    EXPECT_TRUE(same_bits(velocities_two.spheres, velocities_one.spheres));
    EXPECT_TRUE(same_bits(velocities_two.piston_velocity, velocities_one.piston_velocity));
    // the bonds counted by the lookups (or, without the warm start, by a merge of the keys)
    // are those of a merge of the keys, on any pieces
    EXPECT_EQ(bonds_one.formed(), bonds_two.formed());
    EXPECT_EQ(bonds_one.broken(), bonds_two.broken());
    const BondChanges merged = bond_changes(cache_one.last(), contacts_one);
    EXPECT_EQ(bonds_one.pairs_formed, merged.pairs_formed);
    EXPECT_EQ(bonds_one.pairs_broken, merged.pairs_broken);
    EXPECT_EQ(bonds_one.walls_formed, merged.walls_formed);
    EXPECT_EQ(bonds_one.walls_broken, merged.walls_broken);
    // the warm start moved the spheres away from v + Δt g
    if (warm_start) {
      const auto moved =
          std::count_if(velocities_one.spheres.begin(), velocities_one.spheres.end(),
                        [&](const SphereVelocity& s) { return s.angular.squaredNorm() > 0.0; });
      EXPECT_GT(moved, 100);
    }
  }
}

// Bonds formed and broken as the build counts them, on one piece and two, against a merge of
// the two lists' keys: a shorter range than the last step's breaks bonds, a longer one forms
// them (the graph rule decides on the gap alone).
TEST(StagesInPieces, TheBuildCountsTheBondsAMergeOfTheKeysFinds) {
  for (const double range : {1e-9, 0.5}) {
    SmallPacking packing = stepped_packing();
    TinyScene& scene = packing.scene;
    take_last_step(scene.work);
    scene.settings.laws.spheres.cohesion_range = range;
    detect_contacts(scene.world, scene.settings.detection(), scene.work.grid, scene.work.contacts);
    Contacts contacts_one = scene.work.contacts;
    Contacts contacts_two = scene.work.contacts;
    VelocityCache velocities_one;
    VelocityCache velocities_two;
    TileThreads threads(2);
    const BondChanges one = build_local_problems(
        scene.world, scene.settings, scene.work.action_cache, contacts_one, velocities_one);
    const BondChanges two =
        build_local_problems(scene.world, scene.settings, scene.work.action_cache, contacts_two,
                             velocities_two, &threads);
    const BondChanges merged = bond_changes(scene.work.action_cache.last(), contacts_one);
    EXPECT_GT(range < 0.01 ? merged.pairs_broken : merged.pairs_formed, 0) << range;
    for (const BondChanges& c : {one, two}) {
      EXPECT_EQ(c.pairs_formed, merged.pairs_formed) << range;
      EXPECT_EQ(c.pairs_broken, merged.pairs_broken) << range;
      EXPECT_EQ(c.walls_formed, merged.walls_formed) << range;
      EXPECT_EQ(c.walls_broken, merged.walls_broken) << range;
    }
  }
}

// Whole steps (mixing and stopping rules included) in 16 tiles with solver.threads = 1, 2, 3, 4:
// one state hash.
TEST(TileThreads, StepsGiveTheSameStateHashForAnyThreadCount) {
  std::vector<std::string> hashes;
  for (const int n : {1, 2, 3, 4}) {
    SmallPacking packing(0.1);
    packing.scene.settings.solver.kernel = PassKernel::Coloured;
    packing.scene.settings.solver.tile_width = kSmallTileWidth;
    packing.scene.settings.solver.threads = n;
    packing.scene.work.solver.thread_choice.always_threaded();
    packing.scene.settings.solver.kinematic_tolerance = 1e-3;  // the kinematic rule's pass too
    const StepReport last = packing.scene.run(6);
    EXPECT_TRUE(last.solver.converged);
    hashes.push_back(hash_text(state_hash(packing.scene.world, packing.scene.work)));
  }
  for (std::size_t k = 1; k < hashes.size(); ++k) EXPECT_EQ(hashes[k], hashes[0]) << k + 1;
}

// Two steps of the paper's (0,0) compaction front (≈ 1 000 spheres in 8 × 8 tiles of 3.125 R,
// and the piston): the hash of one thread with two and four.
TEST(TileThreads, APaperSizeStepGivesTheSameStateHashOnTwoAndFourThreads) {
  const std::vector<SceneOverride> settings{"solver.kinematic_tolerance=1e-4",
                                            "solver.tile_width=3.0"};
  const auto one = fixture_hash("paper_front_mu00_t350.cdps", 2, settings);
  for (const char* threads : {"solver.threads=2", "solver.threads=4"}) {
    std::vector<SceneOverride> many = settings;
    many.emplace_back(threads);
    EXPECT_EQ(fixture_hash("paper_front_mu00_t350.cdps", 2, many), one) << threads;
  }
}

// release_step_scratch frees what a step rebuilds (the mixing, the colour batches, the
// candidate list): steps taken after it rebuild them, with the bits of a run never freed.
TEST(StepScratch, StepsAfterItsReleaseGiveTheBitsOfAnUnbrokenRun) {
  const std::vector<SceneOverride> settings{"solver.kinematic_tolerance=1e-4",
                                            "solver.tile_width=3.0"};
  const auto unbroken = fixture_hash("paper_front_mu00_t350.cdps", 3, settings);
  EXPECT_EQ(fixture_hash("paper_front_mu00_t350.cdps", 3, settings, 1), unbroken);
  // and untiled (the scalar kernel: the mixing of the whole step at once)
  const std::vector<SceneOverride> untiled{"solver.kernel=\"scalar\""};
  EXPECT_EQ(fixture_hash("paper_mid_mu11_t240.cdps", 3, untiled, 1),
            fixture_hash("paper_mid_mu11_t240.cdps", 3, untiled));
}

// The stages after a threaded solve run their halves side by side (step.cpp): each step's
// diagnostics on two threads have the bits of one.
// The paper's 25 R cell in the default tiles (2 × 2: one tile a phase) has nothing to share:
// its steps stay on one thread whatever solver.threads says.
TEST(TileThreads, AStepWithOneTileAPhaseStaysOnOneThread) {
  SmallPacking packing(0.1);
  packing.scene.settings.solver.threads = 2;
  packing.scene.settings.solver.tile_width = 5.0;  // 11.3 R: 2 × 2 tiles
  packing.scene.work.solver.thread_choice.always_threaded();
  const StepReport report = packing.scene.run(1);
  EXPECT_TRUE(packing.scene.work.solver.tiles.tiled());
  EXPECT_FALSE(packing.scene.work.solver.tiles.tiles_to_share());
  EXPECT_FALSE(report.solver.threaded);
  packing.scene.settings.solver.tile_width = 2.8;  // 4 × 4: four a phase
  EXPECT_TRUE(packing.scene.run(1).solver.threaded);
}

TEST(TileThreads, AThreadedStepsDiagnosticsHaveTheBitsOfOneThread) {
  const auto reports = [](int threads) {
    const std::filesystem::path file =
        std::filesystem::path(CDPOWDER_SOURCE_DIR) / "bench/fixtures/paper_front_mu00_t350.cdps";
    SavedRun saved = load_state(file);
    const Scene saved_scene = read_scene_text(saved.scene_toml, file.string(), {}, ".");
    // tiles of 3.1 R (8 × 8): the default's 2 × 2 have one tile a phase, nothing to share
    const Scene scene = read_scene_text(
        saved.scene_toml, file.string(),
        {"solver.threads=" + std::to_string(threads), "solver.tile_width=3.0"}, ".");
    World world;
    StepWorkspace work(scene.step.solver.seed);
    RunState run;
    restore_run(std::move(saved), saved_scene.run, saved_scene.step.solver.dt, world, work, run);
    std::vector<StepReport> out;
    out.reserve(3);
    for (int k = 0; k < 3; ++k) out.push_back(step(world, work, scene.step));
    return out;
  };
  const std::vector<StepReport> one = reports(1);
  const std::vector<StepReport> two = reports(2);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t k = 0; k < one.size(); ++k) {
    EXPECT_TRUE(two[k].solver.threaded);  // the first block of steps runs on the threads
    const StepDiagnostics& a = one[k].diagnostics;
    const StepDiagnostics& b = two[k].diagnostics;
    EXPECT_EQ(a.contacts, b.contacts);
    EXPECT_EQ(a.closed_contacts, b.closed_contacts);
    EXPECT_EQ(a.cohesive_contacts, b.cohesive_contacts);
    for (const auto field : {&StepDiagnostics::mean_overlap, &StepDiagnostics::max_overlap,
                             &StepDiagnostics::kinetic_energy, &StepDiagnostics::max_speed,
                             &StepDiagnostics::rms_speed, &StepDiagnostics::piston_contact_force,
                             &StepDiagnostics::piston_imbalance, &StepDiagnostics::max_net_force,
                             &StepDiagnostics::max_cohesive_opening_speed,
                             &StepDiagnostics::max_cohesive_opening_per_range,
                             &StepDiagnostics::largest_surface_speed}) {
      EXPECT_TRUE(same_bits(a.*field, b.*field)) << "step " << k;
    }
    EXPECT_TRUE(a.spheres_finite && b.spheres_finite);
    EXPECT_GT(a.kinetic_energy, 0.0);
    EXPECT_GT(a.closed_contacts, 0U);
  }
}

}  // namespace
}  // namespace cdpowder::testing
