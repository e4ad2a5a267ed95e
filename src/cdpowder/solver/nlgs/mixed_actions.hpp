// mixed_actions.hpp — the contact actions as the flat vectors the Anderson mixing works on
// (anderson.hpp): which fields it carries, the actions into a vector and back.
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/contact/local_solve.hpp"
#include "cdpowder/core/aligned_vector.hpp"

#include <array>
#include <cstddef>
#include <type_traits>

namespace cdpowder {

/// Which parts of the actions the mixing carries. Modes without a threshold anywhere in the
/// step (μ_t = 0: rolling torques; μ_n = 0: torsion torques) stay +0 at every contact (the
/// kernels write +0 for a mode without a threshold), so leaving them out changes no sum the
/// mixing forms while it cuts the memory the mixing streams through: 4 instead of 8 doubles
/// per contact at the paper's (0,0) corner, where the mixing costs a quarter of the run.
/// Without either mode the coloured kernel also skips the torques (ColouredPass::torques).
struct MixedModes {
  bool rolling = true;
  bool twisting = true;

  [[nodiscard]] constexpr std::size_t doubles_per_action() const {
    return 4 + (rolling ? 3 : 0) + (twisting ? 1 : 0);
  }
};

/// The modes the mixing must carry this step: those with a threshold at some contact, and
/// those some (warm-started) action already holds non-zero.
MixedModes mixed_modes(const Contacts& contacts);

/// A ContactAction as its 8 doubles R_n, R_t, T_t, T_n (one 64-byte line), and which of them
/// the mixing carries: R_n and R_t always, T_t with kRolling, T_n with kTwisting.
using ActionFields = std::array<double, 8>;

inline ActionFields fields_of(const ContactAction& a) {
  const Vec3& t = a.tangential_force;
  const Vec3& r = a.rolling_torque;
  return {a.normal_force, t.x(), t.y(), t.z(), r.x(), r.y(), r.z(), a.twisting_torque};
}

inline ContactAction action_of(const ActionFields& f) {
  ContactAction a;
  a.normal_force = f[0];
  a.tangential_force = Vec3(f[1], f[2], f[3]);
  a.rolling_torque = Vec3(f[4], f[5], f[6]);
  a.twisting_torque = f[7];
  return a;
}

template <bool kRolling, bool kTwisting>
constexpr bool carried(std::size_t field) {
  if (field < 4) return true;  // R_n, R_t
  if (field < 7) return kRolling;
  return kTwisting;
}

/// Calls f(std::bool_constant<rolling>, std::bool_constant<twisting>) for `modes`, so the
/// loops over the contacts know their fields at compile time.
template <class F>
void with_modes(MixedModes modes, F&& f) {
  if (modes.rolling) {
    if (modes.twisting) return f(std::true_type{}, std::true_type{});
    return f(std::true_type{}, std::false_type{});
  }
  if (modes.twisting) return f(std::false_type{}, std::true_type{});
  return f(std::false_type{}, std::false_type{});
}

/// The actions of contacts [first, last) of the combined range (pairs, then walls), the
/// fields `modes` carries, into out[first × stride, last × stride); `out` has room for all
/// contacts. With `wall_at`, the walls' entries are in that order: entry pairs + j holds wall
/// wall_at[j] (a tiled step's mixing keeps each tile's walls together: tile_solve.hpp).
void flatten_range(const Contacts& contacts, MixedModes modes, std::size_t first, std::size_t last,
                   double* out, const ContactIndex* wall_at = nullptr);

/// All actions, flattened: out is resized to stride × contacts.
void flatten(const Contacts& contacts, MixedModes modes, AlignedVector<double>& out,
             const ContactIndex* wall_at = nullptr);

/// The next action from the mixed values at `mixed` (the fields carried; the others stay),
/// and its change from `action`, which it replaces: next − action field by field.
template <bool kRolling, bool kTwisting>
[[gnu::always_inline]] inline ContactAction take_mixed(const double* mixed, ContactAction& action) {
  const ActionFields a = fields_of(action);
  ActionFields next;
  ActionFields delta;
  std::size_t o = 0;
  for (std::size_t f = 0; f < a.size(); ++f) {
    next[f] = carried<kRolling, kTwisting>(f) ? mixed[o++] : a[f];
    delta[f] = next[f] - a[f];
  }
  action = action_of(next);
  return action_of(delta);
}

}  // namespace cdpowder
