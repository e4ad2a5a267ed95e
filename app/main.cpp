// main.cpp — the cdpowder command line. The only place that turns exceptions into text
// and exit codes: 0 done, 1 the run failed, 2 bad input (nothing written).
#include "commands/simulate.hpp"

#include "cdpowder/config/config_error.hpp"
#include "cdpowder/version.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

namespace {

constexpr int kExitRunFailed = 1;
constexpr int kExitBadInput = 2;

}  // namespace

int main(int argc, char** argv) {
  using cdpowder::app::SimulateOptions;
  CLI::App cli{"cdpowder — contact dynamics of cohesive powders of rigid spheres"};
  cli.set_version_flag("--version",
                       std::string(cdpowder::kVersion) + " (commit " + cdpowder::kGitCommit + ")");
  cli.require_subcommand(1);

  SimulateOptions simulate;
  CLI::App* simulate_cmd =
      cli.add_subcommand("simulate", "Run a scene (TOML) and write its outputs to a folder");
  simulate_cmd->add_option("scene", simulate.scene, "Scene file (TOML); see docs/config.md")
      ->required();
  simulate_cmd->add_option("--out,-o", simulate.out, "Output folder (created if missing)")
      ->required();
  simulate_cmd->add_option("--set", simulate.overrides,
                           "Override a scene key: --set section.key=value (repeatable)");
  simulate_cmd->add_flag("--quiet,-q", simulate.quiet, "No progress line on stderr");

  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = cli.exit(e);
    return code == 0 ? 0 : kExitBadInput;
  }

  try {
    if (simulate_cmd->parsed()) return cdpowder::app::run_simulate(simulate);
  } catch (const cdpowder::ConfigError& e) {
    for (const cdpowder::ConfigIssue& issue : e.issues()) {
      std::fprintf(stderr, "error: %s\n", cdpowder::format(issue).c_str());
    }
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitRunFailed;
  }
  return kExitRunFailed;
}
