// cohesive_opening.cpp — one pass over the cohesion-active contacts (the pairs in lanes:
// opening_lanes.inc).
#include "cdpowder/analysis/cohesive_opening.hpp"

#include "cdpowder/contact/contact_view.hpp"
#include "cdpowder/core/lanes.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace cdpowder {

namespace {

/// What the pairs' pass reads, through pointers held in locals.
struct PairOpeningInputs {
  const PairProblem* pairs = nullptr;
  const std::uint8_t* cohesive = nullptr;
  const std::uint8_t* fixed = nullptr;
  const Vec3* velocity = nullptr;        ///< bodies.velocity (a fixed sphere's)
  const SphereVelocity* next = nullptr;  ///< v* of the passes
};

}  // namespace

#define CDP_LANE_CODE "cdpowder/analysis/opening_lanes.inc"
#include "cdpowder/core/lanes_instantiate.inc"

namespace {

/// The largest opening speed of each kind over a range of contacts; −∞ where it has none.
struct OpeningSpeeds {
  double pair = -std::numeric_limits<double>::infinity();
  double wall = -std::numeric_limits<double>::infinity();
};

/// A piece's result on a cache line of its own (the pieces write theirs side by side).
struct alignas(64) PieceSpeeds {
  OpeningSpeeds value;
};

OpeningSpeeds opening_speeds(const World& world, const Contacts& contacts,
                             const VelocityCache& velocities, std::size_t first, std::size_t last) {
  const Bodies& bodies = world.bodies;
  // what integrate() leaves in bodies.velocity: v* unless the sphere is fixed
  const auto end_velocity = [&](BodyIndex i) -> const Vec3& {
    return bodies.fixed[i] != 0 ? bodies.velocity[i] : velocities.spheres[i].linear;
  };
  const Piston& piston = world.walls.piston;
  const double piston_speed = piston.enabled ? velocities.piston_velocity : piston.velocity;
  OpeningSpeeds out;
  // the pairs in blocks of lanes, then the rest of the pairs and the walls one by one
  const PairOpeningInputs lanes_in{.pairs = contacts.pairs.data(),
                                   .cohesive = contacts.pair_cohesive.data(),
                                   .fixed = bodies.fixed.data(),
                                   .velocity = bodies.velocity.data(),
                                   .next = velocities.spheres.data()};
  std::size_t rest = first;
  out.pair = CDP_LANES_FOR_CPU(pair_opening_lanes)(
      lanes_in, first, std::min(last, contacts.pairs.size()), out.pair, rest);
  for_each_contact_in(contacts, rest, last, [&](const ContactView& c) {
    if (!c.cohesive) return;
    if (c.is_pair()) {
      out.pair = std::max(out.pair, (end_velocity(c.b) - end_velocity(c.a)).dot(c.normal));
      return;
    }
    const double moving = *c.wall == WallKind::Piston ? piston_speed : 0.0;
    out.wall = std::max(out.wall, (end_velocity(c.b).z() - moving) * c.normal.z());
  });
  return out;
}

}  // namespace

CohesiveOpening cohesive_opening(const World& world, const Contacts& contacts,
                                 const VelocityCache& velocities, const ContactLaws& laws,
                                 double dt, PieceRunner* pieces) {
  // the largest opening speed of each kind; s ↦ s Δt / d_coh rounds monotonically (Δt and
  // d_coh are positive), so its largest value is that of the largest speed: one division per
  // kind instead of one per contact, with the same bits
  OpeningSpeeds speeds;
  if (pieces == nullptr) {
    speeds = opening_speeds(world, contacts, velocities, 0, contacts.size());
  } else {
    // maxima: any cut gives the same bits
    std::array<PieceSpeeds, kMaxPieces> of_piece{};
    const std::uint32_t count = pieces_of(contacts.size());
    run_pieces(pieces, count, [&](std::uint32_t piece) {
      const IndexRange range = piece_of(contacts.size(), count, piece);
      of_piece[piece].value = opening_speeds(world, contacts, velocities, range.first, range.last);
    });
    for (std::uint32_t piece = 0; piece < count; ++piece) {
      speeds.pair = std::max(speeds.pair, of_piece[piece].value.pair);
      speeds.wall = std::max(speeds.wall, of_piece[piece].value.wall);
    }
  }
  CohesiveOpening out;
  const auto track = [&](double opening_speed, double range) {
    out.speed = std::max(out.speed, opening_speed);
    if (range > 0.0) out.per_range = std::max(out.per_range, opening_speed * dt / range);
  };
  track(speeds.pair, laws.spheres.cohesion_range);
  track(speeds.wall, laws.walls.cohesion_range);
  return out;
}

}  // namespace cdpowder
