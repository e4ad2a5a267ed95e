// deposit.hpp — `cdpowder deposit SCENE --out DIR`: the ballistic deposit of the scene's
// [deposition] section (physics.md §8), written as a particles CSV that `simulate` and
// `compact` read (--particles, or [particles] file).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace cdpowder::app {

struct DepositOptions {
  std::filesystem::path scene;
  std::filesystem::path out;
  std::vector<std::string> overrides;  ///< --set section.key=value
  bool quiet = false;                  ///< --quiet: as compact and simulate take it
};

/// Writes scene.toml, particles.csv, particles.vtp and summary.json (porosity, height,
/// spheres) to `out` and prints one result line. Throws ConfigError for bad input (or a
/// scene without [deposition]) before anything is written. Returns the exit code.
int run_deposit(const DepositOptions& options);

}  // namespace cdpowder::app
