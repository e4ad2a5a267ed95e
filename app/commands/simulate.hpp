// simulate.hpp — `cdpowder simulate SCENE --out DIR`: run a scene, write its outputs.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace cdpowder::app {

struct SimulateOptions {
  std::filesystem::path scene;
  std::filesystem::path out;
  std::vector<std::string> overrides;  ///< --set section.key=value
  bool quiet = false;
};

/// Runs the scene and writes particles.csv, contacts.csv, timeseries.csv and summary.json
/// to `out`. Throws ConfigError for bad input before anything is written.
/// Returns the process exit code (0: done).
int run_simulate(const SimulateOptions& options);

}  // namespace cdpowder::app
