// particles_csv.cpp — parses the particles CSV (particles_csv.hpp): header by column name,
// one sphere per line, every field checked; issues are collected over the whole file and the
// spheres are added only when there is none. Also the cell-width check of a scene.
#include "cdpowder/config/particles_csv.hpp"

#include "cdpowder/config/scene_keys.hpp"
#include "cdpowder/model/world_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace cdpowder {
namespace {

// Column order of a parsed row; kColumnNames[i] names column i. `id` (written by the
// outputs, so that particles.csv reads back as input) is accepted and ignored: a sphere's
// index is its row.
enum Column : std::size_t { X, Y, Z, R, Vx, Vy, Vz, Wx, Wy, Wz, Fx, Fy, Fz, Tx, Ty, Tz, Fixed, Id };

constexpr std::array<std::string_view, 18> kColumnNames = {"x",  "y",  "z",  "r",  "vx",    "vy",
                                                           "vz", "wx", "wy", "wz", "fx",    "fy",
                                                           "fz", "tx", "ty", "tz", "fixed", "id"};
constexpr std::size_t kRequiredColumns = 4;  // x, y, z, r
// A file with a systematic mistake would repeat it on every line; the first ones suffice.
constexpr std::size_t kMaxIssues = 50;

using Row = std::array<double, kColumnNames.size()>;

std::string_view trim(std::string_view s) {
  const std::size_t first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) {
    return {};
  }
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(
        trim(line.substr(start, comma == std::string_view::npos ? comma : comma - start)));
    if (comma == std::string_view::npos) {
      return fields;
    }
    start = comma + 1;
  }
}

std::optional<double> parse_number(std::string_view text) {
  if (!text.empty() && text.front() == '+') {
    text.remove_prefix(1);  // from_chars does not take a leading '+'
  }
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size()) {
    return std::nullopt;
  }
  return value;
}

/// 0 or 1, as cdpowder writes it; true/false, and pandas' True/False (DataFrame.to_csv of a
/// bool column, measured: "False" was refused before).
std::optional<double> parse_flag(std::string_view text) {
  if (text == "1" || text == "true" || text == "True") {
    return 1.0;
  }
  if (text == "0" || text == "false" || text == "False") {
    return 0.0;
  }
  return std::nullopt;
}

/// Reads the file line by line; `issues` gets every mistake, `rows` the good spheres.
class CsvParser {
 public:
  CsvParser(std::string file, std::vector<ConfigIssue>& issues)
      : file_(std::move(file)), issues_(issues) {}

  /// Maps header fields to columns; false if the header is unusable.
  bool read_header(std::string_view line, int line_number) {
    std::vector<std::string> known(kColumnNames.begin(), kColumnNames.end());
    std::size_t position = 0;
    for (const std::string_view field : split_fields(line)) {
      ++position;
      const auto column = static_cast<std::size_t>(
          std::find(kColumnNames.begin(), kColumnNames.end(), field) - kColumnNames.begin());
      if (field.empty()) {  // "x,y,z,r," once read as an unknown column "did you mean 'x'?"
        add(line_number, "",
            fmt::format("column {} of the header has no name ({})", position,
                        position == 1 ? "pandas' index column? write the file with "
                                        "DataFrame.to_csv(path, index=False)"
                                      : "a trailing or doubled comma?"));
      } else if (column == kColumnNames.size()) {
        add(line_number, shown(field),
            "unknown column" + did_you_mean(field, known) +
                "; known: x, y, z, r, vx..vz, wx..wz, fx..fz, "
                "tx..tz, fixed, id");
      } else if (std::find(order_.begin(), order_.end(), column) != order_.end()) {
        add(line_number, std::string(field), "column appears twice");
      }
      order_.push_back(column);
    }
    for (std::size_t c = 0; c < kRequiredColumns; ++c) {
      if (std::find(order_.begin(), order_.end(), c) == order_.end()) {
        add(line_number, std::string(kColumnNames[c]), "missing required column (x, y, z, r)");
      }
    }
    return issues_.empty();
  }

  void read_row(std::string_view line, int line_number) {
    const std::vector<std::string_view> fields = split_fields(line);
    if (fields.size() != order_.size()) {
      add(line_number, "",
          fmt::format("got {} fields, expected {} as in the header", fields.size(), order_.size()));
      return;
    }
    Row row{};
    bool ok = true;
    for (std::size_t i = 0; i < fields.size(); ++i) {
      const std::size_t column = order_[i];
      const std::string name(kColumnNames[column]);
      const std::optional<double> value =
          column == Fixed ? parse_flag(fields[i]) : parse_number(fields[i]);
      if (!value) {
        add(line_number, name,
            fmt::format("cannot read '{}' as {}", shown(fields[i]),
                        column == Fixed ? "0, 1, true or false (True, False)" : "a number"));
        ok = false;
      } else if (!std::isfinite(*value)) {
        add(line_number, name, fmt::format("got {}, expected a finite number", fields[i]));
        ok = false;
      } else if (column == R && *value <= 0.0) {
        add(line_number, name, fmt::format("got {}, expected a radius > 0", fields[i]));
        ok = false;
      } else if ((column == X || column == Y || column == Z || column == R) &&
                 std::abs(*value) > kMaxCoordinate) {
        add(line_number, name,
            fmt::format("got {}, expected a number within ±{:g} R (doubles are too sparse "
                        "beyond for a contact's geometry)",
                        fields[i], kMaxCoordinate));
        ok = false;
      } else {
        row[column] = *value;
      }
    }
    if (ok) {
      rows_.push_back(row);
    }
  }

  void add(int line_number, std::string column, std::string message) {
    if (issues_.size() < kMaxIssues) {
      issues_.push_back({file_, line_number, 0, std::move(column), std::move(message)});
    } else if (issues_.size() == kMaxIssues) {
      issues_.push_back({file_, 0, 0, "", "more issues not shown"});
    }
  }

  [[nodiscard]] const std::vector<Row>& rows() const { return rows_; }

 private:
  std::string file_;
  std::vector<ConfigIssue>& issues_;
  std::vector<std::size_t> order_;  // column of each header field
  std::vector<Row> rows_;
};

}  // namespace

namespace {

/// The reader proper, on a stream; `name` names it in messages.
void read_particles(std::istream& stream, const std::string& name, double density, Bodies& bodies) {
  std::vector<ConfigIssue> issues;
  CsvParser parser(name, issues);
  bool have_header = false;
  bool header_ok = false;
  int line_number = 0;
  for (std::string line; std::getline(stream, line);) {
    ++line_number;
    std::string_view content = trim(line);
    // a UTF-8 byte order mark (spreadsheets write one) is not part of the first column's
    // name (measured: "id" became an unknown column)
    constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";
    if (line_number == 1 && content.starts_with(kByteOrderMark)) {
      content = trim(content.substr(kByteOrderMark.size()));
    }
    if (content.empty() || content.front() == '#') {
      continue;  // blank, or a provenance header of our own outputs
    }
    if (!have_header) {
      have_header = true;
      header_ok = parser.read_header(content, line_number);
    } else if (header_ok) {
      parser.read_row(content, line_number);
    }
  }
  if (!have_header) {
    issues.push_back({name, 0, 0, "", "no header line; expected columns x, y, z, r"});
  } else if (header_ok && issues.empty() && parser.rows().empty()) {
    issues.push_back({name, 0, 0, "", "no particles: the file has a header only"});
  }
  if (!issues.empty()) {
    throw ConfigError(std::move(issues));
  }
  for (const Row& row : parser.rows()) {
    const std::size_t i = static_cast<std::size_t>(
        bodies.add_sphere({row[X], row[Y], row[Z]}, row[R], density, row[Fixed] != 0.0));
    bodies.velocity[i] = Vec3(row[Vx], row[Vy], row[Vz]);
    bodies.angular_velocity[i] = Vec3(row[Wx], row[Wy], row[Wz]);
    bodies.external_force[i] = Vec3(row[Fx], row[Fy], row[Fz]);
    bodies.external_torque[i] = Vec3(row[Tx], row[Ty], row[Tz]);
  }
}

}  // namespace

void read_particles_csv(const std::filesystem::path& file, double density, Bodies& bodies) {
  std::ifstream stream(file);
  if (!stream) {
    throw ConfigError({{file.string(), 0, 0, "",
                        std::string("cannot open the particles file: ") + std::strerror(errno)}});
  }
  read_particles(stream, file.string(), density, bodies);
}

void read_particles_csv_text(std::string_view text, std::string_view source_name, double density,
                             Bodies& bodies) {
  std::istringstream stream{std::string(text)};
  read_particles(stream, std::string(source_name), density, bodies);
}

void check_box_fits(const Scene& scene, const Bodies& bodies) {
  const ContactLaws& laws = scene.step.laws;
  const double range = std::max(laws.spheres.cohesion_range, laws.walls.cohesion_range);
  const double r_max = bodies.max_radius();
  const double minimum = 2.0 * (2.0 * r_max + range + scene.step.solver.skin);
  std::vector<ConfigIssue> issues;
  const std::array<std::pair<std::string, double>, 2> sides = {
      {{detail::key_name(scene, scene.system.lx), scene.system.lx},
       {detail::key_name(scene, scene.system.ly), scene.system.ly}}};
  // R_max comes from the particles file, or from the deposit ([deposition] radii)
  const std::string origin = scene.particles_file.empty()
                                 ? std::string("the deposit")
                                 : fmt::format("'{}'", scene.particles_file.string());
  for (const auto& [key, length] : sides) {
    if (length < minimum) {
      issues.push_back(
          {scene.source.string(), 0, 0, key,
           fmt::format("got {}, expected ≥ 2 (2 R_max + max({}, {}) + {}) = {} with R_max = {} "
                       "of {}, so that the periodic minimum image is unique",
                       length, detail::key_name(scene, laws.spheres.cohesion_range),
                       detail::key_name(scene, laws.walls.cohesion_range),
                       detail::key_name(scene, scene.step.solver.skin), minimum, r_max, origin)});
    }
  }
  if (!issues.empty()) {
    throw ConfigError(std::move(issues));
  }
}

}  // namespace cdpowder
