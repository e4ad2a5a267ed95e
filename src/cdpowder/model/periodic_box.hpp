// periodic_box.hpp — the simulation cell: periodic in x and y, open in z (physics.md §4.2).
#pragma once

#include "cdpowder/core/vec3.hpp"

#include <cmath>

namespace cdpowder {

struct PeriodicBox {
  double lx = 25.0;  ///< L_x, period along x [R]
  double ly = 25.0;  ///< L_y, period along y [R]

  /// Shortest periodic image of a separation vector: d_x -= L_x round(d_x/L_x), same for y;
  /// z is not periodic.
  [[nodiscard]] Vec3 minimum_image(Vec3 d) const {
    d.x() = minimum_image_1d(d.x(), lx);
    d.y() = minimum_image_1d(d.y(), ly);
    return d;
  }

  /// d − L round(d/L), rounding half to even. Nearly every separation is already its own
  /// image, |d| ≤ L/2: then d/L rounds to at most 1/2 in magnitude (L/2 is exact), which rounds
  /// to ±0, and d − L·(±0) = d + 0.0 (−0.0 becomes +0.0, every other d stays). That branch
  /// gives the formula's bits without its division and its call into the maths library
  /// (x86-64 without SSE4.1 has no rounding instruction); NaN takes the formula.
  [[nodiscard]] static double minimum_image_1d(double d, double length) {
    if (std::abs(d) <= 0.5 * length) return d + 0.0;
    return d - length * std::nearbyint(d / length);
  }

  /// Maps a position into [0, L_x) × [0, L_y) × R.
  void wrap(Vec3& position) const {
    // A position already in the cell is its own image: for +0 ≤ x < L, x/L ≤ pred(L)/L
    // rounds to at most 1 − 2⁻⁵³, so ⌊x/L⌋ = 0 and x − L·0 = x. It is left alone without the
    // two divisions: most positions, every step, in detection and integration. −0.0 is not
    // in the cell here: the formula turns it into +0.0.
    if (!std::signbit(position.x()) && position.x() < lx && !std::signbit(position.y()) &&
        position.y() < ly) {
      return;
    }
    position.x() -= lx * std::floor(position.x() / lx);
    position.y() -= ly * std::floor(position.y() / ly);
    // x − L floor(x/L) can round to exactly L for x just below a multiple of L (and the
    // minus above can leave −0.0); keep the half-open interval [0, L).
    if (position.x() >= lx || position.x() < 0.0) position.x() = 0.0;
    if (position.y() >= ly || position.y() < 0.0) position.y() = 0.0;
  }

  [[nodiscard]] double area() const { return lx * ly; }
};

}  // namespace cdpowder
