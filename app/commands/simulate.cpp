// simulate.cpp — the simulate and compact commands: read and validate everything first,
// then run, then write every output atomically. Prints one result line on stdout.
// In an MPI job (`mpirun -np P`, core/ranks.hpp) every rank runs the same steps, sharing the
// tiles of each pass (solver/nlgs/tile_ranks.hpp); rank 0 alone writes the run folder and
// prints, so the outputs are those of one process.
#include "commands/simulate.hpp"

#include "progress.hpp"
#include "run_phase.hpp"
#include "stop_signals.hpp"

#include "cdpowder/analysis/porosity.hpp"
#include "cdpowder/config/config_error.hpp"
#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/core/ranks.hpp"
#include "cdpowder/io/atomic_file.hpp"
#include "cdpowder/io/provenance.hpp"
#include "cdpowder/run/checkpoint_interval.hpp"
#include "cdpowder/run/folder_lock.hpp"
#include "cdpowder/run/run_folder.hpp"
#include "cdpowder/run/run_loop.hpp"
#include "cdpowder/run/run_messages.hpp"
#include "cdpowder/run/state_file.hpp"
#include "cdpowder/setup/scene_setup.hpp"

#include <fmt/format.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string_view>
// sigaction and struct sigaction are POSIX, declared by <signal.h> and not by <csignal>
#include <signal.h>  // NOLINT(modernize-deprecated-headers)

namespace cdpowder::app {

namespace {

/// The first line of a run's log, written before any step (stderr is unbuffered), so a
/// killed run's log says what ran.
void announce(std::string_view what, const Scene& scene, const std::filesystem::path& out,
              std::size_t spheres) {
  std::fprintf(stderr, "%s\n", run_announcement(what, scene, out, spheres).c_str());
  std::fflush(stderr);
}

/// A run between its setup (fresh or continued from a checkpoint) and its outputs.
struct Session {
  Scene scene;
  std::filesystem::path out;
  double initial_porosity = 0.0;
  World world;
  StepWorkspace work{1};
  RunState state;
  std::optional<RunFolder> files;  ///< on rank 0 of an MPI job alone
  std::optional<double> checkpoint_every;
  bool quiet = false;
  ProgressLine* progress = nullptr;  ///< while the run goes: warnings end its line first
};

/// RunFolder's messages: on stderr, after the progress line is ended.
RunFolder::Warn warn_on_stderr(Session& s) {
  return [&s](const std::string& message) {
    if (s.progress != nullptr) s.progress->finish();
    std::fprintf(stderr, "warning: %s\n", message.c_str());
  };
}

/// The exit status of a run that ended so (the messages are run_and_write's).
int exit_status(RunEnding ending) {
  switch (ending) {
    case RunEnding::Failed:
      return kExitFault;
    case RunEnding::Interrupted:
      return kExitInterrupted;
    case RunEnding::NotBlocked:
      return kExitNotBlocked;
  }
  return 0;
}

/// An MPI job's VTK outputs: every rank writes its pieces (run_folder.hpp, write_vtk_pieces)
/// before rank 0 writes their collections and the summary. A rank that cannot write its pieces
/// throws its OutputError (its message names the file); rank 0 then throws one that says so,
/// and the other ranks return false, so no summary is written and every rank fails.
bool write_pieces(const Session& s) {
  std::optional<OutputError> failed;
  try {
    write_vtk_pieces(s.out, s.scene, s.world, s.work.contacts, this_rank(), rank_count());
  } catch (const OutputError& error) {
    failed = error;
  } catch (const std::filesystem::filesystem_error& error) {
    failed = OutputError(error.what());
  }
  if (!any_rank(failed.has_value())) return true;
  if (failed) throw *failed;
  if (this_rank() == 0) {
    throw OutputError(
        "another rank could not write its piece of the VTK outputs (its message "
        "names the file): the run's outputs are not written");
  }
  return false;
}

/// Runs to the end, writes every output and prints the result line; returns the exit code.
int run_and_write(Session& s) {
  const Scene& scene = s.scene;
  World& world = s.world;
  StepWorkspace& work = s.work;
  ProgressLine progress(s.quiet);
  s.progress = &progress;
  const StepObserver observer = [&](const World& w, const StepReport& report, double fraction) {
    if (s.files) s.files->after_step(w, report, work.contacts);
    progress.update(w, report, fraction);
  };
  // every `checkpoint_every` of simulated time the loop is stopped after a step, the state
  // saved, and the loop continued: a loop stopped and continued is the loop never stopped
  // (run_loop.hpp), so checkpoints change no result
  // (at least one step between two checkpoints: with T below Δt, or rounded at t = k T, the
  // next multiple could fall on t itself, and the loop stopped again without a step)
  const auto next_checkpoint = [&] {
    if (!s.checkpoint_every) return std::numeric_limits<double>::infinity();
    const double every = *s.checkpoint_every;
    const double next = (std::floor(world.time / every) + 1.0) * every;
    return next > world.time ? next
                             : std::nextafter(world.time, std::numeric_limits<double>::infinity());
  };
  double checkpoint_at = next_checkpoint();
  RunResult result;
  set_run_phase("stepping", world.bodies.size());
  for (;;) {
    result = run_simulation(world, work, scene.step, scene.run, s.state, observer, [&] {
      return run_stop_requested_on_any_rank() || world.time >= checkpoint_at;
    });
    if (!result.interrupted) break;
    set_run_phase("writing a checkpoint");
    // asked for, or stopped by a signal: either way the state is saved
    if (s.files) s.files->save_checkpoint(scene, world, work, s.state);
    if (run_stop_requested_on_any_rank()) break;
    set_run_phase("stepping");
    checkpoint_at = next_checkpoint();
  }
  progress.finish();
  s.progress = nullptr;
  if (rank_count() > 1 && !write_pieces(s)) return kExitOutputFailed;
  // rank 0 of an MPI job writes and reports; every rank ends with the same exit status
  const bool reports = s.files.has_value();
  if (reports) {
    set_run_phase("writing the outputs");
    // the run steps no more: the outputs' buffers take the memory of the step's scratch
    release_step_scratch(work);
    s.files->finish(scene, world, work, s.state, result, s.initial_porosity);
    std::printf("%s\n", result_line(scene, world, work.contacts, result).c_str());
  }
  const std::optional<RunEndNotice> notice = run_end_notice(scene, world, result, s.out);
  if (!notice) return 0;
  if (reports) {
    // an interrupted run's outputs are written, but incomplete: a notice, not an error
    const bool error = notice->ending != RunEnding::Interrupted;
    std::fprintf(stderr, "%s%s\n", error ? "error: " : "", notice->message.c_str());
  }
  return exit_status(notice->ending);
}

int run_scene(const RunOptions& options, const SceneReadOptions& read_options,
              std::string_view command) {
  // from the start, so that a signal during setup also ends the run cleanly (first step);
  // every stop keeps the run (stop_signals.hpp)
  const StopSignals stop_on_signal(request_run_stop, 0);
  // all input is checked before DIR is touched
  refuse_input_among_outputs(options.out, options.scene, "the scene file");
  if (options.particles) refuse_input_among_outputs(options.out, *options.particles, "--particles");
  SceneReadOptions how = read_options;
  how.particles_file = options.particles;
  Session s;
  set_run_phase("reading the scene");
  s.scene = read_scene(options.scene, command_line_overrides(options.overrides), how);
  s.out = options.out;
  s.checkpoint_every = options.checkpoint_every;
  s.quiet = options.quiet || this_rank() != 0;
  const Scene& scene = s.scene;
  set_run_phase(scene.deposition ? "depositing the spheres" : "reading the spheres",
                scene.deposition ? static_cast<std::size_t>(scene.deposition->spheres) : 0);
  s.world = make_world(scene, [] { return run_stop_requested_on_any_rank(); });
  set_run_phase("setting up the run", s.world.bodies.size());
  s.work = StepWorkspace(scene.step.solver.seed);
  s.initial_porosity = porosity(s.world);
  if (this_rank() != 0) return run_and_write(s);

  std::filesystem::create_directories(options.out);
  // one run per folder at a time: held until the process ends, whatever ends it
  const FolderLock lock(run_lock_file(options.out), "another cdpowder run");
  s.files = RunFolder::begin(options.out, scene, s.world, s.work.contacts, warn_on_stderr(s));
  announce(fmt::format("{} {}", command, options.scene.string()), scene, options.out,
           s.world.bodies.size());
  if (options.checkpoint_every) {
    remember_checkpoint_interval(options.out, *options.checkpoint_every);
  }
  return run_and_write(s);
}

}  // namespace

int run_resume(const ResumeOptions& options) {
  const StopSignals stop_on_signal(request_run_stop, 0);
  const std::filesystem::path& out = options.folder;
  const std::filesystem::path checkpoint = checkpoint_path(out);
  require_checkpoint(out);
  // rank 0 of an MPI job holds the folder for all (every rank reads it, rank 0 writes it)
  std::optional<FolderLock> lock;
  if (this_rank() == 0) lock.emplace(run_lock_file(out), "another cdpowder run");
  set_run_phase("reading the checkpoint");
  SavedRun saved = load_state(checkpoint);  // the checkpoint's own faults first
  require_initial_particles(out);
  // the run's interval, unless this resume gives another (kept for the next resume)
  const std::optional<double> checkpoint_every =
      options.checkpoint_every ? options.checkpoint_every : remembered_checkpoint_interval(out);
  if (const std::string warning =
          other_build_warning(checkpoint, saved.program_version, saved.git_commit);
      !warning.empty() && this_rank() == 0) {
    std::fprintf(stderr, "warning: %s\n", warning.c_str());
  }
  // the scene as the run resolved it, with the spheres it started from (for the initial
  // porosity; the deposit is not made again)
  SceneReadOptions how;
  how.particles_file = out / "initial_particles.csv";
  Session s;
  s.scene = read_scene_text(saved.scene_toml, (out / "scene.toml").string(), {}, out, how);
  s.out = out;
  s.checkpoint_every = checkpoint_every;
  s.quiet = options.quiet || this_rank() != 0;
  s.scene.effective_toml = saved.scene_toml;  // the summary's scene, as the run began it
  // the threads change no bit (solver/nlgs/tiles.hpp), so a resume may take others
  if (options.threads) s.scene.step.solver.threads = *options.threads;
  // the spheres it started from must be the checkpoint's (another run's file would give
  // another initial porosity without a word)
  const World initial = make_world(s.scene);
  require_same_spheres(initial, saved.world, "scene.toml with initial_particles.csv",
                       checkpoint.string());
  require_initial_packing(
      saved.scene_toml, out, initial,
      [](const std::string& message) {
        if (this_rank() == 0) std::fprintf(stderr, "warning: %s\n", message.c_str());
      },
      [] { return run_stop_requested_on_any_rank(); });
  s.initial_porosity = porosity(initial);
  s.work = StepWorkspace(s.scene.step.solver.seed);
  restore_run(std::move(saved), s.scene.run, s.scene.step.solver.dt, s.world, s.work, s.state);
  if (this_rank() != 0) return run_and_write(s);
  announce(fmt::format("resume from step {} (t = {} t0)", s.world.step, s.world.time), s.scene, out,
           s.world.bodies.size());
  s.files = RunFolder::resume(out, s.scene, s.world, s.state, warn_on_stderr(s));
  if (options.checkpoint_every) remember_checkpoint_interval(out, *options.checkpoint_every);
  return run_and_write(s);
}

int run_simulate(const RunOptions& options) {
  return run_scene(options, SceneReadOptions{}, "simulate");
}

int run_compact(const RunOptions& options) {
  SceneReadOptions how;
  how.compaction = true;
  return run_scene(options, how, "compact");
}

}  // namespace cdpowder::app
