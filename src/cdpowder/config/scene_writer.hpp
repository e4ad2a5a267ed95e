// scene_writer.hpp — a validated Scene back to TOML (Scene::effective_toml): every key with
// the value the run used, defaults filled in, numbers in their shortest exact form. Every
// output records it (style guide 3.7).
#pragma once

#include "cdpowder/config/scene.hpp"

#include <string>

namespace cdpowder::detail {

/// The validated scene as TOML: every key with its effective value. Unset optional keys
/// (piston.pressure, piston.force, piston.height) are left out: TOML has no null.
std::string write_effective_toml(const Scene& s);

/// A double as the effective TOML writes it: fmt's shortest exact form, with ".0" when that
/// looks like an integer (25.0, 0.01, 1e-07).
std::string shortest_float_text(double value);

}  // namespace cdpowder::detail
