// The coloured sweep kernel (solver.kernel = "coloured"): the colouring is a partition of
// the pair contacts into colours without a shared sphere (plus an overflow set), and a
// coloured sweep is an exact reordering of the scalar one: visiting the same contacts in
// the same sequence gives the same bits.
#include "cdpowder/solver/nlgs/coloured_pass.hpp"

#include "cdpowder/contact/velocity_change.hpp"
#include "cdpowder/core/lanes.hpp"
#include "cdpowder/detect/detect_contacts.hpp"
#include "cdpowder/solver/nlgs/nlgs.hpp"
#include "cdpowder/solver/nlgs/tile_threads.hpp"
#include "cdpowder/solver/nlgs/tiles.hpp"
#include "support/small_packing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <numeric>
#include <set>

namespace cdpowder::testing {
namespace {

/// Every instruction set of the kernel, each where the CPU has it: they give the same bits.
constexpr std::array<lanes::Isa, 3> kIsas = {lanes::Isa::Sse2, lanes::Isa::Avx2,
                                             lanes::Isa::Avx512};

template <typename T>
bool same_bits(const std::vector<T>& x, const std::vector<T>& y) {
  return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(T)) == 0;
}

void expect_same_state(const Contacts& c, const VelocityCache& v, const Contacts& d,
                       const VelocityCache& u) {
  EXPECT_TRUE(same_bits(c.pair_actions, d.pair_actions));
  EXPECT_TRUE(same_bits(c.wall_actions, d.wall_actions));
  EXPECT_TRUE(same_bits(v.spheres, u.spheres));
  EXPECT_EQ(std::memcmp(&v.piston_velocity, &u.piston_velocity, sizeof(double)), 0);
}

void expect_same_sums(const PassSums& s, const PassSums& t) {
  EXPECT_EQ(std::memcmp(&s.max_change_sq, &t.max_change_sq, sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(&s.sum_change_sq, &t.sum_change_sq, sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(&s.sum_closed_normal, &t.sum_closed_normal, sizeof(double)), 0);
  EXPECT_EQ(s.closed, t.closed);
}

/// Both sweeps' groups in the order of one draw, then `sweeps` sweeps of each, their sums
/// compared sweep by sweep.
void expect_same_sweeps(Contacts& c, VelocityCache& v, ColouredPass& a, Contacts& d,
                        VelocityCache& u, ColouredPass& b, int sweeps) {
  Rng rng_a = make_rng(5, RngStream::PassOrder);
  Rng rng_b = make_rng(5, RngStream::PassOrder);
  order_groups(a, VisitOrder::RandomEachStep, rng_a);
  order_groups(b, VisitOrder::RandomEachStep, rng_b);
  ASSERT_EQ(a.group_order, b.group_order);
  for (int s = 0; s < sweeps; ++s) {
    expect_same_sums(run_coloured_pass(c, v, a), run_coloured_pass(d, u, b));
  }
}

void expect_valid_colouring(const PairColouring& colouring, const std::vector<PairProblem>& pairs,
                            int max_colours) {
  ASSERT_FALSE(colouring.chunk_colours.empty());
  ASSERT_EQ(colouring.chunk_colours.back(), colouring.colours());
  for (std::size_t j = 0; j + 1 < colouring.chunk_colours.size(); ++j) {
    EXPECT_LE(colouring.chunk_colours[j + 1] - colouring.chunk_colours[j],
              static_cast<std::uint32_t>(max_colours));
  }
  std::vector<int> seen(pairs.size(), 0);
  for (std::size_t c = 0; c < colouring.colours(); ++c) {
    std::set<BodyIndex> spheres;
    for (std::uint32_t m = colouring.colour_start[c]; m < colouring.colour_start[c + 1]; ++m) {
      const PairProblem& p = pairs[colouring.members[m]];
      EXPECT_TRUE(spheres.insert(p.a).second) << "colour " << c << " repeats sphere " << p.a;
      EXPECT_TRUE(spheres.insert(p.b).second) << "colour " << c << " repeats sphere " << p.b;
      ++seen[colouring.members[m]];
      if (m > colouring.colour_start[c]) {
        EXPECT_LT(colouring.members[m - 1], colouring.members[m]) << "storage order";
      }
    }
  }
  for (const ContactIndex k : colouring.overflow) ++seen[k];
  for (std::size_t k = 0; k < pairs.size(); ++k) EXPECT_EQ(seen[k], 1) << "contact " << k;
}

// The lane kernel reads and writes a sphere's and a contact's record as one row of 8
// doubles (coloured_kernel.inc): v*, ω*, Δt/m, Δt/I and R_n, R_t, T_t, T_n, in this order.
TEST(ColouredPass, RecordsAreRowsOfEightDoublesInTheKernelsOrder) {
  SphereVelocity s;
  s.linear = Vec3(0, 1, 2);
  s.angular = Vec3(3, 4, 5);
  s.dt_inverse_mass = 6;
  s.dt_inverse_inertia = 7;
  ContactAction x;
  x.normal_force = 0;
  x.tangential_force = Vec3(1, 2, 3);
  x.rolling_torque = Vec3(4, 5, 6);
  x.twisting_torque = 7;
  std::array<double, 8> s_row{};
  std::array<double, 8> x_row{};
  // the records' bytes as the kernel reads them: eight doubles, Eigen's vectors among them
  std::memcpy(s_row.data(), &s, sizeof s_row);  // NOLINT(bugprone-undefined-memory-manipulation)
  std::memcpy(x_row.data(), &x, sizeof x_row);  // NOLINT(bugprone-undefined-memory-manipulation)
  for (int f = 0; f < 8; ++f) {
    EXPECT_EQ(s_row[f], f);
    EXPECT_EQ(x_row[f], f);
  }
}

TEST(Colouring, EveryContactOnceAndNoSharedSphereWithinAColour) {
  SmallPacking packing(0.1);
  const Contacts& c = packing.scene.work.contacts;
  ASSERT_GT(c.pairs.size(), 500U);
  const std::size_t spheres = packing.scene.world.bodies.size();
  PairColouring colouring;
  std::vector<std::uint64_t> masks;
  colour_pairs(c.pairs, spheres, kMaxColours, 0, colouring, masks);
  expect_valid_colouring(colouring, c.pairs, kMaxColours);
  EXPECT_TRUE(colouring.overflow.empty());  // coordination ≤ 12: at most 23 colours needed
  EXPECT_EQ(colouring.chunk_colours.size(), 2U);
  // in chunks of 100 consecutive contacts, each chunk with its own colours
  colour_pairs(c.pairs, spheres, kMaxColours, 100, colouring, masks);
  expect_valid_colouring(colouring, c.pairs, kMaxColours);
  ASSERT_EQ(colouring.chunk_colours.size(), (c.pairs.size() + 99) / 100 + 1);
  for (std::size_t j = 0; j + 1 < colouring.chunk_colours.size(); ++j) {
    for (std::uint32_t m = colouring.colour_start[colouring.chunk_colours[j]];
         m < colouring.colour_start[colouring.chunk_colours[j + 1]]; ++m) {
      EXPECT_EQ(colouring.members[m] / 100, j) << "a chunk holds its own contacts";
    }
  }
  // few colours: the contacts that find none go to the overflow set
  colour_pairs(c.pairs, spheres, 3, 0, colouring, masks);
  expect_valid_colouring(colouring, c.pairs, 3);
  EXPECT_FALSE(colouring.overflow.empty());
}

// One contact per colour, colours in storage order, the wall group last: the scalar sweep's
// storage order, so the batched kernel (one lane in use) must give the scalar bits.
TEST(ColouredPass, OneContactPerColourEqualsTheScalarSweepBitForBit) {
  for (const lanes::Isa isa : kIsas) {
    if (!allow_kernel_isa(isa)) continue;  // not on this CPU
    for (const double mu_roll : {0.0, 0.1}) {
      SmallPacking packing(mu_roll);
      Contacts scalar = packing.scene.work.contacts;
      VelocityCache scalar_v = packing.scene.work.velocities;
      Contacts coloured = scalar;
      VelocityCache coloured_v = scalar_v;
      scalar.visit_order.resize(scalar.size());
      std::iota(scalar.visit_order.begin(), scalar.visit_order.end(), ContactIndex{0});
      ColouredPass sweep;
      colour_one_per_colour(coloured.pairs.size(), sweep.colouring);
      build_batches(coloured, coloured_v, sweep);
      Rng rng = make_rng(1, RngStream::PassOrder);
      order_groups(sweep, VisitOrder::Fixed, rng);
      for (int s = 0; s < 5; ++s) {
        const PassSums a = run_scalar_pass(scalar, scalar_v);
        const PassSums b = run_coloured_pass(coloured, coloured_v, sweep);
        expect_same_sums(a, b);
        expect_same_state(scalar, scalar_v, coloured, coloured_v);
      }
    }
  }
  allow_kernel_isa(lanes::Isa::Avx512);
}

// Which branches of the kernel a sweep took: open contacts, sliding ones (on the rim of the
// friction disc), rolling and twisting ones at their thresholds.
struct Branches {
  int open = 0, sliding = 0, rolling = 0, twisting = 0;
};

Branches branches(const Contacts& c) {
  Branches b;
  for (std::size_t k = 0; k < c.pairs.size(); ++k) {
    const PairProblem& p = c.pairs[k];
    const ContactAction& x = c.pair_actions[k];
    const double S = x.normal_force + p.cohesion;
    if (S == 0.0) ++b.open;
    if (S > 0.0 && std::abs(x.tangential_force.norm() - p.mu * S) < 1e-12 * S) ++b.sliding;
    if (S > 0.0 && std::abs(x.rolling_torque.norm() - p.roll_cap * S) < 1e-12 * S &&
        p.roll_cap > 0) {
      ++b.rolling;
    }
    if (S > 0.0 && std::abs(std::abs(x.twisting_torque) - p.twist_cap * S) < 1e-12 * S)
      ++b.twisting;
  }
  return b;
}

struct BatchStates {
  int all_closed = 0, some_open = 0;
};

/// The batches of `colouring` (four members of a colour at a time) whose contacts are all
/// closed, and those with an open one (R_n = −F_c), after a sweep.
BatchStates closed_batches(const Contacts& c, const PairColouring& colouring) {
  BatchStates states;
  for (std::size_t colour = 0; colour < colouring.colours(); ++colour) {
    for (std::uint32_t m = colouring.colour_start[colour]; m < colouring.colour_start[colour + 1];
         m += kBatchLanes) {
      const std::uint32_t end =
          std::min<std::uint32_t>(m + kBatchLanes, colouring.colour_start[colour + 1]);
      bool all_closed = true;
      for (std::uint32_t j = m; j < end; ++j) {
        const ContactIndex k = colouring.members[j];
        all_closed = all_closed && is_closed(c.pair_actions[k].normal_force, c.pairs[k].cohesion);
      }
      ++(all_closed ? states.all_closed : states.some_open);
    }
  }
  return states;
}

// The greedy colouring (chunks of 256 contacts) in a random order: batches of 4 independent
// contacts give the bits of the scalar sweep visiting the same contacts one by one in the same
// sequence, and so do the bottom-wall contacts in their batches. Also without rolling and
// torsion friction (the (0,0) corner), where the kernel leaves the pairs' torques alone
// (ColouredPass::torques = false) and the scalar one keeps them +0.
// Both kernels of ColouredPass::open_rare (the one that skips the open branch where no lane of
// a call is open, and the one that always selects) give these bits: on the packing as it is,
// where most calls have an open lane, and with most pairs held closed by a strong cohesion, where
// many calls have none.
TEST(ColouredPass, FullBatchesEqualTheScalarSweepInTheSameSequence) {
  struct Case {
    double mu_roll, mu_twist;
  };

  struct Kernel {
    bool open_rare, mostly_closed;
  };

  for (const lanes::Isa isa : kIsas) {
    if (!allow_kernel_isa(isa)) continue;  // not on this CPU
    for (const Kernel kernel :
         {Kernel{false, false}, Kernel{true, false}, Kernel{false, true}, Kernel{true, true}}) {
      for (const Case friction : {Case{0.0, 0.2}, Case{0.1, 0.2}, Case{0.0, 0.0}}) {
        SCOPED_TRACE(::testing::Message()
                     << "open_rare " << kernel.open_rare << ", mostly closed "
                     << kernel.mostly_closed << ", mu_roll " << friction.mu_roll << ", mu_twist "
                     << friction.mu_twist);
        const double mu_roll = friction.mu_roll;
        SmallPacking packing(mu_roll, friction.mu_twist);
        Contacts scalar = packing.scene.work.contacts;
        // wall torques of −0, as warm-start caches may hold them: solve_wall writes +0 over them
        // (and the bottom-wall batches must too, even without the pairs' torques)
        for (ContactAction& x : scalar.wall_actions) {
          x.rolling_torque = Vec3(-0.0, -0.0, -0.0);
          x.twisting_torque = -0.0;
        }
        if (kernel.mostly_closed) {
          // four pairs in five closed by F_c = 50 (no gap to close); every fifth as it was
          for (std::size_t k = 0; k < scalar.pairs.size(); ++k) {
            if (k % 5 == 0) continue;
            scalar.pairs[k].cohesion = 50.0;
            scalar.pairs[k].gap_rate = 0.0;
          }
        }
        VelocityCache scalar_v = packing.scene.work.velocities;
        Contacts coloured = scalar;
        VelocityCache coloured_v = scalar_v;
        ColouredPass sweep;
        colour_pairs(coloured.pairs, coloured_v.spheres.size(), kMaxColours, 256, sweep.colouring,
                     sweep.masks);
        build_batches(coloured, coloured_v, sweep);
        sweep.torques = friction.mu_roll > 0.0 || friction.mu_twist > 0.0;
        // the bottom-wall contacts are solved side by side, in batches of their own
        const auto [bottom_first, bottom_last] = sweep.bottom_walls[0];
        ASSERT_GT(bottom_last - bottom_first, 2U * kBatchLanes);
        ASSERT_EQ(sweep.part_wall_batches[1] - sweep.part_wall_batches[0],
                  2 * sweep.wall_batch_pairs.size());
        ASSERT_GT(sweep.colouring.chunk_colours.size(), 3U);
        ASSERT_GT(sweep.colours(), 6U);
        Rng rng = make_rng(3, RngStream::PassOrder);
        order_groups(sweep, VisitOrder::RandomEachStep, rng);
        scalar.visit_order.clear();
        for (const std::uint32_t g : sweep.group_order) {
          if (g >= sweep.colours()) {  // a part's sequential group
            const std::size_t part = g - sweep.colours();
            scalar.visit_order.insert(scalar.visit_order.end(),
                                      sweep.sequential.begin() + sweep.part_sequential[part],
                                      sweep.sequential.begin() + sweep.part_sequential[part + 1]);
          } else {
            for (std::uint32_t m = sweep.colouring.colour_start[g];
                 m < sweep.colouring.colour_start[g + 1]; ++m) {
              scalar.visit_order.push_back(sweep.colouring.members[m]);
            }
          }
        }
        ASSERT_EQ(scalar.visit_order.size(), scalar.size());
        for (int s = 0; s < 5; ++s) {
          const PassSums a = run_scalar_pass(scalar, scalar_v);
          sweep.open_rare = kernel.open_rare;  // the sweep before set it from its sums
          const PassSums b = run_coloured_pass(coloured, coloured_v, sweep);
          expect_same_sums(a, b);
          expect_same_state(scalar, scalar_v, coloured, coloured_v);
        }
        const Branches taken = branches(coloured);
        EXPECT_GT(taken.open, 0);
        // batches of four closed contacts (the branch's fast path) and batches with an open one
        const BatchStates batch_states = closed_batches(coloured, sweep.colouring);
        if (kernel.mostly_closed) {
          EXPECT_GT(batch_states.all_closed, 0);
        }
        EXPECT_GT(batch_states.some_open, 0);
        EXPECT_GT(taken.sliding, 0);
        if (friction.mu_twist > 0.0) {
          EXPECT_GT(taken.twisting, 0);
        }
        if (mu_roll > 0.0) {
          EXPECT_GT(taken.rolling, 0);
        }
        if (!sweep.torques) {
          for (const ContactAction& x : coloured.pair_actions) {
            EXPECT_FALSE(std::signbit(x.twisting_torque));
            EXPECT_EQ(x.rolling_torque, Vec3::Zero());
          }
        }
      }
    }
  }
  allow_kernel_isa(lanes::Isa::Avx512);
}

// The mixing's velocity update batch by batch (apply_pair_deltas) gives the bits of
// apply_pair_action over the pairs in storage order, with and without torques.
TEST(ColouredPass, BatchedActionChangesMoveTheVelocitiesAsOneByOne) {
  for (const lanes::Isa isa : kIsas) {
    if (!allow_kernel_isa(isa)) continue;  // not on this CPU
    for (const bool torques : {true, false}) {
      SmallPacking packing(0.1);
      Contacts contacts = packing.scene.work.contacts;
      VelocityCache one_by_one = packing.scene.work.velocities;
      ColouredPass sweep;
      prepare_coloured_pass(contacts, one_by_one, sweep, 256);
      sweep.torques = torques;
      VelocityCache batched = one_by_one;
      Rng rng = make_rng(9, RngStream::Deposition);
      std::vector<ContactAction> deltas(contacts.pairs.size());
      for (ContactAction& d : deltas) {
        d.normal_force = uniform01(rng) - 0.5;
        d.tangential_force =
            Vec3(uniform01(rng), uniform01(rng), uniform01(rng)) - Vec3::Constant(0.5);
        if (torques) {
          d.rolling_torque = Vec3(uniform01(rng), uniform01(rng), uniform01(rng));
          d.twisting_torque = uniform01(rng);
        }
      }
      for (std::size_t k = 0; k < contacts.pairs.size(); ++k) {
        apply_pair_action(sweep.pair_record(contacts, static_cast<ContactIndex>(k)), deltas[k],
                          one_by_one);
      }
      apply_pair_deltas(sweep, deltas, contacts, batched);
      EXPECT_TRUE(same_bits(one_by_one.spheres, batched.spheres));
    }
  }
  allow_kernel_isa(lanes::Isa::Avx512);
}

// The solver stores the pairs' actions in colour order during a step (the records stay in
// storage order): the same sweeps as on the pairs in storage order, and restore_storage_order
// gives the storage order back.
TEST(ColouredPass, StoringThePairsInColourOrderChangesNoBit) {
  SmallPacking packing(0.1);
  Contacts in_place = packing.scene.work.contacts;
  VelocityCache in_place_v = packing.scene.work.velocities;
  Contacts moved = in_place;
  VelocityCache moved_v = in_place_v;
  ColouredPass a;
  colour_pairs(in_place.pairs, in_place_v.spheres.size(), kMaxColours, 256, a.colouring, a.masks);
  build_batches(in_place, in_place_v, a);
  ColouredPass b;
  prepare_coloured_pass(moved, moved_v, b, 256);
  ASSERT_EQ(a.colours(), b.colours());
  ASSERT_GT(b.colouring.chunk_colours.size(), 3U);
  expect_same_sweeps(in_place, in_place_v, a, moved, moved_v, b, 5);
  restore_storage_order(moved, b);
  EXPECT_TRUE(same_bits(in_place.pairs, moved.pairs));
  EXPECT_TRUE(same_bits(in_place.pair_cohesive, moved.pair_cohesive));
  expect_same_state(in_place, in_place_v, moved, moved_v);
}

/// The packing in tiles of 2.83 R (a 4 × 4 grid of its 11.3 R cell), or not tiled.
StepTiles tiles_of(const World& world, const Contacts& contacts, bool tiled) {
  StepTiles tiles;
  if (tiled) {
    assign_tiles(world.bodies.position, world.box, world.bodies.max_radius(),
                 2.0 * std::numbers::sqrt2, contacts, tiles);
  }
  return tiles;
}

/// Sphere i moved to the next tile along x.
void move_to_next_tile(StepTiles& tiles, BodyIndex i) {
  tiles.sphere_x[i] = (tiles.sphere_x[i] + 1) % tiles.grid.nx;
  tiles.sphere_part[i] = tiles.part_of_tile[tiles.sphere_y[i] * tiles.grid.nx + tiles.sphere_x[i]];
}

/// Prepares a step as the solver does with `reused` (its colouring kept when the inputs are
/// those of its last build; the parts refilled on `pieces`) and afresh, and expects the same
/// structure, batches, sweeps and end state; the step's contacts and velocities end restored.
void expect_same_preparation(Contacts& contacts, VelocityCache& velocities, const StepTiles& tiles,
                             ColouredPass& reused, PieceRunner* pieces) {
  Contacts fresh_contacts = contacts;
  VelocityCache fresh_velocities = velocities;
  ColouredPass fresh;
  prepare_coloured_pass(fresh_contacts, fresh_velocities, fresh, 256, &tiles);
  prepare_coloured_pass(contacts, velocities, reused, 256, &tiles, pieces);
  ASSERT_EQ(reused.colours(), fresh.colours());
  EXPECT_EQ(reused.colouring.members, fresh.colouring.members);
  EXPECT_EQ(reused.colouring.colour_start, fresh.colouring.colour_start);
  EXPECT_EQ(reused.colouring.overflow, fresh.colouring.overflow);
  EXPECT_EQ(reused.colouring.part_overflow, fresh.colouring.part_overflow);
  EXPECT_TRUE(same_bits(reused.batch_pairs, fresh.batch_pairs));
  EXPECT_TRUE(same_bits(reused.wall_batch_pairs, fresh.wall_batch_pairs));
  EXPECT_EQ(reused.colour_batches, fresh.colour_batches);
  EXPECT_EQ(reused.sequential, fresh.sequential);
  EXPECT_EQ(reused.bottom_walls, fresh.bottom_walls);
  EXPECT_EQ(reused.part_wall_batches, fresh.part_wall_batches);
  EXPECT_EQ(reused.wall_part, fresh.wall_part);
  EXPECT_EQ(reused.storage_index, fresh.storage_index);
  EXPECT_TRUE(same_bits(contacts.pairs, fresh_contacts.pairs));
  EXPECT_TRUE(same_bits(contacts.pair_actions, fresh_contacts.pair_actions));
  expect_same_sweeps(contacts, velocities, reused, fresh_contacts, fresh_velocities, fresh, 3);
  restore_storage_order(contacts, reused);
  restore_storage_order(fresh_contacts, fresh);
  expect_same_state(contacts, velocities, fresh_contacts, fresh_velocities);
}

/// New values for the same contacts: the next step of a packing that moved a little.
void move_a_little(Contacts& contacts, VelocityCache& velocities, Rng& rng) {
  for (PairProblem& p : contacts.pairs) {
    p.normal =
        (p.normal + 0.01 * Vec3(uniform01(rng), uniform01(rng), uniform01(rng))).normalized();
    p.gap_rate = 0.01 * uniform01(rng);
    p.inv_dt_w_t *= 1.0 + 0.1 * uniform01(rng);
  }
  for (WallProblem& w : contacts.walls) w.gap_rate = 0.01 * uniform01(rng);
  for (SphereVelocity& v : velocities.spheres) {
    v.linear += Vec3::Constant(0.01 * uniform01(rng));
    v.dt_inverse_mass *= 0.5;
  }
}

// A step with the pairs, walls and tiles of the last keeps its colouring and the batches' rows
// and fills in only the values (part by part, on two threads for a tiled step): the structure,
// batches, sweeps and end state of a fresh preparation, bit for bit; a step whose pairs, tiles or
// walls differ is coloured afresh, again as a fresh preparation. With a sphere of many contacts,
// so that there are overflow pairs.
TEST(ColouredPass, AStepWithTheLastStepsContactsReusesItsColouring) {
  for (const bool tiled : {false, true}) {
    SmallPacking packing(0.1);
    Contacts contacts = packing.scene.work.contacts;
    VelocityCache velocities = packing.scene.work.velocities;
    // sphere 0 in 80 more (made-up) pairs: more than kMaxColours contacts, also in the hub of
    // a tiled step (where the pairs between distant tiles go), so some overflow
    const std::size_t spheres = velocities.spheres.size();
    ASSERT_GT(spheres, 81U);
    const PairProblem model = contacts.pairs.front();
    for (BodyIndex b = 1; b <= 80; ++b) {
      PairProblem p = model;
      p.a = 0;
      p.b = b;
      contacts.pairs.push_back(p);
      contacts.pair_actions.push_back(contacts.pair_actions.front());
      contacts.pair_cohesive.push_back(0);
    }
    StepTiles tiles = tiles_of(packing.scene.world, contacts, tiled);
    const std::span<const std::uint32_t> parts = tiles.sphere_part;
    TileThreads threads(2);
    PieceRunner* const pieces = tiled ? &threads : nullptr;
    ColouredPass reused;
    expect_same_preparation(contacts, velocities, tiles, reused, pieces);
    EXPECT_FALSE(reused.colouring.overflow.empty());
    EXPECT_EQ(reused.tiled(), tiled);
    ASSERT_TRUE(reused.built_from.match(contacts.pairs, contacts.walls, parts, 256, pieces));
    Rng rng = make_rng(3, RngStream::Deposition);
    // the same contacts with other values: the colouring is kept
    move_a_little(contacts, velocities, rng);
    expect_same_preparation(contacts, velocities, tiles, reused, pieces);
    // a pair fewer, a wall of another kind, a sphere in another tile: coloured afresh
    contacts.pairs.erase(contacts.pairs.begin() + 3);
    contacts.pair_actions.erase(contacts.pair_actions.begin() + 3);
    contacts.pair_cohesive.erase(contacts.pair_cohesive.begin() + 3);
    EXPECT_FALSE(reused.built_from.match(contacts.pairs, contacts.walls, parts, 256, pieces));
    expect_same_preparation(contacts, velocities, tiles, reused, pieces);
    ASSERT_FALSE(contacts.walls.empty());
    WallProblem& wall = contacts.walls.back();
    wall.wall = wall.wall == WallKind::Piston ? WallKind::Bottom : WallKind::Piston;
    EXPECT_FALSE(reused.built_from.match(contacts.pairs, contacts.walls, parts, 256, pieces));
    expect_same_preparation(contacts, velocities, tiles, reused, pieces);
    if (tiled) {
      move_to_next_tile(tiles, contacts.pairs[5].a);
      EXPECT_FALSE(reused.built_from.match(contacts.pairs, contacts.walls, parts, 256, pieces));
      expect_same_preparation(contacts, velocities, tiles, reused, pieces);
    }
    move_a_little(contacts, velocities, rng);
    expect_same_preparation(contacts, velocities, tiles, reused, pieces);
    // another chunk, or a build by other means (the tests' colourings): not the last build
    EXPECT_FALSE(reused.built_from.match(contacts.pairs, contacts.walls, parts, 512));
    EXPECT_TRUE(reused.built_from.match(contacts.pairs, contacts.walls, parts, 256, pieces));
    build_batches(contacts, velocities, reused);
    EXPECT_FALSE(reused.built_from.match(contacts.pairs, contacts.walls, parts, 256, pieces));
  }
}

// The pairs are compared in pieces of kChunkIndices on a runner: a change in any piece is
// found, and the answer is the caller's.
TEST(ColouredPass, KeptInputsAreComparedInPiecesOnTheThreads) {
  std::vector<PairProblem> pairs(3 * kChunkIndices + 5);
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    pairs[k].a = static_cast<BodyIndex>(k);
    pairs[k].b = static_cast<BodyIndex>(k + 1);
  }
  const std::vector<WallProblem> walls;
  const std::vector<std::uint32_t> parts{0, 1, 1, 0};
  ColouringInputs inputs;
  inputs.record(pairs, walls, parts, 256);
  TileThreads threads(2);
  for (PieceRunner* runner :
       {static_cast<PieceRunner*>(nullptr), static_cast<PieceRunner*>(&threads)}) {
    EXPECT_TRUE(inputs.match(pairs, walls, parts, 256, runner));
    for (const std::size_t changed : {std::size_t{0}, kChunkIndices + 7, pairs.size() - 1}) {
      std::vector<PairProblem> other = pairs;
      other[changed].b += 1;
      EXPECT_FALSE(inputs.match(other, walls, parts, 256, runner)) << changed;
    }
  }
}

// Whole steps with the coloured kernel converge to forces within the contact laws, with
// the same contact set as the scalar kernel (a different visiting order, so not the same bits).
TEST(ColouredPass, StepsConvergeLikeTheScalarKernel) {
  SmallPacking scalar(0.1);
  SmallPacking coloured(0.1);
  coloured.scene.settings.solver.kernel = PassKernel::Coloured;
  for (int k = 0; k < 5; ++k) {
    const StepReport a = scalar.scene.run(1);
    const StepReport b = coloured.scene.run(1);
    EXPECT_TRUE(a.solver.converged);
    EXPECT_TRUE(b.solver.converged);
    EXPECT_EQ(a.diagnostics.contacts, b.diagnostics.contacts);
  }
  const Bodies& x = scalar.scene.world.bodies;
  const Bodies& y = coloured.scene.world.bodies;
  for (std::size_t i = 0; i < x.size(); ++i) {
    EXPECT_LT((x.velocity[i] - y.velocity[i]).norm(), 1e-6) << "sphere " << i;
  }
}

}  // namespace
}  // namespace cdpowder::testing
