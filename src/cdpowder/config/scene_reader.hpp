// scene_reader.hpp — reads a scene TOML file plus `--set section.key=value` overrides into
// a validated Scene. This is the one place where the scene is checked (style guide 3.8);
// every mistake becomes a ConfigIssue and all of them are thrown together as a ConfigError.
// docs/config.md lists every key, its symbol, unit, default and allowed range.
#pragma once

#include "cdpowder/config/config_error.hpp"
#include "cdpowder/config/scene.hpp"
#include "cdpowder/config/scene_override.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cdpowder {

/// What the command reading a scene needs of it, beyond the scene's own rules.
struct SceneReadOptions {
  /// Take the spheres from this particles CSV instead of the scene's [particles] or
  /// [deposition] (both are dropped). A relative path is taken from the working folder.
  std::optional<std::filesystem::path> particles_file;
  /// `compact`: the piston must be enabled, and the run goes until the blocked state.
  bool compaction = false;
  /// `deposit`: the scene must have a [deposition] section.
  bool deposition_required = false;
  /// The caller makes the spheres (make_world(scene, spheres)): the scene's [particles] and
  /// [deposition] are dropped, and none is needed.
  bool spheres_from_caller = false;
};

/// ConfigIssue::file of a mistake in SceneReadOptions::particles_file.
inline constexpr std::string_view kParticlesOption = "--particles";

/// Reads and validates `file` with `overrides` ("section.key=value", applied in order, after
/// the file and before validation; a mistake in one is reported at its origin). [particles] file is
/// resolved against the folder of `file`. Throws ConfigError listing every issue found (unreadable
/// file, TOML syntax, malformed override, unknown key, wrong type, value out of range, inconsistent
/// keys).
Scene read_scene(const std::filesystem::path& file, const std::vector<SceneOverride>& overrides,
                 const SceneReadOptions& options = {});

/// As read_scene, from text already in memory. `source_name` names the text in messages and
/// becomes Scene::source; a relative [particles] file is resolved against `base_dir`.
Scene read_scene_text(std::string_view toml_text, std::string_view source_name,
                      const std::vector<SceneOverride>& overrides,
                      const std::filesystem::path& base_dir, const SceneReadOptions& options = {});

}  // namespace cdpowder
