// particles_csv.hpp — the initial spheres of a scene from a CSV file ([particles] file), and
// the check that the periodic cell is wide enough for them. Bad input becomes ConfigIssues
// naming file, line and column, all thrown together as one ConfigError (style guide 3.7).
// docs/config.md lists the columns.
#pragma once

#include "cdpowder/config/config_error.hpp"
#include "cdpowder/config/scene.hpp"
#include "cdpowder/model/bodies.hpp"

#include <filesystem>
#include <string_view>

namespace cdpowder {

/// Appends the spheres of `file` to `bodies`, with mass and inertia from `density` [ρ].
/// A header line names the columns, in any order: x, y, z, r required [R]; optional vx, vy,
/// vz [R/t0], wx, wy, wz [1/t0], fx, fy, fz [F_coh], tx, ty, tz [F_coh R], fixed (0/1 or
/// true/false). Blank lines and lines starting with '#' are skipped. On any issue, throws
/// ConfigError and leaves `bodies` unchanged.
void read_particles_csv(const std::filesystem::path& file, double density, Bodies& bodies);

/// As read_particles_csv, from text already in memory; `source_name` names it in messages.
void read_particles_csv_text(std::string_view text, std::string_view source_name, double density,
                             Bodies& bodies);

/// Throws ConfigError naming system.lx / system.ly when L < 2 (2 R_max + d + skin), with
/// d = max(contact.cohesion_range, contact.wall.cohesion_range): below that, a sphere could
/// meet two images of the same neighbour, and the minimum image is not unique.
/// Spheres overlapping the bottom wall (z < r) are allowed here.
void check_box_fits(const Scene& scene, const Bodies& bodies);

}  // namespace cdpowder
