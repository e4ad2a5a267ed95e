// run_folder.hpp — a run's output folder holds one run: what an earlier run left there (its
// outputs, snapshots, temporaries of a killed run) is removed before a new run writes, so
// a folder never mixes two runs (measured before: a rerun that failed left its new
// scene.toml beside the old summary.json, and old snapshots outlived later runs).
#pragma once

#include "cdpowder/config/config_error.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>

namespace cdpowder::app {

/// The files and folders a run writes into its folder (README, "Outputs"); log.txt (a
/// sweep's, written before the run starts) and the lock are left alone.
inline constexpr std::array<std::string_view, 14> kRunOutputs{
    "summary.json",    "scene.toml",     "initial_particles.csv",
    "particles.csv",   "contacts.csv",   "timeseries.csv",
    "particles.vtp",   "contacts.vtp",   "particles.pvd",
    "contacts.pvd",    "snapshots",      "failed_state.cdps",
    "checkpoint.cdps", "checkpoint.toml"};

/// Throws ConfigError when `input`, a file the command reads (`what`: "the scene file"), is
/// one of the files a run writes in `folder`: the run would remove or overwrite it (found:
/// a scene kept as DIR/scene.toml and run with --out DIR was replaced by the resolved one).
inline void refuse_input_among_outputs(const std::filesystem::path& folder,
                                       const std::filesystem::path& input, std::string_view what) {
  // where the input is, links followed (a link elsewhere to DIR/scene.toml is DIR/scene.toml)
  std::error_code error;
  const std::filesystem::path in = std::filesystem::weakly_canonical(input, error);
  if (error) return;
  const std::string name = in.filename().string();
  if (std::find(kRunOutputs.begin(), kRunOutputs.end(), name) == kRunOutputs.end()) return;
  const std::filesystem::path out = std::filesystem::weakly_canonical(folder, error);
  if (error || in.parent_path() != out) return;
  throw ConfigError({{input.string(), 0, 0, "",
                      fmt::format("{} is the output folder's own {}, which the run writes (an "
                                  "earlier run's is removed first): copy it elsewhere or "
                                  "choose another --out",
                                  what, name)}});
}

/// Removes an earlier run's outputs and any temporary file (".NAME.PID.tmp") from `folder`.
/// Throws std::filesystem::filesystem_error when one cannot be removed.
inline void clear_earlier_run(const std::filesystem::path& folder) {
  for (const std::string_view name : kRunOutputs) std::filesystem::remove_all(folder / name);
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const std::string file = entry.path().filename().string();
    if (file.size() > 5 && file.front() == '.' && file.ends_with(".tmp")) {
      std::filesystem::remove(entry.path());
    }
  }
}

/// Removes the temporary files (".NAME.PID.tmp") a killed process left in `folder`, all but
/// those of the time series (`resume` continues the longest of them). Only the process that
/// holds the folder's run lock calls this, so no live writer owns them.
inline void remove_stale_temporaries(const std::filesystem::path& folder) {
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const std::string file = entry.path().filename().string();
    if (file.size() > 5 && file.front() == '.' && file.ends_with(".tmp") &&
        !file.starts_with(".timeseries.csv.")) {
      std::filesystem::remove(entry.path());
    }
  }
}

}  // namespace cdpowder::app
