// timeseries.cpp — rows of the per-step diagnostics.
#include "cdpowder/io/timeseries.hpp"

#include "cdpowder/analysis/porosity.hpp"

#include <fmt/format.h>

#include <charconv>
#include <fstream>
#include <stdexcept>
#include <string_view>

namespace cdpowder {

namespace {

constexpr std::string_view kColumns =
    "step,time,piston_height,piston_velocity,porosity,kinetic_energy,passes,"
    "converged,residual,error_estimate,contacts,closed_contacts,mean_overlap,"
    "max_overlap,piston_imbalance,max_net_force,max_cohesive_opening_speed,dt\n";

/// The same columns as written before the NLGS pass was called a pass (column 7 was
/// `sweeps`, CHANGELOG.md): a run of that program continues its file under this header.
constexpr std::string_view kFormerColumns =
    "step,time,piston_height,piston_velocity,porosity,kinetic_energy,sweeps,"
    "converged,residual,error_estimate,contacts,closed_contacts,mean_overlap,"
    "max_overlap,piston_imbalance,max_net_force,max_cohesive_opening_speed,dt\n";

/// The step and time of a row "step,time,…", or nothing when `line` is not one.
std::optional<std::pair<std::int64_t, double>> row_step_and_time(std::string_view line) {
  std::int64_t step = 0;
  const char* end = line.data() + line.size();
  // NOLINTNEXTLINE(bugprone-suspicious-stringview-data-usage): from_chars stops at `end`
  auto [after_step, step_error] = std::from_chars(line.data(), end, step);
  if (step_error != std::errc() || after_step == end || *after_step != ',') return std::nullopt;
  double time = 0.0;
  auto [after_time, time_error] = std::from_chars(after_step + 1, end, time);
  if (time_error != std::errc() || after_time == end || *after_time != ',') return std::nullopt;
  return std::make_pair(step, time);
}

}  // namespace

TimeseriesCut cut_timeseries(const std::filesystem::path& file, std::int64_t step) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("cannot read {}", file.string()));
  TimeseriesCut cut;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    if (in.eof()) break;  // no newline: cut short by a killed process
    ++number;
    if (line.starts_with('#') || line + '\n' == kColumns || line + '\n' == kFormerColumns) {
      if (cut.rows > 0) break;  // a header after rows: not one time series
      cut.has_header = cut.has_header || !line.starts_with('#');
    } else {
      const auto row = row_step_and_time(line);
      if (!row || !cut.has_header) {
        cut.bad_line = number;
        cut.bad_text = line;
        break;
      }
      if (row->first >= step) break;
      ++cut.rows;
      cut.last_row_time = row->second;
    }
    cut.bytes += line.size() + 1;
  }
  return cut;
}

TimeseriesWriter::TimeseriesWriter(const std::filesystem::path& path, const std::string& header,
                                   Cadence cadence)
    : file_(path), cadence_(cadence) {
  file_.write(header);
  file_.write(kColumns);
}

TimeseriesWriter::TimeseriesWriter(const std::filesystem::path& path,
                                   const std::filesystem::path& existing, const TimeseriesCut& cut,
                                   Cadence cadence)
    : file_(path, existing, cut.bytes), cadence_(cadence) {
  if (cut.last_row_time) cadence_.resume_after(*cut.last_row_time);
}

void TimeseriesWriter::record(const World& world, const StepReport& r, bool force) {
  if (world.step == last_step_) return;
  if (!cadence_.due(world) && !force) return;
  last_step_ = world.step;
  const StepDiagnostics& d = r.diagnostics;
  file_.write(fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", world.step,
                          world.time, world.walls.piston.height, world.walls.piston.velocity,
                          porosity(world), d.kinetic_energy, r.solver.passes,
                          r.solver.converged ? 1 : 0, r.solver.residual, r.solver.error_estimate,
                          d.contacts, d.closed_contacts, d.mean_overlap, d.max_overlap,
                          d.piston_imbalance, d.max_net_force, d.max_cohesive_opening_speed, r.dt));
}

}  // namespace cdpowder
