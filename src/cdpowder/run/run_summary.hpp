// run_summary.hpp — summary.json: the measurements at the end of a run with their accuracy
// gauges (physics.md §17), how the run went, and everything needed to rerun it. Written and
// read here only, with a schema number (docs/outputs.md, "summary.json"), so the sweep, the
// tests and a library user read the same fields the command line wrote.
#pragma once

#include "cdpowder/config/scene.hpp"
#include "cdpowder/core/vec3.hpp"
#include "cdpowder/model/world.hpp"
#include "cdpowder/run/run_fault.hpp"
#include "cdpowder/run/run_loop.hpp"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace cdpowder {

/// The schema summary.json files are written with. 0 is every summary written before the
/// number existed (no "schema" key); they read with the fields they lack as absent
/// (numbers NaN, counts 0, flags false). A change that renames or removes a field, or
/// changes its meaning, raises the number; adding a field does not. Schema 2 names the NLGS
/// pass a pass (`total_passes`, `passes_per_step`, …); 0 and 1 read with their `sweeps` names.
inline constexpr int kRunSummarySchema = 2;

/// A summary.json that cannot be read: not JSON, a field of the wrong type, a required one
/// missing, or a schema newer than this program's. The message names the field.
class SummaryError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Everything summary.json holds, section by section as in the file. Numbers not measured
/// (σ/p without an applied pressure, fields a schema-0 file lacks) are NaN and are written
/// as JSON null.
struct RunSummary {
  int schema = kRunSummarySchema;

  struct Program {
    std::string name = "cdpowder";
    std::string version;
    std::string commit;
    /// where it ran, for reading its timings: the coloured kernel's instruction set
    /// (lanes::kernel_isa_name) and the CPU's model name, family and model (empty where the
    /// system names none); both empty in a summary written before they were recorded
    std::string kernel;
    std::string cpu;
  } program;

  std::uint64_t seed = 0;  ///< solver.seed, the visiting-order stream
  double porosity = 0.0;
  double initial_porosity = 0.0;  ///< the starting packing's (the deposit before compaction)
  double packing_volume = 0.0;    ///< the volume σ is measured over [R³]
  std::size_t spheres = 0;
  double time = 0.0;  ///< [t0]

  struct PistonState {
    bool enabled = false;
    double height = 0.0;            ///< [R]
    double velocity = 0.0;          ///< [R/t0]
    double applied_force = 0.0;     ///< F [F_coh]
    double applied_pressure = 0.0;  ///< F / (L_x L_y) [F_coh/R²]
    double load = 0.0;              ///< F − M_P g_z: what the spheres carry at rest [F_coh]
    double contact_force = 0.0;     ///< Σ R·e_z of the spheres on the piston [F_coh]
    double force_imbalance = 0.0;   ///< |contact_force − load| / load
  } piston;

  struct Stress {
    double volume = 0.0;                    ///< [R³]
    Mat3 sigma = Mat3::Zero();              ///< σ [F_coh/R²]
    Mat3 sigma_compressive = Mat3::Zero();  ///< σ⁺
    Mat3 sigma_tensile = Mat3::Zero();      ///< σ⁻
    std::size_t compressive_contacts = 0;
    std::size_t tensile_contacts = 0;
    double piston_load_per_area = 0.0;    ///< normal force of the spheres on the piston / area
    double bottom_load_per_area = 0.0;    ///< the same on the bottom wall
    double sigma_zz_over_pressure = 0.0;  ///< σzz / p (NaN without an applied pressure)
    double sigma_zz_compressive_over_pressure = 0.0;
    double sigma_zz_tensile_over_pressure = 0.0;
  } stress;

  struct ContactCounts {
    std::size_t candidates = 0;  ///< pairs and wall contacts of the last step
    std::size_t closed = 0;      ///< carrying force (R_n + F_c > 0)
    std::size_t cohesive = 0;    ///< cohesion-active
    double coordination_number = 0.0;
  } contacts;

  struct Accuracy {
    double mean_overlap = 0.0;            ///< [R], at the end
    double max_overlap = 0.0;             ///< [R], at the end
    double max_overlap_during_run = 0.0;  ///< [R], after any step
    double max_net_force = 0.0;           ///< largest net force on a sphere at the end [F_coh]
    double max_cohesive_opening_per_range = 0.0;  ///< largest V_n Δt / d_coh of any step
    double last_step_residual = 0.0;
    double last_step_error_estimate = 0.0;
    bool last_step_converged = false;
    std::int64_t capped_steps = 0;  ///< steps whose NLGS hit max_passes

    /// the static solve of a blocked run at run.blocked.final_tolerance, on whose forces σ
    /// is measured; absent unless blocked
    struct FinalSolve {
      int passes = 0;
      bool converged = false;
      double residual = 0.0;
      double error_estimate = 0.0;
    };

    std::optional<FinalSolve> final_solve;
  } accuracy;

  double kinetic_energy = 0.0;  ///< [F_coh R]
  double max_speed = 0.0;       ///< [R/t0]
  double rms_speed = 0.0;       ///< mass-weighted [R/t0]

  /// The run's energy budget (analysis/energy_budget.hpp, physics.md §17, "The energy budget"), all
  /// in [F_coh R]: piston_work + gravity_work = ΔK + ΔU_coh + dissipated. NaN (null in the file)
  /// and complete false where it is not known: a run continued from a format-1 state file, a scene
  /// with forces the budget leaves out (budget_is_complete), or a summary written before the budget
  /// existed.
  struct Energy {
    bool complete = false;
    double piston_work = 0.0;   ///< F (Z_P,start − Z_P,end), the applied force's
    double gravity_work = 0.0;  ///< −g_z Δ(Σ m z) − g_z M_P ΔZ_P
    double kinetic_start = 0.0;
    double kinetic_end = 0.0;
    double cohesive_start = 0.0;    ///< U_coh of the first step's contacts
    double cohesive_end = 0.0;      ///< U_coh of the last step's (the final solve's) contacts
    std::int64_t bonds_formed = 0;  ///< over the steps after the first
    std::int64_t bonds_broken = 0;
    double breaking_work = 0.0;  ///< Σ over broken bonds of F_coh d_coh (each family's law)
    double dissipated = 0.0;     ///< what is left: W − ΔK − ΔU_coh ≥ 0
  } energy;

  struct Run {
    bool blocked = false;
    /// which test found the rest: "window" (the window mean of the imbalance) or "probe"
    /// (a static probe); empty when not blocked
    std::string blocked_by;
    int probes = 0;
    std::int64_t probe_passes = 0;
    double probe_seconds = 0.0;
    int unbalanced_rest_solves = 0;
    /// why a compaction that came to rest is not blocked (RunResult::not_blocked); empty
    /// otherwise
    std::string not_blocked;
    bool interrupted = false;
    bool failed = false;  ///< a fault ended the run (RunSummary::fault says which)
    bool until_blocked = false;
    std::int64_t steps = 0;
    double dt_min = 0.0;  ///< [t0]
    double dt_max = 0.0;
    std::int64_t repeated_steps = 0;
    std::int64_t repeated_passes = 0;
    std::int64_t total_passes = 0;
    double passes_per_step = 0.0;
    std::int64_t threaded_steps = 0;  ///< this process's steps solved on the threads
    double wall_seconds = 0.0;
    StageTimes stage_seconds{};  ///< summed over the steps, in Stage order
  } run;

  std::optional<RunFault> fault;
  std::string scene_toml;  ///< the fully resolved scene (the "scene" object is its JSON form)
};

/// The energy budget of a run (RunSummary::Energy, physics.md §17, "The energy budget") from its
/// start (RunResult::energy_start), its bond counts, the world it ends on and `contacts`, its
/// last step's (whose gaps give U_coh at the end).
RunSummary::Energy energy_budget(const ContactLaws& laws, const World& world,
                                 const Contacts& contacts, const RunResult& result);

/// The summary of a run that ended in `world` with `contacts` holding its last forces.
/// `initial_porosity` is that of the starting packing.
RunSummary summarise_run(const Scene& scene, const World& world, const Contacts& contacts,
                         const RunResult& result, double initial_porosity);

/// summary.json's text (schema kRunSummarySchema), with the resolved scene also as a JSON
/// object under "scene" so tools need no TOML parser.
std::string run_summary_json(const RunSummary& summary);

/// Reads summary.json's text, any schema up to kRunSummarySchema. Throws SummaryError.
RunSummary parse_run_summary(std::string_view json_text);

/// The summary in `path`; nullopt when the file is missing or is not a complete summary (a
/// run killed while writing one leaves none: outputs are written atomically).
std::optional<RunSummary> read_run_summary(const std::filesystem::path& path);

/// JSON text of a deposit's summary: porosity and height of the deposit (physics.md §8.2),
/// sphere count, the resolved scene, the deposition seed, version and commit, schema.
std::string deposit_summary_json(const Scene& scene, const World& world);

}  // namespace cdpowder
