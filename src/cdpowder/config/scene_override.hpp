// scene_override.hpp — one "section.key=value" edit of a scene before it is read, and where
// it came from, so that a bad value is reported where the user wrote it: a command-line
// `--set`, a command option such as `--particles`, or a line of a sweep file.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace cdpowder {

/// ConfigIssue::file of a mistake in a command-line override (and in a table an override
/// created, which has no origin of its own).
inline constexpr const char* kCommandLineOverride = "--set";

struct SceneOverride {
  std::string text;                           ///< "section.key=value", the value in TOML
  std::string origin = kCommandLineOverride;  ///< "--set", or e.g. "sweep.toml:4:8"

  SceneOverride() = default;

  // NOLINTNEXTLINE(google-explicit-constructor): a plain string is a command-line --set
  SceneOverride(std::string override_text) : text(std::move(override_text)) {}

  // NOLINTNEXTLINE(google-explicit-constructor)
  SceneOverride(const char* override_text) : text(override_text) {}

  SceneOverride(std::string override_text, std::string where)
      : text(std::move(override_text)), origin(std::move(where)) {}
};

/// Command-line `--set` values as overrides.
inline std::vector<SceneOverride> command_line_overrides(const std::vector<std::string>& texts) {
  return {texts.begin(), texts.end()};
}

}  // namespace cdpowder
