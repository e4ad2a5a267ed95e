// provenance.cpp — the '#' header of CSV outputs.
#include "cdpowder/io/provenance.hpp"

#include "cdpowder/version.hpp"

#include <fmt/format.h>

namespace cdpowder {

std::string provenance_header(const Scene& scene) {
  return fmt::format("# cdpowder {} (commit {})\n# scene: {}\n# seed: {}\n", kVersion, kGitCommit,
                     scene.source.string(), scene.step.solver.seed);
}

}  // namespace cdpowder
