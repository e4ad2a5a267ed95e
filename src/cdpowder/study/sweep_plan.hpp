// sweep_plan.hpp — a parameter study: which runs a sweep file asks for.
//
// A sweep file (TOML, docs/sweeps.md) names a base scene, fixed overrides, the seeds, and
// the parameter points: a grid (Cartesian product of value lists) and/or explicit points.
// Each (point, seed) becomes one run of `compact` (or `simulate`, or a Python protocol: the
// file's `command`) with its own `--set` overrides and its own folder, named from the parameter
// values so that a restarted or extended sweep finds the runs it already has.
#pragma once

#include "cdpowder/config/scene_override.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace cdpowder {

/// One parameter of a point: a dotted scene key and its value as TOML text ("0.1", "true",
/// "\"history\"").
struct SweepSetting {
  std::string key;
  std::string value;
  std::string origin;  ///< where the sweep file gives the value ("sweep.toml:6:12"), for messages
};

/// One parameter point; its settings are in the order of the sweep's parameter keys.
struct SweepPoint {
  std::vector<SweepSetting> settings;
  /// "contact.mu_roll=0.1,contact.mu_twist=0.3"; "base" for a sweep without parameters.
  std::string name;
};

/// One run: a point and a seed.
struct SweepRun {
  std::size_t point = 0;         ///< index into SweepPlan::points
  std::int64_t seed = 1;         ///< written to every key of SweepPlan::seed_keys
  std::filesystem::path folder;  ///< relative to the sweep's output folder: runs/<point>/seed_<s>
  std::vector<SceneOverride> overrides;  ///< fixed ones, then the point's, then the seed's
};

/// The command each run of a sweep is (the file's `command`): `cdpowder compact`,
/// `cdpowder simulate`, or a Python protocol (`python3 -m cdpowder.protocol`).
enum class SweepCommand : std::uint8_t { Compact, Simulate, Python };

/// "compact", "simulate" or "python", as the sweep file names it.
const char* command_name(SweepCommand command);

/// A Python protocol (the file's `protocol = "FILE:FUNCTION"`): FUNCTION(scene, out) of the
/// Python file FILE runs each point (docs/sweeps.md, "A Python protocol").
struct SweepProtocol {
  std::filesystem::path file;  ///< resolved against the sweep file
  std::string function;        ///< a Python identifier
  /// "FILE:FUNCTION" as the sweep file writes it, the protocol's name in protocol.json
  std::string name;
};

struct SweepPlan {
  std::filesystem::path source;                  ///< the sweep file
  SweepCommand command = SweepCommand::Compact;  ///< `command`: what each run is
  SweepProtocol protocol;                        ///< `protocol`, with command "python"
  std::filesystem::path scene;              ///< the base scene, resolved against the sweep file
  std::vector<SceneOverride> fixed;         ///< `set`, then the command's --set: every run's
  std::vector<std::int64_t> seeds;          ///< `seeds`
  std::vector<std::string> seed_keys;       ///< `seed_keys`: scene keys that take the seed
  std::vector<std::string> parameter_keys;  ///< keys of the grid and the points, first-seen order
  std::vector<SweepPoint> points;  ///< grid points (last key fastest), then explicit points
  std::vector<SweepRun> runs;      ///< points × seeds, point-major
};

/// Reads and checks a sweep file; `extra_fixed` (the command's --set) come after the file's
/// `set`. Throws ConfigError naming file, key, value and what is allowed. Does not read the
/// scene (the sweep command checks every run's scene before it starts any).
SweepPlan read_sweep_plan(const std::filesystem::path& file,
                          const std::vector<std::string>& extra_fixed = {});

/// As read_sweep_plan, from text; `source_name` names it in messages and relative scene
/// paths are taken from `base_dir`.
SweepPlan read_sweep_plan_text(std::string_view text, std::string_view source_name,
                               const std::filesystem::path& base_dir,
                               const std::vector<std::string>& extra_fixed = {});

/// Sorts run indices (into plan.runs) seed by seed: every point's run with the first seed
/// comes before any point's run with the second, points in plan order within a seed. A
/// sweep stopped early (paper-scale sweeps outlast a sitting) then has every point, and
/// error bars wherever it has any.
void order_seed_by_seed(const SweepPlan& plan, std::vector<std::size_t>& runs);

}  // namespace cdpowder
