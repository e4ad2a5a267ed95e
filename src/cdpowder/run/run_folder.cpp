// run_folder.cpp — a run's files: written at the start, after steps, at checkpoints and at
// the end; picked up again by a continued run (run_folder.hpp).
#include "cdpowder/run/run_folder.hpp"

#include "cdpowder/config/config_error.hpp"
#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/core/ranks.hpp"
#include "cdpowder/io/atomic_file.hpp"
#include "cdpowder/io/provenance.hpp"
#include "cdpowder/io/state_csv.hpp"
#include "cdpowder/run/run_summary.hpp"
#include "cdpowder/run/state_file.hpp"
#include "cdpowder/setup/scene_setup.hpp"
#include "cdpowder/solver/nlgs/tiles.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <optional>
#include <system_error>
#include <utility>
#include <vector>

namespace cdpowder {

namespace {

/// Removes the VTK outputs of the other kind from `folder`: with `pieces` > 1 (an MPI job's
/// .pvtp files) the whole-state particles.vtp and contacts.vtp and any piece beyond the job's
/// ranks; with 0 the .pvtp files and their pieces. A run continued on another number of ranks
/// must not leave an earlier process's files beside its own.
void remove_other_vtk_outputs(const std::filesystem::path& folder, int pieces) {
  for (const char* kind : {"particles", "contacts"}) {
    if (pieces == 0) {
      std::filesystem::remove(folder / fmt::format("{}.pvtp", kind));
      std::filesystem::remove_all(folder / kind);
      continue;
    }
    std::filesystem::remove(folder / fmt::format("{}.vtp", kind));
    for (int r = pieces;; ++r) {
      if (!std::filesystem::remove(folder / kind / fmt::format("{}_{}.vtp", kind, r))) break;
    }
  }
}

/// A temporary file of an atomic write: ".NAME.PID.tmp".
bool is_temporary(const std::string& file) {
  return file.size() > 5 && file.front() == '.' && file.ends_with(".tmp");
}

/// The '#' lines at the top of `file` (the provenance header of a CSV output).
std::string leading_comments(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string header;
  std::string line;
  while (std::getline(in, line) && line.starts_with('#')) header += line + '\n';
  return header;
}

Cadence timeseries_cadence(const Scene& scene) {
  return {scene.run.timeseries_every, scene.run.timeseries_interval};
}

Cadence snapshot_cadence(const Scene& scene) {
  return {scene.run.snapshot_every, scene.run.snapshot_interval};
}

/// The time series of the run before, cut back to the checkpoint after `world.step`: of the
/// final file (an interrupted run committed it) and the temporary files of killed processes,
/// the one that keeps the most rows; the others are removed.
std::unique_ptr<TimeseriesWriter> continue_timeseries(const std::filesystem::path& folder,
                                                      const Scene& scene, const World& world,
                                                      const RunState& state,
                                                      const std::string& header,
                                                      const RunFolder::Warn& warn) {
  const std::filesystem::path final_file = folder / "timeseries.csv";
  std::vector<std::filesystem::path> candidates;
  if (std::filesystem::exists(final_file)) candidates.push_back(final_file);
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with(".timeseries.csv.") && name.ends_with(".tmp")) {
      candidates.push_back(entry.path());
    }
  }
  std::optional<std::filesystem::path> best;
  TimeseriesCut best_cut;
  for (const std::filesystem::path& file : candidates) {
    const TimeseriesCut cut = cut_timeseries(file, world.step);
    if (cut.bad_line > 0) {  // refused by name: dropping the rows after it would lose them
      throw ConfigError(
          {{file.string(), cut.bad_line, 0, "",
            fmt::format("'{}' is not a row of the time series (an edited or damaged line); "
                        "mend or remove it, and resume again",
                        shown(cut.bad_text, 80))}});
    }
    if (cut.has_header && (!best || cut.rows > best_cut.rows)) {
      best = file;
      best_cut = cut;
    }
  }
  std::unique_ptr<TimeseriesWriter> writer;
  if (best) {
    writer =
        std::make_unique<TimeseriesWriter>(final_file, *best, best_cut, timeseries_cadence(scene));
  } else {
    warn(
        fmt::format("{}: no time series of the run before the checkpoint; timeseries.csv "
                    "starts at step {}",
                    folder.string(), world.step));
    writer = std::make_unique<TimeseriesWriter>(final_file, header, timeseries_cadence(scene));
  }
  for (const std::filesystem::path& file : candidates) {
    if (!best || file != *best) std::filesystem::remove(file);
  }
  // the checkpoint's own step: its row, if the cadence had one there
  if (state.result.steps > 0) writer->record(world, state.result.last);
  return writer;
}

}  // namespace

std::filesystem::path checkpoint_path(const std::filesystem::path& folder) {
  return folder / "checkpoint.cdps";
}

std::filesystem::path checkpoint_interval_path(const std::filesystem::path& folder) {
  return folder / "checkpoint.toml";
}

void require_checkpoint(const std::filesystem::path& folder) {
  if (std::filesystem::is_regular_file(checkpoint_path(folder))) return;
  throw ConfigError(
      {{folder.string(), 0, 0, "",
        fmt::format("no checkpoint.cdps to continue from; a run keeps one while it is "
                    "unfinished (written every --checkpoint-every T and when it is stopped by a "
                    "signal){}",
                    std::filesystem::exists(folder / "summary.json") ? ", and this run has finished"
                                                                     : "")}});
}

void require_initial_particles(const std::filesystem::path& folder) {
  if (std::filesystem::is_regular_file(folder / "initial_particles.csv")) return;
  throw ConfigError({{folder.string(), 0, 0, "",
                      "initial_particles.csv is missing: the run's starting packing, which "
                      "resume needs (for the initial porosity); the run cannot be continued"}});
}

void require_initial_packing(const std::string& scene_toml, const std::filesystem::path& folder,
                             const World& from_file,
                             const std::function<void(const std::string&)>& warn,
                             const StopRequest& stop_requested) {
  const std::filesystem::path initial = folder / "initial_particles.csv";
  Scene scene;
  World began;
  try {
    // the scene as the run began: its deposit again (stopped by Ctrl-C as any deposit), or its
    // own particles file
    scene = read_scene_text(scene_toml, (folder / "scene.toml").string(), {}, folder);
    began = make_world(scene, stop_requested);
  } catch (const ConfigError& error) {
    warn(fmt::format("{} could not be checked against the run's own starting packing: {}",
                     initial.string(), error.what()));
    return;
  }
  const Bodies& a = began.bodies;
  const Bodies& b = from_file.bodies;
  std::size_t differs = 0;
  while (differs < a.size() && differs < b.size() && a.position[differs] == b.position[differs] &&
         a.radius[differs] == b.radius[differs]) {
    ++differs;
  }
  if (differs == a.size() && a.size() == b.size()) return;
  // a particles file outside the folder may have changed since the run began: only a deposit,
  // which the scene makes again exactly, decides
  if (!scene.deposition) {
    warn(
        fmt::format("{} differs from the particles file the run's scene names (sphere {}): "
                    "that file changed since the run began, or this is another run's; going "
                    "on with {}",
                    initial.string(), differs, initial.string()));
    return;
  }
  if (a.size() != b.size()) {
    throw StateFileError(fmt::format("{} holds {} spheres, the run began with {}", initial.string(),
                                     b.size(), a.size()));
  }
  const std::size_t i = differs;
  throw StateFileError(fmt::format(
      "{} is not the packing this run began with: sphere {} is at ({}, {}, {}) with radius {} in "
      "it, at ({}, {}, {}) with radius {} in the deposit the run's scene makes again (another "
      "run's file would give another initial porosity)",
      initial.string(), i, b.position[i].x(), b.position[i].y(), b.position[i].z(), b.radius[i],
      a.position[i].x(), a.position[i].y(), a.position[i].z(), a.radius[i]));
}

void refuse_input_among_outputs(const std::filesystem::path& folder,
                                const std::filesystem::path& input, std::string_view what) {
  // where the input is, links followed (a link elsewhere to DIR/scene.toml is DIR/scene.toml)
  std::error_code error;
  const std::filesystem::path in = std::filesystem::weakly_canonical(input, error);
  if (error) return;
  const std::string name = in.filename().string();
  if (std::find(kRunOutputs.begin(), kRunOutputs.end(), name) == kRunOutputs.end()) return;
  const std::filesystem::path out = std::filesystem::weakly_canonical(folder, error);
  if (error || in.parent_path() != out) return;
  throw ConfigError({{input.string(), 0, 0, "",
                      fmt::format("{} is the output folder's own {}, which the run writes (an "
                                  "earlier run's is removed first): copy it elsewhere or "
                                  "choose another --out",
                                  what, name)}});
}

void clear_earlier_run(const std::filesystem::path& folder) {
  for (const std::string_view name : kRunOutputs) std::filesystem::remove_all(folder / name);
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (is_temporary(entry.path().filename().string())) std::filesystem::remove(entry.path());
  }
}

void remove_stale_temporaries(const std::filesystem::path& folder) {
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const std::string file = entry.path().filename().string();
    if (is_temporary(file) && !file.starts_with(".timeseries.csv.")) {
      std::filesystem::remove(entry.path());
    }
  }
}

void write_vtk_pieces(const std::filesystem::path& folder, const Scene& scene, const World& world,
                      const Contacts& contacts, int rank, int ranks) {
  const VtkFormat vtk = vtk_format_for(scene.run.vtk_format, world.bodies.size());
  const std::vector<int> sphere_rank =
      sphere_ranks(world.bodies.position, world.box, world.bodies.max_radius(),
                   scene.step.solver.tile_width, ranks);
  for (const char* kind : {"particles", "contacts"}) {
    std::filesystem::create_directories(folder / kind);
  }
  write_file_atomically(folder / "particles" / fmt::format("particles_{}.vtp", rank),
                        [&](OutputSink& sink) {
                          write_particles_piece(sink, world, &contacts, sphere_rank, rank, vtk);
                        });
  write_file_atomically(folder / "contacts" / fmt::format("contacts_{}.vtp", rank),
                        [&](OutputSink& sink) {
                          write_contacts_piece(sink, world, contacts, sphere_rank, rank, vtk);
                        });
}

void write_deposit_outputs(const std::filesystem::path& folder, const Scene& scene,
                           const World& world) {
  std::filesystem::create_directories(folder);
  const std::string header = provenance_header(scene);
  write_file_atomically(folder / "scene.toml", scene.effective_toml);
  write_file_atomically(folder / "particles.csv",
                        [&](OutputSink& sink) { write_particles_csv(sink, world.bodies, header); });
  const VtkFormat vtk = vtk_format_for(scene.run.vtk_format, world.bodies.size());
  write_file_atomically(folder / "particles.vtp",
                        [&](OutputSink& sink) { write_particles_vtp(sink, world, nullptr, vtk); });
  write_file_atomically(folder / "walls.vtp",
                        [&](OutputSink& sink) { write_walls_vtp(sink, world, vtk); });
  write_file_atomically(folder / "summary.json", deposit_summary_json(scene, world));
}

RunFolder::RunFolder(std::filesystem::path folder, std::string header, Warn warn,
                     VtkFormat vtk_format)
    : folder_(std::move(folder)),
      header_(std::move(header)),
      warn_(std::move(warn)),
      snapshots_(folder_, vtk_format) {
  if (!warn_) warn_ = [](const std::string&) {};
}

RunFolder::RunFolder(RunFolder&&) noexcept = default;
RunFolder& RunFolder::operator=(RunFolder&&) noexcept = default;
RunFolder::~RunFolder() = default;

RunFolder RunFolder::begin(const std::filesystem::path& folder, const Scene& scene,
                           const World& world, const Contacts& contacts, Warn warn) {
  std::filesystem::create_directories(folder);
  clear_earlier_run(folder);
  RunFolder f(folder, provenance_header(scene), std::move(warn),
              vtk_format_for(scene.run.vtk_format, world.bodies.size()));
  write_file_atomically(folder / "scene.toml", scene.effective_toml);
  write_file_atomically(folder / "initial_particles.csv", [&](OutputSink& sink) {
    write_particles_csv(sink, world.bodies, f.header_);
  });
  f.timeseries_ = std::make_unique<TimeseriesWriter>(folder / "timeseries.csv", f.header_,
                                                     timeseries_cadence(scene));
  f.snapshot_cadence_ = snapshot_cadence(scene);
  f.last_snapshot_step_ = world.step;
  if (f.snapshot_cadence_.enabled()) {
    f.snapshots_.write(world, contacts);  // t = 0, no contacts yet
    f.snapshot_cadence_.due(world);       // and the time cadence starts from there
  }
  return f;
}

RunFolder RunFolder::resume(const std::filesystem::path& folder, const Scene& scene,
                            const World& world, const RunState& state, Warn warn) {
  RunFolder f(folder, leading_comments(folder / "initial_particles.csv"), std::move(warn),
              vtk_format_for(scene.run.vtk_format, world.bodies.size()));
  remove_stale_temporaries(folder);  // e.g. a .pvd a killed run was writing
  if (std::filesystem::is_directory(folder / "snapshots")) {
    remove_stale_temporaries(folder / "snapshots");
  }
  f.timeseries_ = continue_timeseries(folder, scene, world, state, f.header_, f.warn_);

  // the snapshots of the run before, cut back to the checkpoint: those before its time, and
  // the one at its time if the cadence had one there (not the extra one an interrupted run
  // writes at its end)
  f.snapshot_cadence_ = snapshot_cadence(scene);
  f.last_snapshot_step_ = -1;
  if (!f.snapshot_cadence_.enabled()) return f;
  const std::vector<double> times = f.snapshots_.read_earlier();
  std::size_t kept = 0;
  while (kept < times.size() && times[kept] < world.time) ++kept;
  if (kept > 0) f.snapshot_cadence_.resume_after(times[kept - 1]);
  if (f.snapshot_cadence_.due(world)) {
    if (kept < times.size() && times[kept] == world.time) {
      ++kept;
    } else {
      f.warn_(fmt::format("{}: the snapshot at the checkpoint's step is missing", folder.string()));
    }
    f.last_snapshot_step_ = world.step;
  }
  f.snapshots_.keep_earlier(kept);
  return f;
}

void RunFolder::after_step(const World& world, const StepReport& report, const Contacts& contacts) {
  const bool failed_before = timeseries_->failed();
  timeseries_->record(world, report);
  if (timeseries_->failed() && !failed_before) {  // said at once; the run goes on
    warn_(fmt::format("{}; the run goes on and writes its other outputs at its end",
                      timeseries_->error()));
  }
  if (snapshot_cadence_.enabled() && world.step != last_snapshot_step_ &&
      snapshot_cadence_.due(world)) {
    last_snapshot_step_ = world.step;
    snapshots_.write(world, contacts);
  }
}

void RunFolder::save_checkpoint(const Scene& scene, const World& world, const StepWorkspace& work,
                                const RunState& state) {
  timeseries_->flush();
  save_state(checkpoint_path(folder_), scene.effective_toml, world, work, state);
}

void RunFolder::finish(const Scene& scene, const World& world, const StepWorkspace& work,
                       const RunState& state, const RunResult& result, double initial_porosity) {
  // every output first and the summary last, once the rest is on the disk: a run killed
  // while it writes them has no summary, so it is not taken for finished (a sweep runs it
  // again, or resume continues it from its checkpoint). Each is handed to its file as it is
  // made, so no file is held whole beside the state.
  write_file_atomically(folder_ / "particles.csv", [&](OutputSink& sink) {
    write_particles_csv(sink, world.bodies, header_);
  });
  write_file_atomically(folder_ / "contacts.csv", [&](OutputSink& sink) {
    write_contacts_csv(sink, work.contacts, header_);
  });
  const VtkFormat vtk = vtk_format_for(scene.run.vtk_format, world.bodies.size());
  if (const int pieces = rank_count(); pieces > 1) {
    // the ranks' pieces are on the disk (write_vtk_pieces): their collections, and no file of
    // a run continued from an earlier process on other ranks
    write_file_atomically(folder_ / "particles.pvtp", particles_pvtp(pieces, true));
    write_file_atomically(folder_ / "contacts.pvtp", contacts_pvtp(pieces));
    remove_other_vtk_outputs(folder_, pieces);
  } else {
    write_file_atomically(folder_ / "particles.vtp", [&](OutputSink& sink) {
      write_particles_vtp(sink, world, &work.contacts, vtk);
    });
    write_file_atomically(folder_ / "contacts.vtp", [&](OutputSink& sink) {
      write_contacts_vtp(sink, world, work.contacts, vtk);
    });
    remove_other_vtk_outputs(folder_, 0);
  }
  write_file_atomically(folder_ / "walls.vtp",
                        [&](OutputSink& sink) { write_walls_vtp(sink, world, vtk); });
  if (snapshot_cadence_.enabled() && world.step != last_snapshot_step_) {
    snapshots_.write(world, work.contacts);
  }
  timeseries_->record(world, result.last, /*force=*/true);
  const auto write_summary = [&] {
    write_file_atomically(
        folder_ / "summary.json",
        run_summary_json(summarise_run(scene, world, work.contacts, result, initial_porosity)));
  };
  try {
    timeseries_->commit();
  } catch (const OutputError&) {
    // the run's results are not lost with its time series: the summary is written, and the
    // folder, without timeseries.csv, reads as incomplete (missing_run_outputs); a sweep runs
    // it again once it can write
    write_summary();
    throw;
  }
  if (result.fault) {
    // the state at the fault, to look at or to rerun the step from (run/state_file.hpp)
    save_state(folder_ / "failed_state.cdps", scene.effective_toml, world, work, state);
  }
  write_summary();
  // a finished run (done, not blocked, failed) keeps no checkpoint: only an unfinished one
  // can be continued, and the folder ends as a run never stopped leaves it
  if (!result.interrupted) {
    std::filesystem::remove(checkpoint_path(folder_));
    std::filesystem::remove(checkpoint_interval_path(folder_));
  }
}

std::vector<std::string> missing_run_outputs(const std::filesystem::path& folder) {
  std::vector<std::string> missing;
  // a run kept as its summary alone (results/ in git keeps no other file) is a record, not a
  // run cut short: every run writes scene.toml first
  if (!std::filesystem::exists(folder / "scene.toml")) return missing;
  for (const std::string_view name : kFinishedRunOutputs) {
    if (std::filesystem::is_regular_file(folder / name)) continue;
    // an MPI job's collection over its ranks' pieces stands for the .vtp file
    const std::string collection = fmt::format("{}.pvtp", name.substr(0, name.find('.')));
    if (name.ends_with(".vtp") && std::filesystem::is_regular_file(folder / collection)) continue;
    missing.emplace_back(name);
  }
  return missing;
}

}  // namespace cdpowder
