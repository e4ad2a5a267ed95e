// detect_contacts.hpp — stage 1 of a step: the candidate contacts and their frozen
// geometry (physics.md §4.2–4.3).
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/core/pieces.hpp"
#include "cdpowder/detect/candidate_list.hpp"
#include "cdpowder/detect/cell_grid.hpp"
#include "cdpowder/detect/detection_settings.hpp"
#include "cdpowder/detect/sphere_scan.hpp"
#include "cdpowder/model/world.hpp"

#include <vector>

namespace cdpowder {

/// Largest gap at which a pair is a candidate this step:
/// max(d_coh, 2 v_max Δt) + skin (physics.md §4.3), v_max the largest surface speed.
double candidate_gap(const World& world, const DetectionSettings& settings);

/// What a detection in two pieces keeps from step to step: the second piece's wall contacts
/// (the piston's) before they join the first's (so that no step allocates). The pairs are
/// written in place.
struct DetectionScratch {
  std::vector<WallProblem> walls;
};

/// Wraps positions into the box and fills the geometry of every candidate (a, b, n, g,
/// levers, r_eff) in `contacts`, pairs sorted by (a, b), walls by (wall, sphere). Pairs of
/// two fixed spheres are skipped: nothing can move them. Sphere pairs come from `reuse`,
/// rebuilt through `grid` when it no longer covers the step (candidate_list.hpp); without
/// one, from a list built for this call. The contacts are the same either way.
/// With `pieces` and `scratch` (and a list to reuse), the passes over the spheres and over the
/// candidate list run in pieces side by side on the runner's threads: each piece of the list
/// counts its pairs, then writes them in place, after the pieces before it: the same contacts,
/// bit for bit. A rebuild of the list runs in pieces on the runner's threads too.
void detect_contacts(World& world, const DetectionSettings& settings, CellGrid& grid,
                     Contacts& contacts, CandidateList* reuse = nullptr,
                     PieceRunner* pieces = nullptr, DetectionScratch* scratch = nullptr);

}  // namespace cdpowder
