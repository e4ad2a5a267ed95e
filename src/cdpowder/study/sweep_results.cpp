// sweep_results.cpp — the sweep's two tables from its runs' summaries.
#include "cdpowder/study/sweep_results.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace cdpowder {

namespace {

/// A quoted CSV field when it holds a comma (point names do).
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

std::string number(double v) {
  return std::isfinite(v) ? fmt::format("{:.10g}", v) : std::string();
}

/// The value a point gives its parameter `key`, unquoted; "" when the point keeps the base.
std::string parameter_value(const SweepPoint& point, const std::string& key) {
  for (const SweepSetting& s : point.settings) {
    if (s.key != key) continue;
    std::string v = s.value;
    if (v.size() >= 2 && v.front() == '"') v = v.substr(1, v.size() - 2);
    return v;
  }
  return "";
}

/// A column of results.csv: its name and the summary field it shows (docs/sweeps.md).
/// "point,KEY1,KEY2…": the first cells of both tables' header rows.
std::string point_header(const SweepPlan& plan) {
  // (appended piece by piece: GCC 12 warns falsely on "," + std::string at -O3, -Wrestrict)
  std::string out = "point";
  for (const std::string& key : plan.parameter_keys) {
    out += ',';
    out += csv_field(key);
  }
  return out;
}

/// The point's name and the value it gives each parameter key ("" for the base's).
std::string point_cells(const SweepPlan& plan, const SweepPoint& point) {
  std::string out = csv_field(point.name);
  for (const std::string& key : plan.parameter_keys) {
    out += ',';
    out += csv_field(parameter_value(point, key));
  }
  return out;
}

struct Column {
  const char* name;
  double (*get)(const RunSummary&);
};

const std::vector<Column>& run_columns() {
  using S = RunSummary;
  static const std::vector<Column> columns{
      {"porosity", [](const S& s) { return s.porosity; }},
      {"initial_porosity", [](const S& s) { return s.initial_porosity; }},
      {"sigma_zz_over_p", [](const S& s) { return s.stress.sigma_zz_over_pressure; }},
      {"sigma_zz_compressive_over_p",
       [](const S& s) { return s.stress.sigma_zz_compressive_over_pressure; }},
      {"sigma_zz_tensile_over_p",
       [](const S& s) { return s.stress.sigma_zz_tensile_over_pressure; }},
      {"compressive_contacts",
       [](const S& s) { return static_cast<double>(s.stress.compressive_contacts); }},
      {"tensile_contacts",
       [](const S& s) { return static_cast<double>(s.stress.tensile_contacts); }},
      {"coordination_number", [](const S& s) { return s.contacts.coordination_number; }},
      {"steps", [](const S& s) { return static_cast<double>(s.run.steps); }},
      {"total_passes", [](const S& s) { return static_cast<double>(s.run.total_passes); }},
      {"capped_steps", [](const S& s) { return static_cast<double>(s.accuracy.capped_steps); }},
      {"mean_overlap", [](const S& s) { return s.accuracy.mean_overlap; }},
      {"max_overlap", [](const S& s) { return s.accuracy.max_overlap; }},
      {"piston_imbalance", [](const S& s) { return s.piston.force_imbalance; }},
      {"max_net_force", [](const S& s) { return s.accuracy.max_net_force; }},
      {"wall_seconds", [](const S& s) { return s.run.wall_seconds; }},
  };
  return columns;
}

/// The quantities aggregated per point: a subset of run_columns(), by name.
const std::vector<Column>& aggregated() {
  static const std::vector<Column> columns = [] {
    std::vector<Column> chosen;
    for (const std::string_view name :
         {"porosity", "sigma_zz_over_p", "sigma_zz_compressive_over_p", "sigma_zz_tensile_over_p",
          "compressive_contacts", "tensile_contacts", "coordination_number", "wall_seconds"}) {
      const auto& all = run_columns();
      const auto found =
          std::find_if(all.begin(), all.end(), [&](const Column& c) { return name == c.name; });
      if (found == all.end()) throw std::logic_error(fmt::format("no run column {}", name));
      chosen.push_back(*found);
    }
    return chosen;
  }();
  return columns;
}

}  // namespace

bool is_reusable(const std::optional<RunSummary>& summary, const std::string& expected_scene_toml) {
  return summary.has_value() && !summary->run.interrupted && !summary->run.failed &&
         summary->scene_toml == expected_scene_toml;
}

std::string results_csv(const SweepPlan& plan,
                        const std::vector<std::optional<RunSummary>>& summaries,
                        const std::string& header) {
  std::string out = header + point_header(plan) + ",seed";
  for (const Column& c : run_columns()) out += fmt::format(",{}", c.name);
  out += ",blocked,commit,folder\n";
  for (std::size_t i = 0; i < plan.runs.size() && i < summaries.size(); ++i) {
    const std::optional<RunSummary>& summary = summaries[i];
    if (!summary) continue;
    const SweepRun& run = plan.runs[i];
    const SweepPoint& point = plan.points[run.point];
    const RunSummary& r = *summary;
    out += point_cells(plan, point);
    out += fmt::format(",{}", run.seed);
    for (const Column& c : run_columns()) {
      out += ',';
      out += number(c.get(r));
    }
    out += fmt::format(",{},{},{}\n", r.run.blocked ? 1 : 0, csv_field(r.program.commit),
                       csv_field(run.folder.generic_string()));
  }
  return out;
}

std::string points_csv(const SweepPlan& plan,
                       const std::vector<std::optional<RunSummary>>& summaries,
                       const std::string& header) {
  std::string out = header + point_header(plan) + ",runs,n";
  for (const Column& c : aggregated()) out += fmt::format(",{0}_mean,{0}_sem", c.name);
  out += '\n';
  for (std::size_t p = 0; p < plan.points.size(); ++p) {
    std::vector<const RunSummary*> blocked;
    std::size_t finished = 0;
    for (std::size_t i = 0; i < plan.runs.size() && i < summaries.size(); ++i) {
      const std::optional<RunSummary>& summary = summaries[i];
      if (plan.runs[i].point != p || !summary) continue;
      ++finished;
      if (summary->run.blocked) blocked.push_back(&*summary);
    }
    out += point_cells(plan, plan.points[p]);
    out += fmt::format(",{},{}", finished, blocked.size());
    for (const Column& column : aggregated()) {
      const auto n = static_cast<double>(blocked.size());
      double sum = 0.0;
      for (const RunSummary* r : blocked) sum += column.get(*r);
      const double mean = blocked.empty() ? NAN : sum / n;
      double squares = 0.0;
      for (const RunSummary* r : blocked) squares += std::pow(column.get(*r) - mean, 2);
      const double sem = blocked.size() < 2 ? NAN : std::sqrt(squares / (n - 1.0) / n);
      out += ',';
      out += number(mean);
      out += ',';
      out += number(sem);
    }
    out += '\n';
  }
  return out;
}

std::map<std::string, std::filesystem::path> finished_runs_by_scene(
    const std::filesystem::path& sweep_folder) {
  std::map<std::string, std::filesystem::path> found;
  const std::filesystem::path runs = sweep_folder / "runs";
  std::error_code error;
  if (!std::filesystem::is_directory(runs, error)) return found;
  // a folder that cannot be read is skipped, not the end of the scan
  for (auto it = std::filesystem::recursive_directory_iterator(
           runs, std::filesystem::directory_options::skip_permission_denied, error);
       !error && it != std::filesystem::recursive_directory_iterator(); it.increment(error)) {
    if (it->path().filename() != "summary.json") continue;
    const std::optional<RunSummary> summary = read_run_summary(it->path());
    if (summary && !summary->run.interrupted && !summary->run.failed)
      found.emplace(summary->scene_toml, it->path());
  }
  return found;
}

std::string finished_run_text(const RunSummary& summary) {
  return fmt::format("porosity={:.5f} blocked={} wall={:.1f}s", summary.porosity,
                     summary.run.blocked ? "yes" : "no", summary.run.wall_seconds);
}

std::string unfinished_run_text(bool stopped, bool fault, bool unwritten) {
  if (stopped) return "interrupted";
  if (fault) return "FAILED (a fault stopped it: unphysical state)";
  if (unwritten) return "FAILED (could not write its outputs)";
  return "FAILED";
}

}  // namespace cdpowder
