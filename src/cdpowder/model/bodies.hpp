// bodies.hpp — per-sphere state as structure of arrays.
// Index i is the same sphere in every array. Units: lengths [R], velocities [R/t0],
// masses [ρR³], forces [F_coh], torques [F_coh R] (physics.md §2).
#pragma once

#include "cdpowder/core/index.hpp"
#include "cdpowder/core/vec3.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

namespace cdpowder {

struct Bodies {
  std::vector<Vec3> position;           ///< r_i, sphere centre [R]
  std::vector<Vec3> velocity;           ///< v_i(t) [R/t0]
  std::vector<Vec3> angular_velocity;   ///< ω_i(t) [1/t0]
  std::vector<double> radius;           ///< R_i [R]
  std::vector<double> inverse_mass;     ///< 1/m_i, 0 for a fixed sphere [1/(ρR³)]
  std::vector<double> inverse_inertia;  ///< 1/I_i, solid sphere I = (2/5) m R², 0 if fixed
  std::vector<Vec3> external_force;     ///< constant applied force (gravity not included) [F_coh]
  std::vector<Vec3> external_torque;    ///< constant applied torque [F_coh R]
  std::vector<std::uint8_t> fixed;      ///< 1: the sphere never moves (infinite mass and inertia)

  [[nodiscard]] std::size_t size() const { return position.size(); }

  /// Appends a sphere of the given radius and density at rest; returns its index.
  BodyIndex add_sphere(const Vec3& centre, double sphere_radius, double density,
                       bool is_fixed = false) {
    const double mass =
        density * 4.0 / 3.0 * std::numbers::pi * sphere_radius * sphere_radius * sphere_radius;
    const double inertia = 0.4 * mass * sphere_radius * sphere_radius;
    position.push_back(centre);
    velocity.emplace_back(Vec3::Zero());
    angular_velocity.emplace_back(Vec3::Zero());
    radius.push_back(sphere_radius);
    inverse_mass.push_back(is_fixed ? 0.0 : 1.0 / mass);
    inverse_inertia.push_back(is_fixed ? 0.0 : 1.0 / inertia);
    external_force.emplace_back(Vec3::Zero());
    external_torque.emplace_back(Vec3::Zero());
    fixed.push_back(is_fixed ? 1 : 0);
    return static_cast<BodyIndex>(position.size() - 1);
  }

  [[nodiscard]] double mass(std::size_t i) const {
    return inverse_mass[i] > 0.0 ? 1.0 / inverse_mass[i] : 0.0;
  }

  [[nodiscard]] double inertia(std::size_t i) const {
    return inverse_inertia[i] > 0.0 ? 1.0 / inverse_inertia[i] : 0.0;
  }

  /// The smallest radius; ∞ without spheres.
  [[nodiscard]] double min_radius() const {
    double r = std::numeric_limits<double>::infinity();
    for (const double ri : radius) r = ri < r ? ri : r;
    return r;
  }

  [[nodiscard]] double max_radius() const {
    double r = 0.0;
    for (const double ri : radius) r = ri > r ? ri : r;
    return r;
  }
};

}  // namespace cdpowder
