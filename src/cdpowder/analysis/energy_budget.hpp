// energy_budget.hpp — a run's energy budget (physics.md §17, "The energy budget"): the work the
// piston and gravity do, the kinetic energy, the cohesion's potential energy, and the cohesive
// bonds the steps form and break. What is left over is the energy the contacts dissipated
// (inelastic impacts, friction, rolling and torsion), which rigid contact dynamics never
// stores: W_piston + W_gravity = ΔK + ΔU_coh + D with D ≥ 0.
#pragma once

#include "cdpowder/contact/action_cache.hpp"
#include "cdpowder/contact/contact_law.hpp"
#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/model/world.hpp"

#include <cstdint>

namespace cdpowder {

/// Cohesive bonds one step formed and broke, against the step before: a contact is a bond
/// while it is cohesion-active (pair_cohesive / wall_cohesive, physics.md §6.2). Counted for
/// sphere pairs and wall contacts apart, whose laws may have other F_coh and d_coh.
struct BondChanges {
  std::int64_t pairs_formed = 0;
  std::int64_t pairs_broken = 0;
  std::int64_t walls_formed = 0;
  std::int64_t walls_broken = 0;

  BondChanges& operator+=(const BondChanges& o) {
    pairs_formed += o.pairs_formed;
    pairs_broken += o.pairs_broken;
    walls_formed += o.walls_formed;
    walls_broken += o.walls_broken;
    return *this;
  }

  [[nodiscard]] std::int64_t formed() const { return pairs_formed + walls_formed; }

  [[nodiscard]] std::int64_t broken() const { return pairs_broken + walls_broken; }
};

/// The bonds of `now` that were not bonds in `last` (formed) and those of `last` that are
/// not bonds in `now` (broken, also when the contact left the list): one merge pass over
/// each family, both sorted by key (contact/action_cache.hpp). `last` is the step before's
/// contacts as the warm-start cache holds them (ActionCache::last): every bond of that step
/// is there, also after a restore from a state file.
[[nodiscard]] BondChanges bond_changes(const KeyedContacts& last, const Contacts& now);

/// The cohesion's potential energy at the start of the step `contacts` was built for:
/// U = −Σ F_c (d_coh − max(g, 0)) over the cohesion-active contacts, each with its law's
/// d_coh, so a bond at contact holds −F_coh d_coh and one at the end of its range 0; breaking
/// a bond costs F_coh d_coh (physics.md §6.2) [F_coh R]. Summed in contact order.
[[nodiscard]] double cohesive_energy(const Contacts& contacts, const ContactLaws& laws);

/// Σ ½ m v² + ½ I ω² over the spheres, plus ½ M_P V_P² of an enabled piston [F_coh R].
[[nodiscard]] double kinetic_energy(const World& world);

/// Σ m_i z_i over the free spheres [ρR³ R]: their weight's potential is −g_z times it.
[[nodiscard]] double height_moment(const World& world);

/// Whether the budget covers every force that does work: no sphere has an applied force or
/// torque of its own (a particles file's fx … tz), and gravity is along z (a periodic wrap in
/// x or y would hide the work of a horizontal part).
[[nodiscard]] bool budget_is_complete(const World& world);

}  // namespace cdpowder
