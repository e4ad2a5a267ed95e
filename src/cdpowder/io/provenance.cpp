// provenance.cpp — the '#' header of CSV outputs.
#include "cdpowder/io/provenance.hpp"

#include <fmt/format.h>

#include "cdpowder/version.hpp"

namespace cdpowder {

std::string provenance_header(const Scene& scene) {
  return fmt::format("# cdpowder {} (commit {})\n# scene: {}\n# seed: {}\n", kVersion, kGitCommit,
                     scene.source.string(), scene.step.solver.seed);
}

}  // namespace cdpowder
