// small_packing.hpp — a small packing whose first sweeps take every branch of the contact
// kernel, shared by the tests of the coloured sweep and its threads.
#pragma once

#include "cdpowder/detect/detect_contacts.hpp"
#include "cdpowder/solver/build.hpp"
#include "support/tiny_world.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace cdpowder::testing {

// A jittered FCC block of ≈ 300 spheres of slightly unequal radii (so the sliding change
// moves Ω: c ≠ 0) on the bottom wall under a piston, random velocities: contacts that
// open, stick, slide, roll and twist in the first sweeps.
struct SmallPacking {
  TinyScene scene{4 * 2.0 * std::sqrt(2.0), 4 * 2.0 * std::sqrt(2.0)};

  explicit SmallPacking(double mu_roll, double mu_twist = 0.2) {
    Rng rng = make_rng(7, RngStream::Deposition);
    const double a = 2.0 * std::sqrt(2.0);
    const std::array<Vec3, 4> basis = {Vec3(0, 0, 0), Vec3(0.5, 0.5, 0), Vec3(0.5, 0, 0.5),
                                       Vec3(0, 0.5, 0.5)};
    double top = 0.0;
    for (int k = 0; k < 5; ++k) {
      for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) {
          for (const Vec3& b : basis) {
            if (uniform01(rng) < 0.1) continue;  // a few vacancies
            const Vec3 jitter(uniform01(rng) - 0.5, uniform01(rng) - 0.5, uniform01(rng) - 0.5);
            const Vec3 p = a * (Vec3(i, j, k) + b) + Vec3(0, 0, 1.01) + 0.004 * jitter;
            const double r = 1.0 - 0.004 * uniform01(rng);
            const BodyIndex s = scene.add(p, r);
            scene.world.bodies.velocity[s] =
                0.05 * Vec3(uniform01(rng) - 0.5, uniform01(rng) - 0.5, uniform01(rng) - 0.5);
            scene.world.bodies.angular_velocity[s] =
                0.05 * Vec3(uniform01(rng) - 0.5, uniform01(rng) - 0.5, uniform01(rng) - 0.5);
            top = std::max(top, p.z() + r);
          }
        }
      }
    }
    scene.settings.laws.spheres.mu_roll = mu_roll;
    scene.settings.laws.spheres.mu_twist = mu_twist;
    scene.settings.laws.walls = scene.settings.laws.spheres;
    scene.world.walls.bottom.enabled = true;
    scene.world.walls.piston.enabled = true;
    scene.world.walls.piston.mass = 100.0;
    scene.world.walls.piston.force = 1.0;
    scene.world.walls.piston.height = top + 0.002;
    StepWorkspace& w = scene.work;
    detect_contacts(scene.world, scene.settings.detection(), w.grid, w.contacts);
    build_local_problems(scene.world, scene.settings, w.action_cache, w.contacts, w.velocities);
  }
};

}  // namespace cdpowder::testing
