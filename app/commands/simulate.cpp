// simulate.cpp — the simulate and compact commands: read and validate everything first,
// then run, then write every output atomically. Prints one result line on stdout.
#include "commands/simulate.hpp"

#include "folder_lock.hpp"
#include "progress.hpp"
#include "run_folder.hpp"
#include "stop_signals.hpp"

#include "cdpowder/analysis/porosity.hpp"
#include "cdpowder/analysis/stress.hpp"
#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/experiment/run_loop.hpp"
#include "cdpowder/experiment/scene_setup.hpp"
#include "cdpowder/io/atomic_file.hpp"
#include "cdpowder/io/provenance.hpp"
#include "cdpowder/io/state_csv.hpp"
#include "cdpowder/io/state_file.hpp"
#include "cdpowder/io/summary.hpp"
#include "cdpowder/io/timeseries.hpp"
#include "cdpowder/io/vtk.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
// sigaction and struct sigaction are POSIX, declared by <signal.h> and not by <csignal>
#include <signal.h>  // NOLINT(modernize-deprecated-headers)

namespace cdpowder::app {

namespace {

/// Set by SIGINT/SIGTERM: the run stops after the current step and writes its outputs,
/// flagged interrupted, instead of losing them.
std::atomic<bool> g_stop_requested{false};

extern "C" void request_stop(int /*signal*/) {
  g_stop_requested.store(true);
}

/// "porosity=… sigma_zz…" — normalised by the applied pressure when there is one (the
/// paper's Table 1 quantities), in F_coh/R² otherwise.
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
  line += fmt::format(" steps={} sweeps/step={:.1f} wall={:.2f}s", result.steps,
                      static_cast<double>(result.total_sweeps) /
                          static_cast<double>(std::max<std::int64_t>(1, result.steps)),
                      result.wall_seconds);
  return line;
}

int run_scene(const RunOptions& options, const SceneReadOptions& read_options) {
  // from the start, so that a signal during setup also ends the run cleanly (first step)
  // one-shot: a second Ctrl-C during a long step ends the program at once
  const StopSignals stop_on_signal(request_stop, SA_RESETHAND);
  // all input is checked before DIR is touched
  SceneReadOptions how = read_options;
  how.particles_file = options.particles;
  const Scene scene = read_scene(options.scene, options.overrides, how);
  World world = make_world(scene, [] { return g_stop_requested.load(); });
  const double initial_porosity = porosity(world);

  std::filesystem::create_directories(options.out);
  // one run per folder at a time: held until the process ends, whatever ends it
  const FolderLock lock(run_lock_file(options.out), "another cdpowder run");
  clear_earlier_run(options.out);
  const std::string header = provenance_header(scene);
  write_file_atomically(options.out / "scene.toml", scene.effective_toml);
  write_file_atomically(options.out / "initial_particles.csv", particles_csv(world.bodies, header));
  TimeseriesWriter timeseries(options.out / "timeseries.csv", header,
                              Cadence(scene.run.timeseries_every, scene.run.timeseries_interval));

  StepWorkspace work(scene.step.solver.seed);
  VtkSnapshotSeries snapshots(options.out);
  Cadence snapshot_cadence(scene.run.snapshot_every, scene.run.snapshot_interval);
  const bool snapshots_on = snapshot_cadence.enabled();
  std::int64_t last_snapshot_step = world.step;
  if (snapshots_on) {
    snapshots.write(world, work.contacts);  // t = 0, no contacts yet
    snapshot_cadence.due(world);            // and the time cadence starts from there
  }
  ProgressLine progress(options.quiet);
  RunState state;  // kept for the failed state file
  const RunResult result = run_simulation(
      world, work, scene.step, scene.run, state,
      [&](const World& w, const StepReport& report, double fraction) {
        const bool failed_before = timeseries.failed();
        timeseries.record(w, report);
        if (timeseries.failed() && !failed_before) {  // said at once; the run goes on
          progress.finish();
          std::fprintf(stderr,
                       "warning: %s; the run goes on and writes its other outputs at its end\n",
                       timeseries.error().c_str());
        }
        progress.update(w, report, fraction);
        if (snapshots_on && w.step != last_snapshot_step && snapshot_cadence.due(w)) {
          last_snapshot_step = w.step;
          snapshots.write(w, work.contacts);
        }
      },
      [] { return g_stop_requested.load(); });
  progress.finish();
  // the results first, the summary before the larger files, the time series last: a full
  // disk then costs the least (measured before: the time series failed first and stopped
  // everything after it)
  write_file_atomically(options.out / "summary.json",
                        summary_json(scene, world, work.contacts, result, initial_porosity));
  write_file_atomically(options.out / "particles.csv", particles_csv(world.bodies, header));
  write_file_atomically(options.out / "contacts.csv", contacts_csv(work.contacts, header));
  write_file_atomically(options.out / "particles.vtp", particles_vtp(world, &work.contacts));
  write_file_atomically(options.out / "contacts.vtp", contacts_vtp(world, work.contacts));
  if (snapshots_on && world.step != last_snapshot_step) snapshots.write(world, work.contacts);
  timeseries.record(world, result.last, /*force=*/true);
  timeseries.commit();

  if (result.fault) {
    // the state at the fault, to look at or to rerun the step from (io/state_file.hpp)
    save_state(options.out / "failed_state.cdps", scene.effective_toml, world, work, state);
  }

  std::printf("%s\n", result_line(scene, world, work.contacts, result).c_str());
  if (result.fault) {
    std::fprintf(stderr, "error: the run failed: %s; outputs and failed_state.cdps in %s\n",
                 result.fault->message.c_str(), options.out.string().c_str());
    return kExitFault;
  }
  if (result.interrupted) return kExitInterrupted;  // outputs written, but incomplete
  if (scene.run.until_blocked && !result.blocked) {
    std::fprintf(stderr,
                 "error: the packing did not block within run.max_duration = %g t0 (t = %g "
                 "t0); the summary says blocked = false\n",
                 scene.run.max_duration, world.time);
    return kExitNotBlocked;
  }
  return 0;
}

}  // namespace

int run_simulate(const RunOptions& options) {
  return run_scene(options, SceneReadOptions{});
}

int run_compact(const RunOptions& options) {
  SceneReadOptions how;
  how.compaction = true;
  return run_scene(options, how);
}

}  // namespace cdpowder::app
