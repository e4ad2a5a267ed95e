// scene_reader.cpp — the scene schema (scene_reader.hpp): which keys exist, their defaults
// (from scene.hpp), types and ranges, and the checks across keys. Passes: parse, apply the
// `--set` overrides, read every key, report keys nobody read and inconsistent pairs. Each
// mistake is an issue, not an exception, so one run names every mistake (style guide 3.7).
// The typed reads are in table_reader.cpp, the effective TOML in scene_writer.cpp.
#include "cdpowder/config/scene_reader.hpp"

#include "cdpowder/config/input_file.hpp"
#include "cdpowder/config/scene_writer.hpp"
#include "cdpowder/config/table_reader.hpp"
#include "cdpowder/solver/anderson.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <system_error>
#include <utility>

namespace cdpowder {
namespace {

using detail::kAnyNumber;
using detail::kNonNegative;
using detail::kPositive;
using detail::TableReader;

constexpr std::int64_t kIntMax = std::numeric_limits<int>::max();  // keys stored as int

void read_system(TableReader& in, SystemConfig& system) {
  system.lx = in.number("system.lx", system.lx, kPositive);
  system.ly = in.number("system.ly", system.ly, kPositive);
  system.gravity = in.vector3("system.gravity", system.gravity);
  system.density = in.number("system.density", system.density, kPositive);
  system.bottom_wall = in.boolean("system.bottom_wall", system.bottom_wall);
}

void read_laws(TableReader& in, ContactLaws& laws) {
  const auto read_law = [&in](const std::string& table, const ContactLaw& defaults) {
    ContactLaw law;
    law.mu = in.number(table + ".mu", defaults.mu, kNonNegative);
    law.mu_roll = in.number(table + ".mu_roll", defaults.mu_roll, kNonNegative);
    law.mu_twist = in.number(table + ".mu_twist", defaults.mu_twist, kNonNegative);
    law.cohesion_force =
        in.number(table + ".cohesion_force", defaults.cohesion_force, kNonNegative);
    law.cohesion_range =
        in.number(table + ".cohesion_range", defaults.cohesion_range, kNonNegative);
    return law;
  };
  laws.spheres = read_law("contact", laws.spheres);
  laws.cohesion_rule =
      in.choice("contact.cohesion_rule", laws.cohesion_rule, detail::kCohesionRuleNames);
  // Wall laws default to the sphere–sphere ones (physics.md §5.4 notes).
  laws.walls = read_law("contact.wall", laws.spheres);
  laws.wall_r_eff_factor =
      in.number("contact.wall.r_eff_factor", laws.wall_r_eff_factor, kNonNegative);
}

void read_time_step(TableReader& in, SolverSettings& solver) {
  solver.dt = in.number("solver.dt", solver.dt, kPositive);
  TimeStepControl& control = solver.time_step;
  control.adaptive = in.boolean("solver.adaptive_dt", control.adaptive);
  control.dt_min = in.number("solver.dt_min", control.dt_min, kPositive);
  control.dt_max = in.number("solver.dt_max", control.dt_max, kPositive);
  constexpr detail::Range kFraction{detail::Range::Kind::FractionAbove, 0.0};
  control.opening_per_step =
      in.number("solver.opening_per_step", control.opening_per_step, kFraction);
  control.max_opening_per_step =
      in.number("solver.max_opening_per_step", control.max_opening_per_step, kPositive);
  control.displacement_per_step =
      in.number("solver.displacement_per_step", control.displacement_per_step, kFraction);
  control.growth = in.number("solver.dt_growth", control.growth,
                             detail::Range{detail::Range::Kind::AtLeast, 1.0});
}

void read_solver(TableReader& in, SolverSettings& solver) {
  read_time_step(in, solver);
  solver.tolerance = in.number("solver.tolerance", solver.tolerance, kPositive);
  solver.max_error_amplification =
      in.number("solver.max_error_amplification", solver.max_error_amplification,
                detail::Range{detail::Range::Kind::AtLeast, 1.0});
  solver.kinematic_tolerance =
      in.number("solver.kinematic_tolerance", solver.kinematic_tolerance, kNonNegative);
  solver.min_sweeps =
      static_cast<int>(in.integer("solver.min_sweeps", solver.min_sweeps, 1, kIntMax));
  solver.max_sweeps =
      static_cast<int>(in.integer("solver.max_sweeps", solver.max_sweeps, 1, kIntMax));
  solver.stopping_rule =
      in.choice("solver.stopping_rule", solver.stopping_rule, detail::kStoppingRuleNames);
  solver.visit_order =
      in.choice("solver.visit_order", solver.visit_order, detail::kVisitOrderNames);
  solver.kernel = in.choice("solver.kernel", solver.kernel, detail::kSweepKernelNames);
  solver.threads =
      static_cast<int>(in.integer("solver.threads", solver.threads, 1, kMaxSweepThreads));
  solver.acceleration_depth = static_cast<int>(in.integer(
      "solver.acceleration_depth", solver.acceleration_depth, 0, AndersonAccelerator::kMaxDepth));
  solver.acceleration_interval = static_cast<int>(
      in.integer("solver.acceleration_interval", solver.acceleration_interval, 1, 100));
  solver.warm_start = in.boolean("solver.warm_start", solver.warm_start);
  solver.skin = in.number("solver.skin", solver.skin, kNonNegative);
  solver.verlet_margin = in.number("solver.verlet_margin", solver.verlet_margin, kNonNegative);
  solver.seed = static_cast<std::uint64_t>(
      in.integer("solver.seed", static_cast<std::int64_t>(solver.seed), 0));
}

void read_piston(TableReader& in, PistonConfig& piston) {
  piston.enabled = in.boolean("piston.enabled", piston.enabled);
  piston.mass = in.number("piston.mass", piston.mass, kPositive);
  piston.pressure = in.optional_number("piston.pressure", kNonNegative);
  piston.force = in.optional_number("piston.force", kNonNegative);
  // above the bottom wall z = 0; below the spheres' tops the first step stops the run at
  // its overlap bound (run.max_overlap)
  piston.height = in.optional_number("piston.height", kPositive);
  piston.start_gap = in.number("piston.start_gap", piston.start_gap, kNonNegative);
  piston.velocity = in.number("piston.velocity", piston.velocity, kAnyNumber);
}

/// [deposition], when given; the deposit fills the cell `system` describes.
std::optional<DepositionConfig> read_deposition(TableReader& in, const SystemConfig& system) {
  if (!in.has("deposition")) return std::nullopt;
  DepositionConfig d;
  // a run holds about 2 kB per sphere (state, candidates, contacts): 10⁷ spheres need
  // ≈ 20 GB; beyond that the allocation would fail after the outputs were begun
  constexpr std::int64_t kMaxSpheres = 10'000'000;
  d.spheres = static_cast<int>(in.integer("deposition.spheres", d.spheres, 1, kMaxSpheres));
  // `radius` sets both ends of a monodisperse deposit; radius_min/max a uniform spread
  const double radius = in.number("deposition.radius", 1.0, kPositive);
  d.radius_min = in.number("deposition.radius_min", radius, kPositive);
  d.radius_max = in.number("deposition.radius_max", radius, kPositive);
  d.capture_radius = in.number("deposition.capture_radius", d.capture_radius, kPositive);
  d.capture_rule = in.choice("deposition.capture_rule", d.capture_rule, detail::kCaptureRuleNames);
  d.seed = static_cast<std::uint64_t>(
      in.integer("deposition.seed", static_cast<std::int64_t>(d.seed), 0));
  d.lx = system.lx;
  d.ly = system.ly;
  return d;
}

/// [particles] file = "….csv", unless the spheres come from a deposit; the path relative to
/// the scene file, checked to be a readable file.
void read_particles(TableReader& in, const std::filesystem::path& base_dir,
                    const SceneReadOptions& options, Scene& s) {
  const bool spheres_elsewhere =
      s.deposition.has_value() || options.deposition_required || options.spheres_from_caller;
  if (spheres_elsewhere && in.has("particles.file")) {
    in.find("particles.file");  // known: a [particles] beside [deposition] is reported once, below
  }
  if (!spheres_elsewhere && !in.has("particles")) {
    in.add_issue("particles", toml::source_region{},
                 "missing: the spheres come from a [deposition] section (a ballistic deposit) "
                 "or a [particles] file = \"….csv\" (docs/config.md)",
                 /*in_file=*/true);
  }
  const std::string particles = spheres_elsewhere || !in.has("particles")
                                    ? std::string()
                                    : in.required_string("particles.file");
  if (!particles.empty()) {
    s.particles_file = (base_dir / std::filesystem::path(particles)).lexically_normal();
    std::error_code missing;
    if (!std::filesystem::exists(s.particles_file, missing) && !missing) {
      in.add_issue("particles.file", in.find("particles.file")->source(),
                   fmt::format("no such file: '{}'", s.particles_file.string()));
    } else if (const std::string problem = input_file_problem(s.particles_file, "a particles CSV");
               !problem.empty()) {
      in.add_issue("particles.file", in.find("particles.file")->source(),
                   fmt::format("'{}' {}", s.particles_file.string(), problem));
    }
  }
}

void read_run(TableReader& in, RunConfig& run) {
  run.duration = in.number("run.duration", run.duration, kPositive);
  run.until_blocked = in.boolean("run.until_blocked", run.until_blocked);
  run.max_duration = in.number("run.max_duration", run.max_duration, kPositive);
  run.timeseries_every =
      static_cast<int>(in.integer("run.timeseries_every", run.timeseries_every, 1, kIntMax));
  run.snapshot_every =
      static_cast<int>(in.integer("run.snapshot_every", run.snapshot_every, 0, kIntMax));
  run.timeseries_interval =
      in.number("run.timeseries_interval", run.timeseries_interval, kNonNegative);
  run.snapshot_interval = in.number("run.snapshot_interval", run.snapshot_interval, kNonNegative);
  run.max_overlap = in.number("run.max_overlap", run.max_overlap, kPositive);
  run.vtk_format = in.choice("run.vtk_format", run.vtk_format, detail::kVtkFormatNames);
  BlockedCriteria& blocked = run.blocked;
  blocked.window = in.number("run.blocked.window", blocked.window, kPositive);
  blocked.piston_speed = in.number("run.blocked.piston_speed", blocked.piston_speed, kPositive);
  blocked.sphere_speed = in.number("run.blocked.sphere_speed", blocked.sphere_speed, kPositive);
  blocked.force_balance = in.number("run.blocked.force_balance", blocked.force_balance, kPositive);
  blocked.height_change = in.number("run.blocked.height_change", blocked.height_change, kPositive);
  blocked.final_tolerance =
      in.number("run.blocked.final_tolerance", blocked.final_tolerance, kPositive);
  blocked.final_max_sweeps = static_cast<int>(
      in.integer("run.blocked.final_max_sweeps", blocked.final_max_sweeps, 1, kIntMax));
}

/// All values of the scene, each checked where it is read (in this order, so the messages
/// come in the file's section order); defaults come from scene.hpp.
Scene read_values(TableReader& in, const std::filesystem::path& base_dir,
                  const SceneReadOptions& options) {
  Scene s;
  read_system(in, s.system);
  read_laws(in, s.step.laws);
  read_solver(in, s.step.solver);
  read_piston(in, s.piston);
  s.deposition = read_deposition(in, s.system);
  read_particles(in, base_dir, options, s);
  read_run(in, s.run);
  return s;
}

/// Where the file gives `key` (an empty region when it does not).
toml::source_region where(TableReader& in, std::string_view key) {
  const toml::node* node = in.find(key);
  return node != nullptr ? node->source() : toml::source_region{};
}

/// Whether an issue of `key` belongs to the file as a whole: the key is not in it.
bool in_file(TableReader& in, std::string_view key) {
  return in.find(key) == nullptr;
}

/// The piston's load, and what compaction and the blocked state need of it.
void check_piston(TableReader& in, const Scene& s, const SceneReadOptions& options) {
  const bool has_pressure = in.find("piston.pressure") != nullptr;
  const bool has_force = in.find("piston.force") != nullptr;
  if (has_pressure && has_force) {
    in.add_issue("piston.force", where(in, "piston.force"),
                 "set together with piston.pressure; set exactly one of them");
  }
  if (s.piston.enabled && !has_pressure && !has_force) {
    in.add_issue("piston.enabled", where(in, "piston.enabled"),
                 "is true but neither piston.pressure nor piston.force is set; set exactly one",
                 in_file(in, "piston.enabled"));
  }
  if (options.compaction && !s.piston.enabled && !in.failed("piston.enabled")) {
    in.add_issue("piston.enabled", where(in, "piston.enabled"),
                 "is false, but compaction needs the piston: set [piston] enabled = true and "
                 "a pressure or force",
                 in_file(in, "piston.enabled"));
  } else if (s.run.until_blocked && !s.piston.enabled && !in.failed("piston.enabled")) {
    in.add_issue("run.until_blocked", where(in, "run.until_blocked"),
                 "is true but piston.enabled is false; the blocked state needs the piston",
                 in_file(in, "run.until_blocked"));
  }
  if (options.compaction && !s.run.until_blocked && !in.failed("run.until_blocked")) {
    in.add_issue("run.until_blocked", where(in, "run.until_blocked"),
                 "is false, but compact always runs until the blocked state (use simulate for a "
                 "fixed duration)");
  }
}

/// The deposit's radii and capture radius, and one source of spheres.
void check_deposition(TableReader& in, const Scene& s) {
  if (in.has("deposition.radius") && in.has("deposition.radius_min") &&
      in.has("deposition.radius_max")) {
    in.add_issue("deposition.radius", where(in, "deposition.radius"),
                 "set together with radius_min and radius_max; give either radius or the range");
  }
  if (s.deposition && in.has("particles")) {
    in.add_issue("particles", where(in, "particles"),
                 "given together with [deposition]; the spheres come from exactly one of them");
  }
  if (s.deposition) {
    const DepositionConfig& d = *s.deposition;
    if (d.radius_min > d.radius_max && !in.failed("deposition.radius_min") &&
        !in.failed("deposition.radius_max")) {
      in.add_issue("deposition.radius_min", where(in, "deposition.radius_min"),
                   fmt::format("got {}, expected at most deposition.radius_max = {}", d.radius_min,
                               d.radius_max),
                   in_file(in, "deposition.radius_min"));
    }
    if (d.capture_rule == CaptureRule::CentreDistance && d.capture_gap() < 0.0 &&
        !in.failed("deposition.capture_radius")) {
      in.add_issue("deposition.capture_radius", where(in, "deposition.capture_radius"),
                   fmt::format("got {}, expected ≥ radius_min + radius_max = {} for the "
                               "centre_distance rule (below it captured spheres would overlap)",
                               d.capture_radius, d.radius_min + d.radius_max),
                   in_file(in, "deposition.capture_radius"));
    }
    // a capture sphere wider than half the periodic cell reaches a sphere's own images
    // (measured: capture_radius = 1e10 put the spheres on top of each other)
    const double half_cell = 0.5 * std::min(s.system.lx, s.system.ly);
    if (d.capture_radius > half_cell && !in.failed("deposition.capture_radius") &&
        !in.failed("system.lx") && !in.failed("system.ly")) {
      in.add_issue("deposition.capture_radius", where(in, "deposition.capture_radius"),
                   fmt::format("got {}, expected at most half the cell, min(system.lx, "
                               "system.ly) / 2 = {}",
                               d.capture_radius, half_cell),
                   in_file(in, "deposition.capture_radius"));
    }
  }
}

/// Δt against the run's length, the blocked-state window and the adaptive bounds.
void check_time_step(TableReader& in, const Scene& s) {
  const SolverSettings& solver = s.step.solver;
  // a first step longer than the whole run would make a run of no step at all
  const char* budget_key = s.run.until_blocked ? "run.max_duration" : "run.duration";
  const double budget = s.run.until_blocked ? s.run.max_duration : s.run.duration;
  if (solver.dt > budget && !in.failed("solver.dt") && !in.failed(budget_key)) {
    in.add_issue("solver.dt", where(in, "solver.dt"),
                 fmt::format("got {}, expected at most {} = {} (the run would take no step)",
                             solver.dt, budget_key, budget),
                 in_file(in, "solver.dt"));
  }
  // a step so short that the run could never end (and t + Δt = t below 2^-52 t: measured,
  // solver.dt = 1e-300 "ran" zero steps and exited 0)
  constexpr double kMaxRunSteps = 1e12;
  // (with the adaptive step the controller may go down to dt_min)
  const bool adaptive = solver.time_step.adaptive;
  const char* shortest_key = adaptive ? "solver.dt_min" : "solver.dt";
  const double shortest = adaptive ? solver.time_step.dt_min : solver.dt;
  if (budget / shortest > kMaxRunSteps && !in.failed(shortest_key) && !in.failed(budget_key)) {
    in.add_issue(shortest_key, where(in, shortest_key),
                 fmt::format("got {}, expected at least {} / 1e12 = {} (a run of more than "
                             "10^12 steps could not end)",
                             shortest, budget_key, budget / kMaxRunSteps),
                 in_file(in, shortest_key));
  }
  // the detector keeps the last window of piston heights and imbalances (16 bytes a step)
  constexpr double kMaxWindowSteps = 1e6;
  if (s.run.until_blocked && s.run.blocked.window / solver.dt > kMaxWindowSteps &&
      !in.failed("run.blocked.window") && !in.failed("solver.dt")) {
    in.add_issue("run.blocked.window", where(in, "run.blocked.window"),
                 fmt::format("got {}, expected at most 1e6 steps of solver.dt = {}, i.e. {}",
                             s.run.blocked.window, solver.dt, kMaxWindowSteps * solver.dt),
                 in_file(in, "run.blocked.window"));
  }
  // an adaptive Δt starts at solver.dt and stays in [dt_min, dt_max]
  const TimeStepControl& control = solver.time_step;
  if (control.adaptive && !in.failed("solver.dt") && !in.failed("solver.dt_min") &&
      !in.failed("solver.dt_max") && (control.dt_min > solver.dt || solver.dt > control.dt_max)) {
    const char* key = control.dt_min > solver.dt ? "solver.dt_min" : "solver.dt_max";
    in.add_issue(key, where(in, key),
                 fmt::format("with solver.adaptive_dt = true, expected solver.dt_min = {} ≤ "
                             "solver.dt = {} ≤ solver.dt_max = {}",
                             control.dt_min, solver.dt, control.dt_max),
                 in_file(in, key));
  }
  if (control.opening_per_step > control.max_opening_per_step &&
      !in.failed("solver.opening_per_step") && !in.failed("solver.max_opening_per_step")) {
    in.add_issue("solver.opening_per_step", where(in, "solver.opening_per_step"),
                 fmt::format("got {}, expected at most solver.max_opening_per_step = {}",
                             control.opening_per_step, control.max_opening_per_step),
                 in_file(in, "solver.opening_per_step"));
  }
}

void check_solver(TableReader& in, const Scene& s) {
  const SolverSettings& solver = s.step.solver;
  // only the coloured kernel's sweeps are split among threads
  if (solver.threads > 1 && solver.kernel != SweepKernel::Coloured &&
      !in.failed("solver.threads") && !in.failed("solver.kernel")) {
    in.add_issue("solver.threads", where(in, "solver.threads"),
                 fmt::format("got {}, but solver.kernel = \"scalar\" runs on one thread: "
                             "expected 1, or solver.kernel = \"coloured\" for 1 to {} threads",
                             solver.threads, kMaxSweepThreads),
                 in_file(in, "solver.threads"));
  }
  if (solver.min_sweeps > solver.max_sweeps && !in.failed("solver.min_sweeps") &&
      !in.failed("solver.max_sweeps")) {
    in.add_issue("solver.min_sweeps", where(in, "solver.min_sweeps"),
                 fmt::format("got {}, expected at most solver.max_sweeps = {}", solver.min_sweeps,
                             solver.max_sweeps),
                 in_file(in, "solver.min_sweeps"));
  }
}

/// Checks between keys, after the single values; each message names both keys. A pair
/// with an already reported value is skipped, so one mistake gives one message.
void check_consistency(TableReader& in, const Scene& s, const SceneReadOptions& options) {
  check_piston(in, s, options);
  check_deposition(in, s);
  check_time_step(in, s);
  check_solver(in, s);
}

/// The command's demands (SceneReadOptions) as edits of the parsed scene, before it is read.
void apply_read_options(toml::table& root, const SceneReadOptions& options) {
  if (options.spheres_from_caller) {
    root.erase("deposition");
    root.erase("particles");
  }
  if (options.particles_file) {
    std::error_code error;
    const std::filesystem::path absolute =
        std::filesystem::absolute(*options.particles_file, error);
    root.erase("deposition");
    // the path as given (bytes that are not UTF-8 included); its mistakes are reported under
    // the option (TableReader::set_origin in read_scene_text)
    root.insert_or_assign(
        "particles", toml::table{{"file", (error ? *options.particles_file : absolute).string()}});
  }
  if (options.compaction) {
    if (!root.contains("run")) root.insert("run", toml::table{});
    // an explicit value is kept, so that `false` is reported (check_consistency)
    if (toml::table* run = root.get("run")->as_table(); run != nullptr) {
      run->insert("until_blocked", true);
    }
  }
}

}  // namespace

/// The TOML parser's description of a syntax error as the message shows it (it quotes the
/// input it saw).
constexpr std::size_t kMaxSyntaxExcerpt = 160;

Scene read_scene_text(std::string_view toml_text, std::string_view source_name,
                      const std::vector<SceneOverride>& overrides,
                      const std::filesystem::path& base_dir, const SceneReadOptions& options) {
  std::vector<ConfigIssue> issues;
  toml::table root;
  try {
    root = toml::parse(toml_text, std::string(source_name));
  } catch (const toml::parse_error& error) {
    issues.push_back(
        {std::string(source_name), static_cast<int>(error.source().begin.line),
         static_cast<int>(error.source().begin.column), "",
         fmt::format("TOML syntax error: {}", shown(error.description(), kMaxSyntaxExcerpt))});
    toml::table ignored;
    detail::apply_overrides(ignored, overrides, issues);  // still report malformed overrides
    throw ConfigError(std::move(issues));
  }
  detail::apply_overrides(root, overrides, issues);
  apply_read_options(root, options);
  TableReader in(root, std::string(source_name), issues);
  if (options.particles_file) in.set_origin("particles.file", std::string(kParticlesOption));
  if (options.deposition_required && root.get("deposition") == nullptr) {
    in.add_issue("deposition", toml::source_region{},
                 "missing: deposit needs a [deposition] section (docs/config.md)", true);
  }
  Scene scene = read_values(in, base_dir, options);
  in.check_unknown_keys();
  check_consistency(in, scene, options);
  if (!issues.empty()) {
    detail::sort_issues(issues, source_name);
    throw ConfigError(std::move(issues));
  }
  scene.source = std::filesystem::path(source_name);
  scene.effective_toml = detail::write_effective_toml(scene);
  return scene;
}

Scene read_scene(const std::filesystem::path& file, const std::vector<SceneOverride>& overrides,
                 const SceneReadOptions& options) {
  // (a folder opens as an empty stream on Linux: measured "particles.file: missing")
  const std::string text =
      read_input_file(file, "a scene file (TOML), e.g. examples/quick/scene.toml");
  std::error_code error;
  const std::filesystem::path absolute = std::filesystem::absolute(file, error);
  Scene scene = read_scene_text(text, file.string(), overrides,
                                error ? file.parent_path() : absolute.parent_path(), options);
  scene.source = file;
  return scene;
}

}  // namespace cdpowder