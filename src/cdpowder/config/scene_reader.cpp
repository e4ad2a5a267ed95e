// scene_reader.cpp — reads a scene (scene_reader.hpp): the keys of scene_keys.hpp in their
// order, and the checks across keys. Passes: parse, apply the `--set` overrides, read every
// key, report keys nobody read and inconsistent pairs. Each mistake is an issue, not an
// exception, so one run names every mistake (style guide 3.7). The typed reads are in
// table_reader.cpp, the effective TOML in scene_writer.cpp.
#include "cdpowder/config/scene_reader.hpp"

#include "cdpowder/config/input_file.hpp"
#include "cdpowder/config/scene_keys.hpp"
#include "cdpowder/config/scene_writer.hpp"
#include "cdpowder/config/table_reader.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <system_error>
#include <type_traits>
#include <utility>

namespace cdpowder {
namespace {

using detail::SceneKey;
using detail::TableReader;

/// Reads one key of the table (scene_keys.hpp) into its field, with the field as the fallback:
/// the in-class default, or the default another key set before.
struct KeyReader {
  TableReader& in;

  void operator()(const SceneKey& key, double& value) const {
    value = in.number(key.dotted(), value, key.range);
  }

  void operator()(const SceneKey& key, std::optional<double>& value) const {
    value = in.optional_number(key.dotted(), key.range);
  }

  void operator()(const SceneKey& key, int& value) const {
    constexpr std::int64_t kIntMax = std::numeric_limits<int>::max();  // keys stored as int
    value = static_cast<int>(
        in.integer(key.dotted(), value, key.minimum, std::min(key.maximum, kIntMax)));
  }

  void operator()(const SceneKey& key, std::uint64_t& value) const {
    value = static_cast<std::uint64_t>(
        in.integer(key.dotted(), static_cast<std::int64_t>(value), key.minimum, key.maximum));
  }

  void operator()(const SceneKey& key, bool& value) const {
    value = in.boolean(key.dotted(), value);
  }

  void operator()(const SceneKey& key, Vec3& value) const {
    value = in.vector3(key.dotted(), value);
  }

  template <typename Enum>
  requires std::is_enum_v<Enum>

  void operator()(const SceneKey& key, Enum& value) const {
    value = in.choice(key.dotted(), value, detail::choices_of(value));
  }

  void operator()(const SceneKey& key, detail::SetsBoth<double> both) const {
    both.first = both.second = in.number(key.dotted(), both.first, key.range);
  }
};

/// The name of the one key of a table list that a field is visited with.
std::string key_of(const auto& visit_keys) {
  std::string name;
  visit_keys([&name](const SceneKey& key, const auto& /*field*/) { name = key.dotted(); });
  return name;
}

/// [deposition], when given; the deposit fills the cell `system` describes.
std::optional<DepositionConfig> read_deposition(TableReader& in, const SystemConfig& system) {
  if (!in.has(detail::kDepositionTable)) return std::nullopt;
  DepositionConfig d;
  detail::visit_deposition_keys(d, KeyReader{in});
  d.lx = system.lx;
  d.ly = system.ly;
  return d;
}

/// [particles] file = "….csv", unless the spheres come from a deposit; the path relative to
/// the scene file, checked to be a readable file.
void read_particles(TableReader& in, const std::filesystem::path& base_dir,
                    const SceneReadOptions& options, Scene& s) {
  const std::string file_key =
      key_of([&s](auto&& visit) { detail::visit_particles_keys(s.particles_file, visit); });
  const std::string table(detail::kParticlesTable);
  const bool spheres_elsewhere = s.deposition.has_value() || options.deposition_required;
  if (spheres_elsewhere && in.has(file_key)) {
    in.find(file_key);  // known: a [particles] beside [deposition] is reported once, below
  }
  if (!spheres_elsewhere && !in.has(table)) {
    in.add_issue(table, toml::source_region{},
                 "missing: the spheres come from a [deposition] section (a ballistic deposit) "
                 "or a [particles] file = \"….csv\" (docs/config.md)",
                 /*in_file=*/true);
  }
  const std::string particles =
      spheres_elsewhere || !in.has(table) ? std::string() : in.required_string(file_key);
  if (!particles.empty()) {
    s.particles_file = (base_dir / std::filesystem::path(particles)).lexically_normal();
    std::error_code missing;
    if (!std::filesystem::exists(s.particles_file, missing) && !missing) {
      in.add_issue(file_key, in.find(file_key)->source(),
                   fmt::format("no such file: '{}'", s.particles_file.string()));
    } else if (const std::string problem = input_file_problem(s.particles_file, "a particles CSV");
               !problem.empty()) {
      in.add_issue(file_key, in.find(file_key)->source(),
                   fmt::format("'{}' {}", s.particles_file.string(), problem));
    }
  }
}

/// All values of the scene, each checked where it is read (in this order, so the messages
/// come in the file's section order); defaults come from scene.hpp.
Scene read_values(TableReader& in, const std::filesystem::path& base_dir,
                  const SceneReadOptions& options) {
  Scene s;
  const KeyReader read{in};
  detail::visit_system_keys(s.system, read);
  detail::visit_contact_keys(s.step.laws, read);
  // the wall laws default to the sphere–sphere ones (physics.md §5.4 notes)
  s.step.laws.walls = s.step.laws.spheres;
  detail::visit_wall_keys(s.step.laws, read);
  detail::visit_solver_keys(s.step.solver, read);
  detail::visit_piston_keys(s.piston, read);
  s.deposition = read_deposition(in, s.system);
  read_particles(in, base_dir, options, s);
  detail::visit_run_keys(s.run, read);
  detail::visit_blocked_keys(s.run.blocked, read);
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