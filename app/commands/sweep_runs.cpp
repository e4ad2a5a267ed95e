// sweep_runs.cpp — posix_spawn into a process group of its own, output into the run's log.
#include "commands/sweep_runs.hpp"

#include "commands/simulate.hpp"
#include "python_child.hpp"

#include "cdpowder/core/cpu_budget.hpp"
#include "cdpowder/run/folder_lock.hpp"
#include "cdpowder/run/run_folder.hpp"
#include "cdpowder/run/state_file.hpp"
#include "cdpowder/study/protocol_record.hpp"
#include "cdpowder/study/sweep_results.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <spawn.h>
#include <string_view>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

extern char** environ;

namespace cdpowder::app {

RunningRuns::~RunningRuns() {
  for (const auto& entry : runs) kill(entry.first, SIGTERM);
  for (int waited = 0; !runs.empty() && waited < 600; ++waited) {  // ≤ 60 s, then kill
    int status = 0;
    const pid_t pid = waitpid(-1, &status, WNOHANG);
    if (pid > 0) {
      runs.erase(pid);
    } else if (pid < 0 && errno == ECHILD) {
      break;
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
  for (const auto& entry : runs) kill(entry.first, SIGKILL);
  for (const auto& entry : runs) waitpid(entry.first, nullptr, 0);
}

bool has_usable_checkpoint(SweepCommand command, const std::filesystem::path& folder,
                           const std::string& scene_text, std::string& why_not) {
  // a Python protocol starts again: the sweep cannot tell where in it a checkpoint was written
  if (command == SweepCommand::Python) return false;
  const std::filesystem::path file = checkpoint_path(folder);
  if (!std::filesystem::exists(file)) return false;
  try {
    const StateHeader header = read_state_header(file);
    if (!readable_state_format(header.format_version)) {
      why_not =
          fmt::format("its checkpoint is of state format {}, this build reads formats {} to {}",
                      header.format_version, kOldestStateFormatVersion, kStateFormatVersion);
      return false;
    }
    if (header.scene_toml != scene_text) {
      why_not = "its checkpoint is of another scene";
      return false;
    }
    return true;
  } catch (const StateFileError& error) {
    why_not = error.what();
    return false;
  }
}

namespace {

/// This process's environment for a run: the lock passed down (kInheritedLockVariable) and
/// the run's share of the cores (kMaxThreadsVariable), unless the user set that for the sweep;
/// for a Python protocol, the build tree's package first on PYTHONPATH.
std::vector<std::string> child_environment(const RunStart& run, bool python) {
  const std::string lock_prefix = std::string(kInheritedLockVariable) + "=";
  const std::string threads_prefix = std::string(kMaxThreadsVariable) + "=";
  const std::string path_prefix = "PYTHONPATH=";
  const std::string python_path = python ? python_path_for_child() : std::string();
  std::vector<std::string> variables;
  bool threads_set = false;
  for (char** v = environ; *v != nullptr; ++v) {
    const std::string_view variable(*v);
    threads_set = threads_set || variable.starts_with(threads_prefix);
    if (variable.starts_with(lock_prefix)) continue;
    if (!python_path.empty() && variable.starts_with(path_prefix)) continue;
    variables.emplace_back(variable);
  }
  if (!python_path.empty()) variables.push_back(path_prefix + python_path);
  if (run.lock_fd >= 0) {
    variables.push_back(fmt::format("{}={}", kInheritedLockVariable, run.lock_fd));
  }
  if (run.max_threads > 0 && !threads_set) {
    variables.push_back(fmt::format("{}={}", kMaxThreadsVariable, run.max_threads));
  }
  return variables;
}

}  // namespace

pid_t start_run(const RunStart& run, std::string& error) {
  const std::filesystem::path& folder = run.folder;
  const bool python = run.command == SweepCommand::Python;
  std::vector<std::string> args{"cdpowder", "resume", folder.string(), "--quiet"};
  if (python) {
    // a protocol starts again from its point's scene: its own engine runs keep no checkpoint
    // the sweep knows how to continue
    args = {python_interpreter(),
            "-m",
            "cdpowder.protocol",
            run.protocol.file.string(),
            run.protocol.function,
            run.scene.string(),
            "--out",
            folder.string(),
            "--name",
            run.protocol.name};
  } else if (!run.resume) {
    args = {"cdpowder", command_name(run.command), run.scene.string(),
            "--out",    folder.string(),           "--quiet"};
  }
  if (python || !run.resume) {
    for (const SceneOverride& o : run.overrides) {
      args.emplace_back("--set");
      args.push_back(o.text);
    }
  }
  if (run.checkpoint_every && !python) {
    args.emplace_back("--checkpoint-every");
    args.push_back(fmt::format("{}", *run.checkpoint_every));
  }
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  const std::string log = (folder / "log.txt").string();
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | (run.resume ? O_APPEND : O_TRUNC), 0644);
  posix_spawn_file_actions_adddup2(&files, STDOUT_FILENO, STDERR_FILENO);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attributes, 0);
  std::vector<std::string> variables = child_environment(run, python);
  std::vector<char*> envp;
  envp.reserve(variables.size() + 1);
  for (std::string& v : variables) envp.push_back(v.data());
  envp.push_back(nullptr);
  pid_t pid = 0;
  // a protocol's interpreter is looked up on PATH, as a shell would
  const int failed =
      python
          ? posix_spawnp(&pid, args.front().c_str(), &files, &attributes, argv.data(), envp.data())
          : posix_spawn(&pid, kSelf, &files, &attributes, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&files);
  posix_spawnattr_destroy(&attributes);
  if (failed != 0) {
    error = fmt::format("cannot start {}: {}", python ? args.front() : std::string(kSelf),
                        std::strerror(failed));
    return 0;
  }
  return pid;
}

std::optional<RunSummary> read_sweep_run(const SweepPlan& plan,
                                         const std::filesystem::path& folder) {
  std::optional<RunSummary> summary = read_run_summary(folder / "summary.json");
  if (plan.command != SweepCommand::Python || !summary) return summary;
  const std::optional<ProtocolRecord> record = read_protocol_record(folder);
  if (!record || record->protocol != plan.protocol.name) return std::nullopt;
  summary->scene_toml = record->scene_toml;
  return summary;
}

RunExit run_exit(int status, const std::optional<RunSummary>& summary,
                 const std::string& scene_text) {
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  RunExit out;
  out.fault = code == kExitFault;
  out.unwritten = code == kExitOutputFailed;
  // a run whose output failed wrote its summary, but its folder lacks an output: not finished
  out.counts = (code == 0 || code == kExitNotBlocked) && is_reusable(summary, scene_text);
  return out;
}

std::string last_error_of(const std::filesystem::path& log) {
  std::ifstream in(log);
  std::string line;
  std::string last;
  while (std::getline(in, line)) {
    if (line.starts_with("error: ")) last = line.substr(7);
  }
  return last.empty() ? "a run could not write its outputs, see " + log.string() : last;
}

}  // namespace cdpowder::app
