// main.cpp — the cdpowder command line. The only place that turns exceptions into text
// and exit codes: 0 done, 1 the run failed or was interrupted, 2 bad input (nothing
// written); a run also exits 3 when a fault stopped it and 4 when it did not block
// (simulate.hpp).
#include "commands/deposit.hpp"
#include "commands/simulate.hpp"
#include "commands/stress_bounds.hpp"
#include "commands/sweep.hpp"
#include "die_with_parent.hpp"
#include "duration.hpp"
#include "run_phase.hpp"

#include "cdpowder/config/config_error.hpp"
#include "cdpowder/core/ranks.hpp"
#include "cdpowder/core/stop_request.hpp"
#include "cdpowder/io/atomic_file.hpp"
#include "cdpowder/io/byte_stream.hpp"
#include "cdpowder/solver/settings.hpp"
#include "cdpowder/study/time_limit.hpp"
#include "cdpowder/version.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <new>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>

namespace {

constexpr int kExitRunFailed = 1;
constexpr int kExitBadInput = 2;
/// std::bad_alloc: the run could not get the memory it needs; its checkpoint, if any, is kept
constexpr int kExitOutOfMemory = 6;

/// Why `--out` cannot be the output folder, or nothing: it (or a folder above it) is a file.
/// Checked while the command line is read, so nothing is run or written (once the run's
/// end brought the file system's own words and exit status 1).
std::string output_folder_problem(const std::string& text) {
  if (text.empty()) return "empty; name a folder (created if missing)";
  constexpr std::size_t kMaxPath = 4095;  // PATH_MAX of Linux, less the terminating zero
  if (text.size() > kMaxPath) {
    return "a path of " + std::to_string(text.size()) +
           " characters; the system allows at most 4095";
  }
  constexpr std::size_t kMaxName = 255;  // NAME_MAX of Linux file systems
  for (const std::filesystem::path& part : std::filesystem::path(text)) {
    if (part.string().size() > kMaxName) {
      return "a folder name of " + std::to_string(part.string().size()) +
             " characters; the file system allows at most 255";
    }
  }
  std::error_code error;
  for (std::filesystem::path p = text; !p.empty(); p = p.parent_path()) {
    if (std::filesystem::is_symlink(std::filesystem::symlink_status(p, error)) &&
        !std::filesystem::exists(p, error)) {
      return "'" + p.string() + "' is a link to '" +
             std::filesystem::read_symlink(p, error).string() +
             "', which does not exist; name a folder (created if missing)";
    }
    const std::filesystem::file_status status = std::filesystem::status(p, error);
    if (std::filesystem::is_directory(status)) return {};
    if (std::filesystem::exists(status)) {
      return p == std::filesystem::path(text)
                 ? "'" + text + "' is a file; name a folder (created if missing)"
                 : "'" + p.string() + "' in '" + text + "' is a file, not a folder";
    }
    if (p == p.parent_path()) break;
  }
  return {};
}

/// A check that the text is a whole number ≥ 0 (`allowed`: what it is), before CLI11
/// converts it (an unsigned -1 became 18446744073709551615, and CLI11's own range check
/// printed a bound of 310 digits). CLI11 puts the option's name in front.
std::function<std::string(const std::string&)> count_problem(std::string allowed) {
  return [allowed = std::move(allowed)](const std::string& text) {
    const bool digits = !text.empty() && text.size() <= 9 &&
                        text.find_first_not_of("0123456789") == std::string::npos;
    return digits ? std::string() : "got '" + cdpowder::shown(text) + "', expected " + allowed;
  };
}

/// The subcommands, for the message when the first word names none of them.
constexpr std::array<std::string_view, 6> kCommands{"simulate", "compact", "resume",
                                                    "deposit",  "sweep",   "stress-bounds"};

/// Why `text` is not a --checkpoint-every interval, or nothing.
std::string checkpoint_interval_problem(const std::string& text) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || !std::isfinite(value) || value <= 0.0) {
    return "got '" + cdpowder::shown(text) +
           "', expected a simulated time in t0 > 0 (e.g. 50: a checkpoint every 50 t0)";
  }
  return {};
}

/// --checkpoint-every T, shared by simulate, compact, resume and sweep.
void add_checkpoint_option(CLI::App& command, std::optional<double>& every) {
  command
      .add_option("--checkpoint-every", every,
                  "Keep the full state in DIR/checkpoint.cdps, renewed every T of simulated "
                  "time [t0]; `cdpowder resume DIR` continues from it (a signal writes one too)")
      ->check(checkpoint_interval_problem, "T");
}

/// The options shared by simulate and compact.
void add_run_options(CLI::App& command, cdpowder::app::RunOptions& options) {
  command.add_option("scene", options.scene, "Scene file (TOML); see docs/config.md")->required();
  command.add_option("--out,-o", options.out, "Output folder (created if missing)")
      ->required()
      ->check(output_folder_problem, "FOLDER");
  command.add_option("--set", options.overrides,
                     "Override a scene key: --set section.key=value (repeatable)");
  command.add_option("--particles", options.particles,
                     "Start from this particles CSV (e.g. a deposit's particles.csv) instead of "
                     "the scene's [particles] or [deposition]");
  command.add_flag("--quiet,-q", options.quiet, "No progress line on stderr");
  add_checkpoint_option(command, options.checkpoint_every);
}

/// The message and exit code when the first word names no command (CLI11 says only "A
/// subcommand is required" for a misspelt one), or nullopt.
std::optional<int> refuse_missing_command(int argc, char** argv) {
  if (argc >= 2 && argv[1][0] != '-' &&
      std::find(kCommands.begin(), kCommands.end(), std::string_view(argv[1])) == kCommands.end()) {
    std::fprintf(stderr,
                 "error: unknown command '%s'; the commands are simulate, compact, resume, "
                 "deposit, sweep and stress-bounds (cdpowder --help)\n",
                 cdpowder::shown(argv[1]).c_str());
    return kExitBadInput;
  }
  if (argc == 1) {
    std::fprintf(stderr,
                 "error: a command is required: simulate, compact, resume, deposit, sweep or "
                 "stress-bounds (cdpowder --help; the quick start is in README.md)\n");
    return kExitBadInput;
  }
  return std::nullopt;
}

CLI::App* add_resume_command(CLI::App& cli, cdpowder::app::ResumeOptions& resume) {
  CLI::App* command = cli.add_subcommand(
      "resume",
      "Continue the unfinished run in DIR from its checkpoint.cdps; it ends bit-identical to "
      "the run never stopped (docs/outputs.md)");
  command->add_option("folder", resume.folder, "The run's output folder")
      ->required()
      ->check(CLI::ExistingDirectory);
  command->add_flag("--quiet,-q", resume.quiet, "No progress line on stderr");
  add_checkpoint_option(*command, resume.checkpoint_every);
  command
      ->add_option("--threads", resume.threads,
                   "Solve on N threads from here on (0: every core the process may use) instead "
                   "of the run's solver.threads; the results are the same bits for any count")
      ->check(CLI::Range(0, cdpowder::kMaxSolverThreads))
      ->type_name("N");
  return command;
}

CLI::App* add_deposit_command(CLI::App& cli, cdpowder::app::DepositOptions& deposit) {
  CLI::App* command = cli.add_subcommand(
      "deposit", "Ballistic deposition with a capture radius ([deposition]); write particles.csv");
  command->add_option("scene", deposit.scene, "Scene file (TOML) with a [deposition] section")
      ->required();
  command->add_option("--out,-o", deposit.out, "Output folder (created if missing)")
      ->required()
      ->check(output_folder_problem, "FOLDER");
  command->add_option("--set", deposit.overrides,
                      "Override a scene key: --set section.key=value (repeatable)");
  command->add_flag("--quiet,-q", deposit.quiet,
                    "No progress on stderr (a deposit draws none; taken as compact and simulate "
                    "take it)");
  return command;
}

/// --time-limit DURATION of the sweep: seconds, or numbers with units h, m, s.
void add_time_limit_option(CLI::App& command, cdpowder::app::SweepOptions& sweep) {
  command
      .add_option_function<std::string>(
          "--time-limit",
          [&sweep](const std::string& text) {
            sweep.time_limit = cdpowder::app::parse_duration(text);
          },
          "Wall time for the whole sweep (5400, 90m, 2h30m): a run starts only when it is "
          "expected to finish by then (1.25 × the longest finished run of its point); runs "
          "still going at the limit stop as at Ctrl-C")
      ->check(
          [](const std::string& text) {
            const std::optional<double> seconds = cdpowder::app::parse_duration(text);
            return seconds && *seconds > 0.0
                       ? std::string()
                       : "'" + text +
                             "' is not a positive duration: a number of seconds, or numbers "
                             "with units h, m, s, largest first (5400, 90m, 2.5h, 2h30m)";
          },
          "DURATION");
}

CLI::App* add_sweep_command(CLI::App& cli, cdpowder::app::SweepOptions& sweep) {
  CLI::App* command = cli.add_subcommand(
      "sweep",
      "Compact every parameter point × seed of a sweep file, in parallel and resumable; write "
      "results.csv and points.csv (docs/sweeps.md)");
  command->add_option("sweep", sweep.sweep, "Sweep file (TOML); see docs/sweeps.md")->required();
  command->add_option("--out,-o", sweep.out, "Output folder (created if missing)")
      ->required()
      ->check(output_folder_problem, "FOLDER");
  command->add_option("--set", sweep.overrides,
                      "Override a scene key in every run: --set section.key=value (repeatable)");
  command->add_option("--jobs,-j", sweep.jobs, "Runs at a time (default: the number of cores)")
      ->check(count_problem("runs at a time, e.g. 2 (0: one per core)"), "N");
  command->add_flag("--quiet,-q", sweep.quiet, "No progress lines on stderr");
  add_checkpoint_option(*command, sweep.checkpoint_every);
  command->add_flag("--stress-bounds", sweep.stress_bounds,
                    "Once every run has finished, compute each blocked run's admissible stress "
                    "interval (cdpowder stress-bounds OUT; physics.md §11.3)");
  command->add_flag("--dry-run", sweep.dry_run,
                    "List the runs and whether each is finished; run nothing");
  CLI::Option* list = command->add_flag(
      "--list", sweep.list,
      "Print one shell command per run still to do (for GNU parallel, xargs -P or a Slurm "
      "array; docs/sweeps.md); run nothing");
  CLI::Option* task =
      command
          ->add_option(
              "--task", sweep.task,
              "Run exactly run I of the plan (the index --list prints), as one of many runners")
          ->check(count_problem("a run index ≥ 0 (--list prints them)"), "I");
  CLI::Option* collect = command->add_flag(
      "--collect", sweep.collect, "Write results.csv and points.csv from the finished runs");
  list->excludes(task)->excludes(collect);
  task->excludes(collect);
  command
      ->add_option("--reuse", sweep.reuse,
                   "Another sweep folder: copy in its finished runs whose scene is exactly a "
                   "run's own instead of running them again (repeatable)")
      ->check(CLI::ExistingDirectory);
  add_time_limit_option(*command, sweep);
  return command;
}

/// Runs `command`, turning the expected exceptions into messages and exit codes.
int run_reporting_errors(const std::function<int()>& command) {
  try {
    return command();
  } catch (const cdpowder::Interrupted& e) {
    std::fprintf(stderr, "error: %s; nothing written\n", e.what());
    return kExitRunFailed;
  } catch (const cdpowder::StateFileError& e) {
    // a checkpoint this build cannot continue: nothing was written
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  } catch (const cdpowder::ConfigError& e) {
    for (const cdpowder::ConfigIssue& issue : e.issues()) {
      std::fprintf(stderr, "error: %s\n", cdpowder::format(issue).c_str());
    }
    return kExitBadInput;
  } catch (const cdpowder::OutputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return cdpowder::app::kExitOutputFailed;
  } catch (const std::filesystem::filesystem_error& e) {
    // a folder that cannot be made on a full disk is the same failure as a file
    std::fprintf(stderr, "error: %s\n", e.what());
    const std::error_code code = e.code();
    const bool unwritable = code == std::errc::no_space_on_device ||
                            code == std::errc::file_too_large ||
                            code == std::errc::read_only_file_system ||
                            code.value() == EDQUOT;  // a quota: a cluster's full disk
    return unwritable ? cdpowder::app::kExitOutputFailed : kExitRunFailed;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "error: %s\n", cdpowder::app::out_of_memory_message().c_str());
    return kExitOutOfMemory;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitRunFailed;
  }
}

CLI::App* add_stress_bounds_command(CLI::App& cli, cdpowder::app::StressBoundsOptions& bounds) {
  CLI::App* command = cli.add_subcommand(
      "stress-bounds",
      "The admissible stress interval of finished runs' packings (physics.md §11.3): the "
      "smallest and largest sigma, sigma+ and sigma- over every admissible force set, added to "
      "DIR/summary.json; `cdpowder stress-bounds --help` after the word lists its options");
  // every word after the command goes to the Python module, which reads them (its --help
  // lists them); `bounds` gets them after parsing
  command->prefix_command();
  command->set_help_flag();
  command->allow_extras();
  static_cast<void>(bounds);
  return command;
}

int run_command_line(int argc, char** argv) {
  if (const std::optional<int> refused = refuse_missing_command(argc, argv)) return *refused;
  CLI::App cli{"cdpowder — contact dynamics of cohesive powders of rigid spheres"};
  cli.set_version_flag("--version",
                       std::string(cdpowder::kVersion) + " (commit " + cdpowder::kGitCommit + ")");
  cli.require_subcommand(1);

  cdpowder::app::RunOptions simulate;
  CLI::App* simulate_cmd = cli.add_subcommand(
      "simulate", "Run a scene (TOML) for its duration or until it blocks; write the outputs");
  add_run_options(*simulate_cmd, simulate);
  cdpowder::app::RunOptions compact;
  CLI::App* compact_cmd = cli.add_subcommand(
      "compact",
      "Compact a deposit (or a particles CSV) with the piston until the blocked state; "
      "write porosity, stress and the packing");
  add_run_options(*compact_cmd, compact);
  cdpowder::app::ResumeOptions resume;
  CLI::App* resume_cmd = add_resume_command(cli, resume);
  cdpowder::app::DepositOptions deposit;
  CLI::App* deposit_cmd = add_deposit_command(cli, deposit);
  cdpowder::app::SweepOptions sweep;
  CLI::App* sweep_cmd = add_sweep_command(cli, sweep);
  cdpowder::app::StressBoundsOptions bounds;
  CLI::App* bounds_cmd = add_stress_bounds_command(cli, bounds);

  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return cli.exit(e);  // --help, --version
    // as every other mistake is named: "error: " first
    std::fprintf(stderr, "error: %s\nRun with --help for more information.\n", e.what());
    return kExitBadInput;
  }
  const char* one_process = deposit_cmd->parsed()  ? "deposit"
                            : sweep_cmd->parsed()  ? "sweep"
                            : bounds_cmd->parsed() ? "stress-bounds"
                                                   : nullptr;
  if (cdpowder::rank_count() > 1 && one_process != nullptr) {
    // a sweep runs its own processes; a deposit and the bounds are one process's work
    if (cdpowder::this_rank() == 0) {
      std::fprintf(stderr,
                   "error: %s: under mpirun (%d ranks) cdpowder runs compact, simulate and "
                   "resume; run %s as one process\n",
                   one_process, cdpowder::rank_count(), one_process);
    }
    return kExitBadInput;
  }
  if (simulate_cmd->parsed() || compact_cmd->parsed() || resume_cmd->parsed()) {
    if (const std::string why = cdpowder::copies_without_ranks(); !why.empty()) {
      std::fprintf(stderr, "error: %s\n", why.c_str());
      return kExitBadInput;
    }
  }
  return run_reporting_errors([&] {
    if (simulate_cmd->parsed()) return cdpowder::app::run_simulate(simulate);
    if (compact_cmd->parsed()) return cdpowder::app::run_compact(compact);
    if (resume_cmd->parsed()) return cdpowder::app::run_resume(resume);
    if (deposit_cmd->parsed()) return cdpowder::app::run_deposit(deposit);
    if (sweep_cmd->parsed()) return cdpowder::app::run_sweep(sweep);
    if (bounds_cmd->parsed()) {
      bounds.arguments = bounds_cmd->remaining();
      return cdpowder::app::run_stress_bounds(bounds);
    }
    return kExitRunFailed;
  });
}

}  // namespace

int main(int argc, char** argv) {
  cdpowder::app::die_with_parent_if_asked();
  // a file-size limit (ulimit -f) then fails the write with EFBIG, reported as any failed
  // write, instead of killing the process without a word
  std::signal(SIGXFSZ, SIG_IGN);
  // a reader that closed the pipe (`cdpowder compact … | head -0`) loses the result line, not
  // the run: the write fails with EPIPE instead of killing the process with SIGPIPE
  std::signal(SIGPIPE, SIG_IGN);
  // run_command_line turns the expected exceptions into messages; building the command line
  // itself may still throw (CLI::ConstructionError, std::bad_alloc): a message, not terminate
  try {
    // MPI, when an MPI launcher started this process (core/ranks.hpp); ended on every return
    const cdpowder::RankSession ranks(argc, argv);
    return run_command_line(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
  } catch (...) {
    std::fprintf(stderr, "error: unknown exception\n");
  }
  return kExitRunFailed;
}
