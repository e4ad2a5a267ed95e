// run_folder.hpp — the files of one run in its folder, defined in one place: which they are,
// when each is written (at the start, after steps, at a checkpoint, at the end), and how a
// run continued from a checkpoint picks up the time series and snapshots of the run before.
// The command line and a library user get the same outputs from it (README, "Outputs").
#pragma once

#include "cdpowder/config/scene.hpp"
#include "cdpowder/core/stop_request.hpp"
#include "cdpowder/io/cadence.hpp"
#include "cdpowder/io/timeseries.hpp"
#include "cdpowder/io/vtk.hpp"
#include "cdpowder/model/world.hpp"
#include "cdpowder/run/run_loop.hpp"
#include "cdpowder/solver/step.hpp"

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace cdpowder {

/// The files and folders a run writes into its folder; a sweep's log.txt (written before
/// the run starts) and the run lock are not among them.
inline constexpr std::array<std::string_view, 20> kRunOutputs{
    "summary.json",    "scene.toml",        "initial_particles.csv",
    "particles.csv",   "contacts.csv",      "timeseries.csv",
    "particles.vtp",   "contacts.vtp",      "walls.vtp",
    "particles.pvd",   "contacts.pvd",      "walls.pvd",
    "snapshots",       "failed_state.cdps", "checkpoint.cdps",
    "checkpoint.toml", "particles.pvtp",    "contacts.pvtp",
    "particles",       "contacts"};

/// The outputs every run writes by its end, the summary last: a folder with a summary and
/// without one of these was cut short by a build that wrote the summary first. An MPI job
/// writes particles.pvtp and contacts.pvtp (over its ranks' pieces) for the two .vtp files.
inline constexpr std::array<std::string_view, 8> kFinishedRunOutputs{
    "scene.toml",     "initial_particles.csv", "particles.csv", "contacts.csv",
    "timeseries.csv", "particles.vtp",         "contacts.vtp",  "walls.vtp"};

/// The outputs of kFinishedRunOutputs missing from `folder`: a run is finished only with none
/// missing and its summary in place. A folder without scene.toml (which every run writes
/// first) is a run kept as its summary alone, as results/ keeps them in git: nothing missing.
std::vector<std::string> missing_run_outputs(const std::filesystem::path& folder);

/// The state of an unfinished run, from which it continues (run/state_file.hpp).
std::filesystem::path checkpoint_path(const std::filesystem::path& folder);

/// Where the interval between a run's checkpoints is kept, for the runs that continue it.
std::filesystem::path checkpoint_interval_path(const std::filesystem::path& folder);

/// Throws ConfigError naming `folder` when it holds no checkpoint to continue from (a run keeps
/// one while it is unfinished), saying whether the run has finished.
void require_checkpoint(const std::filesystem::path& folder);

/// Throws ConfigError when the run's starting packing (initial_particles.csv, for the initial
/// porosity) is gone from `folder`: the run cannot be continued.
void require_initial_particles(const std::filesystem::path& folder);

/// Throws StateFileError when `from_file`, the world of initial_particles.csv in `folder`, is
/// not the packing the run began with: the deposit the run's scene (`scene_toml`, the
/// checkpoint's) makes again, or the particles file it names, compared sphere by sphere, bit
/// for bit. Another run's initial_particles.csv would give another initial porosity without a
/// word. When the scene's particles file is gone, `warn` says the check could not be made.
void require_initial_packing(const std::string& scene_toml, const std::filesystem::path& folder,
                             const World& from_file,
                             const std::function<void(const std::string&)>& warn,
                             const StopRequest& stop_requested = {});

/// Throws ConfigError when `input`, a file the run reads (`what`: "the scene file"), is one
/// of the files a run writes in `folder`: the run would remove or overwrite it (found: a
/// scene kept as DIR/scene.toml and run with --out DIR was replaced by the resolved one).
void refuse_input_among_outputs(const std::filesystem::path& folder,
                                const std::filesystem::path& input, std::string_view what);

/// Removes an earlier run's outputs and any temporary file (".NAME.PID.tmp") from `folder`,
/// so a folder never mixes two runs (measured before: a rerun that failed left its new
/// scene.toml beside the old summary.json, and old snapshots outlived later runs). Throws
/// std::filesystem::filesystem_error when one cannot be removed.
void clear_earlier_run(const std::filesystem::path& folder);

/// Removes the temporary files (".NAME.PID.tmp") a killed process left in `folder`, all but
/// those of the time series (a continued run picks the longest of them). Call only while no
/// other process writes into the folder.
void remove_stale_temporaries(const std::filesystem::path& folder);

/// A deposit's outputs in `folder` (created if missing): scene.toml, particles.csv,
/// particles.vtp and its summary.json (run_summary.hpp, deposit_summary_json).
void write_deposit_outputs(const std::filesystem::path& folder, const Scene& scene,
                           const World& world);

/// An MPI job's pieces of the VTK outputs (io/vtk.hpp, write_particles_piece): rank `rank` of
/// `ranks` writes folder/particles/particles_RANK.vtp and folder/contacts/contacts_RANK.vtp,
/// each atomically, with the spheres of its strip of tile rows (sphere_ranks,
/// solver/nlgs/tiles.hpp). Every rank writes its own before rank 0's RunFolder::finish writes
/// the .pvtp files that name them. Throws OutputError when a piece cannot be written.
void write_vtk_pieces(const std::filesystem::path& folder, const Scene& scene, const World& world,
                      const Contacts& contacts, int rank, int ranks);

/// A run's outputs while it runs. Messages for the user (a time series that could not be
/// written, a snapshot missing at a checkpoint) go to `warn`; the library prints nothing.
class RunFolder {
 public:
  using Warn = std::function<void(const std::string& message)>;

  /// A fresh run in `folder` (created if missing): an earlier run's outputs are removed, then
  /// scene.toml and initial_particles.csv written, timeseries.csv opened and, when snapshots
  /// are on, the snapshot at the start written.
  static RunFolder begin(const std::filesystem::path& folder, const Scene& scene,
                         const World& world, const Contacts& contacts, Warn warn);

  /// The run whose checkpoint `folder` holds, with `world` and `state` restored from it:
  /// the time series and the snapshots are cut back to the checkpoint (the rows and
  /// snapshots a run never stopped would have at that step), stale temporaries removed.
  static RunFolder resume(const std::filesystem::path& folder, const Scene& scene,
                          const World& world, const RunState& state, Warn warn);

  RunFolder(RunFolder&&) noexcept;
  RunFolder& operator=(RunFolder&&) noexcept;
  ~RunFolder();

  /// After every step (the run loop's StepObserver): a time-series row and a snapshot when
  /// their cadences say so.
  void after_step(const World& world, const StepReport& report, const Contacts& contacts);

  /// The checkpoint: the time series' rows so far onto the disk, then the state, so the
  /// rows a continued run keeps are all there (io/timeseries.hpp, cut_timeseries).
  void save_checkpoint(const Scene& scene, const World& world, const StepWorkspace& work,
                       const RunState& state);

  /// Every output of the ended run, each written atomically and synced: particles.csv,
  /// contacts.csv, the .vtp files (in an MPI job, rank_count() > 1, the .pvtp files over the
  /// ranks' pieces, which write_vtk_pieces has written), the last snapshot, timeseries.csv, a
  /// failed run's failed_state.cdps (the state at the fault), and summary.json last, once the rest
  /// is on the disk. A finished run (not interrupted) then drops its checkpoint.
  void finish(const Scene& scene, const World& world, const StepWorkspace& work,
              const RunState& state, const RunResult& result, double initial_porosity);

  [[nodiscard]] const std::filesystem::path& folder() const { return folder_; }

  /// The provenance lines the CSV outputs start with.
  [[nodiscard]] const std::string& header() const { return header_; }

 private:
  RunFolder(std::filesystem::path folder, std::string header, Warn warn, VtkFormat vtk_format);

  std::filesystem::path folder_;
  std::string header_;
  Warn warn_;
  std::unique_ptr<TimeseriesWriter> timeseries_;
  VtkSnapshotSeries snapshots_;
  Cadence snapshot_cadence_{0, 0.0};
  std::int64_t last_snapshot_step_ = -1;
};

}  // namespace cdpowder
