// stress_bounds.hpp — `cdpowder stress-bounds DIR… [OPTIONS]`: the admissible stress interval of
// finished runs' packings (physics.md §11.3), added to each DIR/summary.json. The linear
// programs are the package's (python/cdpowder/stress_bounds.py, SciPy's HiGHS): the command
// runs `python3 -m cdpowder.stress_bounds` with its arguments, the package of a build tree
// first on PYTHONPATH.
#pragma once

#include <string>
#include <vector>

namespace cdpowder::app {

struct StressBoundsOptions {
  std::vector<std::string> arguments;  ///< the folders and options, passed on as they are
};

/// Replaces this process with the Python module; returns only when it could not be started
/// (the message printed), with the exit code of bad input.
int run_stress_bounds(const StressBoundsOptions& options);

/// Runs the module on `arguments` as a child and waits for it; returns its exit status (2 when
/// it could not be started, the message printed).
int spawn_stress_bounds(const std::vector<std::string>& arguments);

}  // namespace cdpowder::app
