// packings.hpp — reproducible dense cohesive packings for the benchmarks, defined once.
// An FCC lattice of touching unit spheres (nearest-neighbour distance 2R) on the bottom
// wall, with a random 40 % of the sites left empty, under the paper's piston: a connected,
// fully cohesive network with coordination ≈ 7 (a compacted cohesive powder has 3–6).
#pragma once

#include "cdpowder/solver/step.hpp"

#include <cstdint>

namespace cdpowder::bench {

struct Packing {
  World world;
  StepSettings settings;
};

/// About `spheres` spheres (exactly, unless the lattice is too small), fixed seed.
Packing fcc_packing_with_vacancies(int spheres, std::uint64_t seed = 1);

/// Runs detection and the build stage, so `work` holds the step's contact problems.
void prepare_contacts(Packing& packing, StepWorkspace& work);

}  // namespace cdpowder::bench
