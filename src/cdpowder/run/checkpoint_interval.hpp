// checkpoint_interval.hpp — a run's --checkpoint-every, kept in its folder (checkpoint.toml)
// beside the checkpoint, so that `cdpowder resume DIR` goes on writing checkpoints at the
// same interval without being told again (docs/outputs.md, "Checkpoints and resume").
#pragma once

#include <filesystem>
#include <optional>

namespace cdpowder {

/// Writes (atomically) the interval [t0] the run keeps its checkpoint at.
void remember_checkpoint_interval(const std::filesystem::path& out, double every);

/// The interval a run in `out` was started or last resumed with, or nothing (no
/// --checkpoint-every, or a folder of a build that did not keep it). Throws ConfigError for a
/// file that is not what remember_checkpoint_interval writes.
std::optional<double> remembered_checkpoint_interval(const std::filesystem::path& out);

}  // namespace cdpowder
