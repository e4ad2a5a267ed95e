// state_file.hpp — the full engine state in one versioned binary file: a run saved at step
// k and continued from the file ends bit-identical to a run never stopped (tested in
// tests/run/state_file_test.cpp). It is the program's checkpoint format and the fixture the
// benchmarks start from; the determinism hashes (state_hash.hpp) encode the same sections
// with the same serialiser. docs/outputs.md describes the layout.
//
// What a step needs from the past, and so what the file holds: the World (spheres, walls,
// piston, cell, gravity, time, step), the warm-start cache (last step's contact actions,
// which also carry the history cohesion rule), the pass-order random stream, and the run
// loop's RunState (counts, gauges, the blocked-state window, when the next static solve may
// run). Everything else in a StepWorkspace is rebuilt at the start of every step. The
// deposition stream is spent before the first step and is not needed to continue.
// The resolved scene is stored as TOML text beside them, with the program version and
// commit that wrote the file.
#pragma once

#include "cdpowder/contact/action_cache.hpp"
#include "cdpowder/core/rng.hpp"
#include "cdpowder/io/byte_stream.hpp"
#include "cdpowder/model/world.hpp"
#include "cdpowder/run/run_loop.hpp"
#include "cdpowder/solver/step.hpp"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace cdpowder {

/// Format of the files this build writes. Bump it with every change of the layout (and say
/// so in docs/outputs.md). Format 2 added the energy budget (analysis/energy_budget.hpp).
inline constexpr std::uint32_t kStateFormatVersion = 2;

/// The oldest format this build reads: a format-1 file continues bit-identical, with its
/// energy budget unknown (RunResult::energy_known false), since its start was not saved.
inline constexpr std::uint32_t kOldestStateFormatVersion = 1;

/// Whether this build reads state files of `format`.
[[nodiscard]] constexpr bool readable_state_format(std::uint32_t format) {
  return format >= kOldestStateFormatVersion && format <= kStateFormatVersion;
}

/// The first eight bytes of every state file.
inline constexpr std::string_view kStateFileMagic = "CDPSTATE";

/// A state file's contents, decoded but not yet put back into the engine (restore_run).
struct SavedRun {
  std::uint32_t format_version = kStateFormatVersion;
  std::string program_version;  ///< kVersion of the build that wrote the file
  std::string git_commit;       ///< kGitCommit of that build
  std::string scene_toml;       ///< the resolved scene of the run (Scene::effective_toml)
  World world;
  ActionCache actions;
  Rng pass_order;  ///< NlgsWorkspace::rng
  RunResult result;
  std::optional<BlockedStateDetector::Memory> detector;
  double last_rest_check = 0.0;
  double last_probe = 0.0;
  int deferred_windows = 0;
  bool probing = true;
  bool started = false;
  double start_time = 0.0;
  double dt = 0.0;
};

/// The World and the warm-start actions through the shared serialiser (also state_hash):
/// write_actions saves the actions of the last committed step's contacts that carry over
/// (last_step_actions, solver/step.hpp); read_actions gives them back as the cache the next
/// step starts from.
void write_world(ByteWriter& out, const World& world);
World read_world(ByteReader& in);
void write_actions(ByteWriter& out, const CarriedActions& last_step);
ActionCache read_actions(ByteReader& in);

/// The whole file's bytes for a run after some steps.
std::string encode_state(std::string_view scene_toml, const World& world, const StepWorkspace& work,
                         const RunState& run);

/// Decodes a state file's bytes. Throws StateFileError, naming `source`, for anything that
/// is not a complete state file of kStateFormatVersion (another format is refused with both
/// version numbers: there is no silent conversion), and for values no run reaches (checked
/// as a particles file's are, model/world_check.hpp; a started run's Δt finite, > 0 and
/// still advancing its time), which only an edited file holds.
SavedRun decode_state(std::string_view bytes, const std::string& source);

/// Throws StateFileError when the saved run's spheres are not those its scene and starting
/// packing describe (`initial`, e.g. the world of scene.toml and initial_particles.csv): another
/// number of spheres, another cell, or another radius or fixed flag of a sphere.
void require_same_spheres(const World& initial, const World& saved,
                          const std::string& initial_source, const std::string& saved_source);

/// Writes the state atomically (a temporary file renamed into place: a crash while writing
/// leaves the previous file intact).
void save_state(const std::filesystem::path& path, std::string_view scene_toml, const World& world,
                const StepWorkspace& work, const RunState& run);

/// Reads and decodes a state file. Throws StateFileError.
SavedRun load_state(const std::filesystem::path& path);

/// The start of a state file: who wrote it and for which scene, read without decoding (or
/// checking) the rest, so that a caller can decide what to do with a file of another format
/// or another build before reading it whole (a pass choosing between continuing a run from
/// its checkpoint and starting it again).
struct StateHeader {
  std::uint32_t format_version = 0;
  std::string program_version;
  std::string git_commit;
  std::string scene_toml;
};

/// Reads the header of the state file `path`. Throws StateFileError for a file that cannot
/// be read or does not start as a state file; another format version is returned, not
/// refused (its scene is then left empty: its layout is unknown).
StateHeader read_state_header(const std::filesystem::path& path);

/// Whether a file written by the build `program_version` (commit `git_commit`) comes from
/// another build than this one: a run continued from it then goes on with other code, and
/// does not end bit-identical to the run never stopped.
bool written_by_another_build(std::string_view program_version, std::string_view git_commit);

/// Puts a saved run back: the World, the workspace's warm-start cache and pass-order
/// stream, and the loop's state with its blocked-state window for `run` and `dt` (the
/// scene's; Throws StateFileError if the window's length does not match them).
void restore_run(SavedRun saved, const RunConfig& run, double dt, World& world, StepWorkspace& work,
                 RunState& state);

}  // namespace cdpowder
