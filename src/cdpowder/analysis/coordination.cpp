// coordination.cpp — closed-contact counts.
#include "cdpowder/analysis/coordination.hpp"

#include "cdpowder/contact/contact_view.hpp"

#include <numeric>

namespace cdpowder {

std::vector<int> contacts_per_sphere(const Contacts& contacts, std::size_t sphere_count) {
  std::vector<int> count(sphere_count, 0);
  for_each_contact(contacts, [&](const ContactView& c) {
    if (!c.closed()) return;
    ++count[c.b];
    if (c.is_pair()) ++count[c.a];
  });
  return count;
}

double coordination_number(const Contacts& contacts, std::size_t sphere_count) {
  if (sphere_count == 0) return 0.0;
  const std::vector<int> count = contacts_per_sphere(contacts, sphere_count);
  return static_cast<double>(std::accumulate(count.begin(), count.end(), 0L)) /
         static_cast<double>(sphere_count);
}

}  // namespace cdpowder
