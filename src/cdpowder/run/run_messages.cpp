// run_messages.cpp — the words a run says (run_messages.hpp).
#include "cdpowder/run/run_messages.hpp"

#include "cdpowder/analysis/porosity.hpp"
#include "cdpowder/analysis/stress.hpp"
#include "cdpowder/config/config_error.hpp"
#include "cdpowder/config/scene_keys.hpp"
#include "cdpowder/run/state_file.hpp"
#include "cdpowder/setup/deposition.hpp"
#include "cdpowder/version.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace cdpowder {

std::string deposit_line(const World& world, double seconds) {
  return fmt::format("porosity={:.5f} spheres={} height={:.4f} wall={:.3f}s",
                     deposit_porosity(world.bodies, world.box), world.bodies.size(),
                     deposit_height(world.bodies), seconds);
}

std::string clock_text(double seconds) {
  const long s = std::lround(seconds);
  return s >= 3600 ? fmt::format("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60)
                   : fmt::format("{:02}:{:02}", s / 60, s % 60);
}

std::string progress_text(const World& world, std::size_t contacts, double passes_per_step,
                          double elapsed_seconds, double fraction) {
  const std::string remaining =
      fraction > 0.0 ? clock_text(elapsed_seconds * (1.0 - fraction) / fraction) : "?";
  std::string line = fmt::format("t={:.4g}", world.time);
  if (world.walls.piston.enabled) {
    line += fmt::format(" Z_P={:.4g} E={:.4f}", world.walls.piston.height, porosity(world));
  }
  line += fmt::format(" passes/step={:.1f} contacts={} elapsed {} remaining <= {}", passes_per_step,
                      contacts, clock_text(elapsed_seconds), remaining);
  return line;
}

std::string run_announcement(std::string_view what, const Scene& scene,
                             const std::filesystem::path& out, std::size_t spheres) {
  // one line, whatever the folder's name holds (a newline once split it)
  std::string line =
      fmt::format("cdpowder {} (commit {}): {} --out {}; {} spheres, seed {}", kVersion, kGitCommit,
                  one_line(what), one_line(out.string()), spheres, scene.step.solver.seed);
  if (scene.deposition) line += fmt::format(", deposition seed {}", scene.deposition->seed);
  // the threads the solve runs on within the process's CPU budget (core/cpu_budget.hpp)
  const int threads = solve_threads(scene.step.solver);
  line += fmt::format(", {} thread{}", threads, threads == 1 ? "" : "s");
  return line;
}

std::string result_line(const Scene& scene, const World& world, const Contacts& contacts,
                        const RunResult& result) {
  const StressTensors sigma = stress_tensors(contacts, packing_volume(world));
  const Piston& piston = world.walls.piston;
  const double pressure = piston.enabled ? piston.force / world.box.area() : 0.0;
  std::string line = fmt::format("porosity={:.5f}", porosity(world));
  if (pressure > 0.0) {
    line += fmt::format(" sigma_zz/p={:.4f} sigma_zz+/p={:.4f} sigma_zz-/p={:.4f}",
                        sigma.total(2, 2) / pressure, sigma.compressive(2, 2) / pressure,
                        sigma.tensile(2, 2) / pressure);
  } else {
    line += fmt::format(" sigma_zz={:.6g} sigma_zz+={:.6g} sigma_zz-={:.6g}", sigma.total(2, 2),
                        sigma.compressive(2, 2), sigma.tensile(2, 2));
  }
  if (scene.run.until_blocked) line += fmt::format(" blocked={}", result.blocked ? "yes" : "no");
  if (result.interrupted) line += " interrupted=yes";
  line += fmt::format(" steps={} passes/step={:.1f} wall={:.2f}s", result.steps,
                      static_cast<double>(result.total_passes) /
                          static_cast<double>(std::max<std::int64_t>(1, result.steps)),
                      result.wall_seconds);
  return line;
}

std::optional<RunEndNotice> run_end_notice(const Scene& scene, const World& world,
                                           const RunResult& result,
                                           const std::filesystem::path& out) {
  if (result.fault) {
    return RunEndNotice{RunEnding::Failed,
                        fmt::format("the run failed: {}; outputs and failed_state.cdps in {}",
                                    result.fault->message, out.string())};
  }
  if (result.interrupted) {  // outputs written, but incomplete
    return RunEndNotice{RunEnding::Interrupted,
                        fmt::format("interrupted at step {} (t = {:g} t0); cdpowder resume {} "
                                    "continues it",
                                    result.steps, world.time, out.string())};
  }
  if (scene.run.until_blocked && !result.blocked && !result.not_blocked.empty()) {
    return RunEndNotice{RunEnding::NotBlocked,
                        fmt::format("not blocked at t = {:g} t0: {}; the summary says blocked = "
                                    "false",
                                    world.time, result.not_blocked)};
  }
  if (scene.run.until_blocked && !result.blocked) {
    return RunEndNotice{RunEnding::NotBlocked,
                        fmt::format("the packing did not block within {} = {:g} t0 "
                                    "(t = {:g} t0); the summary says blocked = false",
                                    detail::key_name(scene, scene.run.max_duration),
                                    scene.run.max_duration, world.time)};
  }
  return std::nullopt;
}

std::string other_build_warning(const std::filesystem::path& checkpoint,
                                std::string_view program_version, std::string_view git_commit) {
  if (!written_by_another_build(program_version, git_commit)) return {};
  return fmt::format(
      "{} was written by cdpowder {} (commit {}), this is cdpowder {} (commit {}): the run goes "
      "on, but its result will not be bit-identical to a run never stopped",
      checkpoint.string(), program_version, git_commit, kVersion, kGitCommit);
}

}  // namespace cdpowder
