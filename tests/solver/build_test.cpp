// Tests of build_local_problems' pair constants: W's blocks, the closing rate and the caps,
// against the formulas of physics.md §5.2 written out here, bit for bit, with fixed spheres
// and gaps on both sides of the touching dead band, in one pass and in the two pieces of a
// threaded step (whose constants take Δt/m, Δt/I from the bodies, not the velocity cache).
#include "cdpowder/solver/build.hpp"

#include "cdpowder/solver/nlgs/tile_threads.hpp"
#include "support/small_packing.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>

namespace cdpowder {
namespace {

using testing::SmallPacking;

bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

/// Δt/m or Δt/I of sphere i, zero for a fixed sphere.
double response(const Bodies& bodies, const std::vector<double>& inverse, BodyIndex i, double dt) {
  return bodies.fixed[i] != 0 ? 0.0 : dt * inverse[i];
}

/// The pair's constants as physics.md §5.2 gives them (times Δt), with the levers to the
/// common contact point, compared bit for bit with what the build wrote.
void expect_constants(const Bodies& bodies, const ContactLaw& law, double dt,
                      const PairProblem& p) {
  const double ma = response(bodies, bodies.inverse_mass, p.a, dt);
  const double mb = response(bodies, bodies.inverse_mass, p.b, dt);
  const double ia = response(bodies, bodies.inverse_inertia, p.a, dt);
  const double ib = response(bodies, bodies.inverse_inertia, p.b, dt);
  const double dt_w_n = ma + mb;
  const double dt_w_t = dt_w_n + p.lever_a * p.lever_a * ia + p.lever_b * p.lever_b * ib;
  EXPECT_TRUE(same_bits(p.inv_dt_w_n, 1.0 / dt_w_n));
  EXPECT_TRUE(same_bits(p.inv_dt_w_t, 1.0 / dt_w_t));
  EXPECT_TRUE(same_bits(p.inv_dt_w_r, 1.0 / (ia + ib)));
  // g_pos/Δt with the dead band of 1e-6 R (build.cpp, kTouchingGap)
  EXPECT_TRUE(same_bits(p.gap_rate, p.gap > 1e-6 ? p.gap / dt : 0.0));
  EXPECT_TRUE(same_bits(p.mu, law.mu));
  EXPECT_TRUE(same_bits(p.roll_cap, law.mu_roll * p.r_eff));
  EXPECT_TRUE(same_bits(p.twist_cap, law.mu_twist * p.r_eff));
}

TEST(BuildLocalProblems, PairConstantsAreTheFormulasOfW) {
  SmallPacking packing(0.3, 0.2);
  testing::TinyScene& s = packing.scene;
  // fixed spheres (Δt/m = Δt/I = 0 on their side) and gaps on both sides of the dead band
  s.world.bodies.fixed[0] = 1;
  s.world.bodies.fixed[5] = 1;
  s.settings.laws.spheres.mu = 0.4;
  Contacts& contacts = s.work.contacts;
  ASSERT_GT(contacts.pairs.size(), 40U);
  for (std::size_t k = 0; k < contacts.pairs.size(); k += 3) contacts.pairs[k].gap = 1e-3;
  for (std::size_t k = 1; k < contacts.pairs.size(); k += 5) contacts.pairs[k].gap = 1e-6;
  bool touches_fixed = false;
  for (const PairProblem& p : contacts.pairs) touches_fixed |= p.a == 0 || p.a == 5;
  EXPECT_TRUE(touches_fixed);
  TileThreads pieces(1);  // the two pieces, one after the other on this thread
  for (PieceRunner* runner :
       {static_cast<PieceRunner*>(nullptr), static_cast<PieceRunner*>(&pieces)}) {
    SCOPED_TRACE(::testing::Message() << "in pieces " << (runner != nullptr));
    for (PairProblem& p : contacts.pairs) p.inv_dt_w_n = p.inv_dt_w_t = p.inv_dt_w_r = -1.0;
    build_local_problems(s.world, s.settings, s.work.action_cache, contacts, s.work.velocities,
                         runner);
    for (const PairProblem& p : contacts.pairs) {
      expect_constants(s.world.bodies, s.settings.laws.spheres, s.settings.solver.dt, p);
    }
  }
}

}  // namespace
}  // namespace cdpowder
