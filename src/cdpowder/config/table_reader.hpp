// table_reader.hpp — the generic half of the scene reader: typed values (numbers, integers,
// booleans, strings, choices, 3-vectors) at dotted keys of a parsed TOML table, each bad
// value recorded as a ConfigIssue at file:line:column, and every key nobody asked for
// reported unknown with a "did you mean" (style guide 3.7). Also the `--set` overrides,
// applied to the parsed table so their values pass the same checks. Knows no scene keys.
#pragma once

#include "cdpowder/config/config_error.hpp"
#include "cdpowder/config/scene_override.hpp"
#include "cdpowder/core/vec3.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace cdpowder::detail {

/// No upper bound for TableReader::integer.
inline constexpr std::int64_t kNoMaximum = std::numeric_limits<std::int64_t>::max();

/// The allowed values of a number: any finite one, ≥ bound, > bound, or a fraction
/// (> bound and ≤ 1).
struct Range {
  enum class Kind { Any, AtLeast, Above, FractionAbove };
  Kind kind = Kind::Any;
  double bound = 0.0;

  /// False for inf and nan (TOML allows both), whatever the kind.
  [[nodiscard]] bool contains(double value) const;

  /// "a number ≥ 0" and the like, for "expected …".
  [[nodiscard]] std::string describe() const;
};

inline constexpr Range kAnyNumber{};
inline constexpr Range kNonNegative{Range::Kind::AtLeast, 0.0};
inline constexpr Range kPositive{Range::Kind::Above, 0.0};

/// The TOML spelling of each enumerator of a string-valued key.
template <typename Enum, std::size_t N>
using EnumNames = std::array<std::pair<std::string_view, Enum>, N>;

/// The value as the user wrote it, for "got …" (fmt prints the shortest exact form).
std::string describe(const toml::node& node);

/// Reads typed values at dotted keys of a parsed table, collecting one issue per bad value
/// and remembering which keys were asked for, so that every other key is reported unknown.
/// A bad or missing value yields the fallback, so one read reports every mistake.
class TableReader {
 public:
  /// Reads `root`; issues name `source_name` and are appended to `issues`. Both `root` and
  /// `issues` must outlive the reader.
  TableReader(const toml::table& root, std::string source_name, std::vector<ConfigIssue>& issues)
      : root_(root), source_name_(std::move(source_name)), issues_(issues) {}

  /// The node at a dotted key, or nullptr; marks the key as known. A key absent under its
  /// name is looked up under its former name (allow_former_name), and the issues of its
  /// value then name the key as written.
  const toml::node* find(std::string_view key);

  /// Accepts `former` ("solver.max_sweeps") as the old spelling of `key`
  /// ("solver.max_passes"), for scene files written before the rename. Setting both is an
  /// issue.
  void allow_former_name(std::string key, std::string former) {
    former_names_.insert_or_assign(std::move(key), std::move(former));
  }

  /// Whether a dotted key is present. Does not mark it known, so the keys inside a table
  /// asked about this way are still checked.
  [[nodiscard]] bool has(std::string_view key) const {
    return root_.at_path(key).node() != nullptr;
  }

  /// Reports the issues of `key` under `origin` ("--particles"): a value a command option put
  /// into the table, which has no source of its own.
  void set_origin(std::string key, std::string origin) {
    origins_.insert_or_assign(std::move(key), std::move(origin));
  }

  /// Whether an issue has been recorded for `key`.
  [[nodiscard]] bool failed(std::string_view key) const { return failed_.count(key) > 0; }

  /// A number (TOML integers accepted) in `range`; nullopt when absent or bad.
  std::optional<double> optional_number(std::string_view key, Range range);

  /// A number in `range`, or `fallback` when absent or bad.
  double number(std::string_view key, double fallback, Range range) {
    return optional_number(key, range).value_or(fallback);
  }

  /// An integer in [minimum, maximum], or `fallback` when absent or bad.
  std::int64_t integer(std::string_view key, std::int64_t fallback, std::int64_t minimum,
                       std::int64_t maximum = kNoMaximum);

  /// true or false, or `fallback` when absent or bad.
  bool boolean(std::string_view key, bool fallback);

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

  /// An array of exactly three finite numbers, or `fallback` when absent or bad.
  Vec3 vector3(std::string_view key, const Vec3& fallback);

  /// A non-empty string that must be present; "" (and an issue) otherwise.
  std::string required_string(std::string_view key);

  /// Adds an issue at `where`. Nodes that came from an override are reported at its origin
  /// ("--set", "--particles", "sweep.toml:4:8"), tables the overrides created as "--set";
  /// `in_file` forces the file name without a position.
  void add_issue(std::string_view key, const toml::source_region& where, std::string message,
                 bool in_file = false);

  /// Reports every key that no read asked for, and known tables that are not tables.
  /// Call after all reads.
  void check_unknown_keys() { check_table(root_, ""); }

 private:
  [[nodiscard]] const toml::node* lookup(std::string_view key) const;
  [[nodiscard]] bool is_known_table(const std::string& key) const;
  [[nodiscard]] std::string suggest(const std::string& key) const;
  void check_table(const toml::table& table, const std::string& prefix);

  const toml::table& root_;
  std::string source_name_;
  std::vector<ConfigIssue>& issues_;
  std::set<std::string, std::less<>> known_;
  std::set<std::string, std::less<>> failed_;
  std::map<std::string, std::string, std::less<>> origins_;
  std::map<std::string, std::string, std::less<>> former_names_;  ///< key → its former name
  std::map<std::string, std::string, std::less<>> written_as_;    ///< key → the name it had
};

/// The key an override sets, as apply_overrides reads it: the text before its first '=',
/// trimmed ("" when there is no '=').
std::string_view override_key(const SceneOverride& change);

/// Applies the overrides ("section.key=value", in order) to `root`, creating the tables on
/// their keys' paths. Each value is parsed as TOML with the override's origin as source; a
/// malformed override becomes an issue in `issues` and is skipped.
void apply_overrides(toml::table& root, const std::vector<SceneOverride>& overrides,
                     std::vector<ConfigIssue>& issues);

/// File order for a reader fixing the file top to bottom: positioned issues by line and
/// column, then those of the whole file (`source_name`), then those of the overrides
/// (malformed ones first).
void sort_issues(std::vector<ConfigIssue>& issues, std::string_view source_name);

}  // namespace cdpowder::detail
