// detect_contacts.cpp — candidate pairs from the cell grid, sphere–wall candidates,
// and the start-of-step geometry that stays frozen during the passes (physics.md §3).
#include "cdpowder/detect/detect_contacts.hpp"

#include "cdpowder/contact/contact_law.hpp"
#include "cdpowder/core/assert.hpp"
#include "cdpowder/core/grow.hpp"
#include "cdpowder/core/lanes.hpp"
#include "cdpowder/detect/sphere_scan.hpp"
#include "cdpowder/model/finite.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace cdpowder {

#define CDP_LANE_CODE "cdpowder/detect/find_pairs_lanes.inc"
#include "cdpowder/core/lanes_instantiate.inc"

namespace {

/// max(d_coh, 2 v_max Δt) + skin, v_max the spheres' largest surface speed and the piston's.
double gap_for_speed(double sphere_speed, const World& world, const DetectionSettings& settings) {
  double v_max = sphere_speed;
  if (world.walls.piston.enabled) v_max = std::max(v_max, std::abs(world.walls.piston.velocity));
  return std::max(settings.cohesion_range, 2.0 * v_max * settings.dt) + settings.skin;
}

/// Room made for a known count of pairs, written in order: what find_pairs appends to when a
/// piece writes its pairs in place (detect_in_pieces).
struct PairCursor {
  PairProblem* at;

  void push_back(const PairProblem& p) { *at++ = p; }
};

/// What find_pairs_one_by_one appends to when only the count of its pairs is wanted.
struct PairCounter {
  std::size_t found = 0;

  void push_back(const PairProblem& /*p*/) { ++found; }
};

/// find_pairs one pair at a time: the definition of its arithmetic (find_pairs_lanes.inc takes
/// the same operations in lanes), and the list's last pairs that fill no block of lanes.
template <typename Out>
void find_pairs_one_by_one(const Bodies& bodies, const PeriodicBox& box, double cutoff,
                           const std::vector<CandidateList::Pair>& list, std::size_t first,
                           std::size_t last, Out& out) {
  for (std::size_t k = first; k < last; ++k) {
    const BodyIndex a = list[k].a;
    const BodyIndex b = list[k].b;
    const Vec3 d = box.minimum_image(bodies.position[b] - bodies.position[a]);
    const double reach = bodies.radius[a] + bodies.radius[b] + cutoff;
    const double distance_squared = d.squaredNorm();
    if (distance_squared >= reach * reach) continue;
    const double distance = std::sqrt(distance_squared);
    PairProblem p;
    p.a = a;
    p.b = b;
    // coincident centres have no normal; any unit vector keeps the kernel finite
    p.normal = distance > 0.0 ? Vec3(d / distance) : Vec3::UnitZ();
    p.gap = distance - bodies.radius[a] - bodies.radius[b];
    // levers to the common contact point, the middle of the gap (physics.md §4.2)
    p.lever_a = bodies.radius[a] + 0.5 * p.gap;
    p.lever_b = bodies.radius[b] + 0.5 * p.gap;
    p.r_eff = effective_radius(bodies.radius[a], bodies.radius[b]);
    // the kernels assume a unit normal (d/|d| is one to a few ulp) and a finite gap
    CDP_ASSERT(std::abs(p.normal.norm() - 1.0) < 1e-12 && std::isfinite(p.gap), "n or g");
    out.push_back(p);
  }
}

/// How many pairs of list[first, last) find_pairs keeps: the same test, in lanes, and the
/// rest counted by find_pairs_one_by_one itself.
std::size_t count_pairs(const Bodies& bodies, const PeriodicBox& box, double cutoff,
                        const std::vector<CandidateList::Pair>& list, std::size_t first,
                        std::size_t last) {
  PairCounter counter;
  const std::size_t rest = CDP_LANES_FOR_CPU(count_pair_lanes)(bodies, box, cutoff, list.data(),
                                                               first, last, counter.found);
  find_pairs_one_by_one(bodies, box, cutoff, list, rest, last, counter);
  return counter.found;
}

/// find_pairs on list[first, last) into room made for exactly the pairs it keeps (count_pairs).
void write_pairs(const Bodies& bodies, const PeriodicBox& box, double cutoff,
                 const std::vector<CandidateList::Pair>& list, std::size_t first, std::size_t last,
                 PairProblem* at) {
  PairCursor out{at};
  const std::size_t rest = CDP_LANES_FOR_CPU(find_pair_lanes<PairCursor>)(
      bodies, box, cutoff, list.data(), first, last, out);
  find_pairs_one_by_one(bodies, box, cutoff, list, rest, last, out);
}

/// Candidates searched between two reservations of `out` (a multiple of every lane count):
/// the room made for them is the most a block can add, so `out` never doubles.
constexpr std::size_t kPairSearchBlock = 1024;

/// Appends to `out` the geometry of every pair of list[first, last) whose centre distance is
/// below R_a + R_b + cutoff, in list order: blocks of lanes, then the rest one by one.
void find_pairs(const Bodies& bodies, const PeriodicBox& box, double cutoff,
                const std::vector<CandidateList::Pair>& list, std::size_t first, std::size_t last,
                std::vector<PairProblem>& out) {
  for (std::size_t begin = first; begin < last; begin += kPairSearchBlock) {
    const std::size_t end = std::min(last, begin + kPairSearchBlock);
    reserve_for_more(out, end - begin);
    const std::size_t rest = CDP_LANES_FOR_CPU(find_pair_lanes<std::vector<PairProblem>>)(
        bodies, box, cutoff, list.data(), begin, end, out);
    find_pairs_one_by_one(bodies, box, cutoff, list, rest, end, out);
  }
}

/// Appends to `out` the contacts of every sphere (in sphere order) with the wall `kind`: the
/// bottom (z = 0, never for a fixed sphere) or the piston, within the cutoff.
void find_walls(const World& world, WallKind kind, double cutoff, std::vector<WallProblem>& out) {
  const Bodies& bodies = world.bodies;
  const auto sphere_count = static_cast<BodyIndex>(bodies.size());
  const auto add_wall = [&](BodyIndex i, double gap, double normal_z) {
    WallProblem w;
    w.sphere = i;
    w.wall = kind;
    w.normal = Vec3(0.0, 0.0, normal_z);
    w.gap = gap;
    w.radius = bodies.radius[i];
    CDP_ASSERT(std::isfinite(gap), "non-finite wall gap");
    out.push_back(w);
  };
  if (kind == WallKind::Bottom) {
    if (!world.walls.bottom.enabled) return;
    for (BodyIndex i = 0; i < sphere_count; ++i) {
      const double gap = bodies.position[i].z() - bodies.radius[i];
      if (gap < cutoff && bodies.fixed[i] == 0) add_wall(i, gap, 1.0);
    }
    return;
  }
  if (!world.walls.piston.enabled) return;
  const double z_piston = world.walls.piston.height;
  for (BodyIndex i = 0; i < sphere_count; ++i) {
    const double gap = z_piston - bodies.position[i].z() - bodies.radius[i];
    if (gap < cutoff) add_wall(i, gap, -1.0);
  }
}

/// A value of one piece on a cache line of its own (the pieces write theirs side by side).
template <typename T>
struct alignas(64) OnItsLine {
  T value{};
};

/// The pieces of detect_in_pieces: one a chunk of the candidate list or of the spheres,
/// whichever has more (indices_per_piece), at least two (the bottom wall's contacts go with
/// piece 0 and the piston's with piece 1) and at most kMaxPieces. Fixed by the counts, never
/// by the threads; the contacts do not depend on it.
std::uint32_t detection_pieces(std::size_t spheres, std::size_t candidates) {
  const std::size_t most = std::max(spheres, candidates);
  return std::max<std::uint32_t>(
      2, static_cast<std::uint32_t>(chunks_of(most, indices_per_piece(most))));
}

/// detect_contacts in pieces: each piece of the spheres wrapped and its largest speed found;
/// then each piece of the candidate list counted (the pairs it keeps), with the bottom wall's
/// contacts in piece 0 and the piston's in piece 1; then each piece's pairs written in place,
/// after those of the pieces before it. The search assumes that the list covers the step,
/// which the counting pass checks on each piece of the spheres; where it does not, the list is
/// rebuilt and the count run again. Counting first costs a second test of each candidate, on
/// the threads; a join that copied the second half's pairs after the first's ran on this thread
/// alone and read them from the other core (docs/lab/2026-12-01-serial-stages-in-pieces.md),
/// and held them twice.
void detect_in_pieces(World& world, const DetectionSettings& settings, CellGrid& grid,
                      Contacts& contacts, CandidateList& list, PieceRunner* pieces,
                      DetectionScratch& scratch) {
  Bodies& bodies = world.bodies;
  const PeriodicBox& box = world.box;
  const std::size_t sphere_count = bodies.size();
  const std::uint32_t wrap_pieces = detection_pieces(sphere_count, 0);
  std::array<OnItsLine<double>, kMaxPieces> speed{};
  run_pieces(pieces, wrap_pieces, [&](std::uint32_t piece) {
    const IndexRange part = piece_of(sphere_count, wrap_pieces, piece);
    for (std::size_t i = part.first; i < part.last; ++i) box.wrap(bodies.position[i]);
    speed[piece].value = largest_surface_speed(bodies, part.first, part.last);
  });
  // max is exact: the pieces' maxima give candidate_gap's value
  double fastest = 0.0;
  for (std::uint32_t piece = 0; piece < wrap_pieces; ++piece) {
    fastest = std::max(fastest, speed[piece].value);
  }
  const double cutoff = gap_for_speed(fastest, world, settings);
  // the pairs' records are overwritten below, not cleared: a resize to this step's count then
  // constructs only the records beyond the last step's (the walls are cleared by the count)
  contacts.pair_actions.clear();
  contacts.pair_cohesive.clear();
  contacts.wall_actions.clear();
  contacts.wall_cohesive.clear();

  std::array<OnItsLine<std::size_t>, kMaxPieces> found{};
  std::uint32_t count_pieces = 0;
  const auto count = [&](bool check_cover) {
    const std::size_t candidates = list.pairs().size();
    count_pieces = detection_pieces(sphere_count, candidates);
    std::array<OnItsLine<bool>, kMaxPieces> covered{};
    contacts.walls.clear();
    scratch.walls.clear();
    run_pieces(pieces, count_pieces, [&](std::uint32_t piece) {
      if (check_cover) {
        const IndexRange spheres = piece_of(sphere_count, count_pieces, piece);
        covered[piece].value =
            list.covers_spheres(bodies, box, cutoff, spheres.first, spheres.last);
        if (!covered[piece].value) return;
      }
      const IndexRange listed = piece_of(candidates, count_pieces, piece);
      found[piece].value =
          count_pairs(bodies, box, cutoff, list.pairs(), listed.first, listed.last);
      if (piece < 2) {
        find_walls(world, piece == 0 ? WallKind::Bottom : WallKind::Piston, cutoff,
                   piece == 0 ? contacts.walls : scratch.walls);
      }
    });
    return !check_cover || std::all_of(covered.begin(), covered.begin() + count_pieces,
                                       [](const OnItsLine<bool>& c) { return c.value; });
  };
  if (!list.may_cover(bodies, box, cutoff) || !count(true)) {
    list.rebuild(bodies, box, grid, cutoff, settings.verlet_margin, pieces);
    count(false);
  }
  std::array<std::size_t, kMaxPieces + 1> start{};
  for (std::uint32_t piece = 0; piece < count_pieces; ++piece) {
    start[piece + 1] = start[piece] + found[piece].value;
  }
  const std::size_t pair_count = start[count_pieces];
  if (pair_count > contacts.pairs.size()) {
    reserve_for_more(contacts.pairs, pair_count - contacts.pairs.size());
  }
  contacts.pairs.resize(pair_count);
  run_pieces(pieces, count_pieces, [&](std::uint32_t piece) {
    const IndexRange listed = piece_of(list.pairs().size(), count_pieces, piece);
    write_pairs(bodies, box, cutoff, list.pairs(), listed.first, listed.last,
                contacts.pairs.data() + start[piece]);
  });
  contacts.walls.insert(contacts.walls.end(), scratch.walls.begin(), scratch.walls.end());
}

}  // namespace

double candidate_gap(const World& world, const DetectionSettings& settings) {
  return gap_for_speed(largest_surface_speed(world.bodies, 0, world.bodies.size()), world,
                       settings);
}

void detect_contacts(World& world, const DetectionSettings& settings, CellGrid& grid,
                     Contacts& contacts, CandidateList* reuse, PieceRunner* pieces,
                     DetectionScratch* scratch) {
  // stage 1 is the start of a step: its inputs must be finite (debug builds only)
  CDP_ASSERT(all_finite(world) && std::isfinite(settings.dt), "non-finite step input");
  if (pieces != nullptr && scratch != nullptr && reuse != nullptr) {
    detect_in_pieces(world, settings, grid, contacts, *reuse, pieces, *scratch);
    return;
  }
  Bodies& bodies = world.bodies;
  const PeriodicBox& box = world.box;
  for (Vec3& p : bodies.position) box.wrap(p);

  const double cutoff = candidate_gap(world, settings);
  contacts.clear();

  // sphere–sphere: centre distance < R_a + R_b + cutoff, among the pairs of the candidate
  // list (sorted by (a, b), the order of the warm-start cache), rebuilt when it no longer
  // covers this step's cutoff
  CandidateList fresh;
  CandidateList& list = reuse != nullptr ? *reuse : fresh;
  if (!list.covers(bodies, box, cutoff)) {
    list.rebuild(bodies, box, grid, cutoff, settings.verlet_margin);
  }
  find_pairs(bodies, box, cutoff, list.pairs(), 0, list.pairs().size(), contacts.pairs);
  // sphere–wall, bottom first then piston, each in sphere order (the cache's key order)
  find_walls(world, WallKind::Bottom, cutoff, contacts.walls);
  find_walls(world, WallKind::Piston, cutoff, contacts.walls);
}

}  // namespace cdpowder
