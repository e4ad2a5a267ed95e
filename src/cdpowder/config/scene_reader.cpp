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
  const detail::SceneKey file = detail::key_of(s, s.particles_file);
  const std::string file_key = file.dotted();
  const std::string table(file.table);
  const bool spheres_elsewhere =
      s.deposition.has_value() || options.deposition_required || options.spheres_from_caller;
  if (spheres_elsewhere && in.has(file_key)) {
    in.find(file_key);  // known: a [particles] beside [deposition] is reported once, below
  }
  if (!spheres_elsewhere && !in.has(table)) {
    in.add_issue(table, toml::source_region{},
                 fmt::format("missing: the spheres come from a [{}] section (a ballistic deposit) "
                             "or a [{}] {} = \"….csv\" (docs/config.md)",
                             detail::kDepositionTable, file.table, file.name),
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

/// A key as the checks across keys see it: its dotted name, and what the reader knows of it.
class CheckedKey {
 public:
  CheckedKey(TableReader& in, std::string name) : in_(&in), name_(std::move(name)) {}

  [[nodiscard]] const std::string& name() const { return name_; }

  /// Whether the key has a reported mistake of its own.
  [[nodiscard]] bool failed() const { return in_->failed(name_); }

  /// Whether the key is given (marks it known).
  [[nodiscard]] bool given() const { return in_->find(name_) != nullptr; }

  /// Reports `message` at the key where the file gives it, else against the whole file when
  /// `in_file` (the key is not in it) or without a position.
  void report(std::string message, bool in_file) const {
    const toml::node* node = in_->find(name_);
    in_->add_issue(name_, node != nullptr ? node->source() : toml::source_region{},
                   std::move(message), in_file && node == nullptr);
  }

  /// As report(), against the whole file when the key is not in it.
  void report(std::string message) const { report(std::move(message), true); }

 private:
  TableReader* in_;
  std::string name_;
};

/// The key of `field`, a field of `s` (scene_keys.hpp).
template <typename Field>
CheckedKey checked(TableReader& in, const Scene& s, const Field& field) {
  return {in, detail::key_name(s, field)};
}

/// The piston's load, and what compaction and the blocked state need of it.
void check_piston(TableReader& in, const Scene& s, const SceneReadOptions& options) {
  const CheckedKey pressure = checked(in, s, s.piston.pressure);
  const CheckedKey force = checked(in, s, s.piston.force);
  const CheckedKey enabled = checked(in, s, s.piston.enabled);
  const CheckedKey until_blocked = checked(in, s, s.run.until_blocked);
  const bool has_pressure = pressure.given();
  const bool has_force = force.given();
  if (has_pressure && has_force) {
    force.report(fmt::format("set together with {}; set exactly one of them", pressure.name()),
                 /*in_file=*/false);
  }
  if (s.piston.enabled && !has_pressure && !has_force) {
    enabled.report(fmt::format("is true but neither {} nor {} is set; set exactly one",
                               pressure.name(), force.name()));
  }
  const detail::SceneKey enabled_key = detail::key_of(s, s.piston.enabled);
  if (options.compaction && !s.piston.enabled && !enabled.failed()) {
    enabled.report(
        fmt::format("is false, but compaction needs the piston: set [{}] {} = true "
                    "and a pressure or force",
                    enabled_key.table, enabled_key.name));
  }
  if (options.compaction && !s.run.until_blocked && !until_blocked.failed()) {
    until_blocked.report(
        "is false, but compact always runs until the blocked state (use simulate for a fixed "
        "duration)",
        /*in_file=*/false);
  }
}

/// Radius keys that replace each other: an override of radius_min or radius_max turns the
/// file's `radius = r` into the range [r, r] before the overrides apply (so
/// `--set deposition.radius_max=1.2` spreads a monodisperse scene over [r, 1.2]), and an
/// override of `radius` drops the file's range. Overrides that set both still conflict
/// (check_radius_keys).
void let_radius_overrides_replace(toml::table& root, const std::vector<SceneOverride>& overrides) {
  const DepositionConfig defaults;
  const detail::SceneKey radius = detail::key_of(defaults, defaults.radius_min, /*shorthand=*/true);
  const detail::SceneKey radius_min = detail::key_of(defaults, defaults.radius_min);
  const detail::SceneKey radius_max = detail::key_of(defaults, defaults.radius_max);
  bool range_set = false;
  bool radius_set = false;
  for (const SceneOverride& edit : overrides) {
    const std::string_view key = detail::override_key(edit);
    const auto is = [&](const detail::SceneKey& k) { return key == k.dotted(); };
    range_set = range_set || is(radius_min) || is(radius_max);
    radius_set = radius_set || is(radius);
  }
  toml::table* deposition = root[radius.table].as_table();
  if (deposition == nullptr || range_set == radius_set) return;
  if (range_set) {
    const toml::node* file_radius = deposition->get(radius.name);
    if (file_radius == nullptr) return;
    if (!deposition->contains(radius_min.name)) {
      deposition->insert(radius_min.name, *file_radius);
    }
    if (!deposition->contains(radius_max.name)) {
      deposition->insert(radius_max.name, *file_radius);
    }
    deposition->erase(radius.name);
  } else {
    deposition->erase(radius_min.name);
    deposition->erase(radius_max.name);
  }
}

/// The deposit's radius keys: `radius` or the range, not both.
void check_radius_keys(TableReader& in) {
  const DepositionConfig defaults;
  const detail::SceneKey radius = detail::key_of(defaults, defaults.radius_min, /*shorthand=*/true);
  const detail::SceneKey radius_min = detail::key_of(defaults, defaults.radius_min);
  const detail::SceneKey radius_max = detail::key_of(defaults, defaults.radius_max);
  if (in.has(radius.dotted()) && in.has(radius_min.dotted()) && in.has(radius_max.dotted())) {
    CheckedKey(in, radius.dotted())
        .report(fmt::format("set together with {} and {}; give either {} or the range",
                            radius_min.name, radius_max.name, radius.name),
                /*in_file=*/false);
  }
}

/// The deposit's radii and capture radius, and one source of spheres.
void check_deposition(TableReader& in, const Scene& s) {
  check_radius_keys(in);
  const std::string particles(detail::kParticlesTable);
  if (s.deposition && in.has(particles)) {
    CheckedKey(in, particles)
        .report(fmt::format("given together with [{}]; the spheres come from exactly one of them",
                            detail::kDepositionTable),
                /*in_file=*/false);
  }
  if (!s.deposition) return;
  const DepositionConfig& d = *s.deposition;
  const CheckedKey radius_min(in, detail::key_of(d, d.radius_min).dotted());
  const detail::SceneKey radius_max = detail::key_of(d, d.radius_max);
  const CheckedKey capture(in, detail::key_of(d, d.capture_radius).dotted());
  if (d.radius_min > d.radius_max && !radius_min.failed() && !in.failed(radius_max.dotted())) {
    radius_min.report(fmt::format("got {}, expected at most {} = {}", d.radius_min,
                                  radius_max.dotted(), d.radius_max));
  }
  if (d.capture_rule == CaptureRule::CentreDistance && d.capture_gap() < 0.0 && !capture.failed()) {
    capture.report(
        fmt::format("got {}, expected ≥ {} + {} = {} for the centre_distance rule "
                    "(below it captured spheres would overlap)",
                    d.capture_radius, detail::key_of(d, d.radius_min).name, radius_max.name,
                    d.radius_min + d.radius_max));
  }
  // a capture sphere wider than half the periodic cell reaches a sphere's own images
  // (measured: capture_radius = 1e10 put the spheres on top of each other)
  const CheckedKey lx = checked(in, s, s.system.lx);
  const CheckedKey ly = checked(in, s, s.system.ly);
  const double half_cell = 0.5 * std::min(s.system.lx, s.system.ly);
  if (d.capture_radius > half_cell && !capture.failed() && !lx.failed() && !ly.failed()) {
    capture.report(fmt::format("got {}, expected at most half the cell, min({}, {}) / 2 = {}",
                               d.capture_radius, lx.name(), ly.name(), half_cell));
  }
}

/// Δt against the run's length: at least one step, and not so many that the run never ends.
void check_step_count(TableReader& in, const Scene& s) {
  const SolverSettings& solver = s.step.solver;
  const CheckedKey dt = checked(in, s, solver.dt);
  // a first step longer than the whole run would make a run of no step at all
  const double& budget = s.run.until_blocked ? s.run.max_duration : s.run.duration;
  const CheckedKey budget_key = checked(in, s, budget);
  if (solver.dt > budget && !dt.failed() && !budget_key.failed()) {
    dt.report(fmt::format("got {}, expected at most {} = {} (the run would take no step)",
                          solver.dt, budget_key.name(), budget));
  }
  // a step so short that the run could never end (and t + Δt = t below 2^-52 t: measured,
  // solver.dt = 1e-300 "ran" zero steps and exited 0)
  constexpr double kMaxRunSteps = 1e12;
  // (with the adaptive step the controller may go down to dt_min)
  const double& shortest = solver.time_step.adaptive ? solver.time_step.dt_min : solver.dt;
  const CheckedKey shortest_key = checked(in, s, shortest);
  if (budget / shortest > kMaxRunSteps && !shortest_key.failed() && !budget_key.failed()) {
    shortest_key.report(
        fmt::format("got {}, expected at least {} / 1e12 = {} (a run of more "
                    "than 10^12 steps could not end)",
                    shortest, budget_key.name(), budget / kMaxRunSteps));
  }
  // the detector keeps the last window of piston heights and imbalances (16 bytes a step)
  constexpr double kMaxWindowSteps = 1e6;
  const CheckedKey window = checked(in, s, s.run.blocked.window);
  if (s.run.until_blocked && s.run.blocked.window / solver.dt > kMaxWindowSteps &&
      !window.failed() && !dt.failed()) {
    window.report(fmt::format("got {}, expected at most 1e6 steps of {} = {}, i.e. {}",
                              s.run.blocked.window, dt.name(), solver.dt,
                              kMaxWindowSteps * solver.dt));
  }
}

/// The adaptive Δt: its bounds around solver.dt, and its opening target below the limit.
void check_adaptive_step(TableReader& in, const Scene& s) {
  const SolverSettings& solver = s.step.solver;
  const TimeStepControl& control = solver.time_step;
  const CheckedKey dt = checked(in, s, solver.dt);
  const CheckedKey dt_min = checked(in, s, control.dt_min);
  const CheckedKey dt_max = checked(in, s, control.dt_max);
  // an adaptive Δt starts at solver.dt and stays in [dt_min, dt_max]
  if (control.adaptive && !dt.failed() && !dt_min.failed() && !dt_max.failed() &&
      (control.dt_min > solver.dt || solver.dt > control.dt_max)) {
    const CheckedKey& key = control.dt_min > solver.dt ? dt_min : dt_max;
    key.report(fmt::format("with {} = true, expected {} = {} ≤ {} = {} ≤ {} = {}",
                           detail::key_name(s, control.adaptive), dt_min.name(), control.dt_min,
                           dt.name(), solver.dt, dt_max.name(), control.dt_max));
  }
  const CheckedKey opening = checked(in, s, control.opening_per_step);
  const CheckedKey max_opening = checked(in, s, control.max_opening_per_step);
  if (control.opening_per_step > control.max_opening_per_step && !opening.failed() &&
      !max_opening.failed()) {
    opening.report(fmt::format("got {}, expected at most {} = {}", control.opening_per_step,
                               max_opening.name(), control.max_opening_per_step));
  }
}

void check_solver(TableReader& in, const Scene& s) {
  const SolverSettings& solver = s.step.solver;
  const CheckedKey threads = checked(in, s, solver.threads);
  const CheckedKey kernel = checked(in, s, solver.kernel);
  // only the coloured kernel's passes are split among threads
  if (solver.threads > 1 && solver.kernel != PassKernel::Coloured && !threads.failed() &&
      !kernel.failed()) {
    threads.report(
        fmt::format("got {}, but {} = \"scalar\" runs on one thread: expected 1, or "
                    "{} = \"coloured\" for 1 to {} threads",
                    solver.threads, kernel.name(), kernel.name(), kMaxSolverThreads));
  }
  const CheckedKey min_passes = checked(in, s, solver.min_passes);
  const CheckedKey max_passes = checked(in, s, solver.max_passes);
  if (solver.min_passes > solver.max_passes && !min_passes.failed() && !max_passes.failed()) {
    min_passes.report(fmt::format("got {}, expected at most {} = {}", solver.min_passes,
                                  max_passes.name(), solver.max_passes));
  }
}

/// Checks between keys, after the single values; each message names both keys. A pair
/// with an already reported value is skipped, so one mistake gives one message.
void check_consistency(TableReader& in, const Scene& s, const SceneReadOptions& options) {
  check_piston(in, s, options);
  check_deposition(in, s);
  check_step_count(in, s);
  check_adaptive_step(in, s);
  check_solver(in, s);
}

/// The command's demands (SceneReadOptions) as edits of the parsed scene, before it is read.
void apply_read_options(toml::table& root, const SceneReadOptions& options) {
  const Scene defaults;
  if (options.spheres_from_caller) {
    root.erase(detail::kDepositionTable);
    root.erase(detail::key_of(defaults, defaults.particles_file).table);
  }
  if (options.particles_file) {
    std::error_code error;
    const std::filesystem::path absolute =
        std::filesystem::absolute(*options.particles_file, error);
    root.erase(detail::kDepositionTable);
    // the path as given (bytes that are not UTF-8 included); its mistakes are reported under
    // the option (TableReader::set_origin in read_scene_text)
    const detail::SceneKey file = detail::key_of(defaults, defaults.particles_file);
    root.insert_or_assign(
        file.table,
        toml::table{{file.name, (error ? *options.particles_file : absolute).string()}});
  }
  if (options.compaction) {
    const detail::SceneKey until_blocked = detail::key_of(defaults, defaults.run.until_blocked);
    if (!root.contains(until_blocked.table)) root.insert(until_blocked.table, toml::table{});
    // an explicit value is kept, so that `false` is reported (check_consistency)
    if (toml::table* run = root.get(until_blocked.table)->as_table(); run != nullptr) {
      run->insert(until_blocked.name, true);
    }
  }
}

/// Names a key may take for a number: solver.threads = "auto" is 0 (every usable core).
/// Another word is reported here, with the name it may take, and left out of the read.
void read_named_values(toml::table& root, TableReader& in) {
  const Scene defaults;
  const detail::SceneKey threads = detail::key_of(defaults, defaults.step.solver.threads);
  toml::table* solver = root[threads.table].as_table();
  if (solver == nullptr) return;
  const toml::node* node = solver->get(threads.name);
  if (node == nullptr || !node->is_string()) return;
  if (node->as_string()->get() != "auto") {
    in.add_issue(detail::key_name(defaults, defaults.step.solver.threads), node->source(),
                 fmt::format("got {}, expected an integer from 0 to {} or \"auto\"",
                             detail::describe(*node), kMaxSolverThreads));
    solver->erase(threads.name);
    return;
  }
  solver->insert_or_assign(threads.name, std::int64_t{0});
}

/// Keys and values renamed since scene files were first written (CHANGELOG.md, "sweep" for
/// the parameter study only): the old spellings still read, so older scene files, sweep files
/// and the scenes saved in state files still run.
void allow_former_names(toml::table& root, TableReader& in) {
  const Scene d;
  in.allow_former_name(detail::key_name(d, d.step.solver.min_passes), "solver.min_sweeps");
  in.allow_former_name(detail::key_name(d, d.step.solver.max_passes), "solver.max_sweeps");
  in.allow_former_name(detail::key_name(d, d.run.blocked.final_max_passes),
                       "run.blocked.final_max_sweeps");
  const std::string order = detail::key_name(d, d.step.solver.visit_order);
  if (auto* value = root.at_path(order).as_string();
      value != nullptr && value->get() == "random_each_sweep") {
    value->get() = "random_each_pass";  // in place: the value keeps its position for messages
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
  let_radius_overrides_replace(root, overrides);
  detail::apply_overrides(root, overrides, issues);
  apply_read_options(root, options);
  TableReader in(root, std::string(source_name), issues);
  allow_former_names(root, in);
  read_named_values(root, in);
  if (options.particles_file) {
    const Scene defaults;
    in.set_origin(detail::key_name(defaults, defaults.particles_file),
                  std::string(kParticlesOption));
  }
  if (options.deposition_required && root.get(detail::kDepositionTable) == nullptr) {
    in.add_issue(detail::kDepositionTable, toml::source_region{},
                 fmt::format("missing: deposit needs a [{}] section (docs/config.md)",
                             detail::kDepositionTable),
                 true);
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