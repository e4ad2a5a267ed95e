// The contacts' measures of a step taken in lanes (analysis/overlap_lanes.inc,
// analysis/opening_lanes.inc) against passes of their own that take one contact at a time:
// the overlaps, their mean over the closed contacts, the counts, the piston's contact force
// and the opening gauges have the same bits on SSE2 and AVX2, for every number of pairs
// modulo the lanes, with pairs across the periodic boundaries, fixed spheres, open and
// closed, cohesive and non-cohesive contacts.
#include "cdpowder/analysis/cohesive_opening.hpp"
#include "cdpowder/analysis/step_diagnostics.hpp"
#include "cdpowder/contact/contact_view.hpp"
#include "cdpowder/core/lanes.hpp"
#include "cdpowder/core/rng.hpp"
#include "cdpowder/solver/nlgs/tile_threads.hpp"
#include "support/small_packing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace cdpowder::testing {
namespace {

/// measure_contacts one contact at a time, in Contacts' order: the closed pairs' overlaps summed
/// piece by piece (indices_per_piece), the pieces' sums in piece order, then the walls'.
StepDiagnostics scalar_measures(const World& world, const Contacts& contacts) {
  const Bodies& bodies = world.bodies;
  StepDiagnostics d;
  d.contacts = contacts.size();
  const std::size_t per_piece = indices_per_piece(contacts.pairs.size());
  double overlap_sum = 0.0;
  double piece_sum = 0.0;
  std::size_t k = 0;
  for_each_contact(contacts, [&](const ContactView& c) {
    if (k > 0 && (k % per_piece == 0 || k == contacts.pairs.size())) {
      overlap_sum += piece_sum;  // a piece of pairs ends
      piece_sum = 0.0;
    }
    ++k;
    double overlap = 0.0;
    if (c.is_pair()) {
      const Vec3 d_ab = world.box.minimum_image(bodies.position[c.b] - bodies.position[c.a]);
      overlap = std::max(0.0, bodies.radius[c.a] + bodies.radius[c.b] - d_ab.norm());
    } else {
      const double z = bodies.position[c.b].z();
      const double r = bodies.radius[c.b];
      const double gap = *c.wall == WallKind::Bottom ? z - r : world.walls.piston.height - z - r;
      overlap = std::max(0.0, -gap);
    }
    d.max_overlap = std::max(d.max_overlap, overlap);
    if (c.cohesive) ++d.cohesive_contacts;
    if (c.closed()) {
      ++d.closed_contacts;
      (c.is_pair() ? piece_sum : overlap_sum) += overlap;
    }
    if (c.wall == WallKind::Piston) d.piston_contact_force += c.action->normal_force;
  });
  if (contacts.walls.empty()) overlap_sum += piece_sum;
  d.mean_overlap =
      d.closed_contacts > 0 ? overlap_sum / static_cast<double>(d.closed_contacts) : 0.0;
  return d;
}

/// cohesive_opening one contact at a time.
CohesiveOpening scalar_opening(const World& world, const Contacts& contacts,
                               const VelocityCache& velocities, const ContactLaws& laws,
                               double dt) {
  const Bodies& bodies = world.bodies;
  const auto end_velocity = [&](BodyIndex i) -> const Vec3& {
    return bodies.fixed[i] != 0 ? bodies.velocity[i] : velocities.spheres[i].linear;
  };
  double pair = -std::numeric_limits<double>::infinity();
  double wall = pair;
  for_each_contact(contacts, [&](const ContactView& c) {
    if (!c.cohesive) return;
    if (c.is_pair()) {
      pair = std::max(pair, (end_velocity(c.b) - end_velocity(c.a)).dot(c.normal));
      return;
    }
    const double moving = *c.wall == WallKind::Piston ? velocities.piston_velocity : 0.0;
    wall = std::max(wall, (end_velocity(c.b).z() - moving) * c.normal.z());
  });
  CohesiveOpening out;
  out.speed = std::max({out.speed, pair, wall});
  out.per_range = std::max(out.per_range, pair * dt / laws.spheres.cohesion_range);
  out.per_range = std::max(out.per_range, wall * dt / laws.walls.cohesion_range);
  return out;
}

std::uint64_t bits(double x) {
  return std::bit_cast<std::uint64_t>(x);
}

/// The small packing's contacts with made-up forces, cohesion and velocities: about a third
/// of the contacts open (a fifth exactly at R_n = −F_c), half cohesive, every ninth sphere fixed
/// with a velocity of its own, the spheres moved by up to `jitter` so that some overlap.
struct MeasuredPacking {
  SmallPacking packing{0.2};

  MeasuredPacking(std::uint64_t seed, double jitter) {
    Rng rng = make_rng(seed, RngStream::Deposition);
    World& world = packing.scene.world;
    Contacts& contacts = packing.scene.work.contacts;
    VelocityCache& velocities = packing.scene.work.velocities;
    const auto random = [&](double half_width) {
      return half_width * (2.0 * uniform01(rng) - 1.0);
    };
    for (std::size_t k = 0; k < contacts.pairs.size(); ++k) {
      contacts.pair_cohesive[k] = uniform01(rng) < 0.5 ? 1 : 0;
      contacts.pairs[k].cohesion = contacts.pair_cohesive[k] != 0 ? 1.0 : 0.0;
      // every fifth exactly open, R_n = −F_c (S = +0: not closed), as the solver leaves it
      contacts.pair_actions[k].normal_force =
          k % 5 == 0 ? -contacts.pairs[k].cohesion : random(1.5);
    }
    for (std::size_t k = 0; k < contacts.walls.size(); ++k) {
      contacts.wall_cohesive[k] = uniform01(rng) < 0.5 ? 1 : 0;
      contacts.walls[k].cohesion = contacts.wall_cohesive[k] != 0 ? 1.0 : 0.0;
      contacts.wall_actions[k].normal_force = random(1.5);
    }
    Bodies& bodies = world.bodies;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      bodies.fixed[i] = i % 9 == 4 ? 1 : 0;
      bodies.velocity[i] = Vec3(random(0.1), random(0.1), random(0.1));
      velocities.spheres[i].linear = Vec3(random(0.1), random(0.1), random(0.1));
      bodies.position[i] += Vec3(random(jitter), random(jitter), random(jitter));
    }
    velocities.piston_velocity = -0.01;
  }
};

/// Contacts with only the first `pairs` pairs (and every wall contact).
Contacts first_pairs(const Contacts& all, std::size_t pairs) {
  Contacts out = all;
  out.pairs.resize(pairs);
  out.pair_actions.resize(pairs);
  out.pair_cohesive.resize(pairs);
  return out;
}

/// The measures of `contacts` in lanes against the passes one contact at a time.
void expect_bits_of_one_at_a_time(const TinyScene& scene, const Contacts& contacts) {
  const StepDiagnostics expected = scalar_measures(scene.world, contacts);
  StepDiagnostics got;
  measure_contacts(scene.world, contacts, got);
  EXPECT_EQ(got.contacts, expected.contacts);
  EXPECT_EQ(got.closed_contacts, expected.closed_contacts);
  EXPECT_EQ(got.cohesive_contacts, expected.cohesive_contacts);
  EXPECT_EQ(bits(got.max_overlap), bits(expected.max_overlap));
  EXPECT_EQ(bits(got.mean_overlap), bits(expected.mean_overlap));
  EXPECT_EQ(bits(got.piston_contact_force), bits(expected.piston_contact_force));
  const CohesiveOpening expected_opening = scalar_opening(
      scene.world, contacts, scene.work.velocities, scene.settings.laws, scene.settings.solver.dt);
  const CohesiveOpening opening = cohesive_opening(scene.world, contacts, scene.work.velocities,
                                                   scene.settings.laws, scene.settings.solver.dt);
  EXPECT_EQ(bits(opening.speed), bits(expected_opening.speed));
  EXPECT_EQ(bits(opening.per_range), bits(expected_opening.per_range));
}

TEST(ContactMeasuresInLanes, HaveTheBitsOfAPassOneContactAtATime) {
  for (const lanes::Isa isa : {lanes::Isa::Sse2, lanes::Isa::Avx2}) {
    if (!lanes::allow_isa(isa)) continue;  // no AVX2 here
    // every number of pairs modulo the lanes
    const MeasuredPacking measured(11, 0.02);
    const TinyScene& scene = measured.packing.scene;
    const Contacts& all = scene.work.contacts;
    const std::size_t n = all.pairs.size();
    ASSERT_GT(n, 100U);
    ASSERT_GT(all.walls.size(), 10U);
    for (const std::size_t pairs :
         {n, n - 1, n - 2, n - 3, std::size_t{9}, std::size_t{2}, std::size_t{0}}) {
      SCOPED_TRACE(::testing::Message() << pairs << " pairs, avx2 " << (isa == lanes::Isa::Avx2));
      expect_bits_of_one_at_a_time(scene, first_pairs(all, pairs));
    }
    // The largest overlap and opening speed are one contact's, and the overlaps' sum is exact
    // where they share their scale (a difference of nearby numbers): many packings, and moves
    // that make overlaps of every size, so that a lane that rounds otherwise shows.
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
      SCOPED_TRACE(::testing::Message()
                   << "seed " << seed << ", avx2 " << (isa == lanes::Isa::Avx2));
      const MeasuredPacking moved(seed, seed % 2 == 0 ? 0.02 : 0.3);
      const Contacts& contacts = moved.packing.scene.work.contacts;
      expect_bits_of_one_at_a_time(moved.packing.scene, contacts);
      // what the passes measure: overlaps, closed and open contacts, pairs across the periodic
      // boundaries, a contact opening
      const StepDiagnostics d = scalar_measures(moved.packing.scene.world, contacts);
      EXPECT_GT(d.max_overlap, 0.0);
      EXPECT_GT(d.closed_contacts, 0U);
      EXPECT_LT(d.closed_contacts, d.contacts);
      const World& world = moved.packing.scene.world;
      std::size_t across = 0;
      for (const PairProblem& p : contacts.pairs) {
        const Vec3 sep = world.bodies.position[p.b] - world.bodies.position[p.a];
        if (std::abs(sep.x()) > 0.5 * world.box.lx || std::abs(sep.y()) > 0.5 * world.box.ly) {
          ++across;
        }
      }
      EXPECT_GT(across, 0U);
    }
  }
  lanes::allow_isa(lanes::Isa::Avx512);
}

// More pairs than one piece holds (core/pieces.hpp, indices_per_piece): the pieces, one after
// the other or side by side on two threads, give the bits of the pass one contact at a time, on
// SSE2 and AVX2.
TEST(ContactMeasuresInLanes, PiecesOnThreadsHaveTheBitsOfOnePass) {
  const MeasuredPacking measured(5, 0.3);
  const TinyScene& scene = measured.packing.scene;
  Contacts contacts = scene.work.contacts;
  const Contacts& one = scene.work.contacts;
  while (contacts.pairs.size() < 3 * kChunkIndices + 5) {
    contacts.pairs.insert(contacts.pairs.end(), one.pairs.begin(), one.pairs.end());
    contacts.pair_actions.insert(contacts.pair_actions.end(), one.pair_actions.begin(),
                                 one.pair_actions.end());
    contacts.pair_cohesive.insert(contacts.pair_cohesive.end(), one.pair_cohesive.begin(),
                                  one.pair_cohesive.end());
  }
  ASSERT_GT(chunks_of(contacts.pairs.size(), indices_per_piece(contacts.pairs.size())), 1U);
  TileThreads threads(2);
  for (const lanes::Isa isa : {lanes::Isa::Sse2, lanes::Isa::Avx2}) {
    if (!lanes::allow_isa(isa)) continue;  // no AVX2 here
    SCOPED_TRACE(::testing::Message() << "avx2 " << (isa == lanes::Isa::Avx2));
    expect_bits_of_one_at_a_time(scene, contacts);
    StepDiagnostics on_threads;
    measure_contacts(scene.world, contacts, on_threads, &threads);
    const StepDiagnostics expected = scalar_measures(scene.world, contacts);
    EXPECT_EQ(on_threads.closed_contacts, expected.closed_contacts);
    EXPECT_EQ(on_threads.cohesive_contacts, expected.cohesive_contacts);
    EXPECT_EQ(bits(on_threads.max_overlap), bits(expected.max_overlap));
    EXPECT_EQ(bits(on_threads.mean_overlap), bits(expected.mean_overlap));
    EXPECT_EQ(bits(on_threads.piston_contact_force), bits(expected.piston_contact_force));
  }
  lanes::allow_isa(lanes::Isa::Avx512);
}

}  // namespace
}  // namespace cdpowder::testing
