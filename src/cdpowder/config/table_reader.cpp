// table_reader.cpp — typed reads at dotted keys with one issue per bad value, the unknown-key
// check with its suggestions, and the `--set` overrides (table_reader.hpp). Numbers in
// messages are formatted with fmt, which prints the shortest form that reads back exactly,
// so a message echoes what the user typed (style guide 3.7).
#include "cdpowder/config/table_reader.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace cdpowder::detail {
namespace {

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

/// Where a node came from. A table an override created has no position of its own: it is
/// reported where its first value came from.
const toml::source_region& origin_of(const toml::node& node) {
  if (const auto* table = node.as_table();
      table != nullptr && node.source().begin.line == 0 && !table->empty()) {
    return origin_of(table->cbegin()->second);
  }
  return node.source();
}

std::string_view trim(std::string_view s) {
  const std::size_t first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) {
    return {};
  }
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

/// An override split into its dotted key and its value, parsed as the TOML `v = value` with
/// the override's origin as source, so that its nodes are reported there.
struct Override {
  std::string key;
  toml::table parsed;
};

/// The TOML parser's description of a malformed value as an override's message shows it.
constexpr std::size_t kMaxParserExcerpt = 100;

}  // namespace

std::string_view override_key(const SceneOverride& change) {
  const std::size_t equals = change.text.find('=');
  return trim(std::string_view(change.text).substr(0, equals == std::string::npos ? 0 : equals));
}

namespace {

/// Parses one "section.key=value"; nullopt, and an issue naming it, when it is malformed.
std::optional<Override> parse_override(const SceneOverride& change,
                                       std::vector<ConfigIssue>& issues) {
  const std::string& text = change.text;
  const auto fail = [&issues, &change](std::string_view key, std::string message) {
    issues.push_back({change.origin, 0, 0, std::string(key), std::move(message)});
    return std::nullopt;
  };
  constexpr std::string_view kBareKeyCharacters =
      "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-";
  const std::size_t equals = text.find('=');
  const std::string_view key = override_key(change);
  const bool characters_ok =
      key.find_first_not_of(std::string(kBareKeyCharacters) + ".") == std::string_view::npos;
  const bool key_ok = !key.empty() && key.front() != '.' && key.back() != '.' &&
                      key.find("..") == std::string_view::npos && characters_ok;
  if (equals != std::string::npos && !key.empty() && !characters_ok) {
    return fail(shown(key),
                "malformed override: a key holds only the letters a-z and A-Z, "
                "digits, '_', '-' and '.' (e.g. contact.mu_roll=0.5)");
  }
  if (equals == std::string::npos || !key_ok) {
    return fail(shown(text),
                "malformed override, expected section.key=value (e.g. contact.mu_roll=0.5)");
  }
  const std::string_view value = trim(std::string_view(text).substr(equals + 1));
  Override result{std::string(key), {}};
  try {
    result.parsed = toml::parse("v = " + std::string(value), change.origin);
  } catch (const toml::parse_error& error) {
    const bool bare_word =
        !value.empty() && value.find_first_not_of(kBareKeyCharacters) == std::string_view::npos;
    return fail(
        key,
        fmt::format("malformed override '{}': the value is not TOML ({}){}", shown(text),
                    shown(error.description(), kMaxParserExcerpt),
                    bare_word ? fmt::format("; strings need quotes: \"{}\"", shown(value)) : ""));
  }
  if (value.empty() || result.parsed.size() != 1) {
    return fail(key, fmt::format("malformed override '{}': expected one value", shown(text)));
  }
  return result;
}

}  // namespace

bool Range::contains(double value) const {
  if (!std::isfinite(value)) {
    return false;
  }
  switch (kind) {
    case Kind::AtLeast:
      return value >= bound;
    case Kind::Above:
      return value > bound;
    case Kind::FractionAbove:
      return value > bound && value <= 1.0;
    case Kind::Any:
      break;
  }
  return true;
}

std::string Range::describe() const {
  switch (kind) {
    case Kind::AtLeast:
      return fmt::format("a number ≥ {}", bound);
    case Kind::Above:
      return fmt::format("a number > {}", bound);
    case Kind::FractionAbove:
      return fmt::format("a number > {} and ≤ 1", bound);
    case Kind::Any:
      break;
  }
  return "a finite number";
}

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
    return fmt::format("\"{}\"", shown(string->get()));
  }
  if (node.is_array()) {
    return "an array";
  }
  if (node.is_table()) {
    return "a table";
  }
  return "a date or time";
}

const toml::node* TableReader::lookup(std::string_view key) const {
  const toml::table* table = &root_;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key.find('.', start);
    const toml::node* node =
        table->get(key.substr(start, dot == std::string_view::npos ? dot : dot - start));
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

const toml::node* TableReader::find(std::string_view key) {
  known_.emplace(key);
  const toml::node* node = lookup(key);
  const auto former = former_names_.find(key);
  if (former == former_names_.end()) {
    return node;
  }
  known_.emplace(former->second);
  const toml::node* old = lookup(former->second);
  if (old == nullptr) {
    return node;
  }
  if (node != nullptr) {
    add_issue(former->second, old->source(),
              fmt::format("is the former name of '{}', which is set too; keep '{}'", key, key));
    return node;
  }
  written_as_.insert_or_assign(std::string(key), former->second);
  return old;
}

std::optional<double> TableReader::optional_number(std::string_view key, Range range) {
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

std::int64_t TableReader::integer(std::string_view key, std::int64_t fallback, std::int64_t minimum,
                                  std::int64_t maximum) {
  const toml::node* node = find(key);
  if (node == nullptr) {
    return fallback;
  }
  const auto* integer = node->as_integer();
  if (integer == nullptr || integer->get() < minimum || integer->get() > maximum) {
    const bool too_large = integer != nullptr && integer->get() > maximum;
    const std::string allowed = too_large ? fmt::format("an integer ≤ {}", maximum)
                                          : fmt::format("an integer ≥ {}", minimum);
    // 1e9 or 10.0 is a TOML float: say so, and how to write the integer it may mean
    std::string hint;
    if (const auto* floating = node->as_floating_point()) {
      const double value = floating->get();
      hint = std::trunc(value) == value && std::abs(value) < 9e15
                 ? fmt::format(" (written as a floating-point number; write {:.0f})", value)
                 : " (a floating-point number)";
    }
    add_issue(key, node->source(),
              fmt::format("got {}{}, expected {}", describe(*node), hint, allowed));
    return fallback;
  }
  return integer->get();
}

bool TableReader::boolean(std::string_view key, bool fallback) {
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

Vec3 TableReader::vector3(std::string_view key, const Vec3& fallback) {
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
      add_issue(
          key, (*array)[i].source(),
          fmt::format("element {} is {}, expected a finite number", i + 1, describe((*array)[i])));
      ok = false;
    } else {
      result[static_cast<Eigen::Index>(i)] = *value;
    }
  }
  return ok ? result : fallback;
}

std::string TableReader::required_string(std::string_view key) {
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

void TableReader::add_issue(std::string_view key, const toml::source_region& where,
                            std::string message, bool in_file) {
  failed_.emplace(key);
  const auto written = written_as_.find(key);
  ConfigIssue issue{source_name_, 0, 0,
                    written != written_as_.end() ? written->second : std::string(key),
                    std::move(message)};
  if (const auto origin = origins_.find(key); origin != origins_.end() && !in_file) {
    issue.file = origin->second;  // a value a command option set
  } else if (in_file) {
    // the file, without a position
  } else if (where.path && *where.path != source_name_) {
    issue.file = *where.path;  // an override's origin: "--set", "--particles", "sweep.toml:4:8"
  } else if (where.begin.line == 0) {
    issue.file = kCommandLineOverride;  // a table an override created
  } else {
    issue.line = static_cast<int>(where.begin.line);
    issue.column = static_cast<int>(where.begin.column);
  }
  issues_.push_back(std::move(issue));
}

// A prefix of a known key names a table, e.g. "contact.wall" of "contact.wall.mu".
bool TableReader::is_known_table(const std::string& key) const {
  const auto it = known_.lower_bound(key + ".");
  return it != known_.end() && it->starts_with(key + ".");
}

std::string TableReader::suggest(const std::string& key) const {
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

void TableReader::check_table(const toml::table& table, const std::string& prefix) {
  for (const auto& [name, node] : table) {
    const std::string key =
        prefix.empty() ? std::string(name.str()) : prefix + "." + std::string(name.str());
    if (known_.count(key) > 0) {
      continue;  // a value key; its type was checked when it was read
    }
    const toml::source_region& where =
        name.source().begin.line > 0 ? name.source() : origin_of(node);
    if (!is_known_table(key)) {
      add_issue(key, where, "unknown key" + suggest(key));
    } else if (const toml::table* sub = node.as_table()) {
      check_table(*sub, key);
    } else {
      add_issue(key, where, fmt::format("got {}, expected a table", describe(node)));
    }
  }
}

void apply_overrides(toml::table& root, const std::vector<SceneOverride>& overrides,
                     std::vector<ConfigIssue>& issues) {
  for (const SceneOverride& edit : overrides) {
    const std::string& text = edit.text;
    std::optional<Override> change = parse_override(edit, issues);
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
        issues.push_back({edit.origin, 0, 0, change->key,
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

void sort_issues(std::vector<ConfigIssue>& issues, std::string_view source_name) {
  const auto rank = [source_name](const ConfigIssue& issue) {
    const int group = issue.line > 0 ? 0 : (issue.file == source_name ? 1 : 2);
    return std::tuple(group, issue.line, issue.column);
  };
  std::stable_sort(
      issues.begin(), issues.end(),
      [&rank](const ConfigIssue& a, const ConfigIssue& b) { return rank(a) < rank(b); });
}

}  // namespace cdpowder::detail
