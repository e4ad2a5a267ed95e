// deposit.cpp — the deposit command.
#include "commands/deposit.hpp"

#include "stop_signals.hpp"

#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/run/folder_lock.hpp"
#include "cdpowder/run/run_folder.hpp"
#include "cdpowder/run/run_messages.hpp"
#include "cdpowder/setup/scene_setup.hpp"

#include <atomic>
#include <chrono>
#include <cstdio>

namespace cdpowder::app {

namespace {

/// Set by SIGINT/SIGTERM/SIGHUP: the deposit stops within 256 spheres, writing nothing.
std::atomic<bool> g_stop_requested{false};

extern "C" void request_deposit_stop(int /*signal*/) {
  g_stop_requested.store(true);
}

}  // namespace

int run_deposit(const DepositOptions& options) {
  // one-shot: a second Ctrl-C ends the program at once
  const StopSignals stop_on_signal(request_deposit_stop, SA_RESETHAND);
  refuse_input_among_outputs(options.out, options.scene, "the scene file");
  SceneReadOptions how;
  how.deposition_required = true;
  const Scene scene = read_scene(options.scene, command_line_overrides(options.overrides), how);
  const auto start = std::chrono::steady_clock::now();
  const World world = make_world(scene, [] { return g_stop_requested.load(); });  // deposits
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::filesystem::create_directories(options.out);
  // one writer per folder, as for a run (run/folder_lock.hpp)
  const FolderLock lock(run_lock_file(options.out), "another cdpowder run");
  write_deposit_outputs(options.out, scene, world);

  std::printf("%s\n", deposit_line(world, seconds).c_str());
  return 0;
}

}  // namespace cdpowder::app
