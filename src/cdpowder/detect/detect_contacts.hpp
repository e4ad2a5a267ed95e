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

/// What a detection in two pieces keeps from step to step: the second piece's contacts
/// before they join the first's (so that no step allocates).
struct DetectionScratch {
  std::vector<PairProblem> pairs;
  std::vector<WallProblem> walls;
};

/// Wraps positions into the box and fills the geometry of every candidate (a, b, n, g,
/// levers, r_eff) in `contacts`, pairs sorted by (a, b), walls by (wall, sphere). Pairs of
/// two fixed spheres are skipped: nothing can move them. Sphere pairs come from `reuse`,
/// rebuilt through `grid` when it no longer covers the step (candidate_list.hpp); without
/// one, from a list built for this call. The contacts are the same either way.
/// With `pieces` and `scratch` (and a list to reuse), the passes over the spheres and over the
/// candidate list run in two halves side by side on the runner's threads, each half writing
/// its own contacts, joined in order: the same contacts, bit for bit. A rebuild of the list
/// runs on the caller.
void detect_contacts(World& world, const DetectionSettings& settings, CellGrid& grid,
                     Contacts& contacts, CandidateList* reuse = nullptr,
                     PieceRunner* pieces = nullptr, DetectionScratch* scratch = nullptr);

}  // namespace cdpowder
