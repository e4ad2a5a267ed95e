// step_allocation_test.cpp — a step allocates no memory once its workspace has grown to the
// run's contacts (speed issue: "nothing allocated inside a step"; docs/performance.md,
// "Memory"). This test binary counts every operator new while a step runs.
#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/setup/scene_setup.hpp"
#include "cdpowder/solver/step.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <new>
#include <string>
#include <vector>

// The replacements below allocate with malloc and release with free, a matching pair; g++
// cannot see through the replacement and warns at -O1 where gtest's `new TestClass` meets the
// inlined operator delete.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

namespace {

std::atomic<long> g_allocations{0};
std::atomic<bool> g_counting{false};

void* counted(std::size_t size, std::size_t alignment) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  const std::size_t rounded = (size + alignment - 1) / alignment * alignment;
  void* p = alignment <= alignof(std::max_align_t) ? std::malloc(size == 0 ? 1 : size)
                                                   : std::aligned_alloc(alignment, rounded);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}

}  // namespace

// Replacing the global allocation functions (a program may, [replacement.functions]).
void* operator new(std::size_t size) {
  return counted(size, alignof(std::max_align_t));
}

void* operator new[](std::size_t size) {
  return counted(size, alignof(std::max_align_t));
}

void* operator new(std::size_t size, std::align_val_t a) {
  return counted(size, static_cast<std::size_t>(a));
}

void* operator new[](std::size_t size, std::align_val_t a) {
  return counted(size, static_cast<std::size_t>(a));
}

void operator delete(void* p) noexcept {
  std::free(p);
}

void operator delete[](void* p) noexcept {
  std::free(p);
}

void operator delete(void* p, std::size_t /*size*/) noexcept {
  std::free(p);
}

void operator delete[](void* p, std::size_t /*size*/) noexcept {
  std::free(p);
}

void operator delete(void* p, std::align_val_t /*a*/) noexcept {
  std::free(p);
}

void operator delete[](void* p, std::align_val_t /*a*/) noexcept {
  std::free(p);
}

void operator delete(void* p, std::size_t /*size*/, std::align_val_t /*a*/) noexcept {
  std::free(p);
}

void operator delete[](void* p, std::size_t /*size*/, std::align_val_t /*a*/) noexcept {
  std::free(p);
}

namespace cdpowder {
namespace {

struct Allocations {
  long total = 0;
  int steps_that_allocated = 0;
};

/// Allocations during `steps` steps of the quick example's compaction with `overrides`,
/// after its first two steps, which size the workspace: the step's actions and cohesion flags
/// and the warm-start cache's trade places every step (ActionCache::take).
Allocations allocations_of_steps(int steps, const std::vector<SceneOverride>& overrides) {
  SceneReadOptions how;
  how.compaction = true;
  const Scene scene = read_scene(
      std::filesystem::path(CDPOWDER_SOURCE_DIR) / "examples/quick/scene.toml", overrides, how);
  World world = make_world(scene);
  StepWorkspace work(scene.step.solver.seed);
  for (int k = 0; k < 2; ++k) (void)step(world, work, scene.step);
  Allocations found;
  for (int k = 0; k < steps; ++k) {
    g_allocations = 0;
    g_counting = true;
    (void)step(world, work, scene.step);
    g_counting = false;
    found.total += g_allocations;
    found.steps_that_allocated += g_allocations > 0 ? 1 : 0;
  }
  return found;
}

// Steps allocate only when the contacts outgrow every earlier step's: the workspace's
// vectors then grow geometrically, a few times in a run (2 of these 3000 steps of the quick
// example compacted without torques, 7 allocations, when this test was written; 3 steps and
// 10 allocations since the warm-start cache and the step trade contact arrays). A step that
// allocated every time would show here as thousands.
TEST(StepAllocation, StepsAfterTheFirstTwoAllocateInAFewOfThreeThousandStepsOnOneAndTwoThreads) {
  for (const std::string threads : {"1", "2"}) {
    const Allocations found = allocations_of_steps(
        3000, {SceneOverride("contact.mu_roll=0"), SceneOverride("contact.mu_twist=0"),
               SceneOverride("solver.threads=" + threads)});
    EXPECT_LE(found.steps_that_allocated, 4) << threads << " threads";
    EXPECT_LE(found.total, 24) << threads << " threads";
  }
}

TEST(StepAllocation, AStrongTorqueCompactionAllocatesNothingAfterItsFirstTwoSteps) {
  const Allocations found = allocations_of_steps(600, {});
  EXPECT_EQ(found.total, 0);
}

}  // namespace
}  // namespace cdpowder
