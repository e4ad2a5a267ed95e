// scene_writer.cpp — Scene → TOML text (scene_writer.hpp). toml++'s formatter writes the
// table; a post-pass then rewrites its 17-digit doubles in fmt's shortest exact form, so the
// effective config shows 0.3 where the user wrote 0.3 and still reads back bit for bit.
#include "cdpowder/config/scene_writer.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <array>
#include <charconv>
#include <cstdint>
#include <optional>
#include <sstream>
#include <system_error>
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

toml::table contact_table(const ContactLaws& laws) {
  toml::table contact = law_table(laws.spheres);
  contact.insert_or_assign("cohesion_rule", name_of(laws.cohesion_rule, kCohesionRuleNames));
  toml::table wall = law_table(laws.walls);
  wall.insert_or_assign("r_eff_factor", laws.wall_r_eff_factor);
  contact.insert_or_assign("wall", std::move(wall));
  return contact;
}

toml::table piston_table(const PistonConfig& p) {
  toml::table piston{{"enabled", p.enabled},
                     {"mass", p.mass},
                     {"start_gap", p.start_gap},
                     {"velocity", p.velocity}};
  // Unset optional keys stay absent: TOML has no null.
  const std::array<std::pair<const char*, const std::optional<double>*>, 3> optionals = {
      {{"pressure", &p.pressure}, {"force", &p.force}, {"height", &p.height}}};
  for (const auto& [key, value] : optionals) {
    if (value->has_value()) piston.insert_or_assign(key, **value);
  }
  return piston;
}

toml::table solver_table(const SolverSettings& solver) {
  return toml::table{{"dt", solver.dt},
                     {"adaptive_dt", solver.time_step.adaptive},
                     {"dt_min", solver.time_step.dt_min},
                     {"dt_max", solver.time_step.dt_max},
                     {"opening_per_step", solver.time_step.opening_per_step},
                     {"max_opening_per_step", solver.time_step.max_opening_per_step},
                     {"displacement_per_step", solver.time_step.displacement_per_step},
                     {"dt_growth", solver.time_step.growth},
                     {"tolerance", solver.tolerance},
                     {"max_error_amplification", solver.max_error_amplification},
                     {"kinematic_tolerance", solver.kinematic_tolerance},
                     {"min_sweeps", solver.min_sweeps},
                     {"max_sweeps", solver.max_sweeps},
                     {"stopping_rule", name_of(solver.stopping_rule, kStoppingRuleNames)},
                     {"visit_order", name_of(solver.visit_order, kVisitOrderNames)},
                     {"kernel", name_of(solver.kernel, kSweepKernelNames)},
                     {"threads", solver.threads},
                     {"acceleration_depth", solver.acceleration_depth},
                     {"acceleration_interval", solver.acceleration_interval},
                     {"warm_start", solver.warm_start},
                     {"skin", solver.skin},
                     {"verlet_margin", solver.verlet_margin},
                     {"seed", static_cast<std::int64_t>(solver.seed)}};
}

toml::table run_table(const RunConfig& run) {
  const BlockedCriteria& blocked = run.blocked;
  return toml::table{{"duration", run.duration},
                     {"until_blocked", run.until_blocked},
                     {"max_duration", run.max_duration},
                     {"timeseries_every", run.timeseries_every},
                     {"snapshot_every", run.snapshot_every},
                     {"timeseries_interval", run.timeseries_interval},
                     {"snapshot_interval", run.snapshot_interval},
                     {"max_overlap", run.max_overlap},
                     {"vtk_format", name_of(run.vtk_format, kVtkFormatNames)},
                     {"blocked", toml::table{{"window", blocked.window},
                                             {"piston_speed", blocked.piston_speed},
                                             {"sphere_speed", blocked.sphere_speed},
                                             {"force_balance", blocked.force_balance},
                                             {"height_change", blocked.height_change},
                                             {"final_tolerance", blocked.final_tolerance},
                                             {"final_max_sweeps", blocked.final_max_sweeps}}}};
}

/// [deposition], or [particles] file = … when the spheres come from a file.
std::pair<const char*, toml::table> spheres_table(const Scene& s) {
  if (!s.deposition) return {"particles", toml::table{{"file", s.particles_file.string()}}};
  const DepositionConfig& d = *s.deposition;
  return {"deposition", toml::table{{"spheres", d.spheres},
                                    {"radius_min", d.radius_min},
                                    {"radius_max", d.radius_max},
                                    {"capture_radius", d.capture_radius},
                                    {"capture_rule", name_of(d.capture_rule, kCaptureRuleNames)},
                                    {"seed", static_cast<std::int64_t>(d.seed)}}};
}

}  // namespace

std::string write_effective_toml(const Scene& s) {
  const Vec3& g = s.system.gravity;
  toml::table root{{"system", toml::table{{"lx", s.system.lx},
                                          {"ly", s.system.ly},
                                          {"gravity", toml::array{g.x(), g.y(), g.z()}},
                                          {"density", s.system.density},
                                          {"bottom_wall", s.system.bottom_wall}}},
                   {"contact", contact_table(s.step.laws)},
                   {"solver", solver_table(s.step.solver)},
                   {"piston", piston_table(s.piston)},
                   {"run", run_table(s.run)}};
  // spheres the caller made (SceneReadOptions::spheres_from_caller) are in no table
  if (s.deposition || !s.particles_file.empty()) {
    auto [name, spheres] = spheres_table(s);
    root.insert(name, std::move(spheres));
  }
  // Basic single-line strings only, so shorten_floats can tell strings from numbers.
  const toml::format_flags flags =
      toml::toml_formatter::default_flags &
      ~(toml::format_flags::allow_literal_strings | toml::format_flags::allow_multi_line_strings);
  std::ostringstream out;
  out << toml::toml_formatter(root, flags);
  return shorten_floats(out.str());
}

}  // namespace cdpowder::detail
