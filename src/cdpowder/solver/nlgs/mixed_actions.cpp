// mixed_actions.cpp — the modes a step's mixing carries, and the actions flattened.
#include "cdpowder/solver/nlgs/mixed_actions.hpp"

#include <algorithm>

namespace cdpowder {

/// The modes the mixing must carry this step: those with a threshold at some contact, and
/// those some (warm-started) action already holds non-zero.
MixedModes mixed_modes(const Contacts& contacts) {
  MixedModes modes{false, false};
  const auto look = [&](double roll_cap, double twist_cap, const ContactAction& a) {
    modes.rolling = modes.rolling || has_threshold(roll_cap) || a.rolling_torque != Vec3::Zero();
    modes.twisting = modes.twisting || has_threshold(twist_cap) || a.twisting_torque != 0.0;
  };
  // Nothing changes once both modes are found (at the first contact where both have
  // thresholds): the pass stops then, testing between blocks of contacts so that a step with
  // neither mode (the (0,0) corner, every contact looked at) pays no test per contact.
  constexpr std::size_t kBlock = 64;
  const auto both = [&] { return modes.rolling && modes.twisting; };
  const std::size_t pairs = contacts.pairs.size();
  for (std::size_t first = 0; first < pairs && !both(); first += kBlock) {
    for (std::size_t k = first; k < std::min(pairs, first + kBlock); ++k) {
      look(contacts.pairs[k].roll_cap, contacts.pairs[k].twist_cap, contacts.pair_actions[k]);
    }
  }
  for (std::size_t k = 0; k < contacts.walls.size() && !both(); ++k) {
    look(contacts.walls[k].roll_cap, contacts.walls[k].twist_cap, contacts.wall_actions[k]);
  }
  return modes;
}

void flatten_range(const Contacts& contacts, MixedModes modes, std::size_t first, std::size_t last,
                   double* out, const ContactIndex* wall_at) {
  with_modes(modes, [&](auto rolling, auto twisting) {
    constexpr bool kRolling = decltype(rolling)::value;
    constexpr bool kTwisting = decltype(twisting)::value;
    constexpr std::size_t kStride = MixedModes{kRolling, kTwisting}.doubles_per_action();
    const std::size_t pairs = contacts.pairs.size();
    double* o = out + first * kStride;
    const auto put = [&](const ContactAction& action) {
      const ActionFields a = fields_of(action);
      for (std::size_t f = 0; f < a.size(); ++f) {
        if (carried<kRolling, kTwisting>(f)) *o++ = a[f];
      }
    };
    // the actions through pointers held in locals: the vectors' own pointers would be
    // reloaded after every store through `o`
    const ContactAction* const pair_actions = contacts.pair_actions.data();
    const ContactAction* const wall_actions = contacts.wall_actions.data();
    for (std::size_t k = first; k < std::min(last, pairs); ++k) put(pair_actions[k]);
    if (wall_at != nullptr) {
      for (std::size_t k = std::max(first, pairs); k < last; ++k) {
        put(wall_actions[wall_at[k - pairs]]);
      }
      return;
    }
    for (std::size_t k = std::max(first, pairs); k < last; ++k) put(wall_actions[k - pairs]);
  });
}

void flatten(const Contacts& contacts, MixedModes modes, AlignedVector<double>& out,
             const ContactIndex* wall_at) {
  out.resize(modes.doubles_per_action() * contacts.size());
  flatten_range(contacts, modes, 0, contacts.size(), out.data(), wall_at);
}

}  // namespace cdpowder
