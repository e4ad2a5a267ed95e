// coordination.hpp — how many force-carrying (closed, S = R_n + F_c > 0) contacts each
// sphere has, and their mean, the coordination number.
#pragma once

#include "cdpowder/contact/local_problem.hpp"

#include <vector>

namespace cdpowder {

/// Closed contacts per sphere (wall contacts count for the sphere), size = sphere count.
std::vector<int> contacts_per_sphere(const Contacts& contacts, std::size_t sphere_count);

/// Mean of contacts_per_sphere: (2 × closed pairs + closed wall contacts) / N.
double coordination_number(const Contacts& contacts, std::size_t sphere_count);

}  // namespace cdpowder
