// Tests for src/cdpowder/contact/local_solve.hpp: the 6×6 inverse-mass block of
// physics.md §5.2 against rigid-body kinematics, and the one-pass local solution.
#include "cdpowder/contact/local_solve.hpp"

#include "cdpowder/contact/velocity_change.hpp"
#include "cdpowder/core/rng.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <utility>

namespace cdpowder {
namespace {

// 1e-12: W is applied in closed form, only round-off of O(10) operations remains.
constexpr double kRoundOff = 1e-12;
constexpr double kDt = 0.01;

SphereVelocity body(double radius, double density = 1.0) {
  const double m = density * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
  SphereVelocity s;
  s.dt_inverse_mass = kDt / m;
  s.dt_inverse_inertia = kDt / (0.4 * m * radius * radius);
  return s;
}

PairProblem pair(const Vec3& n, double ra, double rb, const SphereVelocity& a,
                 const SphereVelocity& b) {
  PairProblem p;
  p.normal = n.normalized();
  p.lever_a = ra;
  p.lever_b = rb;
  const double dt_w_n = a.dt_inverse_mass + b.dt_inverse_mass;
  p.inv_dt_w_n = 1.0 / dt_w_n;
  p.inv_dt_w_t = 1.0 / (dt_w_n + ra * ra * a.dt_inverse_inertia + rb * rb * b.dt_inverse_inertia);
  p.inv_dt_w_r = 1.0 / (a.dt_inverse_inertia + b.dt_inverse_inertia);
  p.r_eff = effective_radius(ra, rb);
  return p;
}

// Relative velocities (V, Ω) at the contact point from rigid-body kinematics.
void relative(const PairProblem& p, const SphereVelocity& a, const SphereVelocity& b, Vec3& V,
              Vec3& Omega) {
  const Vec3 l_a = p.lever_a * p.normal;
  const Vec3 l_b = -p.lever_b * p.normal;
  V = b.linear + b.angular.cross(l_b) - a.linear - a.angular.cross(l_a);
  Omega = b.angular - a.angular;
}

TEST(DelassusBlock, MatchesRigidBodyKinematicsForRandomRadii) {
  Rng rng = make_rng(7, RngStream::PassOrder);
  for (int trial = 0; trial < 20; ++trial) {
    const double ra = 0.5 + uniform01(rng);
    const double rb = 0.5 + uniform01(rng);
    SphereVelocity a = body(ra, 0.5 + uniform01(rng));
    SphereVelocity b = body(rb, 0.5 + uniform01(rng));
    const Vec3 n = Vec3(uniform01(rng) - 0.5, uniform01(rng) - 0.5, uniform01(rng) - 0.5);
    const PairProblem p = pair(n, ra, rb, a, b);
    const Vec3 R(uniform01(rng), uniform01(rng) - 0.5, 2.0 * uniform01(rng));
    const Vec3 T(uniform01(rng) - 0.5, uniform01(rng), uniform01(rng) - 0.5);

    Vec3 V0;
    Vec3 Omega0;
    relative(p, a, b, V0, Omega0);
    apply_pair_delta(p, R, T, a, b);
    Vec3 V1;
    Vec3 Omega1;
    relative(p, a, b, V1, Omega1);

    // physics.md §5.2, times Δt
    const double m_a_inv = a.dt_inverse_mass / kDt;
    const double m_b_inv = b.dt_inverse_mass / kDt;
    const double i_a_inv = a.dt_inverse_inertia / kDt;
    const double i_b_inv = b.dt_inverse_inertia / kDt;
    const double w_n = m_a_inv + m_b_inv;
    const double w_t = w_n + ra * ra * i_a_inv + rb * rb * i_b_inv;
    const double w_r = i_a_inv + i_b_inv;
    const double c = ra * i_a_inv - rb * i_b_inv;
    const Vec3& nn = p.normal;
    const Vec3 R_n = R.dot(nn) * nn;
    const Vec3 dV = kDt * (w_n * R_n + w_t * (R - R_n) + c * T.cross(nn));
    const Vec3 dOmega = kDt * (c * nn.cross(R) + w_r * T);
    EXPECT_LT((V1 - V0 - dV).norm(), kRoundOff) << "trial " << trial;
    EXPECT_LT((Omega1 - Omega0 - dOmega).norm(), kRoundOff) << "trial " << trial;
  }
}

TEST(LocalSolve, OnePassStopsAllSixModesOfEqualSpheres) {
  SphereVelocity a = body(1.0);
  SphereVelocity b = body(1.0);
  a.linear = Vec3(0.01, -0.02, 0.03);
  a.angular = Vec3(0.2, 0.1, -0.3);
  b.linear = Vec3(-0.02, 0.01, -0.05);
  b.angular = Vec3(-0.1, 0.3, 0.2);
  PairProblem p = pair(Vec3(0.3, -0.2, 0.9), 1.0, 1.0, a, b);
  p.cohesion = 1.0;
  p.mu = p.roll_cap = p.twist_cap = 1e6;  // no threshold reached: every mode sticks
  ContactAction action;
  solve_pair(p, action, a, b);
  Vec3 V;
  Vec3 Omega;
  relative(p, a, b, V, Omega);
  EXPECT_LT(V.norm(), kRoundOff);
  EXPECT_LT(Omega.norm(), kRoundOff);
}

TEST(LocalSolve, ApproachingPairWithGapClosesExactlyWithinTheStep) {
  SphereVelocity a = body(1.0);
  SphereVelocity b = body(1.0);
  b.linear = Vec3(0.0, 0.0, -1.0);  // approaching at 1 R/t0
  PairProblem p = pair(Vec3::UnitZ(), 1.0, 1.0, a, b);
  p.gap = 0.004;  // closes within Δt = 0.01 at this speed
  p.gap_rate = p.gap / kDt;
  ContactAction action;
  solve_pair(p, action, a, b);
  Vec3 V;
  Vec3 Omega;
  relative(p, a, b, V, Omega);
  EXPECT_NEAR(V.z() * kDt, -p.gap, kRoundOff);  // lands exactly on contact, no overlap
  EXPECT_GT(action.normal_force, 0.0);
}

TEST(LocalSolve, SeparatingNonCohesivePairStaysFree) {
  SphereVelocity a = body(1.0);
  SphereVelocity b = body(1.0);
  b.linear = Vec3(0.0, 0.0, 0.1);
  PairProblem p = pair(Vec3::UnitZ(), 1.0, 1.0, a, b);
  ContactAction action;
  const VisitChange change = solve_pair(p, action, a, b);
  EXPECT_EQ(action.normal_force, 0.0);
  EXPECT_EQ(change.change_sq, 0.0);
  EXPECT_EQ(b.linear.z(), 0.1);
}

// Independence of the modes (c = 0): sliding on the rim of its disc leaves the rolling and
// torsion solutions exactly where they would be alone, and vice versa.
TEST(ModeIndependence, SlidingAtThresholdDoesNotTouchRollingOrTorsion) {
  for (const bool slide : {false, true}) {
    SphereVelocity a = body(1.0);
    SphereVelocity b = body(1.0);
    b.linear = Vec3(slide ? 0.5 : 0.0, 0.0, 0.0);  // tangential slip along x
    b.angular = Vec3(0.01, 0.0, 0.02);             // rolling about x, torsion about z
    PairProblem p = pair(Vec3::UnitZ(), 1.0, 1.0, a, b);
    p.cohesion = 1.0;
    p.mu = 0.3;
    p.roll_cap = p.twist_cap = 1e6;
    ContactAction action;
    solve_pair(p, action, a, b);
    const double rolling_alone = -(0.01) * p.inv_dt_w_r;
    const double torsion_alone = -(0.02) * p.inv_dt_w_r;
    EXPECT_NEAR(action.rolling_torque.x(), rolling_alone, kRoundOff) << "slide=" << slide;
    EXPECT_NEAR(action.twisting_torque, torsion_alone, kRoundOff) << "slide=" << slide;
    if (slide) {
      EXPECT_DOUBLE_EQ(action.tangential_force.norm(), 0.3 * 1.0);
    }
  }
}

TEST(ModeIndependence, RollingAndTorsionAtThresholdDoNotTouchSliding) {
  SphereVelocity a = body(1.0);
  SphereVelocity b = body(1.0);
  b.linear = Vec3(0.001, 0.0, 0.0);  // small slip: sticks
  b.angular = Vec3(5.0, 0.0, 5.0);   // strong rolling and torsion: both slip
  PairProblem p = pair(Vec3::UnitZ(), 1.0, 1.0, a, b);
  p.cohesion = 1.0;
  p.mu = 1e6;
  p.roll_cap = p.twist_cap = 0.1;
  ContactAction action;
  solve_pair(p, action, a, b);
  EXPECT_NEAR(action.tangential_force.x(), -0.001 * p.inv_dt_w_t, kRoundOff);
  EXPECT_DOUBLE_EQ(action.rolling_torque.norm(), 0.1);
  EXPECT_DOUBLE_EQ(std::abs(action.twisting_torque), 0.1);
}

// μ_t = 0 (the paper's (0, μn) axis): no rolling torque at all, however fast the spheres
// roll, and every other mode and velocity exactly as with a vanishing threshold.
TEST(ModeIndependence, WithoutRollingFrictionRollingIsFree) {
  const auto visit = [](double roll_cap) {
    SphereVelocity a = body(1.0);
    SphereVelocity b = body(1.0);
    b.linear = Vec3(0.001, 0.0, 0.0);
    b.angular = Vec3(-5.0, 3.0, 0.2);  // rolling and torsion
    PairProblem p = pair(Vec3::UnitZ(), 1.0, 1.0, a, b);
    p.cohesion = 1.0;
    p.mu = 0.3;
    p.roll_cap = roll_cap;
    p.twist_cap = 0.1;
    ContactAction action;
    solve_pair(p, action, a, b);
    return std::pair{action, b};
  };
  const auto [action, b] = visit(0.0);
  EXPECT_EQ(action.rolling_torque, Vec3::Zero());
  EXPECT_FALSE(std::signbit(action.rolling_torque.x()));  // +0 (the clamp gave ±0)
  EXPECT_DOUBLE_EQ(std::abs(action.twisting_torque), 0.1);
  const auto [limit_action, limit_b] = visit(1e-300);
  EXPECT_EQ(action.normal_force, limit_action.normal_force);
  EXPECT_EQ(action.tangential_force, limit_action.tangential_force);
  EXPECT_EQ(action.twisting_torque, limit_action.twisting_torque);
  EXPECT_EQ(b.linear, limit_b.linear);
  EXPECT_EQ(b.angular, limit_b.angular);
}

// Two visits solved side by side give bit for bit what one after the other gives, for
// random contacts on four distinct spheres, sticking or at thresholds, open or closed.
TEST(LocalSolve, TwoIndependentVisitsSideBySideEqualTwoInARow) {
  Rng rng = make_rng(11, RngStream::PassOrder);
  const auto random_vec = [&](double scale) -> Vec3 {
    return Vec3(uniform01(rng) - 0.5, uniform01(rng) - 0.5, uniform01(rng) - 0.5) * scale;
  };
  const auto random_body = [&]() {
    SphereVelocity s = body(0.5 + uniform01(rng));
    s.linear = random_vec(0.2);
    s.angular = random_vec(0.2);
    return s;
  };
  const auto random_pair = [&](const SphereVelocity& a, const SphereVelocity& b) {
    PairProblem p =
        pair(random_vec(1.0) + Vec3(0, 0, 0.6), 0.5 + uniform01(rng), 0.5 + uniform01(rng), a, b);
    p.cohesion = uniform01(rng) < 0.5 ? 1.0 : 0.0;
    p.gap_rate = uniform01(rng) < 0.5 ? 0.0 : 0.1 * uniform01(rng);
    p.mu = 0.3 * uniform01(rng);
    p.roll_cap = uniform01(rng) < 0.3 ? 0.0 : 0.1 * uniform01(rng);
    p.twist_cap = uniform01(rng) < 0.3 ? 0.0 : 0.1 * uniform01(rng);
    return p;
  };
  for (int trial = 0; trial < 2000; ++trial) {
    SphereVelocity a = random_body(), b = random_body(), c = random_body(), d = random_body();
    const PairProblem p = random_pair(a, b);
    const PairProblem q = random_pair(c, d);
    ContactAction x;
    x.normal_force = uniform01(rng) - 0.3;
    x.tangential_force = random_vec(0.1);
    ContactAction y = x;
    SphereVelocity a2 = a, b2 = b, c2 = c, d2 = d;
    ContactAction x2 = x, y2 = y;

    const VisitChange first = solve_pair(p, x, a, b);
    const VisitChange second = solve_pair(q, y, c, d);
    VisitChange first2;
    VisitChange second2;
    solve_two_pairs(p, x2, a2, b2, first2, q, y2, c2, d2, second2);

    // bit-identical is the claim, so memcmp (it tells −0.0 from 0.0); neither type has
    // padding (their static_asserts pin the sizes)
    // NOLINTBEGIN(bugprone-suspicious-memory-comparison)
    ASSERT_EQ(std::memcmp(&x, &x2, sizeof x), 0) << trial;
    ASSERT_EQ(std::memcmp(&y, &y2, sizeof y), 0) << trial;
    for (const auto& [u, v] : {std::pair{&a, &a2}, {&b, &b2}, {&c, &c2}, {&d, &d2}}) {
      ASSERT_EQ(std::memcmp(u, v, sizeof(SphereVelocity)), 0) << trial;
    }
    // NOLINTEND(bugprone-suspicious-memory-comparison)
    ASSERT_EQ(first.change_sq, first2.change_sq);
    ASSERT_EQ(second.change_sq, second2.change_sq);
  }
}

// build_local_problems applies a zero warm-start action (a contact new to the step) by adding
// +0 to the second sphere's six velocity components alone (solver/build.cpp): bit for bit what
// apply_pair_action and apply_wall_action do with it, −0 components and normals of either sign
// included.
TEST(ZeroAction, MovesOnlyTheSecondSpheresNegativeZeros) {
  const auto bits_equal = [](const SphereVelocity& u, const SphereVelocity& v) {
    // tells −0.0 from 0.0; SphereVelocity has no padding (its static_assert pins the size)
    // NOLINTNEXTLINE(bugprone-suspicious-memory-comparison)
    return std::memcmp(&u, &v, sizeof(SphereVelocity)) == 0;
  };
  const auto plus_zero = [](SphereVelocity s) {
    s.linear += Vec3(0.0, 0.0, 0.0);
    s.angular += Vec3(0.0, 0.0, 0.0);
    return s;
  };
  SphereVelocity a = body(1.0);
  a.linear = Vec3(-0.0, 0.0, -0.25);
  a.angular = Vec3(0.5, -0.0, -0.0);
  SphereVelocity b = body(0.7);
  b.linear = Vec3(-0.0, 0.3, -0.0);
  b.angular = Vec3(-0.0, 0.0, -1.5);
  for (const Vec3& n :
       {Vec3(-0.6, 0.0, 0.8), Vec3(0.6, -0.8, 0.0), Vec3(-0.0, -0.6, -0.8), Vec3(0.0, 0.0, 1.0)}) {
    VelocityCache v;
    v.spheres = {a, b};
    v.piston_velocity = -0.0;
    PairProblem p = pair(n, 1.0, 0.7, a, b);
    p.a = 0;
    p.b = 1;
    apply_pair_action(p, ContactAction{}, v);
    EXPECT_TRUE(bits_equal(v.spheres[0], a));
    EXPECT_TRUE(bits_equal(v.spheres[1], plus_zero(b)));
  }
  for (const WallKind kind : {WallKind::Bottom, WallKind::Piston}) {
    VelocityCache v;
    v.spheres = {b};
    v.piston_velocity = -0.0;
    WallProblem w;
    w.wall = kind;
    w.normal = Vec3(0.0, 0.0, kind == WallKind::Bottom ? 1.0 : -1.0);
    w.radius = 0.7;
    w.wall_response = kind == WallKind::Piston ? 0.01 : 0.0;
    w.wall_moves = kind == WallKind::Piston ? 1.0 : 0.0;
    apply_wall_action(w, ContactAction{}, v);
    EXPECT_TRUE(bits_equal(v.spheres[0], plus_zero(b)));
    EXPECT_TRUE(std::signbit(v.piston_velocity));
  }
}

}  // namespace
}  // namespace cdpowder
