// checkpoint_interval.hpp — a run's --checkpoint-every, kept in its folder (checkpoint.toml)
// beside the checkpoint, so that `cdpowder resume DIR` goes on writing checkpoints at the
// same interval without being told again (docs/outputs.md, "Checkpoints and resume").
#pragma once

#include "cdpowder/config/config_error.hpp"
#include "cdpowder/io/atomic_file.hpp"
#include "cdpowder/io/run_folder.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <cmath>
#include <filesystem>
#include <optional>

namespace cdpowder::app {

/// Writes (atomically) the interval [t0] the run keeps its checkpoint at.
inline void remember_checkpoint_interval(const std::filesystem::path& out, double every) {
  write_file_atomically(
      checkpoint_interval_path(out),
      fmt::format("# --checkpoint-every of the run in this folder; `cdpowder resume` goes on "
                  "with it\nevery = {}   # [t0] of simulated time\n",
                  every));
}

/// The interval a run in `out` was started or last resumed with, or nothing (no
/// --checkpoint-every, or a folder of a build that did not keep it). Throws ConfigError for a
/// file that is not what remember_checkpoint_interval writes.
inline std::optional<double> remembered_checkpoint_interval(const std::filesystem::path& out) {
  const std::filesystem::path file = checkpoint_interval_path(out);
  std::error_code error;
  if (!std::filesystem::exists(file, error)) return std::nullopt;
  toml::table table;
  try {
    table = toml::parse_file(file.string());
  } catch (const toml::parse_error& parse) {
    throw ConfigError({{file.string(), static_cast<int>(parse.source().begin.line),
                        static_cast<int>(parse.source().begin.column), "",
                        fmt::format("TOML syntax error: {}", shown(parse.description(), 160))}});
  }
  const std::optional<double> every = table["every"].value<double>();
  if (!every || !std::isfinite(*every) || *every <= 0.0 || table.size() != 1) {
    throw ConfigError(
        {{file.string(), 0, 0, "every",
          "expected the one key `every`, a number > 0 (the run's --checkpoint-every [t0]); "
          "give --checkpoint-every T to resume to replace the file"}});
  }
  return every;
}

}  // namespace cdpowder::app
