// scene_reader.cpp — TOML text + overrides → validated Scene (scene_reader.hpp), in passes:
// parse, apply the `--set` overrides to the parsed table, read every key with its type and
// range, report keys nobody read (unknown) and inconsistent pairs of keys. Each mistake is
// an issue, not an exception, so one run names every mistake (style guide 3.7).
// Scene::effective_toml is written back from the validated Scene with toml++'s formatter.
#include "cdpowder/config/scene_reader.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>
#include <utility>

namespace cdpowder {
namespace {

constexpr std::string_view kOverrideSource = "--set";
constexpr std::int64_t kNoMaximum = std::numeric_limits<std::int64_t>::max();
constexpr std::int64_t kIntMax = std::numeric_limits<int>::max();  // keys stored as int

/// The allowed values of a number: any finite one, ≥ bound, or > bound.
struct Range {
  enum class Kind { Any, AtLeast, Above };
  Kind kind = Kind::Any;
  double bound = 0.0;

  [[nodiscard]] bool contains(double value) const {
    if (!std::isfinite(value)) {
      return false;
    }
    switch (kind) {
      case Kind::AtLeast:
        return value >= bound;
      case Kind::Above:
        return value > bound;
      case Kind::Any:
        break;
    }
    return true;
  }

  [[nodiscard]] std::string describe() const {
    switch (kind) {
      case Kind::AtLeast:
        return fmt::format("a number ≥ {}", bound);
      case Kind::Above:
        return fmt::format("a number > {}", bound);
      case Kind::Any:
        break;
    }
    return "a finite number";
  }
};

constexpr Range kAnyNumber{};
constexpr Range kNonNegative{Range::Kind::AtLeast, 0.0};
constexpr Range kPositive{Range::Kind::Above, 0.0};

/// The TOML spelling of each enumerator of a string-valued key.
template <typename Enum, std::size_t N>
using EnumNames = std::array<std::pair<std::string_view, Enum>, N>;

constexpr EnumNames<CohesionRule, 2> kCohesionRuleNames = {
    {{"graph", CohesionRule::Graph}, {"history", CohesionRule::History}}};
constexpr EnumNames<StoppingRule, 2> kStoppingRuleNames = {
    {{"residual", StoppingRule::Residual}, {"relative_change", StoppingRule::RelativeChange}}};
constexpr EnumNames<VisitOrder, 3> kVisitOrderNames = {
    {{"random_each_step", VisitOrder::RandomEachStep},
     {"random_each_sweep", VisitOrder::RandomEachSweep},
     {"fixed", VisitOrder::Fixed}}};

template <typename Enum, std::size_t N>
std::string name_of(Enum value, const EnumNames<Enum, N>& names) {
  for (const auto& [name, enumerator] : names) {
    if (enumerator == value) {
      return std::string(name);
    }
  }
  return {};
}

/// The value as the user wrote it, for "got …" (fmt prints the shortest exact form).
std::string describe(const toml::node& node) {
  if (const auto* integer = node.as_integer()) {
    return fmt::format("{}", integer->get());
  }
  if (const auto* floating = node.as_floating_point()) {
    return fmt::format("{}", floating->get());
  }
  if (const auto* boolean = node.as_boolean()) {
    return boolean->get() ? "true" : "false";
  }
  if (const auto* string = node.as_string()) {
    return fmt::format("\"{}\"", string->get());
  }
  if (node.is_array()) {
    return "an array";
  }
  if (node.is_table()) {
    return "a table";
  }
  return "a date or time";
}

/// A number node's value; TOML integers are accepted where numbers are expected.
std::optional<double> number_value(const toml::node& node) {
  if (const auto* integer = node.as_integer()) {
    return static_cast<double>(integer->get());
  }
  if (const auto* floating = node.as_floating_point()) {
    return floating->get();
  }
  return std::nullopt;
}

/// Reads typed values at dotted keys of a parsed table, collecting one issue per bad value
/// and remembering which keys were asked for, so that every other key is reported unknown.
class TableReader {
 public:
  TableReader(const toml::table& root, std::string source_name, std::vector<ConfigIssue>& issues)
      : root_(root), source_name_(std::move(source_name)), issues_(issues) {}

  /// The node at a dotted key, or nullptr; marks the key as known.
  const toml::node* find(std::string_view key) {
    known_.emplace(key);
    const toml::table* table = &root_;
    const toml::node* node = nullptr;
    std::size_t start = 0;
    while (true) {
      const std::size_t dot = key.find('.', start);
      node = table->get(key.substr(start, dot == std::string_view::npos ? dot : dot - start));
      if (node == nullptr || dot == std::string_view::npos) {
        return node;
      }
      table = node->as_table();
      if (table == nullptr) {
        return nullptr;  // reported by check_unknown_keys: "expected a table"
      }
      start = dot + 1;
    }
  }

  [[nodiscard]] bool failed(std::string_view key) const { return failed_.count(key) > 0; }

  std::optional<double> optional_number(std::string_view key, Range range) {
    const toml::node* node = find(key);
    if (node == nullptr) {
      return std::nullopt;
    }
    const std::optional<double> value = number_value(*node);
    if (!value || !range.contains(*value)) {
      // TOML allows inf and nan.
      const bool infinite = value && !std::isfinite(*value) && range.kind != Range::Kind::Any;
      add_issue(key, node->source(),
                fmt::format("got {}, expected {}{}", describe(*node),
                            infinite ? "a finite number, " : "", range.describe()));
      return std::nullopt;
    }
    return value;
  }

  double number(std::string_view key, double fallback, Range range) {
    return optional_number(key, range).value_or(fallback);
  }

  std::int64_t integer(std::string_view key, std::int64_t fallback, std::int64_t minimum,
                       std::int64_t maximum = kNoMaximum) {
    const toml::node* node = find(key);
    if (node == nullptr) {
      return fallback;
    }
    const auto* integer = node->as_integer();
    if (integer == nullptr || integer->get() < minimum || integer->get() > maximum) {
      const bool too_large = integer != nullptr && integer->get() > maximum;
      const std::string allowed = too_large ? fmt::format("an integer ≤ {}", maximum)
                                            : fmt::format("an integer ≥ {}", minimum);
      add_issue(key, node->source(), fmt::format("got {}, expected {}", describe(*node), allowed));
      return fallback;
    }
    return integer->get();
  }

  bool boolean(std::string_view key, bool fallback) {
    const toml::node* node = find(key);
    if (node == nullptr) {
      return fallback;
    }
    if (const auto* value = node->as_boolean()) {
      return value->get();
    }
    add_issue(key, node->source(), fmt::format("got {}, expected true or false", describe(*node)));
    return fallback;
  }

  /// One of a fixed set of strings, mapped to its enumerator.
  template <typename Enum, std::size_t N>
  Enum choice(std::string_view key, Enum fallback, const EnumNames<Enum, N>& names) {
    const toml::node* node = find(key);
    if (node == nullptr) {
      return fallback;
    }
    const auto* value = node->as_string();
    std::vector<std::string> allowed;
    std::string listed;
    for (const auto& [name, enumerator] : names) {
      if (value != nullptr && value->get() == name) {
        return enumerator;
      }
      allowed.emplace_back(name);
      listed += fmt::format("{}\"{}\"", listed.empty() ? "" : ", ", name);
    }
    const std::string hint = value != nullptr ? did_you_mean(value->get(), allowed) : "";
    add_issue(key, node->source(),
              fmt::format("got {}, expected one of {}{}", describe(*node), listed, hint));
    return fallback;
  }

  /// An array of exactly three finite numbers.
  Vec3 vector3(std::string_view key, const Vec3& fallback) {
    const toml::node* node = find(key);
    if (node == nullptr) {
      return fallback;
    }
    const toml::array* array = node->as_array();
    if (array == nullptr || array->size() != 3) {
      const std::string got =
          array == nullptr ? describe(*node) : fmt::format("{} elements", array->size());
      add_issue(key, node->source(), fmt::format("got {}, expected an array of 3 numbers", got));
      return fallback;
    }
    Vec3 result = fallback;
    bool ok = true;
    for (std::size_t i = 0; i < 3; ++i) {
      const std::optional<double> value = number_value((*array)[i]);
      if (!value || !std::isfinite(*value)) {
        add_issue(key, (*array)[i].source(),
                  fmt::format("element {} is {}, expected a finite number", i + 1,
                              describe((*array)[i])));
        ok = false;
      } else {
        result[static_cast<Eigen::Index>(i)] = *value;
      }
    }
    return ok ? result : fallback;
  }

  /// A non-empty string that must be present.
  std::string required_string(std::string_view key) {
    const toml::node* node = find(key);
    if (node == nullptr) {
      add_issue(key, toml::source_region{}, "missing; this key is required", /*in_file=*/true);
      return {};
    }
    const auto* value = node->as_string();
    if (value == nullptr || value->get().empty()) {
      add_issue(key, node->source(),
                fmt::format("got {}, expected a non-empty string", describe(*node)));
      return {};
    }
    return value->get();
  }

  /// Adds an issue at `where`. Nodes that came from an override (or tables the overrides
  /// created) are reported as "--set"; `in_file` forces the file name without a position.
  void add_issue(std::string_view key, const toml::source_region& where, std::string message,
                 bool in_file = false) {
    failed_.emplace(key);
    ConfigIssue issue{source_name_, 0, 0, std::string(key), std::move(message)};
    const bool from_override =
        !in_file && (where.begin.line == 0 || (where.path && *where.path == kOverrideSource));
    if (from_override) {
      issue.file = kOverrideSource;
    } else if (!in_file) {
      issue.line = static_cast<int>(where.begin.line);
      issue.column = static_cast<int>(where.begin.column);
    }
    issues_.push_back(std::move(issue));
  }

  /// Reports every key that no read asked for, and known tables that are not tables.
  void check_unknown_keys() { check_table(root_, ""); }

 private:
  // A prefix of a known key names a table, e.g. "contact.wall" of "contact.wall.mu".
  [[nodiscard]] bool is_known_table(const std::string& key) const {
    const auto it = known_.lower_bound(key + ".");
    return it != known_.end() && it->starts_with(key + ".");
  }

  [[nodiscard]] std::string suggest(const std::string& key) const {
    std::vector<std::string> candidates;
    for (const std::string& known : known_) {
      candidates.push_back(known);
      for (std::size_t dot = known.find('.'); dot != std::string::npos;
           dot = known.find('.', dot + 1)) {
        candidates.push_back(known.substr(0, dot));
      }
    }
    std::string hint = did_you_mean(key, candidates);
    if (hint.empty()) {
      // The right name in the wrong table: `solver.mu` → 'contact.mu'.
      const std::string leaf = key.substr(key.rfind('.') + 1);
      for (const std::string& known : known_) {
        if (known.substr(known.rfind('.') + 1) == leaf) {
          return "; did you mean '" + known + "'?";
        }
      }
    }
    return hint;
  }

  void check_table(const toml::table& table, const std::string& prefix) {
    for (const auto& [name, node] : table) {
      const std::string key =
          prefix.empty() ? std::string(name.str()) : prefix + "." + std::string(name.str());
      if (known_.count(key) > 0) {
        continue;  // a value key; its type was checked when it was read
      }
      const toml::source_region& where =
          name.source().begin.line > 0 ? name.source() : node.source();
      if (!is_known_table(key)) {
        add_issue(key, where, "unknown key" + suggest(key));
      } else if (const toml::table* sub = node.as_table()) {
        check_table(*sub, key);
      } else {
        add_issue(key, where, fmt::format("got {}, expected a table", describe(node)));
      }
    }
  }

  const toml::table& root_;
  std::string source_name_;
  std::vector<ConfigIssue>& issues_;
  std::set<std::string, std::less<>> known_;
  std::set<std::string, std::less<>> failed_;
};

std::string_view trim(std::string_view s) {
  const std::size_t first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) {
    return {};
  }
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

/// An override split into its dotted key and its value, parsed as the TOML `v = value` with
/// source "--set" so that its nodes are reported as such.
struct Override {
  std::string key;
  toml::table parsed;
};

/// Parses one "section.key=value"; nullopt, and an issue naming it, when it is malformed.
std::optional<Override> parse_override(const std::string& text, std::vector<ConfigIssue>& issues) {
  const auto fail = [&issues](std::string_view key, std::string message) {
    issues.push_back({std::string(kOverrideSource), 0, 0, std::string(key), std::move(message)});
    return std::nullopt;
  };
  constexpr std::string_view kBareKeyCharacters =
      "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-";
  const std::size_t equals = text.find('=');
  const std::string_view key =
      trim(std::string_view(text).substr(0, equals == std::string::npos ? 0 : equals));
  const bool key_ok =
      !key.empty() && key.front() != '.' && key.back() != '.' &&
      key.find("..") == std::string_view::npos &&
      key.find_first_not_of(std::string(kBareKeyCharacters) + ".") == std::string_view::npos;
  if (equals == std::string::npos || !key_ok) {
    return fail(text, "malformed override, expected section.key=value (e.g. contact.mu_roll=0.5)");
  }
  const std::string_view value = trim(std::string_view(text).substr(equals + 1));
  Override result{std::string(key), {}};
  try {
    result.parsed = toml::parse("v = " + std::string(value), std::string(kOverrideSource));
  } catch (const toml::parse_error& error) {
    const bool bare_word =
        !value.empty() && value.find_first_not_of(kBareKeyCharacters) == std::string_view::npos;
    return fail(key,
                fmt::format("malformed override '{}': the value is not TOML ({}){}", text,
                            error.description(),
                            bare_word ? fmt::format("; strings need quotes: \"{}\"", value) : ""));
  }
  if (value.empty() || result.parsed.size() != 1) {
    return fail(key, fmt::format("malformed override '{}': expected one value", text));
  }
  return result;
}

/// Applies the overrides to `root` in order, creating the tables on their keys' paths.
void apply_overrides(toml::table& root, const std::vector<std::string>& overrides,
                     std::vector<ConfigIssue>& issues) {
  for (const std::string& text : overrides) {
    std::optional<Override> change = parse_override(text, issues);
    if (!change) {
      continue;
    }
    const std::string_view key = change->key;
    toml::table* table = &root;
    std::size_t start = 0;
    for (std::size_t dot = key.find('.'); dot != std::string_view::npos;
         start = dot + 1, dot = key.find('.', start)) {
      toml::node* node = table->get(key.substr(start, dot - start));
      if (node == nullptr) {
        node =
            &table->insert_or_assign(key.substr(start, dot - start), toml::table{}).first->second;
      }
      table = node->as_table();
      if (table == nullptr) {
        issues.push_back({std::string(kOverrideSource), 0, 0, change->key,
                          fmt::format("cannot set '{}': {} is {}, not a table", text,
                                      key.substr(0, dot), describe(*node))});
        break;
      }
    }
    if (table != nullptr) {
      table->insert_or_assign(key.substr(start), std::move(*change->parsed.get("v")));
    }
  }
}

/// All values of the scene, each checked where it is read; defaults come from scene.hpp.
Scene read_values(TableReader& in, const std::filesystem::path& base_dir) {
  Scene s;
  SystemConfig& system = s.system;
  system.lx = in.number("system.lx", system.lx, kPositive);
  system.ly = in.number("system.ly", system.ly, kPositive);
  system.gravity = in.vector3("system.gravity", system.gravity);
  system.density = in.number("system.density", system.density, kPositive);
  system.bottom_wall = in.boolean("system.bottom_wall", system.bottom_wall);

  ContactLaws& laws = s.step.laws;
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
  laws.cohesion_rule = in.choice("contact.cohesion_rule", laws.cohesion_rule, kCohesionRuleNames);
  // Wall laws default to the sphere–sphere ones (physics.md §5.4 notes).
  laws.walls = read_law("contact.wall", laws.spheres);
  laws.wall_r_eff_factor =
      in.number("contact.wall.r_eff_factor", laws.wall_r_eff_factor, kNonNegative);

  SolverSettings& solver = s.step.solver;
  solver.dt = in.number("solver.dt", solver.dt, kPositive);
  solver.tolerance = in.number("solver.tolerance", solver.tolerance, kPositive);
  solver.min_sweeps =
      static_cast<int>(in.integer("solver.min_sweeps", solver.min_sweeps, 1, kIntMax));
  solver.max_sweeps =
      static_cast<int>(in.integer("solver.max_sweeps", solver.max_sweeps, 1, kIntMax));
  solver.stopping_rule =
      in.choice("solver.stopping_rule", solver.stopping_rule, kStoppingRuleNames);
  solver.visit_order = in.choice("solver.visit_order", solver.visit_order, kVisitOrderNames);
  solver.acceleration_depth = static_cast<int>(
      in.integer("solver.acceleration_depth", solver.acceleration_depth, 0, kIntMax));
  solver.warm_start = in.boolean("solver.warm_start", solver.warm_start);
  solver.skin = in.number("solver.skin", solver.skin, kNonNegative);
  solver.seed = static_cast<std::uint64_t>(
      in.integer("solver.seed", static_cast<std::int64_t>(solver.seed), 0));

  PistonConfig& piston = s.piston;
  piston.enabled = in.boolean("piston.enabled", piston.enabled);
  piston.mass = in.number("piston.mass", piston.mass, kPositive);
  piston.pressure = in.optional_number("piston.pressure", kNonNegative);
  piston.force = in.optional_number("piston.force", kNonNegative);
  piston.height = in.optional_number("piston.height", kAnyNumber);
  piston.start_gap = in.number("piston.start_gap", piston.start_gap, kNonNegative);
  piston.velocity = in.number("piston.velocity", piston.velocity, kAnyNumber);

  const std::string particles = in.required_string("particles.file");
  if (!particles.empty()) {
    s.particles_file = (base_dir / std::filesystem::path(particles)).lexically_normal();
    std::error_code error;
    if (!std::filesystem::is_regular_file(s.particles_file, error)) {
      in.add_issue("particles.file", in.find("particles.file")->source(),
                   fmt::format("no such file: '{}'", s.particles_file.string()));
    }
  }

  RunConfig& run = s.run;
  run.duration = in.number("run.duration", run.duration, kPositive);
  run.until_blocked = in.boolean("run.until_blocked", run.until_blocked);
  run.max_duration = in.number("run.max_duration", run.max_duration, kPositive);
  run.timeseries_every =
      static_cast<int>(in.integer("run.timeseries_every", run.timeseries_every, 1, kIntMax));
  BlockedCriteria& blocked = run.blocked;
  blocked.window = in.number("run.blocked.window", blocked.window, kPositive);
  blocked.piston_speed = in.number("run.blocked.piston_speed", blocked.piston_speed, kPositive);
  blocked.sphere_speed = in.number("run.blocked.sphere_speed", blocked.sphere_speed, kPositive);
  blocked.force_balance = in.number("run.blocked.force_balance", blocked.force_balance, kPositive);
  blocked.height_change = in.number("run.blocked.height_change", blocked.height_change, kPositive);
  return s;
}

/// Checks between keys, after the single values; each message names both keys. A pair
/// with an already reported value is skipped, so one mistake gives one message.
void check_consistency(TableReader& in, const Scene& s) {
  const auto where = [&in](std::string_view key) {
    const toml::node* node = in.find(key);
    return node != nullptr ? node->source() : toml::source_region{};
  };
  const auto in_file = [&in](std::string_view key) { return in.find(key) == nullptr; };
  const bool has_pressure = in.find("piston.pressure") != nullptr;
  const bool has_force = in.find("piston.force") != nullptr;
  if (has_pressure && has_force) {
    in.add_issue("piston.force", where("piston.force"),
                 "set together with piston.pressure; set exactly one of them");
  }
  if (s.piston.enabled && !has_pressure && !has_force) {
    in.add_issue("piston.enabled", where("piston.enabled"),
                 "is true but neither piston.pressure nor piston.force is set; set exactly one",
                 in_file("piston.enabled"));
  }
  if (s.run.until_blocked && !s.piston.enabled && !in.failed("piston.enabled")) {
    in.add_issue("run.until_blocked", where("run.until_blocked"),
                 "is true but piston.enabled is false; the blocked state needs the piston",
                 in_file("run.until_blocked"));
  }
  const SolverSettings& solver = s.step.solver;
  if (solver.min_sweeps > solver.max_sweeps && !in.failed("solver.min_sweeps") &&
      !in.failed("solver.max_sweeps")) {
    in.add_issue("solver.min_sweeps", where("solver.min_sweeps"),
                 fmt::format("got {}, expected at most solver.max_sweeps = {}", solver.min_sweeps,
                             solver.max_sweeps),
                 in_file("solver.min_sweeps"));
  }
}

/// toml++ prints doubles with 17 significant digits (0.3 → 0.29999999999999999). Rewrites
/// the floats of value lines in fmt's shortest exact form; strings are left alone.
std::string shorten_floats(const std::string& text) {
  std::istringstream lines(text);
  std::string result;
  std::string line;
  while (std::getline(lines, line)) {
    const std::size_t equals = line.find(" = ");
    if (equals != std::string::npos && line.find('"') == std::string::npos) {
      std::string rewritten = line.substr(0, equals + 3);
      std::size_t i = equals + 3;
      while (i < line.size()) {
        const std::size_t end = line.find_first_of(" ,[]", i);
        const std::size_t stop = end == std::string::npos ? line.size() : end;
        std::string token = line.substr(i, stop - i);
        double value = 0.0;
        const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
        const bool is_float = token.find_first_of(".eE") != std::string::npos;
        if (!token.empty() && is_float && ec == std::errc() && ptr == token.data() + token.size()) {
          token = fmt::format("{}", value);
          if (token.find_first_of(".eEn") == std::string::npos) {
            token += ".0";  // stays a TOML float
          }
        }
        rewritten += token;
        if (stop < line.size()) {
          rewritten += line[stop];
        }
        i = stop + 1;
      }
      line = rewritten;
    }
    result += line + '\n';
  }
  return result;
}

toml::table law_table(const ContactLaw& law) {
  return toml::table{{"mu", law.mu},
                     {"mu_roll", law.mu_roll},
                     {"mu_twist", law.mu_twist},
                     {"cohesion_force", law.cohesion_force},
                     {"cohesion_range", law.cohesion_range}};
}

/// The validated scene as TOML: every key with its effective value.
std::string write_effective_toml(const Scene& s) {
  const Vec3& g = s.system.gravity;
  const ContactLaws& laws = s.step.laws;
  const SolverSettings& solver = s.step.solver;
  toml::table contact = law_table(laws.spheres);
  contact.insert_or_assign("cohesion_rule", name_of(laws.cohesion_rule, kCohesionRuleNames));
  toml::table wall = law_table(laws.walls);
  wall.insert_or_assign("r_eff_factor", laws.wall_r_eff_factor);
  contact.insert_or_assign("wall", std::move(wall));
  toml::table piston{{"enabled", s.piston.enabled},
                     {"mass", s.piston.mass},
                     {"start_gap", s.piston.start_gap},
                     {"velocity", s.piston.velocity}};
  // Unset optional keys stay absent: TOML has no null.
  const std::array<std::pair<const char*, const std::optional<double>*>, 3> optionals = {
      {{"pressure", &s.piston.pressure}, {"force", &s.piston.force}, {"height", &s.piston.height}}};
  for (const auto& [key, value] : optionals) {
    if (value->has_value()) {
      piston.insert_or_assign(key, **value);
    }
  }
  const BlockedCriteria& blocked = s.run.blocked;
  const toml::table root{
      {"system", toml::table{{"lx", s.system.lx},
                             {"ly", s.system.ly},
                             {"gravity", toml::array{g.x(), g.y(), g.z()}},
                             {"density", s.system.density},
                             {"bottom_wall", s.system.bottom_wall}}},
      {"contact", std::move(contact)},
      {"solver", toml::table{{"dt", solver.dt},
                             {"tolerance", solver.tolerance},
                             {"min_sweeps", solver.min_sweeps},
                             {"max_sweeps", solver.max_sweeps},
                             {"stopping_rule", name_of(solver.stopping_rule, kStoppingRuleNames)},
                             {"visit_order", name_of(solver.visit_order, kVisitOrderNames)},
                             {"acceleration_depth", solver.acceleration_depth},
                             {"warm_start", solver.warm_start},
                             {"skin", solver.skin},
                             {"seed", static_cast<std::int64_t>(solver.seed)}}},
      {"piston", std::move(piston)},
      {"particles", toml::table{{"file", s.particles_file.string()}}},
      {"run", toml::table{{"duration", s.run.duration},
                          {"until_blocked", s.run.until_blocked},
                          {"max_duration", s.run.max_duration},
                          {"timeseries_every", s.run.timeseries_every},
                          {"blocked", toml::table{{"window", blocked.window},
                                                  {"piston_speed", blocked.piston_speed},
                                                  {"sphere_speed", blocked.sphere_speed},
                                                  {"force_balance", blocked.force_balance},
                                                  {"height_change", blocked.height_change}}}}}};
  // Basic single-line strings only, so shorten_floats can tell strings from numbers.
  const toml::format_flags flags =
      toml::toml_formatter::default_flags &
      ~(toml::format_flags::allow_literal_strings | toml::format_flags::allow_multi_line_strings);
  std::ostringstream out;
  out << toml::toml_formatter(root, flags);
  return shorten_floats(out.str());
}

/// File order for a reader fixing the file top to bottom: positioned issues by line and
/// column, then those of the whole file, then those of the overrides (malformed ones first).
void sort_issues(std::vector<ConfigIssue>& issues) {
  const auto rank = [](const ConfigIssue& issue) {
    const int group = issue.file == kOverrideSource ? 2 : (issue.line > 0 ? 0 : 1);
    return std::tuple(group, issue.line, issue.column);
  };
  std::stable_sort(
      issues.begin(), issues.end(),
      [&rank](const ConfigIssue& a, const ConfigIssue& b) { return rank(a) < rank(b); });
}

}  // namespace

Scene read_scene_text(std::string_view toml_text, std::string_view source_name,
                      const std::vector<std::string>& overrides,
                      const std::filesystem::path& base_dir) {
  std::vector<ConfigIssue> issues;
  toml::table root;
  try {
    root = toml::parse(toml_text, std::string(source_name));
  } catch (const toml::parse_error& error) {
    issues.push_back({std::string(source_name), static_cast<int>(error.source().begin.line),
                      static_cast<int>(error.source().begin.column), "",
                      fmt::format("TOML syntax error: {}", error.description())});
    toml::table ignored;
    apply_overrides(ignored, overrides, issues);  // still report malformed overrides
    throw ConfigError(std::move(issues));
  }
  apply_overrides(root, overrides, issues);
  TableReader in(root, std::string(source_name), issues);
  Scene scene = read_values(in, base_dir);
  in.check_unknown_keys();
  check_consistency(in, scene);
  if (!issues.empty()) {
    sort_issues(issues);
    throw ConfigError(std::move(issues));
  }
  scene.source = std::filesystem::path(source_name);
  scene.effective_toml = write_effective_toml(scene);
  return scene;
}

Scene read_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides) {
  std::ifstream stream(file, std::ios::binary);
  if (!stream) {
    throw ConfigError({{file.string(), 0, 0, "", "cannot open the scene file"}});
  }
  std::ostringstream text;
  text << stream.rdbuf();
  std::error_code error;
  const std::filesystem::path absolute = std::filesystem::absolute(file, error);
  Scene scene = read_scene_text(text.str(), file.string(), overrides,
                                error ? file.parent_path() : absolute.parent_path());
  scene.source = file;
  return scene;
}

}  // namespace cdpowder
