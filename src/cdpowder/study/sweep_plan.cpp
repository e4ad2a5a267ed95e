// sweep_plan.cpp — reading a sweep file and expanding it into runs. The file's values are found
// and its mistakes recorded through detail::TableReader (config/table_reader.hpp), as a
// scene's are; the sweep's own rules (value lists, seeds, parameter names) are checked here.
#include "cdpowder/study/sweep_plan.hpp"

#include "cdpowder/config/config_error.hpp"
#include "cdpowder/config/input_file.hpp"
#include "cdpowder/config/scene_keys.hpp"
#include "cdpowder/config/table_reader.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <utility>

namespace cdpowder {

namespace {

constexpr std::int64_t kMaxSeedCount = 100000;

const std::vector<std::string>& top_level_keys() {
  static const std::vector<std::string> keys{
      "scene", "command", "protocol", "seeds", "seed_keys", "set", "grid", "points", "points_csv"};
  return keys;
}

using detail::TableReader;

/// "sweep.toml:6:12": where the file gives a value, as the origin of the override it makes.
std::string origin_of(const toml::node& where) {
  const toml::source_region& region = where.source();
  return fmt::format("{}:{}:{}", region.path ? *region.path : std::string(), region.begin.line,
                     region.begin.column);
}

/// A mistake at `where`, or in the file as a whole when there is no node.
void report(TableReader& in, const std::string& key, const toml::node* where, std::string message) {
  in.add_issue(key, where != nullptr ? where->source() : toml::source_region{}, std::move(message),
               /*in_file=*/where == nullptr);
}

/// The value of a sweep parameter as the TOML text `--set` expects; "" after an issue.
std::string override_value(TableReader& in, const std::string& key, const toml::node& node) {
  if (const auto* d = node.as_floating_point()) {
    const double v = d->get();
    if (!std::isfinite(v)) {
      report(in, key, &node, fmt::format("got {}, expected a finite number", v));
      return "";
    }
    std::string text = fmt::format("{}", v);
    if (text.find_first_of(".eE") == std::string::npos) text += ".0";
    return text;
  }
  if (const auto* i = node.as_integer()) return fmt::format("{}", i->get());
  if (const auto* b = node.as_boolean()) return b->get() ? "true" : "false";
  if (const auto* s = node.as_string()) {
    const std::string& v = s->get();
    if (v.find_first_of("\"\\\n,=/") != std::string::npos || v.empty()) {
      report(in, key, &node,
             fmt::format("got \"{}\", expected a non-empty string without quotes, "
                         "backslashes, newlines, ',', '=' or '/'",
                         v));
      return "";
    }
    return "\"" + v + "\"";
  }
  report(in, key, &node,
         fmt::format("got a {}, expected a number, a boolean or a string",
                     node.is_array() ? "list" : (node.is_table() ? "table" : "date or time")));
  return "";
}

/// Flattens nested tables into dotted keys: [grid.contact] mu_roll = … → contact.mu_roll.
void flatten(const toml::table& table, const std::string& prefix,
             std::vector<std::pair<std::string, const toml::node*>>& out) {
  for (const auto& [name, node] : table) {
    const std::string key =
        prefix.empty() ? std::string(name.str()) : prefix + "." + std::string(name.str());
    if (const auto* inner = node.as_table()) {
      flatten(*inner, key, out);
    } else {
      out.emplace_back(key, &node);
    }
  }
}

std::string point_name(const std::vector<SweepSetting>& settings) {
  if (settings.empty()) return "base";
  std::string name;
  for (const SweepSetting& s : settings) {
    if (!name.empty()) name += ',';
    std::string value = s.value;
    value.erase(std::remove(value.begin(), value.end(), '"'), value.end());
    name += s.key + "=" + value;
  }
  return name;
}

/// The file's top-level keys, each known.
void check_top_level_keys(TableReader& in, const toml::table& root) {
  for (const auto& [name, node] : root) {
    const std::string key(name.str());
    const std::vector<std::string>& known = top_level_keys();
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      report(in, key, &node,
             "unknown key; allowed: scene, command, protocol, seeds, seed_keys, set, [grid], "
             "[[points]], points_csv" +
                 did_you_mean(key, known));
    }
  }
}

/// `command`: "compact" (the default: until the blocked state), "simulate" (the scene's own
/// duration or end) or "python" (the `protocol`).
void read_command(TableReader& in, SweepPlan& plan) {
  const auto* command = in.find("command");
  if (command == nullptr) return;
  const auto* name = command->as_string();
  if (name != nullptr && name->get() == "compact") return;
  if (name != nullptr && name->get() == "simulate") {
    plan.command = SweepCommand::Simulate;
    return;
  }
  if (name != nullptr && name->get() == "python") {
    plan.command = SweepCommand::Python;
    return;
  }
  report(in, "command", command,
         fmt::format(R"(got {}, expected "compact", "simulate" or "python")",
                     detail::describe(*command)));
}

/// Whether `name` is a Python identifier of ASCII letters, digits and underscores.
bool is_python_identifier(std::string_view name) {
  const auto letter = [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
  };
  return !name.empty() && letter(name.front()) &&
         std::all_of(name.begin(), name.end(),
                     [&](char c) { return letter(c) || (c >= '0' && c <= '9'); });
}

/// `protocol = "FILE:FUNCTION"`, the Python function each run of command "python" calls; the
/// file relative to the sweep file. Required by that command, refused by the others.
void read_protocol(TableReader& in, const std::filesystem::path& base_dir, SweepPlan& plan) {
  const auto* protocol = in.find("protocol");
  if (plan.command != SweepCommand::Python) {
    if (protocol != nullptr) {
      report(in, "protocol", protocol,
             R"(is read only with command = "python"; remove it, or set command = "python")");
    }
    return;
  }
  const auto* text = protocol != nullptr ? protocol->as_string() : nullptr;
  const std::string value = text != nullptr ? text->get() : std::string();
  const std::size_t colon = value.rfind(':');
  if (protocol == nullptr) {
    report(in, "protocol", nullptr,
           R"(missing: command = "python" needs protocol = "FILE.py:FUNCTION", the function )"
           "each point runs (docs/sweeps.md)");
    return;
  }
  if (text == nullptr || colon == std::string::npos || colon == 0 ||
      !is_python_identifier(std::string_view(value).substr(colon + 1))) {
    report(in, "protocol", protocol,
           fmt::format(R"(got {}, expected "FILE.py:FUNCTION": a Python file (relative to the )"
                       "sweep file) and the name of a function in it",
                       detail::describe(*protocol)));
    return;
  }
  const std::filesystem::path file(value.substr(0, colon));
  plan.protocol.file = file.is_absolute() ? file : base_dir / file;
  plan.protocol.function = value.substr(colon + 1);
  plan.protocol.name = value;
  std::error_code error;
  if (!std::filesystem::is_regular_file(plan.protocol.file, error)) {
    report(in, "protocol", protocol,
           fmt::format("{}: no such file (a Python file, relative to the sweep file)",
                       plan.protocol.file.string()));
  }
}

/// `scene`: the base scene file, relative to the sweep file.
void read_scene_key(TableReader& in, const std::filesystem::path& base_dir, SweepPlan& plan) {
  if (const auto* scene = in.find("scene"); scene == nullptr) {
    report(in, "scene", nullptr, "missing: the base scene file (TOML), relative to the sweep file");
  } else if (const auto* path = scene->as_string(); path == nullptr || path->get().empty()) {
    report(in, "scene", scene, "expected a non-empty string: the base scene file");
  } else {
    const std::filesystem::path p(path->get());
    plan.scene = p.is_absolute() ? p : base_dir / p;
  }
}

/// `seeds`: n (1..n) or a list of distinct integers; returns where the file gives them (the
/// origin of the seed overrides), `source` when it does not.
std::string read_seeds(TableReader& in, const std::string& source, SweepPlan& plan) {
  const auto* seeds = in.find("seeds");
  if (seeds == nullptr) {
    plan.seeds = {1};
    return source;
  }
  if (const auto* n = seeds->as_integer()) {
    if (n->get() < 1 || n->get() > kMaxSeedCount) {
      report(in, "seeds", seeds,
             fmt::format("got {}, expected a count in [1, {}] or a list of seeds", n->get(),
                         kMaxSeedCount));
    } else {
      for (std::int64_t s = 1; s <= n->get(); ++s) plan.seeds.push_back(s);
    }
    return origin_of(*seeds);
  }
  const auto* list = seeds->as_array();
  if (list == nullptr || list->empty()) {
    report(in, "seeds", seeds, "expected a count (e.g. 3) or a non-empty list of seeds");
    return source;
  }
  std::set<std::int64_t> seen;
  for (const auto& item : *list) {
    const auto* s = item.as_integer();
    if (s == nullptr || s->get() < 0) {
      report(in, "seeds", &item, "expected non-negative integers");
    } else if (!seen.insert(s->get()).second) {
      report(in, "seeds", &item, fmt::format("seed {} is listed twice", s->get()));
    } else {
      plan.seeds.push_back(s->get());
    }
  }
  return origin_of(*seeds);
}

/// `seed_keys` (default deposition.seed and solver.seed) and `set`, the fixed overrides.
void read_seed_keys_and_fixed(TableReader& in, SweepPlan& plan) {
  const Scene defaults;
  const DepositionConfig deposit;
  const std::string solver_seed = detail::key_name(defaults, defaults.step.solver.seed);
  plan.seed_keys = {detail::key_of(deposit, deposit.seed).dotted(), solver_seed};
  if (const auto* keys = in.find("seed_keys")) {
    plan.seed_keys.clear();
    const auto* list = keys->as_array();
    if (list == nullptr) report(in, "seed_keys", keys, "expected a list of scene keys");
    for (std::size_t i = 0; list != nullptr && i < list->size(); ++i) {
      const toml::node& item = *list->get(i);
      if (const auto* k = item.as_string(); k != nullptr && !k->get().empty()) {
        plan.seed_keys.push_back(k->get());
      } else {
        report(in, "seed_keys", &item,
               fmt::format("expected scene keys such as \"{}\"", solver_seed));
      }
    }
  }
  if (const auto* fixed = in.find("set")) {
    const auto* list = fixed->as_array();
    if (list == nullptr) report(in, "set", fixed, "expected a list of \"section.key=value\"");
    for (std::size_t i = 0; list != nullptr && i < list->size(); ++i) {
      const toml::node& item = *list->get(i);
      if (const auto* s = item.as_string()) {
        plan.fixed.emplace_back(s->get(), origin_of(item));
      } else {
        report(in, "set", &item, "expected strings \"section.key=value\"");
      }
    }
  }
}

/// One grid parameter: its key and values, in the file's order.
using GridAxis = std::pair<std::string, std::vector<SweepSetting>>;

/// `[grid]`: key = [values] (nested tables flattened to dotted keys); each key becomes a
/// parameter.
std::vector<GridAxis> read_grid(TableReader& in, SweepPlan& plan) {
  std::vector<GridAxis> grid;
  const auto* node = in.find("grid");
  if (node == nullptr) return grid;
  const auto* table = node->as_table();
  if (table == nullptr) report(in, "grid", node, "expected a table of key = [values]");
  std::vector<std::pair<std::string, const toml::node*>> entries;
  if (table != nullptr) flatten(*table, "", entries);
  std::set<std::string> grid_keys;
  for (const auto& [key, value] : entries) {
    if (!grid_keys.insert(key).second) {
      report(in, "grid." + key, value, "is given twice (as a nested table and a dotted key?)");
      continue;
    }
    const auto* list = value->as_array();
    if (list == nullptr || list->empty()) {
      report(in, "grid." + key, value, "expected a non-empty list of values");
      continue;
    }
    std::vector<SweepSetting> values;
    std::set<std::string> seen;
    for (const auto& item : *list) {
      std::string value_text = override_value(in, "grid." + key, item);
      if (value_text.empty()) continue;
      if (!seen.insert(value_text).second) {
        report(in, "grid." + key, &item, fmt::format("value {} is listed twice", value_text));
        continue;
      }
      values.push_back({key, std::move(value_text), origin_of(item)});
    }
    grid.emplace_back(key, std::move(values));
    plan.parameter_keys.push_back(key);
  }
  return grid;
}

/// `[[points]]`: explicit points; a key no grid names becomes a parameter too.
std::vector<std::map<std::string, SweepSetting>> read_points(TableReader& in, SweepPlan& plan) {
  std::vector<std::map<std::string, SweepSetting>> points;
  const auto* node = in.find("points");
  if (node == nullptr) return points;
  const auto* list = node->as_array();
  if (list == nullptr) report(in, "points", node, "expected [[points]] tables of key = value");
  for (std::size_t i = 0; list != nullptr && i < list->size(); ++i) {
    const toml::node& item = *list->get(i);
    const auto* table = item.as_table();
    if (table == nullptr) {
      report(in, "points", &item, "expected [[points]] tables of key = value");
      continue;
    }
    std::vector<std::pair<std::string, const toml::node*>> entries;
    flatten(*table, "", entries);
    std::map<std::string, SweepSetting> point;
    for (const auto& [key, value] : entries) {
      if (point.count(key) > 0) {
        report(in, "points." + key, value, "is given twice in one point");
        continue;
      }
      const std::string value_text = override_value(in, "points." + key, *value);
      if (value_text.empty()) continue;
      point[key] = {key, value_text, origin_of(*value)};
      if (std::find(plan.parameter_keys.begin(), plan.parameter_keys.end(), key) ==
          plan.parameter_keys.end()) {
        plan.parameter_keys.push_back(key);
      }
    }
    points.push_back(std::move(point));
  }
  return points;
}

/// `text` as a TOML basic string: in double quotes, with '"' and '\\' escaped.
std::string toml_string(const std::string& text) {
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  return quoted + "\"";
}

/// A cell of a points table as the TOML text `--set` expects: a number or a boolean as written
/// (TOML reads them), anything else a string.
std::string csv_cell_value(const std::string& cell) {
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + cell);
  } catch (const toml::parse_error&) {
    return toml_string(cell);  // not a TOML value: a string
  }
  const toml::node* v = parsed.get("v");
  return v != nullptr && (v->is_number() || v->is_boolean()) ? cell : toml_string(cell);
}

/// `points_csv`: one point a row of a CSV file (relative to the sweep file) whose header names
/// the keys, as yade-batch's table does; an empty cell leaves its key at the base scene's
/// value. '#' lines and blank lines are skipped; a cell may be quoted ("history").
void read_points_csv(TableReader& in, const std::filesystem::path& base_dir, SweepPlan& plan,
                     std::vector<std::map<std::string, SweepSetting>>& points) {
  const auto* node = in.find("points_csv");
  if (node == nullptr) return;
  const auto* name = node->as_string();
  if (name == nullptr || name->get().empty()) {
    report(in, "points_csv", node, "expected a non-empty string: a CSV file of points");
    return;
  }
  const std::filesystem::path file = std::filesystem::path(name->get()).is_absolute()
                                         ? std::filesystem::path(name->get())
                                         : base_dir / name->get();
  std::ifstream stream(file);
  if (!stream) {
    report(in, "points_csv", node, fmt::format("cannot read '{}'", file.string()));
    return;
  }
  const auto cells_of = [](const std::string& line) {
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) {
      const auto first = cell.find_first_not_of(" \t\r");
      const auto last = cell.find_last_not_of(" \t\r");
      cell = first == std::string::npos ? "" : cell.substr(first, last - first + 1);
      if (cell.size() >= 2 && cell.front() == '"' && cell.back() == '"') {
        cell = cell.substr(1, cell.size() - 2);
      }
      cells.push_back(cell);
    }
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    return cells;
  };
  std::vector<std::string> keys;
  int line_number = 0;
  for (std::string line; std::getline(stream, line);) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos || line.starts_with('#')) continue;
    const std::vector<std::string> cells = cells_of(line);
    const std::string where = fmt::format("{}:{}", name->get(), line_number);
    if (keys.empty()) {
      keys = cells;
      for (const std::string& key : keys) {
        if (key.empty()) report(in, "points_csv", node, where + ": a column without a key");
        if (std::find(plan.parameter_keys.begin(), plan.parameter_keys.end(), key) ==
            plan.parameter_keys.end()) {
          plan.parameter_keys.push_back(key);
        }
      }
      continue;
    }
    if (cells.size() != keys.size()) {
      report(in, "points_csv", node,
             fmt::format("{}: got {} cells, expected {} (the header's keys)", where, cells.size(),
                         keys.size()));
      continue;
    }
    std::map<std::string, SweepSetting> point;
    for (std::size_t k = 0; k < keys.size(); ++k) {
      if (!cells[k].empty()) point[keys[k]] = {keys[k], csv_cell_value(cells[k]), where};
    }
    points.push_back(std::move(point));
  }
  if (keys.empty())
    report(in, "points_csv", node, fmt::format("'{}' has no header", file.string()));
}

/// The points: the grid's, last key fastest, then the explicit ones (a grid key an explicit
/// point does not name keeps the base scene's value there, so explicit points list every
/// parameter they set); the base scene alone when there are none. Named, and a point listed
/// twice (grid and explicit) kept once.
std::vector<SweepPoint> expand_points(const std::vector<GridAxis>& grid,
                                      const std::vector<std::map<std::string, SweepSetting>>& given,
                                      const std::vector<std::string>& parameter_keys) {
  std::vector<SweepPoint> points;
  std::vector<std::size_t> index(grid.size(), 0);
  const bool has_grid = !grid.empty();
  while (has_grid) {
    SweepPoint point;
    for (std::size_t k = 0; k < grid.size(); ++k) {
      point.settings.push_back(grid[k].second[index[k]]);
    }
    points.push_back(std::move(point));
    std::size_t k = grid.size();
    while (k > 0 && ++index[k - 1] == grid[k - 1].second.size()) index[--k] = 0;
    if (k == 0) break;
  }
  for (const auto& values : given) {
    SweepPoint point;
    for (const std::string& key : parameter_keys) {
      if (const auto it = values.find(key); it != values.end()) {
        point.settings.push_back(it->second);
      }
    }
    points.push_back(std::move(point));
  }
  if (points.empty()) points.push_back(SweepPoint{});  // the base scene alone

  std::set<std::string> names;
  std::vector<SweepPoint> unique;
  for (SweepPoint& point : points) {
    point.name = point_name(point.settings);
    if (names.insert(point.name).second) unique.push_back(std::move(point));
  }
  return unique;
}

/// Every point × every seed: its folder and the overrides (fixed, the point's, the seeds).
void make_runs(SweepPlan& plan, const std::string& seeds_origin) {
  for (std::size_t p = 0; p < plan.points.size(); ++p) {
    for (const std::int64_t seed : plan.seeds) {
      SweepRun run;
      run.point = p;
      run.seed = seed;
      run.folder =
          std::filesystem::path("runs") / plan.points[p].name / fmt::format("seed_{}", seed);
      run.overrides = plan.fixed;
      for (const SweepSetting& s : plan.points[p].settings) {
        run.overrides.emplace_back(s.key + "=" + s.value, s.origin);
      }
      for (const std::string& key : plan.seed_keys) {
        run.overrides.emplace_back(fmt::format("{}={}", key, seed), seeds_origin);
      }
      plan.runs.push_back(std::move(run));
    }
  }
}

}  // namespace

SweepPlan read_sweep_plan_text(std::string_view text, std::string_view source_name,
                               const std::filesystem::path& base_dir,
                               const std::vector<std::string>& extra_fixed) {
  std::vector<ConfigIssue> issues;
  const std::string source(source_name);
  toml::table root;
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& error) {
    throw ConfigError({{source, static_cast<int>(error.source().begin.line),
                        static_cast<int>(error.source().begin.column), "",
                        fmt::format("TOML syntax error: {}", error.description())}});
  }
  TableReader in(root, source, issues);
  SweepPlan plan;
  plan.source = std::filesystem::path(source_name);
  check_top_level_keys(in, root);
  read_scene_key(in, base_dir, plan);
  read_command(in, plan);
  read_protocol(in, base_dir, plan);
  const std::string seeds_origin = read_seeds(in, source, plan);
  read_seed_keys_and_fixed(in, plan);
  plan.fixed.insert(plan.fixed.end(), extra_fixed.begin(), extra_fixed.end());
  // the parameters: grid keys first, then keys that only explicit points name
  const std::vector<GridAxis> grid = read_grid(in, plan);
  std::vector<std::map<std::string, SweepSetting>> given = read_points(in, plan);
  read_points_csv(in, base_dir, plan, given);
  for (const std::string& key : plan.parameter_keys) {
    if (std::find(plan.seed_keys.begin(), plan.seed_keys.end(), key) != plan.seed_keys.end()) {
      report(in, key, nullptr, "is a seed key; vary seeds with `seeds`, not as a parameter");
    }
  }
  if (!issues.empty()) throw ConfigError(std::move(issues));
  plan.points = expand_points(grid, given, plan.parameter_keys);
  make_runs(plan, seeds_origin);
  return plan;
}

SweepPlan read_sweep_plan(const std::filesystem::path& file,
                          const std::vector<std::string>& extra_fixed) {
  const std::string text =
      read_input_file(file, "a sweep file (TOML), e.g. examples/quick/fig5_sweep.toml");
  // the base scene relative to the sweep file as the user named it: the runs (children in
  // the same working folder) find it, and outputs record it without this machine's path
  SweepPlan plan = read_sweep_plan_text(text, file.string(), file.parent_path(), extra_fixed);
  plan.source = file;
  return plan;
}

const char* command_name(SweepCommand command) {
  switch (command) {
    case SweepCommand::Simulate:
      return "simulate";
    case SweepCommand::Python:
      return "python";
    case SweepCommand::Compact:
      break;
  }
  return "compact";
}

void order_seed_by_seed(const SweepPlan& plan, std::vector<std::size_t>& runs) {
  // plan.runs is point-major: run i has point i / seeds and seed index i % seeds
  const std::size_t seed_count = std::max<std::size_t>(1, plan.seeds.size());
  std::stable_sort(runs.begin(), runs.end(), [&](std::size_t a, std::size_t b) {
    return std::pair(a % seed_count, a / seed_count) < std::pair(b % seed_count, b / seed_count);
  });
}

}  // namespace cdpowder
