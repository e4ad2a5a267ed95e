// run_fault.cpp — the checks of run_fault.hpp and their one-line messages.
#include "cdpowder/run/run_fault.hpp"

#include "cdpowder/config/scene_keys.hpp"
#include "cdpowder/contact/contact_view.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

namespace cdpowder {

namespace {

RunFault fault(const World& world, std::string quantity, std::int64_t body, double value) {
  RunFault f;
  f.quantity = std::move(quantity);
  f.body = body;
  f.step = world.step;
  f.time = world.time;
  f.value = value;
  return f;
}

std::string where(const RunFault& f) {
  return fmt::format("at step {} (t = {:.6g} t0)", f.step, f.time);
}

/// The first sphere whose `values` hold a non-finite component, or −1.
std::int64_t first_non_finite(const std::vector<Vec3>& values) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!values[i].allFinite()) return static_cast<std::int64_t>(i);
  }
  return -1;
}

/// The first sphere whose position, velocity or angular velocity is not finite.
std::optional<RunFault> non_finite_sphere(const World& world) {
  const Bodies& b = world.bodies;
  const std::array<std::pair<const std::vector<Vec3>*, const char*>, 3> fields{
      {{&b.position, "position"},
       {&b.velocity, "velocity"},
       {&b.angular_velocity, "angular velocity"}}};
  for (const auto& [values, name] : fields) {
    const std::int64_t i = first_non_finite(*values);
    if (i < 0) continue;
    const Vec3& v = (*values)[static_cast<std::size_t>(i)];
    RunFault f = fault(world, name, i, std::numeric_limits<double>::quiet_NaN());
    f.message = fmt::format(
        "the {} of sphere {} is not finite ({}, {}, {}) {}: the state can "
        "no longer be trusted (a Δt, load or size far outside the "
        "scene's scale?)",
        name, i, v.x(), v.y(), v.z(), where(f));
    return f;
  }
  return std::nullopt;
}

std::optional<RunFault> non_finite_piston(const World& world) {
  const Piston& piston = world.walls.piston;
  if (piston.enabled && !(std::isfinite(piston.height) && std::isfinite(piston.velocity))) {
    RunFault f = fault(world, "piston", -1, std::numeric_limits<double>::quiet_NaN());
    f.message = fmt::format("the piston's height or velocity is not finite ({}, {}) {}",
                            piston.height, piston.velocity, where(f));
    return f;
  }
  return std::nullopt;
}

/// The contact with the largest overlap (the step's diagnostics give only its size), found
/// with the diagnostics' own operations (contact_overlaps): the value named is the value the
/// test found, to the bit, and its contact the first that has it in Contacts' order.
RunFault largest_overlap(const World& world, const Contacts& contacts, double bound) {
  RunFault f = fault(world, "overlap", -1, 0.0);
  const char* wall = nullptr;
  const std::vector<double> overlaps = contact_overlaps(world, contacts);
  std::size_t k = 0;
  for_each_contact(contacts, [&](const ContactView& c) {
    const double overlap = overlaps[k++];
    if (overlap > f.value) {
      f.value = overlap;
      f.body = static_cast<std::int64_t>(c.is_pair() ? c.a : c.b);
      f.other = c.is_pair() ? static_cast<std::int64_t>(c.b) : -1;
      wall = c.is_pair() ? nullptr : c.wall == WallKind::Bottom ? "the bottom wall" : "the piston";
    }
  });
  const std::string with = wall != nullptr ? std::string(wall) : fmt::format("sphere {}", f.other);
  const Scene defaults;
  f.message = fmt::format(
      "sphere {} overlaps {} by {:.4g} R {}, more than {} = {:g} "
      "R: the contacts no longer hold the spheres apart (a load, "
      "pressure or Δt too large for the contact solver?)",
      f.body, with, f.value, where(f), detail::key_name(defaults, defaults.run.max_overlap), bound);
  return f;
}

}  // namespace

std::optional<RunFault> find_fault(const World& world, const Contacts& contacts,
                                   const StepDiagnostics& diagnostics, const FaultLimits& limits) {
  // the spheres are searched only when integrate()'s pass did not find them finite
  // (StepDiagnostics::spheres_finite)
  if (!diagnostics.spheres_finite) {
    if (auto f = non_finite_sphere(world)) return f;
  }
  if (auto f = non_finite_piston(world)) return f;
  // NaN compares false, so std::max in the diagnostics never holds one; positions are finite
  // here, so the largest overlap is too
  if (diagnostics.max_overlap > limits.max_overlap) {
    return largest_overlap(world, contacts, limits.max_overlap);
  }
  const Piston& piston = world.walls.piston;
  if (!piston.enabled) return std::nullopt;
  if (piston.height < 0.0) {
    RunFault f = fault(world, "piston height", -1, piston.height);
    f.message = fmt::format("the piston is below the bottom wall (height {:.6g} R) {}",
                            piston.height, where(f));
    return f;
  }
  // E = 1 − V_grains / (A Z_P) ≤ 0 once the piston has come down further than the grains'
  // own volume allows: spheres pressed into each other
  const double volume = world.box.area() * piston.height;
  const double porosity =
      volume > 0.0 ? 1.0 - limits.grain_volume / volume : -std::numeric_limits<double>::infinity();
  if (!(porosity > 0.0 && porosity < 1.0) && limits.grain_volume > 0.0) {
    RunFault f = fault(world, "porosity", -1, porosity);
    f.message = fmt::format(
        "the porosity under the piston is {:.6g}, outside (0, 1) {}: the "
        "spheres are pressed into each other",
        porosity, where(f));
    return f;
  }
  return std::nullopt;
}

}  // namespace cdpowder
