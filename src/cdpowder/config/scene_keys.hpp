// scene_keys.hpp — every scene key, declared once: its TOML table and name, the field of the
// Scene it fills (its type is the field's), its allowed values, and its symbol, unit and
// meaning for docs/config.md. A key's default is its field's in-class value (scene.hpp,
// settings.hpp). The reader (scene_reader.cpp), the writer (scene_writer.cpp) and the key
// tables of docs/config.md (scene_key_docs.hpp) all walk these lists, so a key added here
// is read, written and documented; the checks across keys stay in the reader.
#pragma once

#include "cdpowder/config/scene.hpp"
#include "cdpowder/config/table_reader.hpp"
#include "cdpowder/solver/settings.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>

namespace cdpowder::detail {

/// One key. Each list below calls `visit(key, field)`; the field's type says how the key is
/// read and written (double, optional<double>, int, uint64_t, bool, Vec3, an enum, a path).
struct SceneKey {
  std::string_view table;  ///< "contact.wall"; the key is `table.name`
  std::string_view name;
  std::string_view symbol = "–";
  std::string_view unit = "–";
  Range range = kAnyNumber;           ///< of a number
  std::int64_t minimum = 0;           ///< of an integer
  std::int64_t maximum = kNoMaximum;  ///< of an integer (an int field also stops at INT_MAX)
  std::string_view meaning;
  /// Docs only: the rule across keys that completes the allowed values (", ≤ `max_passes`");
  /// the reader checks it beside the table.
  std::string_view also_allowed = {};
  /// Docs only: the default when it is another key's value (`radius`).
  std::string_view default_text = {};
  /// The key of the same name in this table is the default (after the overrides): the reader
  /// copies it before reading this one; the docs name it.
  std::string_view default_table = {};

  [[nodiscard]] std::string dotted() const { return fmt::format("{}.{}", table, name); }
};

/// A key that only sets two others to its value (deposition.radius sets radius_min and
/// radius_max): read, never written; its default is theirs.
template <typename T>
struct SetsBoth {
  T& first;
  T& second;
};

template <typename T>
SetsBoth(T&, T&) -> SetsBoth<T>;

// The TOML spelling of each enumerator of a string-valued key; the reader lists them in this
// order in its messages.
inline constexpr EnumNames<CohesionRule, 2> kCohesionRuleNames = {
    {{"graph", CohesionRule::Graph}, {"history", CohesionRule::History}}};
inline constexpr EnumNames<StoppingRule, 2> kStoppingRuleNames = {
    {{"residual", StoppingRule::Residual}, {"relative_change", StoppingRule::RelativeChange}}};
inline constexpr EnumNames<KinematicNorm, 2> kKinematicNormNames = {
    {{"max", KinematicNorm::Max}, {"rms", KinematicNorm::Rms}}};
inline constexpr EnumNames<VtkFormat, 4> kVtkFormatNames = {{{"auto", VtkFormat::Auto},
                                                             {"ascii", VtkFormat::Ascii},
                                                             {"binary", VtkFormat::Binary},
                                                             {"zlib", VtkFormat::Zlib}}};
inline constexpr EnumNames<CaptureRule, 2> kCaptureRuleNames = {
    {{"centre_distance", CaptureRule::CentreDistance}, {"surface_gap", CaptureRule::SurfaceGap}}};
inline constexpr EnumNames<VisitOrder, 3> kVisitOrderNames = {
    {{"random_each_step", VisitOrder::RandomEachStep},
     {"random_each_pass", VisitOrder::RandomEachPass},
     {"fixed", VisitOrder::Fixed}}};
inline constexpr EnumNames<PassKernel, 2> kPassKernelNames = {
    {{"scalar", PassKernel::Scalar}, {"coloured", PassKernel::Coloured}}};

// The names of an enum-valued field's choices, found by its type.
constexpr const auto& choices_of(CohesionRule /*unused*/) {
  return kCohesionRuleNames;
}

constexpr const auto& choices_of(StoppingRule /*unused*/) {
  return kStoppingRuleNames;
}

constexpr const auto& choices_of(KinematicNorm /*unused*/) {
  return kKinematicNormNames;
}

constexpr const auto& choices_of(VtkFormat /*unused*/) {
  return kVtkFormatNames;
}

constexpr const auto& choices_of(CaptureRule /*unused*/) {
  return kCaptureRuleNames;
}

constexpr const auto& choices_of(VisitOrder /*unused*/) {
  return kVisitOrderNames;
}

constexpr const auto& choices_of(PassKernel /*unused*/) {
  return kPassKernelNames;
}

// The tables of a scene file, in the order the reader reads them (and reports in).
inline constexpr std::string_view kSystemTable = "system";
inline constexpr std::string_view kContactTable = "contact";
inline constexpr std::string_view kWallTable = "contact.wall";
inline constexpr std::string_view kSolverTable = "solver";
inline constexpr std::string_view kPistonTable = "piston";
inline constexpr std::string_view kDepositionTable = "deposition";
inline constexpr std::string_view kParticlesTable = "particles";
inline constexpr std::string_view kRunTable = "run";
inline constexpr std::string_view kBlockedTable = "run.blocked";

/// A fraction of something: in (0, 1].
inline constexpr Range kFraction{Range::Kind::FractionAbove, 0.0};
inline constexpr Range kAtLeastOne{Range::Kind::AtLeast, 1.0};

// The meanings too long to sit in their list.
inline constexpr std::string_view kThreadsMeaning =
    "threads of a step's solve, 0 for every core the process may use (OMP_NUM_THREADS's count "
    "when it is set); never more than its "
    "affinity mask, its CPU quota (cgroup cpu.max) and CDPOWDER_MAX_THREADS allow (a sweep "
    "running J runs at once gives each its share of the cores). A step with at least 256 pairs "
    "is cut into the tiles of `tile_width`, solved in four phases of a 2 × 2 checkerboard (the "
    "tiles of a phase share no sphere and run side by side) and the hub of the piston's "
    "contacts on one thread, the five in an order drawn per step. The tiles do not depend on the "
    "thread count, so the results are the same bits "
    "for any count. Since the bits do not depend on it, steps go in blocks of 16 on the threads "
    "or on the calling thread alone, by time per contact update: a block tries the other way "
    "after 32 blocks (after twice as many, up to 128, each time that way lost by more than "
    "25 %), or at once when a block took longer than the other way's last, and two tries in a "
    "row that win change the way: when the other cores are busy, a run falls back to about one "
    "thread's speed (summary.json counts the steps on the threads, `run.threaded_steps`; "
    "CDPOWDER_ALWAYS_THREADED=1 keeps every step on them, for tests and measurements). After a "
    "step solved on the threads, the next step's detection and building of the local problems "
    "run on them too. The threads are OpenMP's: OMP_WAIT_POLICY, OMP_PROC_BIND and OMP_PLACES "
    "set how they wait and where they run";
inline constexpr std::string_view kTileWidthMeaning =
    "the width the x–y tiles of a step aim at (docs/architecture.md, \"Scale\"); 0 for "
    "12 × the largest radius. A period L gets the largest even number of tiles n with L/n ≥ "
    "the width, or one tile where L is less than twice it. The tiles fix the order of a pass, "
    "so another width gives other (equally converged) results; the thread count does not";
inline constexpr std::string_view kCaptureRuleMeaning =
    "centre_distance: r_capt is the centre-to-centre distance of two mean spheres, capture at a "
    "surface gap r_capt − (radius_min + radius_max) (needs r_capt ≥ radius_min + radius_max; "
    "r_capt = 2R is plain ballistic deposition); surface_gap: r_capt is the surface gap itself";
inline constexpr std::string_view kVtkFormatMeaning =
    "how every .vtp file holds its arrays: \"ascii\", text with 9 significant digits, one tuple "
    "a line (readable and diffable); \"binary\", appended base64-encoded little-endian binary "
    "at full precision (smaller, faster for ParaView to load); \"zlib\", appended raw binary "
    "compressed with zlib in VTK's own layout (vtkZLibDataCompressor; the smallest, for large "
    "packings; VTK 9 and ParaView read it); \"auto\", \"ascii\" below 10 000 spheres and "
    "\"zlib\" from there on";

// ---------------------------------------------------------------------------------------------
// The lists, one function per table, in file order. Each takes the part of a Scene (or of a
// const Scene) that its table fills and calls visit(key, field) once per key.

void visit_system_keys(auto& system, auto&& visit) {
  const std::string_view table = kSystemTable;
  visit(SceneKey{.table = table,
                 .name = "lx",
                 .symbol = "L_x",
                 .unit = "R",
                 .range = kPositive,
                 .meaning = "period of the cell along x"},
        system.lx);
  visit(SceneKey{.table = table,
                 .name = "ly",
                 .symbol = "L_y",
                 .unit = "R",
                 .range = kPositive,
                 .meaning = "period of the cell along y"},
        system.ly);
  visit(SceneKey{.table = table,
                 .name = "gravity",
                 .symbol = "g",
                 .unit = "R/t0²",
                 .meaning = "acceleration of spheres and piston (the paper has none)"},
        system.gravity);
  visit(SceneKey{.table = table,
                 .name = "density",
                 .symbol = "ρ",
                 .unit = "ρ",
                 .range = kPositive,
                 .meaning = "density of every sphere; sets m = 4π/3 ρ r³ and I = 2/5 m r²"},
        system.density);
  visit(SceneKey{.table = table,
                 .name = "bottom_wall",
                 .symbol = "B",
                 .meaning = "the immobile plane z = 0 (physics.md §4.1)"},
        system.bottom_wall);
}

/// [contact]: the sphere–sphere law and the cohesion rule.
void visit_contact_keys(auto& laws, auto&& visit) {
  const std::string_view table = kContactTable;
  auto& law = laws.spheres;
  visit(SceneKey{.table = table,
                 .name = "mu",
                 .symbol = "μ",
                 .range = kNonNegative,
                 .meaning = "sliding friction: |R_t| ≤ μ (F_n + F_coh)"},
        law.mu);
  visit(SceneKey{.table = table,
                 .name = "mu_roll",
                 .symbol = "μ_t",
                 .range = kNonNegative,
                 .meaning = "rolling friction: |T_t| ≤ μ_t (F_n + F_coh) r_eff"},
        law.mu_roll);
  visit(SceneKey{.table = table,
                 .name = "mu_twist",
                 .symbol = "μ_n",
                 .range = kNonNegative,
                 .meaning = "torsion friction: |T_n| ≤ μ_n (F_n + F_coh) r_eff"},
        law.mu_twist);
  visit(SceneKey{.table = table,
                 .name = "cohesion_force",
                 .symbol = "F_coh",
                 .unit = "F_coh",
                 .range = kNonNegative,
                 .meaning = "constant attraction of a cohesive contact"},
        law.cohesion_force);
  visit(SceneKey{.table = table,
                 .name = "cohesion_range",
                 .symbol = "d_coh",
                 .unit = "R",
                 .range = kNonNegative,
                 .meaning = "start-of-step gap up to which the attraction acts (§6.3)"},
        law.cohesion_range);
  visit(SceneKey{.table = table,
                 .name = "cohesion_rule",
                 .meaning = "graph: active iff g ≤ d_coh; history: iff touching (g ≤ 1e-6 R, the "
                            "contact law's dead band), or active in the previous step and "
                            "g ≤ d_coh (§6.2)"},
        laws.cohesion_rule);
}

/// [contact.wall]: the sphere–wall law. Its coefficients default to [contact]'s after the
/// overrides: the reader copies laws.spheres into laws.walls before it reads them.
void visit_wall_keys(auto& laws, auto&& visit) {
  const std::string_view table = kWallTable;
  const std::string_view same = kContactTable;
  auto& law = laws.walls;
  visit(SceneKey{.table = table,
                 .name = "mu",
                 .symbol = "μ",
                 .range = kNonNegative,
                 .meaning = "sliding friction at a wall",
                 .default_table = same},
        law.mu);
  visit(SceneKey{.table = table,
                 .name = "mu_roll",
                 .symbol = "μ_t",
                 .range = kNonNegative,
                 .meaning = "rolling friction at a wall",
                 .default_table = same},
        law.mu_roll);
  visit(SceneKey{.table = table,
                 .name = "mu_twist",
                 .symbol = "μ_n",
                 .range = kNonNegative,
                 .meaning = "torsion friction at a wall",
                 .default_table = same},
        law.mu_twist);
  visit(SceneKey{.table = table,
                 .name = "cohesion_force",
                 .symbol = "F_coh",
                 .unit = "F_coh",
                 .range = kNonNegative,
                 .meaning = "attraction towards a wall",
                 .default_table = same},
        law.cohesion_force);
  visit(SceneKey{.table = table,
                 .name = "cohesion_range",
                 .symbol = "d_coh",
                 .unit = "R",
                 .range = kNonNegative,
                 .meaning = "range of that attraction",
                 .default_table = same},
        law.cohesion_range);
  visit(SceneKey{.table = table,
                 .name = "r_eff_factor",
                 .symbol = "r_eff / R",
                 .range = kNonNegative,
                 .meaning = "lever at a wall, r_eff = factor × sphere radius (R_wall → ∞ limit, "
                            "§5.4)"},
        laws.wall_r_eff_factor);
}

/// [solver], the time step: fixed, or adaptive within bounds (physics.md §6.4).
void visit_time_step_keys(auto& solver, auto&& visit) {
  const std::string_view table = kSolverTable;
  auto& control = solver.time_step;
  visit(SceneKey{.table = table,
                 .name = "dt",
                 .symbol = "Δt",
                 .unit = "t0",
                 .range = kPositive,
                 .meaning = "time step; with `adaptive_dt`, the first step's",
                 .also_allowed = ", ≥ the run's duration / 10¹²"},
        solver.dt);
  visit(SceneKey{.table = table,
                 .name = "adaptive_dt",
                 .meaning = "choose Δt after every step (physics.md §6.4, below)"},
        control.adaptive);
  visit(SceneKey{.table = table,
                 .name = "dt_min",
                 .unit = "t0",
                 .range = kPositive,
                 .meaning = "lower bound of the adaptive Δt",
                 .also_allowed = ", ≤ dt when adaptive"},
        control.dt_min);
  visit(SceneKey{.table = table,
                 .name = "dt_max",
                 .unit = "t0",
                 .range = kPositive,
                 .meaning = "upper bound of the adaptive Δt",
                 .also_allowed = ", ≥ dt when adaptive"},
        control.dt_max);
  visit(SceneKey{.table = table,
                 .name = "opening_per_step",
                 .range = kFraction,
                 .meaning = "adaptive Δt: the largest opening speed V_n of a cohesion-active "
                            "contact times Δt stays below this fraction of d_coh (the accuracy "
                            "contract allows 0.1)"},
        control.opening_per_step);
  visit(SceneKey{.table = table,
                 .name = "max_opening_per_step",
                 .range = kPositive,
                 .meaning = "adaptive Δt: a step that opened a cohesion-active contact by more "
                            "than this fraction of d_coh is undone and solved again with Δt "
                            "scaled to `opening_per_step` (at most half), down to `dt_min`",
                 .also_allowed = ", ≥ opening_per_step"},
        control.max_opening_per_step);
  visit(SceneKey{.table = table,
                 .name = "displacement_per_step",
                 .range = kFraction,
                 .meaning = "adaptive Δt: the fastest surface (|v| + R|ω|, and the piston) moves "
                            "at most this fraction of min(R_min, skin) per step"},
        control.displacement_per_step);
  visit(SceneKey{.table = table,
                 .name = "dt_growth",
                 .range = kAtLeastOne,
                 .meaning = "adaptive Δt: the largest ratio of two consecutive steps"},
        control.growth);
}

/// [solver], when a step's contact problem is solved.
void visit_stopping_keys(auto& solver, auto&& visit) {
  const std::string_view table = kSolverTable;
  visit(SceneKey{.table = table,
                 .name = "tolerance",
                 .range = kPositive,
                 .meaning = "stopping threshold of the chosen `stopping_rule`"},
        solver.tolerance);
  visit(SceneKey{.table = table,
                 .name = "max_error_amplification",
                 .range = kAtLeastOne,
                 .meaning = "the residual rule's error estimate is residual/(1 − ρ), ρ the "
                            "measured contraction per pass; this bounds the factor 1/(1 − ρ). "
                            "The default leaves it unbounded in effect (ρ ≤ 0.999)"},
        solver.max_error_amplification);
  visit(SceneKey{.table = table,
                 .name = "kinematic_tolerance",
                 .range = kNonNegative,
                 .meaning =
                     "κ, a second way to finish a step (physics.md §7.3): stop once the largest "
                     "change of a sphere's surface velocity √(|Δv|² + R²|Δω|²) over the last "
                     "pass, divided by (1 − ρ) (ρ its measured contraction per pass, after a "
                     "full window of 8 passes), is at most κ × the RMS surface speed of the "
                     "spheres, and the same holds for the piston against its own speed. At the "
                     "compaction front the force residual stalls while the velocities no longer "
                     "change (the forces of a rigid packing are not unique, physics.md §12.4). "
                     "0 = off. A packing at rest never meets it; the static final solve, whose "
                     "forces give the stress, does not use it"},
        solver.kinematic_tolerance);
  visit(SceneKey{.table = table,
                 .name = "kinematic_norm",
                 .meaning =
                     "what the kinematic rule measures of the spheres' velocity changes: max, "
                     "the largest change (it grows with the sphere count, so a wider cell takes "
                     "more passes a step); rms, the RMS change, a relative change of the "
                     "velocity field that does not grow with it (κ/10 takes about the passes "
                     "of max at the paper's 1 015 spheres; physics.md §7.3)"},
        solver.kinematic_norm);
  visit(SceneKey{.table = table,
                 .name = "min_passes",
                 .symbol = "N_min",
                 .minimum = 1,
                 .meaning = "never stop a step earlier",
                 .also_allowed = ", ≤ `max_passes`"},
        solver.min_passes);
  visit(SceneKey{.table = table,
                 .name = "max_passes",
                 .symbol = "N_max",
                 .minimum = 1,
                 .meaning = "pass cap; a capped step is flagged in its report"},
        solver.max_passes);
  visit(SceneKey{.table = table,
                 .name = "stopping_rule",
                 .meaning = "residual: estimated remaining force error (§17); relative_change: "
                            "⟨|ΔR|⟩ ≤ α ⟨|R|⟩ ([S+12] II)"},
        solver.stopping_rule);
}

/// [solver], how the passes go: order, kernel, threads, acceleration.
void visit_pass_keys(auto& solver, auto&& visit) {
  const std::string_view table = kSolverTable;
  visit(SceneKey{.table = table,
                 .name = "visit_order",
                 .meaning = "contact order: a permutation per step, a new one per pass (the "
                            "group's choice, §7.1), or storage order"},
        solver.visit_order);
  visit(SceneKey{.table = table,
                 .name = "kernel",
                 .meaning =
                     "pass kernel. \"coloured\": the sphere–sphere contacts graph-coloured each "
                     "step and solved in batches of 4 per colour, colours in a random order per "
                     "step (`visit_order` applies to colours, physics.md §7.1), bottom-wall "
                     "contacts in batches of 4 too, overflow and piston contacts one by one; "
                     "\"scalar\": one contact after the other in a permutation of blocks of "
                     "contacts. Different visiting orders, so different "
                     "(equally converged) results; \"coloured\" is 2.4× faster per pass with "
                     "AVX2 and 3.9× with AVX-512 (docs/performance.md, \"The kernel "
                     "benchmark\")"},
        solver.kernel);
  visit(SceneKey{.table = table,
                 .name = "threads",
                 .minimum = 0,
                 .maximum = kMaxSolverThreads,
                 .meaning = kThreadsMeaning,
                 .also_allowed = ", or \"auto\" (0); > 1 only with `kernel = \"coloured\"` "
                                 "(the default)"},
        solver.threads);
  visit(SceneKey{.table = table,
                 .name = "tile_width",
                 .unit = "R",
                 .range = kNonNegative,
                 .meaning = kTileWidthMeaning},
        solver.tile_width);
  visit(SceneKey{.table = table,
                 .name = "acceleration_depth",
                 .symbol = "m",
                 .minimum = 0,
                 .maximum = kMaxAndersonDepth,
                 .meaning = "Anderson acceleration history; 0 = plain NLGS (use 0 with "
                            "\"random_each_pass\")"},
        solver.acceleration_depth);
  visit(SceneKey{.table = table,
                 .name = "acceleration_interval",
                 .symbol = "k",
                 .minimum = 1,
                 .maximum = 100,
                 .meaning = "passes per Anderson mixing step (the accelerated map is k passes in a "
                            "row); a mixing cost more than a pass on a paper-size packing, "
                            "so 3 mixed the fastest in its measurement "
                            "(docs/lab/2026-11-23-kernel-and-mixing-levers.md)"},
        solver.acceleration_interval);
}

/// [solver], the rest: warm start, contact detection, the seed.
void visit_solver_keys(auto& solver, auto&& visit) {
  visit_time_step_keys(solver, visit);
  visit_stopping_keys(solver, visit);
  visit_pass_keys(solver, visit);
  const std::string_view table = kSolverTable;
  visit(SceneKey{.table = table,
                 .name = "warm_start",
                 .meaning = "start each step from the previous actions (§7.4)"},
        solver.warm_start);
  visit(SceneKey{.table = table,
                 .name = "skin",
                 .unit = "R",
                 .range = kNonNegative,
                 .meaning = "extra candidate distance beyond max(d_coh, 2 v_max Δt) (§4.3)"},
        solver.skin);
  visit(SceneKey{.table = table,
                 .name = "verlet_margin",
                 .unit = "R",
                 .range = kNonNegative,
                 .meaning = "the candidate list holds pairs up to this beyond the candidate gap "
                            "and is rebuilt (a cell-grid search) only once a sphere has moved "
                            "about half of it; 0 rebuilds every step. Speed only: every step's "
                            "contacts are the same for any value"},
        solver.verlet_margin);
  visit(SceneKey{.table = table,
                 .name = "seed",
                 .minimum = 0,
                 .meaning = "seed of the pass-order random stream"},
        solver.seed);
}

void visit_piston_keys(auto& piston, auto&& visit) {
  const std::string_view table = kPistonTable;
  visit(SceneKey{.table = table,
                 .name = "enabled",
                 .symbol = "P",
                 .meaning = "add the piston; then exactly one of `pressure`, `force` is required"},
        piston.enabled);
  visit(SceneKey{.table = table,
                 .name = "mass",
                 .symbol = "M_P",
                 .unit = "ρR³",
                 .range = kPositive,
                 .meaning = "piston mass (paper: 1000)"},
        piston.mass);
  visit(SceneKey{.table = table,
                 .name = "pressure",
                 .symbol = "F/(L_x L_y)",
                 .unit = "F_coh/R²",
                 .range = kNonNegative,
                 .meaning = "constant push as a pressure (paper: 1/400); not with `force`"},
        piston.pressure);
  visit(SceneKey{.table = table,
                 .name = "force",
                 .symbol = "F",
                 .unit = "F_coh",
                 .range = kNonNegative,
                 .meaning = "constant push as a force; not with `pressure`"},
        piston.force);
  // above the bottom wall z = 0; below the spheres' tops the first step stops the run at its
  // overlap bound (run.max_overlap)
  visit(SceneKey{.table = table,
                 .name = "height",
                 .symbol = "Z_P",
                 .unit = "R",
                 .range = kPositive,
                 .meaning = "initial height of the lower face; unset: highest sphere top + "
                            "`start_gap`"},
        piston.height);
  visit(SceneKey{.table = table,
                 .name = "start_gap",
                 .unit = "R",
                 .range = kNonNegative,
                 .meaning = "initial gap above the highest sphere when `height` is unset"},
        piston.start_gap);
  visit(SceneKey{.table = table,
                 .name = "velocity",
                 .symbol = "V_P",
                 .unit = "R/t0",
                 .meaning = "initial piston velocity (negative = downwards)"},
        piston.velocity);
}

/// A run holds about 2 kB per sphere (state, candidates, contacts): 10⁷ spheres need ≈ 20 GB;
/// beyond that the allocation would fail after the outputs were begun.
inline constexpr std::int64_t kMaxSpheres = 10'000'000;

/// [deposition] (its L_x, L_y are [system]'s, set by the reader).
void visit_deposition_keys(auto& d, auto&& visit) {
  const std::string_view table = kDepositionTable;
  visit(SceneKey{.table = table,
                 .name = "spheres",
                 .symbol = "N",
                 .minimum = 1,
                 .maximum = kMaxSpheres,
                 .meaning = "number of spheres (paper: 1015); a run holds about 2 kB per sphere"},
        d.spheres);
  // `radius` sets both ends of a monodisperse deposit; radius_min/max a uniform spread
  visit(SceneKey{.table = table,
                 .name = "radius",
                 .symbol = "R",
                 .unit = "R",
                 .range = kPositive,
                 .meaning = "radius of a monodisperse deposit; sets both ends below"},
        SetsBoth{d.radius_min, d.radius_max});
  visit(SceneKey{.table = table,
                 .name = "radius_min",
                 .unit = "R",
                 .range = kPositive,
                 .meaning = "smallest radius: radii are uniform in [radius_min, radius_max] "
                            "(polydisperse)",
                 .also_allowed = ", ≤ radius_max",
                 .default_text = "`radius`"},
        d.radius_min);
  visit(SceneKey{.table = table,
                 .name = "radius_max",
                 .unit = "R",
                 .range = kPositive,
                 .meaning = "largest radius",
                 .default_text = "`radius`"},
        d.radius_max);
  visit(SceneKey{.table = table,
                 .name = "capture_radius",
                 .symbol = "r_capt",
                 .unit = "R",
                 .range = kPositive,
                 .meaning = "paper: 3",
                 .also_allowed = ", ≤ min(`system.lx`, `system.ly`)/2"},
        d.capture_radius);
  visit(SceneKey{.table = table, .name = "capture_rule", .meaning = kCaptureRuleMeaning},
        d.capture_rule);
  visit(SceneKey{.table = table,
                 .name = "seed",
                 .minimum = 0,
                 .meaning = "seed of the deposition's random stream (independent of "
                            "`solver.seed`)"},
        d.seed);
}

/// [particles] file: read beside the table (a path against the scene's folder, and only
/// when there is no [deposition]).
void visit_particles_keys(auto& particles_file, auto&& visit) {
  visit(SceneKey{.table = kParticlesTable,
                 .name = "file",
                 .meaning = "CSV of the spheres; a relative path is resolved against the scene "
                            "file's folder",
                 .default_text = "required without `[deposition]`"},
        particles_file);
}

void visit_run_keys(auto& run, auto&& visit) {
  const std::string_view table = kRunTable;
  visit(SceneKey{.table = table,
                 .name = "duration",
                 .unit = "t0",
                 .range = kPositive,
                 .meaning = "simulated time when `until_blocked` is false"},
        run.duration);
  visit(SceneKey{.table = table,
                 .name = "until_blocked",
                 .meaning = "stop at the blocked state: at rest, every sphere in balance (without "
                            "a piston: the spheres alone, physics.md §9)"},
        run.until_blocked);
  visit(SceneKey{.table = table,
                 .name = "max_duration",
                 .unit = "t0",
                 .range = kPositive,
                 .meaning = "give up waiting for the blocked state after this time (flagged)"},
        run.max_duration);
  visit(SceneKey{.table = table,
                 .name = "timeseries_every",
                 .symbol = "K",
                 .minimum = 1,
                 .meaning = "one timeseries.csv row every K steps"},
        run.timeseries_every);
  visit(SceneKey{.table = table,
                 .name = "snapshot_every",
                 .symbol = "K",
                 .minimum = 0,
                 .meaning = "a VTK snapshot (snapshots/*.vtp, particles.pvd, contacts.pvd, "
                            "walls.pvd) every K steps, plus t = 0 and the end; 0 = none"},
        run.snapshot_every);
  visit(SceneKey{.table = table,
                 .name = "timeseries_interval",
                 .unit = "t0",
                 .range = kNonNegative,
                 .meaning = "> 0: a timeseries.csv row at the first step that reaches each "
                            "multiple of this time, instead of every `timeseries_every` steps "
                            "(the cadence for `solver.adaptive_dt`, whose steps differ in "
                            "length)"},
        run.timeseries_interval);
  visit(SceneKey{.table = table,
                 .name = "snapshot_interval",
                 .unit = "t0",
                 .range = kNonNegative,
                 .meaning = "> 0: a snapshot at each multiple of this time instead of every "
                            "`snapshot_every` steps"},
        run.snapshot_interval);
  visit(SceneKey{.table = table,
                 .name = "max_overlap",
                 .unit = "R",
                 .range = kPositive,
                 .meaning = "a step after which any contact overlaps by more than this is a "
                            "fault: the run stops there (below)"},
        run.max_overlap);
  visit(SceneKey{.table = table, .name = "vtk_format", .meaning = kVtkFormatMeaning},
        run.vtk_format);
}

/// [run.blocked]: when the piston has come to rest (physics.md §9).
void visit_blocked_keys(auto& blocked, auto&& visit) {
  const std::string_view table = kBlockedTable;
  visit(SceneKey{.table = table,
                 .name = "window",
                 .unit = "t0",
                 .range = kPositive,
                 .meaning = "length of the window",
                 .also_allowed = ", at most 1e6 steps of `solver.dt`"},
        blocked.window);
  visit(SceneKey{.table = table,
                 .name = "piston_speed",
                 .symbol = "|V_P|",
                 .unit = "R/t0",
                 .range = kPositive,
                 .meaning = "piston speed below"},
        blocked.piston_speed);
  visit(SceneKey{.table = table,
                 .name = "sphere_speed",
                 .symbol = "√(Σ m_i v_i² / Σ m_i)",
                 .unit = "R/t0",
                 .range = kPositive,
                 .meaning = "mass-weighted RMS sphere speed below (not the fastest sphere: a "
                            "rattler does not make a packing flow)"},
        blocked.sphere_speed);
  visit(SceneKey{.table = table,
                 .name = "force_balance",
                 .symbol = "|Σ R_c→P·e_z − F| / F",
                 .range = kPositive,
                 .meaning = "window mean of the relative force imbalance on the piston below"},
        blocked.force_balance);
  visit(SceneKey{.table = table,
                 .name = "height_change",
                 .symbol = "|ΔZ_P| / Z_P",
                 .range = kPositive,
                 .meaning = "relative piston travel over the window below"},
        blocked.height_change);
  visit(SceneKey{.table = table,
                 .name = "final_tolerance",
                 .range = kPositive,
                 .meaning = "once blocked, the velocities are set to zero and one more step is "
                            "solved to this tolerance; the stress, contact counts and force "
                            "balance are measured on its forces (not counted in the run's steps "
                            "and passes)"},
        blocked.final_tolerance);
  visit(SceneKey{.table = table,
                 .name = "final_max_passes",
                 .minimum = 1,
                 .meaning = "pass cap of that step"},
        blocked.final_max_passes);
}

/// Every key of a scene as it is written back (Scene::effective_toml): [deposition] when the
/// spheres come from a deposit, [particles] when from a file, neither when the caller makes
/// them (SceneReadOptions::spheres_from_caller); `deposition.radius` is visited as SetsBoth.
void visit_scene_keys(auto& scene, auto&& visit) {
  visit_system_keys(scene.system, visit);
  visit_contact_keys(scene.step.laws, visit);
  visit_wall_keys(scene.step.laws, visit);
  visit_solver_keys(scene.step.solver, visit);
  visit_piston_keys(scene.piston, visit);
  if (scene.deposition) {
    visit_deposition_keys(*scene.deposition, visit);
  } else if (!scene.particles_file.empty()) {
    visit_particles_keys(scene.particles_file, visit);
  }
  visit_run_keys(scene.run, visit);
  visit_blocked_keys(scene.run.blocked, visit);
}

// ---------------------------------------------------------------------------------------------
// Keys by their fields: the checks across keys and the messages that name a key find it here, so
// each name is spelled once, in the lists above.

/// Remembers the key a list visits with one field (by address and type); with `shorthand`, the
/// SetsBoth key whose first field it is (deposition.radius of radius_min).
template <typename Field>
struct KeyFinder {
  const Field* field;
  bool shorthand;
  SceneKey* found;

  void operator()(const SceneKey& key, const auto& visited) const {
    using Visited = std::remove_cvref_t<decltype(visited)>;
    if constexpr (std::is_same_v<Visited, Field>) {
      if (!shorthand && &visited == field) *found = key;
    } else if constexpr (std::is_same_v<Visited, SetsBoth<const Field>>) {
      if (shorthand && &visited.first == field) *found = key;
    }
  }
};

/// The key of `field`, a field of `d` (any DepositionConfig, e.g. a default one).
template <typename Field>
SceneKey key_of(const DepositionConfig& d, const Field& field, bool shorthand = false) {
  SceneKey found;
  visit_deposition_keys(d, KeyFinder<Field>{&field, shorthand, &found});
  return found;
}

/// The key of `field`, a field of `scene` outside [deposition]: key_of(s, s.piston.force)
/// is piston.force. A message without a scene at hand asks a default one.
template <typename Field>
SceneKey key_of(const Scene& scene, const Field& field) {
  SceneKey found;
  const KeyFinder<Field> finder{&field, false, &found};
  visit_system_keys(scene.system, finder);
  visit_contact_keys(scene.step.laws, finder);
  visit_wall_keys(scene.step.laws, finder);
  visit_solver_keys(scene.step.solver, finder);
  visit_piston_keys(scene.piston, finder);
  visit_particles_keys(scene.particles_file, finder);
  visit_run_keys(scene.run, finder);
  visit_blocked_keys(scene.run.blocked, finder);
  return found;
}

/// The dotted name of a key of `scene` (key_of).
template <typename Field>
std::string key_name(const Scene& scene, const Field& field) {
  return key_of(scene, field).dotted();
}

}  // namespace cdpowder::detail
