// world_check.cpp — one pass over the spheres' arrays, the first problem named.
#include "cdpowder/model/world_check.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace cdpowder {

namespace {

std::optional<std::string> vector_problem(const std::vector<Vec3>& values, const char* name) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!values[i].allFinite()) {
      return fmt::format("the {} of sphere {} is ({}, {}, {}), expected finite numbers", name, i,
                         values[i].x(), values[i].y(), values[i].z());
    }
  }
  return std::nullopt;
}

/// `values[i]` finite and above 0 (`positive`) or at least 0.
std::optional<std::string> scalar_problem(const std::vector<double>& values, const char* name,
                                          bool positive) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double v = values[i];
    if (std::isfinite(v) && (positive ? v > 0.0 : v >= 0.0)) continue;
    return fmt::format("the {} of sphere {} is {}, expected a finite number {}", name, i, v,
                       positive ? "> 0" : "≥ 0");
  }
  return std::nullopt;
}

std::optional<std::string> size_problem(const Bodies& b) {
  const std::size_t n = b.size();
  const std::array<std::size_t, 8> sizes = {b.velocity.size(),        b.angular_velocity.size(),
                                            b.radius.size(),          b.inverse_mass.size(),
                                            b.inverse_inertia.size(), b.external_force.size(),
                                            b.external_torque.size(), b.fixed.size()};
  for (const std::size_t size : sizes) {
    if (size != n) {
      return fmt::format(
          "the spheres' arrays differ in length ({} positions, {} values of "
          "another field)",
          n, size);
    }
  }
  return std::nullopt;
}

std::optional<std::string> fixed_problem(const Bodies& b) {
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (b.fixed[i] > 1) {
      return fmt::format("the fixed flag of sphere {} is {}, expected 0 or 1", i,
                         static_cast<int>(b.fixed[i]));
    }
    if (b.fixed[i] == 1 && (b.inverse_mass[i] != 0.0 || b.inverse_inertia[i] != 0.0)) {
      return fmt::format("sphere {} is fixed but has 1/m = {} and 1/I = {}, expected 0 for both", i,
                         b.inverse_mass[i], b.inverse_inertia[i]);
    }
  }
  return std::nullopt;
}

std::optional<std::string> far_problem(const std::vector<Vec3>& position) {
  for (std::size_t i = 0; i < position.size(); ++i) {
    if (position[i].cwiseAbs().maxCoeff() > kMaxCoordinate) {
      return fmt::format(
          "the position of sphere {} is ({}, {}, {}), expected coordinates within "
          "±{:g} R (doubles are too sparse beyond)",
          i, position[i].x(), position[i].y(), position[i].z(), kMaxCoordinate);
    }
  }
  return std::nullopt;
}

std::optional<std::string> bodies_problem(const Bodies& b) {
  if (auto p = size_problem(b)) return p;
  if (auto p = vector_problem(b.position, "position")) return p;
  if (auto p = far_problem(b.position)) return p;
  if (auto p = vector_problem(b.velocity, "velocity")) return p;
  if (auto p = vector_problem(b.angular_velocity, "angular velocity")) return p;
  if (auto p = vector_problem(b.external_force, "external force")) return p;
  if (auto p = vector_problem(b.external_torque, "external torque")) return p;
  if (auto p = scalar_problem(b.radius, "radius", /*positive=*/true)) return p;
  if (auto p = scalar_problem(b.inverse_mass, "inverse mass", /*positive=*/false)) return p;
  if (auto p = scalar_problem(b.inverse_inertia, "inverse inertia", /*positive=*/false)) return p;
  return fixed_problem(b);
}

std::optional<std::string> global_problem(const World& w) {
  const auto not_finite = [](double v) { return !std::isfinite(v); };
  if (not_finite(w.box.lx) || not_finite(w.box.ly) || w.box.lx <= 0.0 || w.box.ly <= 0.0) {
    return fmt::format("the cell is {} × {}, expected finite sides > 0", w.box.lx, w.box.ly);
  }
  if (!w.gravity.allFinite()) return std::string("gravity is not finite");
  const Piston& p = w.walls.piston;
  if (not_finite(p.height) || not_finite(p.velocity) || not_finite(p.force) || not_finite(p.mass) ||
      p.mass <= 0.0) {
    return fmt::format(
        "the piston has height {}, velocity {}, force {} and mass {}, expected "
        "finite numbers and a mass > 0",
        p.height, p.velocity, p.force, p.mass);
  }
  if (not_finite(w.time) || w.time < 0.0) {
    return fmt::format("the time is {}, expected a finite number ≥ 0", w.time);
  }
  if (w.step < 0) return fmt::format("the step is {}, expected ≥ 0", w.step);
  return std::nullopt;
}

}  // namespace

std::optional<std::string> world_problem(const World& world) {
  if (auto p = global_problem(world)) return p;
  return bodies_problem(world.bodies);
}

}  // namespace cdpowder
