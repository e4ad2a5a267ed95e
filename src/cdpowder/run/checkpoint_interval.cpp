// checkpoint_interval.cpp — checkpoint.toml, one key, written atomically and read strictly.
#include "cdpowder/run/checkpoint_interval.hpp"

#include "cdpowder/config/config_error.hpp"
#include "cdpowder/io/atomic_file.hpp"
#include "cdpowder/run/run_folder.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <cmath>

namespace cdpowder {

void remember_checkpoint_interval(const std::filesystem::path& out, double every) {
  write_file_atomically(
      checkpoint_interval_path(out),
      fmt::format("# --checkpoint-every of the run in this folder; `cdpowder resume` goes on "
                  "with it\nevery = {}   # [t0] of simulated time\n",
                  every));
}

std::optional<double> remembered_checkpoint_interval(const std::filesystem::path& out) {
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

}  // namespace cdpowder
