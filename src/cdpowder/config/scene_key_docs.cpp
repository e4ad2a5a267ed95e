// scene_key_docs.cpp — the key tables of docs/config.md from scene_keys.hpp
// (scene_key_docs.hpp). Every cell comes from the key's entry; the default from a
// default-constructed Scene, written as the effective TOML writes it.
#include "cdpowder/config/scene_key_docs.hpp"

#include "cdpowder/config/scene_keys.hpp"
#include "cdpowder/config/scene_writer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>
#include <type_traits>

namespace cdpowder {
namespace {

using detail::SceneKey;

/// One row of a key table, its cells before escaping.
struct KeyRow {
  std::string table;
  std::string name;
  std::string symbol;
  std::string unit;
  std::string default_value;
  std::string allowed;
  std::string meaning;
};

std::string range_text(const detail::Range& range) {
  switch (range.kind) {
    case detail::Range::Kind::AtLeast:
      return fmt::format("≥ {}", range.bound);
    case detail::Range::Kind::Above:
      return fmt::format("> {}", range.bound);
    case detail::Range::Kind::FractionAbove:
      return fmt::format("in ({}, 1]", range.bound);
    case detail::Range::Kind::Any:
      break;
  }
  return "finite";
}

/// "integer ≥ 1", "integer 1–64"; `largest` is what the field can hold.
std::string integer_text(const SceneKey& key, std::int64_t largest) {
  const std::int64_t maximum = std::min(key.maximum, largest);
  return maximum == largest ? fmt::format("integer ≥ {}", key.minimum)
                            : fmt::format("integer {}–{}", key.minimum, maximum);
}

/// Collects a row per key visited: the field's value is its default.
struct RowCollector {
  std::vector<KeyRow>& rows;

  void add(const SceneKey& key, std::string default_value, const std::string& allowed) const {
    if (!key.default_text.empty()) default_value = key.default_text;
    if (!key.default_table.empty())
      default_value = fmt::format("`{}.{}`", key.default_table, key.name);
    rows.push_back({std::string(key.table), std::string(key.name), std::string(key.symbol),
                    std::string(key.unit), std::move(default_value),
                    allowed + std::string(key.also_allowed), std::string(key.meaning)});
  }

  void operator()(const SceneKey& key, double value) const {
    add(key, detail::shortest_float_text(value), range_text(key.range));
  }

  void operator()(const SceneKey& key, const std::optional<double>& value) const {
    add(key, value ? detail::shortest_float_text(*value) : "unset", range_text(key.range));
  }

  void operator()(const SceneKey& key, int value) const {
    add(key, fmt::format("{}", value), integer_text(key, std::numeric_limits<int>::max()));
  }

  void operator()(const SceneKey& key, std::uint64_t value) const {
    add(key, fmt::format("{}", value), integer_text(key, detail::kNoMaximum));
  }

  void operator()(const SceneKey& key, bool value) const {
    add(key, value ? "true" : "false", "true, false");
  }

  void operator()(const SceneKey& key, const Vec3& value) const {
    add(key,
        fmt::format("[{}, {}, {}]", detail::shortest_float_text(value.x()),
                    detail::shortest_float_text(value.y()), detail::shortest_float_text(value.z())),
        "3 finite numbers");
  }

  void operator()(const SceneKey& key, const std::filesystem::path& /*value*/) const {
    add(key, "", "an existing file");
  }

  template <typename Enum>
  requires std::is_enum_v<Enum>

  void operator()(const SceneKey& key, Enum value) const {
    std::string default_value;
    std::string allowed;
    for (const auto& [name, enumerator] : detail::choices_of(value)) {
      if (enumerator == value) default_value = fmt::format("\"{}\"", name);
      allowed += fmt::format("{}\"{}\"", allowed.empty() ? "" : ", ", name);
    }
    add(key, default_value, allowed);
  }

  void operator()(const SceneKey& key, detail::SetsBoth<double> both) const {
    (*this)(key, both.first);
  }
};

/// Every key, with a default Scene's values: a deposit and a particles file both present.
std::vector<KeyRow> all_rows() {
  std::vector<KeyRow> rows;
  const RowCollector collect{rows};
  Scene s;
  DepositionConfig deposition;
  detail::visit_system_keys(s.system, collect);
  detail::visit_contact_keys(s.step.laws, collect);
  detail::visit_wall_keys(s.step.laws, collect);
  detail::visit_solver_keys(s.step.solver, collect);
  detail::visit_piston_keys(s.piston, collect);
  detail::visit_deposition_keys(deposition, collect);
  detail::visit_particles_keys(s.particles_file, collect);
  detail::visit_run_keys(s.run, collect);
  detail::visit_blocked_keys(s.run.blocked, collect);
  return rows;
}

/// A table cell: a `|` would end it.
std::string cell(std::string_view text) {
  std::string escaped;
  for (const char c : text) {
    if (c == '|') escaped += '\\';
    escaped += c;
  }
  return escaped;
}

}  // namespace

std::vector<std::string> scene_key_tables() {
  std::vector<std::string> tables;
  for (const KeyRow& row : all_rows()) {
    if (std::find(tables.begin(), tables.end(), row.table) == tables.end()) {
      tables.push_back(row.table);
    }
  }
  return tables;
}

std::string scene_key_table_markdown(std::string_view table) {
  std::string text;
  for (const KeyRow& row : all_rows()) {
    if (row.table != table) continue;
    if (text.empty()) {
      text =
          "| key | symbol | unit | default | allowed | meaning |\n"
          "| --- | --- | --- | --- | --- | --- |\n";
    }
    text +=
        fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", row.name, cell(row.symbol),
                    cell(row.unit), cell(row.default_value), cell(row.allowed), cell(row.meaning));
  }
  return text;
}

std::string generated_block_start(std::string_view table) {
  return fmt::format("<!-- generated: scene keys [{}] -->", table);
}

std::string with_generated_key_tables(std::string_view markdown) {
  std::string result;
  const std::vector<std::string> tables = scene_key_tables();
  std::vector<int> blocks(tables.size(), 0);
  std::size_t start = 0;
  int line_number = 0;
  std::optional<int> open_block;  // the line of the block being replaced
  while (start < markdown.size()) {
    const std::size_t end = std::min(markdown.find('\n', start), markdown.size());
    const std::string_view line = markdown.substr(start, end - start);
    ++line_number;
    start = end + 1;
    if (open_block) {
      if (line != kGeneratedBlockEnd) continue;
      open_block.reset();
    } else if (line.starts_with("<!-- generated: scene keys [")) {
      const auto table = std::find_if(tables.begin(), tables.end(), [&line](const std::string& t) {
        return line == generated_block_start(t);
      });
      if (table == tables.end()) {
        throw std::invalid_argument(
            fmt::format("line {}: '{}' names no table with keys", line_number, line));
      }
      ++blocks[static_cast<std::size_t>(table - tables.begin())];
      result += fmt::format("{}\n\n{}\n", line, scene_key_table_markdown(*table));
      open_block = line_number;
      continue;
    }
    result += line;
    if (end < markdown.size()) result += '\n';
  }
  if (open_block) {
    throw std::invalid_argument(fmt::format("line {}: the generated block is not closed by '{}'",
                                            *open_block, kGeneratedBlockEnd));
  }
  for (std::size_t i = 0; i < tables.size(); ++i) {
    if (blocks[i] != 1) {
      throw std::invalid_argument(fmt::format("{} generated blocks of [{}] (expected one: '{}')",
                                              blocks[i], tables[i],
                                              generated_block_start(tables[i])));
    }
  }
  return result;
}

}  // namespace cdpowder
