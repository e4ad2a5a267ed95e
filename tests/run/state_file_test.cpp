// The state file (run/state_file.hpp) and the state hash (run/state_hash.hpp): a run saved
// and continued ends bit-identical to one never stopped; bad files are refused by name.
#include "cdpowder/run/state_file.hpp"

#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/run/state_hash.hpp"
#include "cdpowder/setup/scene_setup.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace cdpowder::testing {
namespace {

// The quick example at (μt, μn) = (0, 0), 1000 steps: a deposit, cohesion, the piston, warm
// start and the sweep-order stream all carry state from step to step.
Scene quick_scene(std::vector<std::string> extra = {}) {
  SceneReadOptions options;
  options.compaction = true;
  std::vector<SceneOverride> overrides = {"contact.mu_roll=0", "contact.mu_twist=0",
                                          "run.max_duration=10"};
  overrides.insert(overrides.end(), extra.begin(), extra.end());
  return read_scene(std::filesystem::path(CDPOWDER_SOURCE_DIR) / "examples/quick/scene.toml",
                    overrides, options);
}

struct Engine {
  explicit Engine(const Scene& scene) : world(make_world(scene)), work(scene.step.solver.seed) {}

  World world;
  StepWorkspace work;
  RunState state;
};

RunResult run(const Scene& scene, Engine& engine, std::int64_t stop_after = -1) {
  return run_simulation(engine.world, engine.work, scene.step, scene.run, engine.state, {},
                        [&] { return engine.state.result.steps == stop_after; });
}

void expect_same_run(const RunResult& a, const RunResult& b) {
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.total_passes, b.total_passes);
  EXPECT_EQ(a.capped_steps, b.capped_steps);
  EXPECT_EQ(a.blocked, b.blocked);
  EXPECT_EQ(a.max_overlap_seen, b.max_overlap_seen);
  EXPECT_EQ(a.max_cohesive_opening_per_range, b.max_cohesive_opening_per_range);
  EXPECT_EQ(a.last.solver.passes, b.last.solver.passes);
  EXPECT_EQ(a.last.diagnostics.kinetic_energy, b.last.diagnostics.kinetic_energy);
}

TEST(StateFile, AResumedRunEndsBitIdenticalToAnUninterruptedOne) {
  const Scene scene = quick_scene();
  Engine whole(scene);
  const RunResult uninterrupted = run(scene, whole);
  ASSERT_EQ(uninterrupted.steps, 1000);

  Engine first(scene);
  const RunResult part = run(scene, first, 377);
  ASSERT_TRUE(part.interrupted);
  ASSERT_EQ(part.steps, 377);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "cdpowder_state_file_test.cdps";
  save_state(file, scene.effective_toml, first.world, first.work, first.state);

  Engine resumed(scene);  // a fresh engine: nothing of `first` survives but the file
  SavedRun saved = load_state(file);
  std::filesystem::remove(file);
  EXPECT_EQ(saved.scene_toml, scene.effective_toml);
  EXPECT_EQ(saved.format_version, kStateFormatVersion);
  restore_run(std::move(saved), scene.run, scene.step.solver.dt, resumed.world, resumed.work,
              resumed.state);
  const RunResult continued = run(scene, resumed);
  EXPECT_FALSE(continued.interrupted);
  expect_same_run(continued, uninterrupted);
  EXPECT_EQ(state_hash(resumed.world, resumed.work), state_hash(whole.world, whole.work));
  EXPECT_EQ(resumed.world.time, whole.world.time);
  EXPECT_EQ(resumed.world.step, whole.world.step);
}

// The same with the adaptive time step: the controller's Δt and the steps it repeated carry
// over too. 60 t0 of the (0,0) compaction, stopped at every tenth step of it once.
TEST(StateFile, AnAdaptiveRunResumesBitIdentically) {
  const Scene scene = quick_scene({"solver.adaptive_dt=true", "run.max_duration=60"});
  Engine whole(scene);
  const RunResult uninterrupted = run(scene, whole);
  ASSERT_GT(uninterrupted.steps, 100);
  EXPECT_LT(uninterrupted.min_dt, uninterrupted.max_dt);  // it did adapt
  for (const std::int64_t stop_at : {uninterrupted.steps / 10, uninterrupted.steps / 2}) {
    Engine first(scene);
    run(scene, first, stop_at);
    Engine resumed(scene);
    restore_run(
        decode_state(encode_state(scene.effective_toml, first.world, first.work, first.state),
                     "memory"),
        scene.run, scene.step.solver.dt, resumed.world, resumed.work, resumed.state);
    const RunResult continued = run(scene, resumed);
    expect_same_run(continued, uninterrupted);
    EXPECT_EQ(continued.repeated_steps, uninterrupted.repeated_steps);
    EXPECT_EQ(continued.min_dt, uninterrupted.min_dt);
    EXPECT_EQ(state_hash(resumed.world, resumed.work), state_hash(whole.world, whole.work))
        << "stopped at " << stop_at;
  }
}

// A deposit before its first step: no contact actions at all, so the spheres are nearly all
// of the file; the corruption checks must still take it.
TEST(StateFile, AStateWithoutContactsReadsBack) {
  const Scene scene = quick_scene();
  Engine engine(scene);
  const std::string bytes = encode_state("", engine.world, engine.work, engine.state);
  Engine copy(scene);
  restore_run(decode_state(bytes, "memory"), scene.run, scene.step.solver.dt, copy.world, copy.work,
              copy.state);
  EXPECT_EQ(state_hash(copy.world, copy.work), state_hash(engine.world, engine.work));
}

TEST(StateFile, EncodingIsStableThroughADecode) {
  const Scene scene = quick_scene();
  Engine engine(scene);
  run(scene, engine, 20);
  const std::string bytes = encode_state("scene", engine.world, engine.work, engine.state);
  Engine copy(scene);
  restore_run(decode_state(bytes, "memory"), scene.run, scene.step.solver.dt, copy.world, copy.work,
              copy.state);
  EXPECT_EQ(encode_state("scene", copy.world, copy.work, copy.state), bytes);
}

// save_state streams the file in chunks (never the whole state in memory): the file holds the
// bytes encode_state returns, checksum included, and the state hash is the hash of its World
// and action sections. 1015 spheres: a state of several chunks.
TEST(StateFile, TheStreamedFileHoldsTheEncodedBytes) {
  SceneReadOptions options;
  options.compaction = true;
  const Scene scene =
      read_scene(std::filesystem::path(CDPOWDER_SOURCE_DIR) / "examples/paper/scene.toml",
                 {"run.max_duration=0.2"}, options);
  Engine engine(scene);
  run(scene, engine);
  const std::string bytes = encode_state("scene", engine.world, engine.work, engine.state);
  ASSERT_GT(bytes.size(), 3 * kOutputChunkBytes);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "cdpowder_streamed_state.cdps";
  save_state(file, "scene", engine.world, engine.work, engine.state);
  std::string written(static_cast<std::size_t>(std::filesystem::file_size(file)), '\0');
  std::ifstream(file, std::ios::binary)
      .read(written.data(), static_cast<std::streamsize>(written.size()));
  std::filesystem::remove(file);
  EXPECT_TRUE(written == bytes) << written.size() << " bytes written, " << bytes.size()
                                << " encoded";
  ByteWriter sections;
  write_world(sections, engine.world);
  write_actions(sections, last_step_actions(engine.work));
  EXPECT_EQ(state_hash(engine.world, engine.work), fnv1a64(sections.bytes()));
}

// The hash sees one ulp of one velocity component, and the contact actions.
TEST(StateHash, ChangesWithOneUlpOfAnyVelocityOrAction) {
  const Scene scene = quick_scene();
  Engine engine(scene);
  run(scene, engine, 10);
  const std::uint64_t before = state_hash(engine.world, engine.work);
  EXPECT_EQ(state_hash(engine.world, engine.work), before);
  Vec3& v = engine.world.bodies.velocity[57];
  const double old = v.y();
  v.y() = std::nextafter(old, 1.0);
  EXPECT_NE(state_hash(engine.world, engine.work), before);
  v.y() = old;
  const CarriedActions last_step = last_step_actions(engine.work);
  ASSERT_FALSE(last_step.pairs.empty());
  std::vector<CachedAction> pairs = last_step.pairs;
  pairs[3].action.twisting_torque = std::nextafter(pairs[3].action.twisting_torque, 1.0);
  StepWorkspace changed(scene.step.solver.seed);
  changed.action_cache.restore(pairs, last_step.walls);
  EXPECT_NE(state_hash(engine.world, changed), before);
  // the same entries restored unchanged give the same hash: the cache a state file gives
  // back is the state of the contacts it was written from
  StepWorkspace same(scene.step.solver.seed);
  same.action_cache.restore(last_step.pairs, last_step.walls);
  EXPECT_EQ(state_hash(engine.world, same), before);
}

std::string message_of(const std::string& bytes) {
  try {
    decode_state(bytes, "run/state.cdps");
  } catch (const StateFileError& error) {
    return error.what();
  }
  return "no error";
}

TEST(StateFile, BadFilesAreRefusedWithTheReason) {
  const Scene scene = quick_scene();
  Engine engine(scene);
  run(scene, engine, 5);
  const std::string good =
      encode_state(scene.effective_toml, engine.world, engine.work, engine.state);
  EXPECT_NE(message_of("particles,x,y\n").find("not a cdpowder state file"), std::string::npos);
  EXPECT_NE(message_of(good.substr(0, good.size() / 2)).find("truncated or damaged"),
            std::string::npos);
  EXPECT_NE(message_of(good.substr(0, 10)).find("truncated"), std::string::npos);
  std::string flipped = good;
  flipped[good.size() / 2] = static_cast<char>(flipped[good.size() / 2] ^ 1);
  const std::string damaged = message_of(flipped);
  EXPECT_NE(damaged.find("checksum"), std::string::npos);
  // the message names where: not "at byte 12" for every damage, as before
  EXPECT_EQ(damaged.find("at byte 12"), std::string::npos) << damaged;
  EXPECT_NE(damaged.find("a value in it was changed"), std::string::npos) << damaged;
  std::string broken_tag = good;
  const std::size_t rngs = good.find("RNGS");
  ASSERT_NE(rngs, std::string::npos);
  broken_tag[rngs] = 'X';
  const std::string lost = message_of(broken_tag);
  EXPECT_NE(lost.find("reading stops at byte"), std::string::npos) << lost;
  EXPECT_NE(message_of(good.substr(0, good.size() / 2)).find("reading stops at byte"),
            std::string::npos);
  std::string other_format = good;
  other_format[8] = 7;  // the format version's low byte
  const std::string refused = message_of(other_format);
  EXPECT_NE(refused.find("state format 7"), std::string::npos) << refused;
  EXPECT_NE(refused.find("reads formats 1 to 2"), std::string::npos) << refused;
  EXPECT_NE(refused.find("run/state.cdps"), std::string::npos) << refused;

  try {
    load_state("/nonexistent/state.cdps");
    FAIL() << "a missing file must throw";
  } catch (const StateFileError& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent/state.cdps"), std::string::npos);
  }
}

// A file whose checksum was fitted again after an edit is refused by its values, as a
// particles file is: each of these ran to "blocked" before, with a radius of −1 or 0, 1/I = −1,
// a fixed flag of 2, a time of 1e300 or NaN, or a step of −5.
TEST(StateFile, ForgedValuesAreRefusedByName) {
  const Scene scene = quick_scene();
  Engine engine(scene);
  run(scene, engine, 5);
  const auto forged = [&](const std::function<void(World&)>& edit) {
    World world = engine.world;
    edit(world);
    return message_of(encode_state(scene.effective_toml, world, engine.work, engine.state));
  };
  const std::vector<std::pair<std::function<void(World&)>, std::string>> cases = {
      {[](World& w) { w.bodies.radius[7] = -1.0; },
       "the radius of sphere 7 is -1, expected a finite number > 0"},
      {[](World& w) { w.bodies.radius[7] = 0.0; }, "the radius of sphere 7 is 0"},
      {[](World& w) { w.bodies.inverse_inertia[2] = -1.0; },
       "the inverse inertia of sphere 2 is -1"},
      {[](World& w) { w.bodies.fixed[4] = 2; }, "the fixed flag of sphere 4 is 2, expected 0 or 1"},
      {[](World& w) { w.time = 1e300; }, "is too large for Δt"},
      {[](World& w) { w.time = std::nan(""); }, "the time is nan"},
      {[](World& w) { w.step = -5; }, "the step is -5"},
      {[](World& w) { w.bodies.position[1].x() = std::numeric_limits<double>::infinity(); },
       "the position of sphere 1 is (inf"},
  };
  for (const auto& [edit, expected] : cases) {
    const std::string message = forged(edit);
    EXPECT_NE(message.find(expected), std::string::npos) << message;
    EXPECT_NE(message.find("no run reaches this state"), std::string::npos) << message;
  }
  EXPECT_EQ(forged([](World&) {}), "no error");  // the untouched state reads back
}

// The spheres a checkpoint holds must be those of its scene and starting packing: another
// run's initial_particles.csv would give another initial porosity without a word.
TEST(StateFile, ASavedRunOfOtherSpheresIsRefused) {
  const Scene scene = quick_scene();
  Engine engine(scene);
  World fewer = engine.world;
  fewer.bodies = Bodies{};
  for (std::size_t i = 0; i < 50; ++i) {
    fewer.bodies.add_sphere(engine.world.bodies.position[i], 1.0, 1.0);
  }
  EXPECT_NO_THROW(require_same_spheres(engine.world, engine.world, "scene", "checkpoint"));
  try {
    require_same_spheres(fewer, engine.world, "scene.toml with initial_particles.csv",
                         "checkpoint.cdps");
    FAIL() << "50 spheres against 100 must be refused";
  } catch (const StateFileError& error) {
    EXPECT_NE(std::string(error.what())
                  .find("checkpoint.cdps holds 100 spheres, scene.toml with "
                        "initial_particles.csv 50"),
              std::string::npos)
        << error.what();
  }
  World larger = engine.world;
  larger.bodies.radius[9] = 1.5;
  EXPECT_THROW(require_same_spheres(larger, engine.world, "scene", "checkpoint"), StateFileError);
}

// A saved blocked-state window that cannot belong to this scene's window (a held step older
// than the window) is refused, not silently cut.
TEST(StateFile, ASavedRunThatDoesNotFitTheSceneIsRefused) {
  const Scene scene = quick_scene();
  Engine engine(scene);
  run(scene, engine, 5);
  SavedRun saved = decode_state(
      encode_state(scene.effective_toml, engine.world, engine.work, engine.state), "memory");
  ASSERT_TRUE(saved.detector.has_value());
  saved.detector->clock = 3.0 * scene.run.blocked.window;
  saved.detector->time_held = 2.0 * scene.run.blocked.window;
  saved.detector->steps_held = 2;
  saved.detector->entries = {{0.5 * scene.run.blocked.window, 10.0, 0.0},
                             {3.0 * scene.run.blocked.window, 10.0, 0.0}};
  Engine other(scene);
  EXPECT_THROW(restore_run(std::move(saved), scene.run, scene.step.solver.dt, other.world,
                           other.work, other.state),
               StateFileError);
}

// A stop asked inside a step's solve abandons the step: the state is the one after the step
// before (the same bits as a run stopped between the two steps), and continued it ends
// bit-identical to the run never stopped.
TEST(StateFile, AStopInsideAStepLeavesTheStateOfTheStepBefore) {
  const Scene scene = quick_scene();
  Engine whole(scene);
  const RunResult uninterrupted = run(scene, whole);
  Engine between(scene);
  run(scene, between, 377);

  Engine inside(scene);
  int polls = 0;  // once after step 377, then after every sweep of step 378
  const RunResult stopped =
      run_simulation(inside.world, inside.work, scene.step, scene.run, inside.state, {},
                     [&] { return inside.state.result.steps == 377 && ++polls == 3; });
  EXPECT_TRUE(stopped.interrupted);
  EXPECT_EQ(stopped.steps, 377);
  EXPECT_EQ(polls, 3);
  // the World, the warm-start cache and the sweep-order stream (the wall times differ)
  EXPECT_EQ(state_hash(inside.world, inside.work), state_hash(between.world, between.work));
  EXPECT_TRUE(inside.work.solver.rng == between.work.solver.rng);
  expect_same_run(inside.state.result, between.state.result);
  EXPECT_EQ(inside.state.dt, between.state.dt);

  Engine resumed(scene);
  restore_run(decode_state(encode_state("", inside.world, inside.work, inside.state), "memory"),
              scene.run, scene.step.solver.dt, resumed.world, resumed.work, resumed.state);
  expect_same_run(run(scene, resumed), uninterrupted);
  EXPECT_EQ(state_hash(resumed.world, resumed.work), state_hash(whole.world, whole.work));
}

// A stop asked after the last step comes too late to cut anything: the run is complete.
TEST(StateFile, AStopAskedAfterTheLastStepLeavesTheRunComplete) {
  const Scene scene = quick_scene();
  Engine engine(scene);
  const RunResult result = run(scene, engine, 1000);
  EXPECT_EQ(result.steps, 1000);
  EXPECT_FALSE(result.interrupted);
}

// The header names the format and the build that wrote the file, read without the rest;
// another build of the same format is told apart from this one.
TEST(StateFile, TheHeaderNamesTheFormatTheBuildAndTheScene) {
  const Scene scene = quick_scene();
  Engine engine(scene);
  run(scene, engine, 5);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "cdpowder_state_header_test.cdps";
  save_state(file, scene.effective_toml, engine.world, engine.work, engine.state);
  const StateHeader header = read_state_header(file);
  EXPECT_EQ(header.format_version, kStateFormatVersion);
  EXPECT_EQ(header.scene_toml, scene.effective_toml);
  EXPECT_FALSE(written_by_another_build(header.program_version, header.git_commit));
  EXPECT_TRUE(written_by_another_build(header.program_version, "0000000"));
  EXPECT_TRUE(written_by_another_build("0.0.0", header.git_commit));
  std::filesystem::resize_file(file, 20);  // cut inside the program version
  EXPECT_THROW(read_state_header(file), StateFileError);
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace cdpowder::testing
