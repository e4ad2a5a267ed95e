// run_messages.hpp — the words a run says: the line that opens its log, the result line, why it
// ended early, and the warnings and refusals of a continued run. The command line prints them;
// a library or Python user gets the same text, so both read the same words (the library itself
// never prints).
#pragma once

#include "cdpowder/config/scene.hpp"
#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/model/world.hpp"
#include "cdpowder/run/run_loop.hpp"

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace cdpowder {

/// "cdpowder 1.2.0 (commit abc): compact examples/quick/scene.toml --out runs/quick; 100
/// spheres, seed 1, deposition seed 1, 1 thread": what ran, on one line whatever the names
/// hold, written before any step so that a killed run's log says what ran, and the threads
/// its solve runs on within the process's CPU budget.
std::string run_announcement(std::string_view what, const Scene& scene,
                             const std::filesystem::path& out, std::size_t spheres);

/// "porosity=… sigma_zz/p=… sigma_zz+/p=… sigma_zz-/p=… [blocked=…] steps=… passes/step=…
/// wall=…s": σ normalised by the applied pressure when there is one (the paper's Table 1
/// quantities), in F_coh/R² otherwise.
std::string result_line(const Scene& scene, const World& world, const Contacts& contacts,
                        const RunResult& result);

/// "porosity=0.92737 spheres=1015 height=93.6608 wall=0.001s": a deposit's result line, its
/// porosity and height as physics.md §8.2 measures a deposit, after `seconds` of wall time.
std::string deposit_line(const World& world, double seconds);

/// "MM:SS" below an hour, "H:MM:SS" from an hour on (seconds rounded to the nearest): a
/// wall-clock duration as progress lines show it.
std::string clock_text(double seconds);

/// "t=373.7 Z_P=39.16 E=0.8263 passes/step=35.9 contacts=1782 elapsed 00:30 remaining <= 26:16":
/// a long run's progress after `elapsed_seconds`, `fraction` of its maximum duration done (the
/// remaining time at this pace is an upper bound for a run until blocked; "?" at 0). Z_P and
/// E only with a piston.
std::string progress_text(const World& world, std::size_t contacts, double passes_per_step,
                          double elapsed_seconds, double fraction);

/// How a run ended, when not as asked.
enum class RunEnding {
  Failed,       ///< a fault stopped it (RunResult::fault)
  Interrupted,  ///< stopped on request; a checkpoint continues it
  NotBlocked,   ///< an until-blocked run reached run.max_duration first
};

/// Why the run ended early, with the message that says what to do; empty when it ended as
/// asked. `out` is the run's folder.
struct RunEndNotice {
  RunEnding ending;
  std::string message;
};

std::optional<RunEndNotice> run_end_notice(const Scene& scene, const World& world,
                                           const RunResult& result,
                                           const std::filesystem::path& out);

/// The warning for a checkpoint written by another version or commit: the continued run will
/// not be bit-identical to one never stopped. Empty when this build wrote it.
std::string other_build_warning(const std::filesystem::path& checkpoint,
                                std::string_view program_version, std::string_view git_commit);

}  // namespace cdpowder
