// provenance.hpp — what produced an output: program version and commit, scene, seed.
// Every CSV starts with these as '#' lines (the particle reader skips them), and
// summary.json carries them as fields, so a result can always be traced and rerun.
#pragma once

#include "cdpowder/config/scene.hpp"

#include <string>

namespace cdpowder {

/// "# cdpowder 0.1.0 (commit abc123)\n# scene: …\n# seed: 1\n", plus "# deposition seed: …"
/// when the spheres come from a deposit.
std::string provenance_header(const Scene& scene);

}  // namespace cdpowder
