// contact_problem — exports a fixture's contact problems and judges any solver's solution
// of them by the engine's own residual and gauges
// (docs/lab/2026-11-25-siconos-newton-solvers.md).
//   contact_problem export FIXTURE.cdps --skip S --count N --out DIR [--set k=v ...]
//       steps the fixture S steps, then writes the next N steps' problems, before the
//       solver stage, to DIR/step_K.json (K = 0..N−1) with what the engine's solver did on
//       them, and the engine's solution to DIR/step_K_cdpowder.json
//   contact_problem judge DIR/step_K.json SOLUTION.json [--presweeps K] [--json]
//       [--velocities OUT.json]: one NLGS sweep from the solution (after K sweeps that
//       post-process it): the residual of physics.md §7.3, and the gauges
//   contact_problem solve DIR/step_K.json [--cold] [--repeat N] [--out SOLUTION.json]
//       [--set k=v ...]: the engine's solver on the exported problem, timed, then judged
#include "contact_problem/judge.hpp"
#include "contact_problem/problem_json.hpp"

#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/run/state_file.hpp"
#include "cdpowder/solver/step.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <exception>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace cdpowder;
using namespace cdpowder::bench;
using nlohmann::json;

std::string rng_text(const Rng& rng) {
  return rng.text();  // pcg-cpp's exact text form
}

Rng rng_from_text(const std::string& text) {
  return Rng::from_text(text).value_or(Rng{});
}

/// The problem begin_step left in `work`, before any sweep.
ContactProblem describe(const World& world, const StepWorkspace& work, const StepSettings& settings,
                        const std::string& scene_toml, const std::string& rng) {
  ContactProblem p;
  p.scene_toml = scene_toml;
  p.sweep_order_rng = rng;
  p.step_index = world.step;
  p.dt = settings.solver.dt;
  p.reference_force = settings.laws.spheres.cohesion_force;
  p.sphere_cohesion_range = settings.laws.spheres.cohesion_range;
  p.wall_cohesion_range = settings.laws.walls.cohesion_range;
  p.piston_force = world.walls.piston.enabled ? world.walls.piston.force : 0.0;
  p.piston_velocity = world.walls.piston.enabled ? world.walls.piston.velocity : 0.0;
  p.contacts = work.contacts;
  p.start_velocities = work.velocities;
  // v_free: the warm start taken back out of v* (round-off of order 1e-16 relative)
  Contacts negated = work.contacts;
  const auto negate = [](ContactAction& a) {
    a.normal_force = -a.normal_force;
    a.tangential_force = -a.tangential_force;
    a.rolling_torque = -a.rolling_torque;
    a.twisting_torque = -a.twisting_torque;
  };
  for (ContactAction& a : negated.pair_actions) negate(a);
  for (ContactAction& a : negated.wall_actions) negate(a);
  p.free_velocities = velocities_for(negated, work.velocities);
  p.velocity = world.bodies.velocity;
  p.angular_velocity = world.bodies.angular_velocity;
  p.radius = world.bodies.radius;
  return p;
}

json stats_json(const SolverStats& s, double seconds) {
  return {{"sweeps", s.passes},           {"solve_seconds", seconds},
          {"residual", s.residual},       {"error_estimate", s.error_estimate},
          {"contraction", s.contraction}, {"force_scale", s.force_scale},
          {"converged", s.converged}};
}

int run_export(const std::filesystem::path& fixture, int skip, int count,
               const std::filesystem::path& out_dir, const std::vector<std::string>& overrides) {
  SavedRun saved = load_state(fixture);
  const Scene saved_scene = read_scene_text(saved.scene_toml, fixture.string(), {}, ".");
  const Scene scene =
      read_scene_text(saved.scene_toml, fixture.string(), command_line_overrides(overrides), ".");
  World world;
  StepWorkspace work(scene.step.solver.seed);
  RunState run;
  restore_run(std::move(saved), saved_scene.run, saved_scene.step.solver.dt, world, work, run);
  std::filesystem::create_directories(out_dir);
  for (int k = 0; k < skip; ++k) step(world, work, scene.step);
  for (int k = 0; k < count; ++k) {
    const std::string rng = rng_text(work.solver.rng);
    StepReport report = begin_step(world, work, scene.step);
    const ContactProblem problem = describe(world, work, scene.step, scene.effective_toml, rng);
    finish_step(world, work, scene.step, report);
    const double seconds = report.times[static_cast<std::size_t>(Stage::SolveNlgs)];
    json j = to_json(problem);
    j["cdpowder"] = stats_json(report.solver, seconds);
    const std::string name = fmt::format("step_{}", k);
    write_json_file((out_dir / (name + ".json")).string(), j);
    write_json_file((out_dir / (name + "_cdpowder.json")).string(),
                    {{"solver", "cdpowder nlgs"},
                     {"stats", j["cdpowder"]},
                     {"actions", actions_to_json(actions_of(work.contacts))}});
    fmt::print(
        "{} step={} contacts={} sweeps={} solve={:.2f}ms residual={:.3g} estimate={:.3g} {}\n",
        name, problem.step_index, problem.contacts.size(), report.solver.passes, 1e3 * seconds,
        report.solver.residual, report.solver.error_estimate,
        report.solver.converged ? "converged" : "capped");
  }
  return 0;
}

void print_judgement(const Judgement& j) {
  fmt::print(
      "residual={:.4g} local_residual={:.4g} force_scale={:.4g} closed={} "
      "max_penetration={:.3g}R max_separation={:.3g}R mean_overlap={:.3g}R max_overlap={:.3g}R "
      "opening/d_coh={:.3g} law_violation={:.3g} piston_imbalance={:.3g} "
      "max_net_force={:.3g}\n",
      j.residual, j.local_residual, j.force_scale, j.closed, j.max_penetration, j.max_separation,
      j.mean_overlap, j.max_overlap, j.max_opening_per_range, j.max_law_violation,
      j.piston_imbalance, j.max_net_force);
}

int run_judge(const std::string& problem_file, const std::string& solution_file, std::uint64_t seed,
              int presweeps, bool as_json, const std::string& velocities_file) {
  const ContactProblem problem = contact_problem_from_json(read_json_file(problem_file));
  const ContactActions actions = actions_from_json(read_json_file(solution_file).at("actions"));
  const Judgement j = judge(problem, actions, seed, presweeps);
  if (!velocities_file.empty()) {
    write_json_file(velocities_file, contact_velocities(problem, actions));
  }
  if (as_json) {
    fmt::print("{}\n", to_json(j).dump());
  } else {
    print_judgement(j);
  }
  return 0;
}

int run_solve(const std::string& problem_file, bool cold, int repeat,
              const std::string& solution_file, const std::vector<std::string>& overrides,
              bool as_json) {
  const ContactProblem problem = contact_problem_from_json(read_json_file(problem_file));
  const Scene scene =
      read_scene_text(problem.scene_toml, problem_file, command_line_overrides(overrides), ".");
  const SolverSettings& settings = scene.step.solver;
  NlgsWorkspace work(settings.seed);
  Contacts contacts;
  VelocityCache velocities;
  SolverStats stats;
  std::vector<double> seconds;
  // one untimed solve first: the engine reuses its buffers from step to step
  for (int r = 0; r <= repeat; ++r) {
    contacts = problem.contacts;
    if (cold) set_actions(ContactActions(contacts.size()), contacts);
    velocities = cold ? problem.free_velocities : problem.start_velocities;
    work.rng = rng_from_text(problem.sweep_order_rng);  // the engine's visiting order
    const auto start = std::chrono::steady_clock::now();
    stats = solve_nlgs(contacts, velocities, settings, problem.reference_force, work);
    const auto stop = std::chrono::steady_clock::now();
    if (r > 0) seconds.push_back(std::chrono::duration<double>(stop - start).count());
  }
  std::sort(seconds.begin(), seconds.end());
  const double median = seconds[seconds.size() / 2];
  const ContactActions actions = actions_of(contacts);
  const Judgement j = judge(problem, actions, 1);
  if (!solution_file.empty()) {
    write_json_file(solution_file, {{"solver", "cdpowder nlgs"},
                                    {"stats", stats_json(stats, median)},
                                    {"actions", actions_to_json(actions)}});
  }
  if (as_json) {
    fmt::print(
        "{}\n",
        json{{"stats", stats_json(stats, median)}, {"seconds", seconds}, {"judge", to_json(j)}}
            .dump());
  } else {
    fmt::print("sweeps={} solve={:.2f}ms (median of {}) residual={:.4g} estimate={:.4g} {}\n",
               stats.passes, 1e3 * median, seconds.size(), stats.residual, stats.error_estimate,
               stats.converged ? "converged" : "capped");
    print_judgement(j);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"Exports a fixture's contact problems; judges solutions of them."};
  cli.require_subcommand(1);

  CLI::App* exporter = cli.add_subcommand("export", "write N steps' contact problems");
  std::filesystem::path fixture;
  std::filesystem::path out_dir;
  int skip = 0;
  int count = 10;
  std::vector<std::string> overrides;
  exporter->add_option("state", fixture, "state file (.cdps)")
      ->required()
      ->check(CLI::ExistingFile);
  exporter->add_option("--skip", skip, "steps to run before the first exported one")
      ->check(CLI::NonNegativeNumber);
  exporter->add_option("--count", count, "steps to export")->check(CLI::PositiveNumber);
  exporter->add_option("--out", out_dir, "output folder")->required();
  exporter->add_option("--set", overrides, "section.key=value override of the saved scene");

  CLI::App* judger = cli.add_subcommand("judge", "residual and gauges of a solution");
  std::string problem_file;
  std::string solution_file;
  std::string velocities_file;
  std::uint64_t seed = 1;
  bool as_json = false;
  judger->add_option("problem", problem_file, "step_K.json")->required()->check(CLI::ExistingFile);
  judger->add_option("solution", solution_file, "JSON with an \"actions\" table")
      ->required()
      ->check(CLI::ExistingFile);
  judger->add_option("--seed", seed, "seed of the judging sweep's block order");
  int presweeps = 0;
  judger
      ->add_option("--presweeps", presweeps,
                   "engine sweeps applied to the solution before it is judged")
      ->check(CLI::NonNegativeNumber);
  judger->add_flag("--json", as_json, "print one JSON object");
  judger->add_option("--velocities", velocities_file, "write each contact's V and g_pos/dt");

  CLI::App* solver = cli.add_subcommand("solve", "the engine's solver on an exported problem");
  bool cold = false;
  int repeat = 3;
  solver->add_option("problem", problem_file, "step_K.json")->required()->check(CLI::ExistingFile);
  solver->add_flag("--cold", cold, "start from zero actions instead of the warm start");
  solver->add_option("--repeat", repeat, "timed solves (median reported)")
      ->check(CLI::PositiveNumber);
  solver->add_option("--out", solution_file, "write the solution");
  solver->add_option("--set", overrides, "section.key=value override of the solver settings");
  solver->add_flag("--json", as_json, "print one JSON object");

  CLI11_PARSE(cli, argc, argv);
  try {
    if (*exporter) return run_export(fixture, skip, count, out_dir, overrides);
    if (*judger) {
      return run_judge(problem_file, solution_file, seed, presweeps, as_json, velocities_file);
    }
    return run_solve(problem_file, cold, repeat, solution_file, overrides, as_json);
  } catch (const std::exception& error) {
    fmt::print(stderr, "contact_problem: {}\n", error.what());
    return 2;
  }
}
