// deposition.cpp — ballistic deposition. The deposited spheres are kept in a 2D column
// grid over (x, y), so a falling sphere only examines the columns within its capture reach:
// O(N × spheres per column) instead of O(N²).
#include "cdpowder/setup/deposition.hpp"

#include "cdpowder/analysis/porosity.hpp"
#include "cdpowder/core/rng.hpp"
#include "cdpowder/detect/cell_grid.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace cdpowder {

namespace {

/// Columns of deposited spheres over the periodic (x, y) cell.
class ColumnGrid {
 public:
  /// Columns of edge ≥ min_edge, at most max(4096, 16 × spheres) of them (edge_within:
  /// lx = 10^9 R once asked for 10^9 columns, std::bad_alloc).
  ColumnGrid(const PeriodicBox& box, double min_edge, int spheres)
      : ColumnGrid(box,
                   edge_within(min_edge, std::max(kMinColumnLimit, kMaxColumnsPerSphere * spheres),
                               [&box](double e) {
                                 return cells_along(box.lx, e) * cells_along(box.ly, e);
                               })) {}

 private:
  static constexpr double kMaxColumnsPerSphere = 16.0;
  static constexpr double kMinColumnLimit = 4096.0;

  ColumnGrid(const PeriodicBox& box, double edge)
      : nx_(static_cast<int>(cells_along(box.lx, edge))),
        ny_(static_cast<int>(cells_along(box.ly, edge))),
        edge_x_(box.lx / nx_),
        edge_y_(box.ly / ny_),
        columns_(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_)) {}

 public:
  void add(BodyIndex i, const Vec3& p) { columns_[column_of(p)].push_back(i); }

  /// Calls visit(j) for every sphere in the column of p and its neighbours (each once).
  template <typename Visitor>
  void for_each_near(const Vec3& p, Visitor&& visit) const {
    const int cx = std::clamp(static_cast<int>(p.x() / edge_x_), 0, nx_ - 1);
    const int cy = std::clamp(static_cast<int>(p.y() / edge_y_), 0, ny_ - 1);
    std::array<int, 9> seen{};
    int count = 0;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const int c = ((cy + dy + ny_) % ny_) * nx_ + (cx + dx + nx_) % nx_;
        if (std::find(seen.begin(), seen.begin() + count, c) != seen.begin() + count) continue;
        seen[count++] = c;
        for (const BodyIndex j : columns_[static_cast<std::size_t>(c)]) visit(j);
      }
    }
  }

 private:
  [[nodiscard]] std::size_t column_of(const Vec3& p) const {
    const int cx = std::clamp(static_cast<int>(p.x() / edge_x_), 0, nx_ - 1);
    const int cy = std::clamp(static_cast<int>(p.y() / edge_y_), 0, ny_ - 1);
    return static_cast<std::size_t>(cy) * static_cast<std::size_t>(nx_) +
           static_cast<std::size_t>(cx);
  }

  int nx_;
  int ny_;
  double edge_x_;
  double edge_y_;
  std::vector<std::vector<BodyIndex>> columns_;
};

/// Smallest t ≥ 0 with |p + t u − c| = reach (u a unit vector), or +∞ if the ray misses.
double ray_hits_sphere(const Vec3& p, const Vec3& u, const Vec3& c, double reach) {
  const Vec3 d = p - c;
  const double b = d.dot(u);
  const double q = d.squaredNorm() - reach * reach;
  if (q <= 0.0) return 0.0;  // already within reach (touching up to round-off)
  const double discriminant = b * b - q;
  if (discriminant < 0.0 || b >= 0.0) return std::numeric_limits<double>::infinity();
  return -b - std::sqrt(discriminant);
}

}  // namespace

void deposit_ballistically(const DepositionConfig& config, double density, Bodies& bodies,
                           const StopRequest& stop_requested) {
  const PeriodicBox box{config.lx, config.ly};
  Rng rng = make_rng(config.seed, RngStream::Deposition);
  const double gap = config.capture_gap();
  const double r_max = config.radius_max;
  // horizontal reach of a capture: two largest spheres plus the capture gap
  ColumnGrid columns(box, 2.0 * r_max + std::max(gap, 0.0), config.spheres);

  constexpr int kSpheresBetweenStopChecks = 256;
  for (int n = 0; n < config.spheres; ++n) {
    if (n % kSpheresBetweenStopChecks == 0 && stop_requested && stop_requested()) {
      throw Interrupted(fmt::format("interrupted during the deposition, after {} of {} spheres", n,
                                    config.spheres));
    }
    const double x = config.lx * uniform01(rng);
    const double y = config.ly * uniform01(rng);
    const double radius =
        config.radius_min + (config.radius_max - config.radius_min) * uniform01(rng);
    const Vec3 column(x, y, 0.0);

    // the highest height at which the falling centre comes within the capture distance
    double capture_z = radius + gap;  // the substrate (same surface gap as for spheres)
    std::int64_t captor = -1;
    columns.for_each_near(column, [&](BodyIndex j) {
      const double reach = radius + bodies.radius[j] + gap;
      const Vec3 d = box.minimum_image(bodies.position[j] - column);
      const double horizontal_sq = d.x() * d.x() + d.y() * d.y();
      if (horizontal_sq >= reach * reach) return;
      const double z = bodies.position[j].z() + std::sqrt(reach * reach - horizontal_sq);
      if (z > capture_z) {
        capture_z = z;
        captor = j;
      }
    });

    // move from the capture point towards the captor's centre (straight down for the
    // substrate) until the first contact with any sphere or the substrate
    const Vec3 start(x, y, capture_z);
    Vec3 direction(0.0, 0.0, -1.0);
    if (captor >= 0) {
      const Vec3 to_captor = box.minimum_image(bodies.position[captor] - start);
      direction = to_captor.normalized();
    }
    double travel = direction.z() < 0.0 ? (start.z() - radius) / -direction.z()
                                        : std::numeric_limits<double>::infinity();
    columns.for_each_near(column, [&](BodyIndex j) {
      const Vec3 image = start + box.minimum_image(bodies.position[j] - start);
      travel =
          std::min(travel, ray_hits_sphere(start, direction, image, radius + bodies.radius[j]));
    });
    Vec3 placed = start + travel * direction;
    box.wrap(placed);
    const BodyIndex i = bodies.add_sphere(placed, radius, density);
    columns.add(i, placed);
  }
}

double deposit_height(const Bodies& bodies) {
  double top = 0.0;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    top = std::max(top, bodies.position[i].z() + bodies.radius[i]);
  }
  return top;
}

double deposit_porosity(const Bodies& bodies, const PeriodicBox& box) {
  const double top = deposit_height(bodies);
  return top > 0.0 ? 1.0 - grain_volume(bodies) / (box.area() * top) : 0.0;
}

}  // namespace cdpowder
