// slabs.hpp — the two slabs a step's passes are cut into, so that two threads can solve them at
// once (docs/lab/2026-11-26-two-slabs.md). The spheres are split by height at one horizontal
// cut: slab 0 below, slab 1 above. A pass visits the contacts across the cut, then those
// inside slab 0 and those inside slab 1: the last two touch no common sphere, so on two threads
// they are solved side by side and the pass waits once, at its end.
// The cut is a function of the state alone (never of the thread count), so the visiting order,
// and with it every result, is the same on one thread or two.
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/core/vec3.hpp"

#include <cstdint>
#include <vector>

namespace cdpowder {

/// Below this many sphere–sphere contacts a step is not cut: a pass then takes a few
/// microseconds, no more than handing work to a second thread costs (≈ 1–2 µs a hand-over,
/// slab_solve.hpp).
inline constexpr std::size_t kMinPairsToCut = 256;

/// What a wall contact costs a cut step, in pair visits (its visits in the passes and its share
/// of the mixing), timed slab by slab on the paper's fixtures
/// (docs/lab/2026-11-27-colourings-kept-cut-retuned.md): a bottom-wall contact is batched like
/// the pairs (coloured_sweep.hpp) and costs about one; the piston's are solved one at a time
/// along the piston's velocity and cost about three.
inline constexpr double kBottomWallVisitCost = 1.0;
inline constexpr double kPistonVisitCost = 3.0;

/// Sets slab[i] ∈ {0, 1} for every sphere: 1 when its height z is at or above the cut, a
/// mid-height (z_a + z_b)/2 of a pair contact chosen so that the two slabs hold about the same
/// work: as many pairs below it as above, less kBottomWallVisitCost per bottom-wall contact
/// (slab 0) and more kPistonVisitCost per piston contact (slab 1). Leaves `slab` empty (one
/// slab, no cut) below kMinPairsToCut pairs. `scratch` is reused.
void cut_into_slabs(const std::vector<Vec3>& positions, const Contacts& contacts,
                    std::vector<std::uint8_t>& slab, std::vector<double>& scratch);

}  // namespace cdpowder
