// The coloured kernel on several threads (solver.threads): a sweep, a step and a paper-size
// step give the bits of one thread (the same visits in the same order, the sums added in
// visiting order).
#include "cdpowder/solver/coloured_threads.hpp"

#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/io/state_file.hpp"
#include "cdpowder/io/state_hash.hpp"
#include "cdpowder/solver/step.hpp"
#include "cdpowder/solver/sweep_threads.hpp"
#include "support/small_packing.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

namespace cdpowder::testing {
namespace {

template <typename T>
bool same_bits(const std::vector<T>& x, const std::vector<T>& y) {
  return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(T)) == 0;
}

bool same_bits(double x, double y) {
  return std::bit_cast<std::uint64_t>(x) == std::bit_cast<std::uint64_t>(y);
}

// The greedy colouring in chunks of 256 contacts (and with 3 colours only, so that overflow
// pairs join the wall contacts in the sequential group), in a random group order: each sweep on
// 2 and 3 threads leaves the bits of the one-thread sweep, and returns the same sums.
TEST(ColouredThreads, ASweepGivesTheBitsOfOneThread) {
  for (const bool avx2 : {false, true}) {
    if (avx2 && !allow_avx2_kernel(true)) continue;  // no AVX2 here
    allow_avx2_kernel(avx2);
    for (const int max_colours : {kMaxColours, 3}) {
      for (const int n : {2, 3}) {
        SmallPacking packing(0.1);
        Contacts one = packing.scene.work.contacts;
        VelocityCache one_v = packing.scene.work.velocities;
        Contacts many = one;
        VelocityCache many_v = one_v;
        ColouredSweep sweep;
        colour_pairs(one.pairs, one_v.spheres.size(), max_colours, 256, sweep.colouring,
                     sweep.masks);
        build_batches(one, one_v, sweep);
        ASSERT_GT(sweep.colours(), 2U);
        ASSERT_GT(sweep.sequential.size(), max_colours == 3 ? one.walls.size() : 0U);
        Rng rng = make_rng(3, RngStream::SweepOrder);
        order_groups(sweep, VisitOrder::RandomEachStep, rng);
        ColouredThreads threads(n, /*adaptive=*/false);  // every sweep on the threads
        for (int s = 0; s < 5; ++s) {
          const SweepSums a = run_coloured_sweep(one, one_v, sweep);
          const SweepSums b = threads.sweep(many, many_v, sweep);
          EXPECT_TRUE(same_bits(a.max_change_sq, b.max_change_sq));
          EXPECT_TRUE(same_bits(a.sum_change_sq, b.sum_change_sq));
          EXPECT_TRUE(same_bits(a.sum_closed_normal, b.sum_closed_normal));
          EXPECT_EQ(a.closed, b.closed);
          EXPECT_TRUE(same_bits(one.pair_actions, many.pair_actions));
          EXPECT_TRUE(same_bits(one.wall_actions, many.wall_actions));
          EXPECT_TRUE(same_bits(one_v.spheres, many_v.spheres));
          EXPECT_TRUE(same_bits(one_v.piston_velocity, many_v.piston_velocity));
          if (s == 2) threads.park();
        }
      }
    }
  }
  allow_avx2_kernel(true);
}

// Whole steps (mixing and stopping rules included) with solver.threads = 1, 2, 3: one state hash.
TEST(ColouredThreads, StepsGiveTheSameStateHashForAnyThreadCount) {
  std::vector<std::string> hashes;
  for (const int n : {1, 2, 3}) {
    SmallPacking packing(0.1);
    packing.scene.settings.solver.kernel = SweepKernel::Coloured;
    packing.scene.settings.solver.threads = n;
    packing.scene.settings.solver.kinematic_tolerance = 1e-3;  // the kinematic rule's pass too
    const StepReport last = packing.scene.run(6);
    EXPECT_TRUE(last.solver.converged);
    hashes.push_back(hash_text(state_hash(packing.scene.world, packing.scene.work.action_cache)));
  }
  EXPECT_EQ(hashes[1], hashes[0]);
  EXPECT_EQ(hashes[2], hashes[0]);
}

/// The state hash after `steps` steps from a bench fixture with the coloured kernel.
std::string fixture_hash(const std::filesystem::path& file, int steps, int threads) {
  SavedRun saved = load_state(file);
  const Scene saved_scene = read_scene_text(saved.scene_toml, file.string(), {}, ".");
  const Scene scene = read_scene_text(
      saved.scene_toml, file.string(),
      {"solver.kernel=\"coloured\"", "solver.threads=" + std::to_string(threads)}, ".");
  World world;
  StepWorkspace work(scene.step.solver.seed);
  RunState run;
  restore_run(std::move(saved), saved_scene.run, saved_scene.step.solver.dt, world, work, run);
  for (int k = 0; k < steps; ++k) step(world, work, scene.step);
  return hash_text(state_hash(world, work.action_cache));
}

// Two steps of the paper's (0,0) compaction front (≈ 1 000 spheres, a full colouring in chunks
// and the piston): the hash of one thread with two.
TEST(ColouredThreads, APaperSizeStepGivesTheSameStateHashOnTwoThreads) {
  const std::filesystem::path fixture =
      std::filesystem::path(CDPOWDER_SOURCE_DIR) / "bench/fixtures/paper_front_mu00_t350.cdps";
  EXPECT_EQ(fixture_hash(fixture, 2, 2), fixture_hash(fixture, 2, 1));
}

}  // namespace
}  // namespace cdpowder::testing
