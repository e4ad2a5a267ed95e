// provenance.cpp — the '#' header of CSV outputs.
#include "cdpowder/io/provenance.hpp"

#include "cdpowder/version.hpp"

#include <fmt/format.h>

namespace cdpowder {

std::string provenance_header(const Scene& scene) {
  std::string header = fmt::format("# cdpowder {} (commit {})\n# scene: {}\n# seed: {}\n", kVersion,
                                   kGitCommit, scene.source.string(), scene.step.solver.seed);
  if (scene.deposition) header += fmt::format("# deposition seed: {}\n", scene.deposition->seed);
  return header;
}

}  // namespace cdpowder
