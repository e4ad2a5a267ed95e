// packings.cpp — the FCC-with-vacancies packing.
#include "support/packings.hpp"

#include "cdpowder/core/rng.hpp"
#include "cdpowder/detect/detect_contacts.hpp"
#include "cdpowder/solver/build.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

namespace cdpowder::bench {

Packing fcc_packing_with_vacancies(int spheres, std::uint64_t seed) {
  constexpr double kVacancy = 0.4;
  const double a = 2.0 * std::sqrt(2.0);  // cubic cell of FCC with neighbour distance 2
  const double sites_needed = spheres / (1.0 - kVacancy);
  // cells_xy² × cells_z × 4 ≥ sites, with the height about equal to the width
  const int cells = std::max(3, static_cast<int>(std::ceil(std::cbrt(sites_needed / 4.0))));
  const int cells_z =
      std::max(1, static_cast<int>(std::ceil(sites_needed / (4.0 * cells * cells))));
  const Vec3 basis[4] = {Vec3(0, 0, 0), Vec3(0.5, 0.5, 0), Vec3(0.5, 0, 0.5), Vec3(0, 0.5, 0.5)};
  std::vector<Vec3> sites;
  for (int k = 0; k < cells_z; ++k) {
    for (int j = 0; j < cells; ++j) {
      for (int i = 0; i < cells; ++i) {
        for (const Vec3& b : basis) sites.push_back(a * (Vec3(i, j, k) + b) + Vec3(0, 0, 1.0));
      }
    }
  }
  Rng rng = make_rng(seed, RngStream::Deposition);
  for (std::size_t i = sites.size(); i > 1; --i) {  // Fisher–Yates, as shuffle_indices draws
    std::swap(sites[i - 1], sites[rng(static_cast<std::uint32_t>(i))]);
  }
  sites.resize(std::min<std::size_t>(sites.size(), static_cast<std::size_t>(spheres)));
  // lattice order (by z, then y, x) as a deposition would produce
  std::sort(sites.begin(), sites.end(), [](const Vec3& p, const Vec3& q) {
    return std::tie(p.z(), p.y(), p.x()) < std::tie(q.z(), q.y(), q.x());
  });

  Packing packing;
  World& world = packing.world;
  world.box = PeriodicBox{a * cells, a * cells};
  world.walls.bottom.enabled = true;
  double top = 0.0;
  for (const Vec3& p : sites) {
    const BodyIndex i = world.bodies.add_sphere(p, 1.0, 1.0);
    // small random motion so that every contact has work to do
    world.bodies.velocity[i] =
        1e-3 * Vec3(uniform01(rng) - 0.5, uniform01(rng) - 0.5, uniform01(rng) - 0.5);
    top = std::max(top, p.z() + 1.0);
  }
  Piston& piston = world.walls.piston;
  piston.enabled = true;
  piston.mass = 1000.0;
  piston.force = world.box.area() / 400.0;  // the paper's pressure F_coh/(400 R²)
  piston.height = top;
  packing.settings.laws.spheres.mu_roll = 0.3;
  packing.settings.laws.spheres.mu_twist = 0.3;
  packing.settings.laws.walls = packing.settings.laws.spheres;
  return packing;
}

void prepare_contacts(Packing& packing, StepWorkspace& work) {
  detect_contacts(packing.world, packing.settings.detection(), work.grid, work.contacts);
  build_local_problems(packing.world, packing.settings, work.action_cache, work.contacts,
                       work.velocities);
}

}  // namespace cdpowder::bench
