// sweep_state.cpp — every run's scene checked before anything starts; the tables written
// atomically with the program's version and commit.
#include "commands/sweep_state.hpp"

#include "commands/sweep_runs.hpp"

#include "cdpowder/config/config_error.hpp"
#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/io/atomic_file.hpp"
#include "cdpowder/run/run_folder.hpp"
#include "cdpowder/study/sweep_messages.hpp"
#include "cdpowder/study/sweep_results.hpp"
#include "cdpowder/version.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>

namespace cdpowder::app {

namespace {

std::string sweep_header(const SweepPlan& plan) {
  return fmt::format("# cdpowder {} (commit {})\n# sweep: {}\n# scene: {}\n", kVersion, kGitCommit,
                     plan.source.string(), plan.scene.string());
}

}  // namespace

SweepState read_sweep_state(const SweepOptions& options) {
  SweepState state{read_sweep_plan(options.sweep, options.overrides), {}, {}, {}, {}, {}};
  const SweepPlan& plan = state.plan;
  std::vector<std::string>& scene_texts = state.scene_texts;
  scene_texts.resize(plan.runs.size());
  // every run's scene is checked before anything starts; each distinct mistake once
  std::vector<ConfigIssue> issues;
  std::set<std::string> seen;
  // each run's scene read as its command reads it (compact demands the piston and the
  // blocked state)
  SceneReadOptions compaction;
  compaction.compaction = plan.command == SweepCommand::Compact;
  for (std::size_t i = 0; i < plan.runs.size(); ++i) {
    try {
      scene_texts[i] = read_scene(plan.scene, plan.runs[i].overrides, compaction).effective_toml;
    } catch (const ConfigError& error) {
      for (const ConfigIssue& issue : error.issues()) {
        if (seen.insert(format(issue)).second) issues.push_back(issue);
      }
    }
  }
  // two points that resolve to the same scene (e.g. 1 and 1.0, or a value equal to the
  // base scene's) would run the same thing twice under two names
  std::map<std::string, std::size_t> first_with_scene;
  for (std::size_t i = 0; issues.empty() && i < plan.runs.size(); ++i) {
    const auto [it, fresh] = first_with_scene.emplace(scene_texts[i], i);
    if (!fresh) {
      issues.push_back({plan.source.string(), 0, 0, "",
                        fmt::format("points '{}' and '{}' give the same scene (seed {}); "
                                    "list each point once",
                                    plan.points[plan.runs[it->second].point].name,
                                    plan.points[plan.runs[i].point].name, plan.runs[i].seed)});
    }
  }
  if (plan.command == SweepCommand::Python && !options.reuse.empty()) {
    // another sweep's run of the same scene ran another program: nothing to reuse
    issues.push_back({plan.source.string(), 0, 0, "command",
                      "--reuse takes the runs of `compact` and `simulate` sweeps; a Python "
                      "protocol's runs are its own: leave --reuse out"});
  }
  if (!issues.empty()) throw ConfigError(std::move(issues));

  std::vector<std::optional<RunSummary>>& summaries = state.summaries;
  summaries.resize(plan.runs.size());
  std::vector<std::size_t>& pending = state.pending;
  for (std::size_t i = 0; i < plan.runs.size(); ++i) {
    const std::filesystem::path folder = options.out / plan.runs[i].folder;
    std::optional<RunSummary> summary = read_sweep_run(plan, folder);
    // a summary beside missing outputs: a build that wrote the summary first was cut short
    std::vector<std::string> missing;
    if (summary) missing = missing_run_outputs(folder);
    if (is_reusable(summary, scene_texts[i]) && missing.empty()) {
      summaries[i] = std::move(summary);
    } else {
      if (!missing.empty()) state.incomplete.emplace(i, std::move(missing));
      pending.push_back(i);
    }
  }
  // runs another sweep has already done, for exactly the same scene
  std::map<std::size_t, std::filesystem::path>& reused = state.reused;
  if (!options.reuse.empty()) {
    std::map<std::string, std::filesystem::path> elsewhere;
    for (const std::filesystem::path& folder : options.reuse) {
      std::map<std::string, std::filesystem::path> found = finished_runs_by_scene(folder);
      if (found.empty() && !options.quiet) {
        std::fprintf(stderr, "%s\n", nothing_to_reuse_line(folder).c_str());
      }
      elsewhere.merge(found);
    }
    std::vector<std::size_t> still_pending;
    for (const std::size_t i : pending) {
      const auto found = elsewhere.find(scene_texts[i]);
      if (found == elsewhere.end()) {
        still_pending.push_back(i);
      } else {
        reused.emplace(i, found->second);
      }
    }
    pending.swap(still_pending);
  }
  order_seed_by_seed(plan, pending);
  return state;
}

std::optional<RunSummary> finished_summary(const SweepPlan& plan,
                                           const std::filesystem::path& folder,
                                           const std::string& scene_text) {
  std::optional<RunSummary> summary = read_sweep_run(plan, folder);
  if (!is_reusable(summary, scene_text) || !missing_run_outputs(folder).empty()) return {};
  return summary;
}

void write_tables(const SweepOptions& options, const SweepPlan& plan,
                  const std::vector<std::optional<RunSummary>>& summaries) {
  const std::string header = sweep_header(plan);
  write_file_atomically(options.out / "results.csv", results_csv(plan, summaries, header));
  write_file_atomically(options.out / "points.csv", points_csv(plan, summaries, header));
}

std::string try_write_tables(const SweepOptions& options, const SweepPlan& plan,
                             const std::vector<std::optional<RunSummary>>& summaries) {
  try {
    write_tables(options, plan, summaries);
  } catch (const OutputError& error) {
    return error.what();
  }
  return {};
}

std::string read_text(const std::filesystem::path& file) {
  std::ifstream stream(file, std::ios::binary);
  std::ostringstream text;
  text << stream.rdbuf();
  return text.str();
}

}  // namespace cdpowder::app
