// grow.hpp — room for more elements in a vector that is refilled every step, by an eighth
// rather than by std::vector's doubling: the contact arrays reach their size in the first
// steps and are kept for the run, so doubling leaves up to half of each unused for the whole
// run (the pairs' geometry, 128 bytes a contact: about 0.3 kB a sphere at 16 240 spheres).
#pragma once

#include <algorithm>
#include <cstddef>

namespace cdpowder {

/// Makes room for `more` elements after v.size(); when it must reallocate, the capacity grows
/// by at least an eighth, so n push_backs reallocate O(log n) times.
template <class Vector>
void reserve_for_more(Vector& v, std::size_t more) {
  const std::size_t need = v.size() + more;
  if (need <= v.capacity()) return;
  v.reserve(std::max(need, v.capacity() + v.capacity() / 8));
}

}  // namespace cdpowder
