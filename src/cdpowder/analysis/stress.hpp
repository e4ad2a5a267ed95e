// stress.hpp — the Christoffersen stress tensor and its compressive and tensile parts
// (Bartels et al. eq. stress; physics.md §11.2):
//   σ_ij = (1/V) Σ_c F^c_i l^c_j,
// F^c the force on body b of contact c, l^c the branch vector from a to b: for a pair
// (R_a + R_b + g) n (minimum image), for a wall contact (R + g) n, from the contact point
// on the wall to the sphere centre. Compression gives σ_zz > 0. Contacts with F_n ≥ 0
// make σ⁺, with F_n < 0 (including open cohesive ones that still pull) σ⁻. In a static
// packing σ_zz = F/(L_x L_y) exactly (§11.2). Contact couples do not enter this average.
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/core/vec3.hpp"

namespace cdpowder {

struct StressTensors {
  Mat3 total = Mat3::Zero();             ///< σ [F_coh/R²]
  Mat3 compressive = Mat3::Zero();       ///< σ⁺
  Mat3 tensile = Mat3::Zero();           ///< σ⁻
  std::size_t compressive_contacts = 0;  ///< contacts with F_n > 0 (or = 0 and closed)
  std::size_t tensile_contacts = 0;      ///< contacts with F_n < 0
};

/// Stress of the contact forces of a solved step over the volume V [R³].
StressTensors stress_tensors(const Contacts& contacts, double volume);

}  // namespace cdpowder
