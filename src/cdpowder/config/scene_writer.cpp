// scene_writer.cpp — Scene → TOML text (scene_writer.hpp): every key of scene_keys.hpp with
// its field's value. toml++'s formatter writes the table (its tables keep their keys sorted,
// so the order of the lists does not matter); a post-pass then rewrites its 17-digit doubles in
// fmt's shortest exact form, so the effective config shows 0.3 where the user wrote 0.3 and still
// reads back bit for bit.
#include "cdpowder/config/scene_writer.hpp"

#include "cdpowder/config/scene_keys.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <utility>

namespace cdpowder::detail {
namespace {

/// The TOML spelling of `value`.
template <typename Enum, std::size_t N>
std::string name_of(Enum value, const EnumNames<Enum, N>& names) {
  for (const auto& [name, enumerator] : names) {
    if (enumerator == value) {
      return std::string(name);
    }
  }
  return {};
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
          token = shortest_float_text(value);
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

/// The table at a dotted path of `root` ("contact.wall"), created when missing.
toml::table& table_at(toml::table& root, std::string_view path) {
  toml::table* table = &root;
  std::size_t start = 0;
  while (start <= path.size()) {
    const std::size_t dot = std::min(path.find('.', start), path.size());
    const std::string_view name = path.substr(start, dot - start);
    toml::node* node = table->get(name);
    if (node == nullptr) node = &table->insert(name, toml::table{}).first->second;
    table = node->as_table();
    start = dot + 1;
  }
  return *table;
}

/// Writes one key of the table (scene_keys.hpp) with its field's value into `root`.
struct KeyWriter {
  toml::table& root;

  void put(const SceneKey& key, auto&& value) const {
    table_at(root, key.table).insert_or_assign(key.name, std::forward<decltype(value)>(value));
  }

  void operator()(const SceneKey& key, const double& value) const { put(key, value); }

  void operator()(const SceneKey& key, const int& value) const { put(key, value); }

  void operator()(const SceneKey& key, const bool& value) const { put(key, value); }

  void operator()(const SceneKey& key, const std::uint64_t& value) const {
    put(key, static_cast<std::int64_t>(value));
  }

  void operator()(const SceneKey& key, const std::optional<double>& value) const {
    if (value.has_value()) put(key, *value);  // unset keys stay absent: TOML has no null
  }

  void operator()(const SceneKey& key, const Vec3& value) const {
    put(key, toml::array{value.x(), value.y(), value.z()});
  }

  void operator()(const SceneKey& key, const std::filesystem::path& value) const {
    put(key, value.string());
  }

  template <typename Enum>
  requires std::is_enum_v<Enum>

  void operator()(const SceneKey& key, const Enum& value) const {
    put(key, name_of(value, choices_of(value)));
  }

  /// deposition.radius: the effective scene has the two it set.
  void operator()(const SceneKey& /*key*/, SetsBoth<const double> /*both*/) const {}
};

}  // namespace

std::string shortest_float_text(double value) {
  std::string text = fmt::format("{}", value);
  if (text.find_first_of(".eEn") == std::string::npos) {
    text += ".0";  // stays a TOML float
  }
  return text;
}

std::string write_effective_toml(const Scene& s) {
  toml::table root;
  visit_scene_keys(s, KeyWriter{root});
  // Basic single-line strings only, so shorten_floats can tell strings from numbers.
  const toml::format_flags flags =
      toml::toml_formatter::default_flags &
      ~(toml::format_flags::allow_literal_strings | toml::format_flags::allow_multi_line_strings);
  std::ostringstream out;
  out << toml::toml_formatter(root, flags);
  return shorten_floats(out.str());
}

}  // namespace cdpowder::detail
