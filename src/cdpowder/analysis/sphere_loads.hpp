// sphere_loads.hpp — the total contact force and torque on every sphere from the last step's
// contact actions (physics.md §5): what the solver applied to each sphere's velocity,
// divided by Δt/m and Δt/I. The same arithmetic as the passes (contact/velocity_change.hpp),
// so a sphere at rest under its contacts and the external load shows their balance.
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/core/vec3.hpp"

#include <cstddef>
#include <vector>

namespace cdpowder {

/// Per sphere, in index order.
struct SphereLoads {
  std::vector<Vec3> force;   ///< Σ of its contacts' forces (pairs and walls) [F_coh]
  std::vector<Vec3> torque;  ///< Σ of their torques about its centre [F_coh R]
};

/// The loads of `spheres` spheres from `contacts` (a step's contacts with their actions).
SphereLoads sphere_contact_loads(const Contacts& contacts, std::size_t spheres);

}  // namespace cdpowder
