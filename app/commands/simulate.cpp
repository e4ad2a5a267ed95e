// simulate.cpp — the simulate command: read and validate everything first, then run,
// then write every output atomically. Prints one result line on stdout.
#include "commands/simulate.hpp"

#include "progress.hpp"

#include "cdpowder/analysis/porosity.hpp"
#include "cdpowder/analysis/stress.hpp"
#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/experiment/run_loop.hpp"
#include "cdpowder/experiment/scene_setup.hpp"
#include "cdpowder/io/atomic_file.hpp"
#include "cdpowder/io/provenance.hpp"
#include "cdpowder/io/state_csv.hpp"
#include "cdpowder/io/summary.hpp"
#include "cdpowder/io/timeseries.hpp"

#include <fmt/format.h>

#include <cstdio>

namespace cdpowder::app {

int run_simulate(const SimulateOptions& options) {
  // all input is checked before DIR is touched
  const Scene scene = read_scene(options.scene, options.overrides);
  World world = make_world(scene);

  std::filesystem::create_directories(options.out);
  const std::string header = provenance_header(scene);
  write_file_atomically(options.out / "scene.toml", scene.effective_toml);
  TimeseriesWriter timeseries(options.out / "timeseries.csv", header, scene.run.timeseries_every);

  StepWorkspace work(scene.step.solver.seed);
  ProgressLine progress(options.quiet);
  const RunResult result =
      run_simulation(world, work, scene.step, scene.run,
                     [&](const World& w, const StepReport& report, double fraction) {
                       timeseries.record(w, report);
                       progress.update(w, report, fraction);
                     });
  progress.finish();
  timeseries.record(world, result.last, /*force=*/true);
  timeseries.commit();

  write_file_atomically(options.out / "particles.csv", particles_csv(world.bodies, header));
  write_file_atomically(options.out / "contacts.csv", contacts_csv(work.contacts, header));
  write_file_atomically(options.out / "summary.json",
                        summary_json(scene, world, work.contacts, result));

  const StressTensors sigma = stress_tensors(work.contacts, packing_volume(world));
  std::string line =
      fmt::format("porosity={:.5f} sigma_zz={:.6g} sigma_zz+={:.6g} sigma_zz-={:.6g}",
                  porosity(world), sigma.total(2, 2), sigma.compressive(2, 2), sigma.tensile(2, 2));
  if (scene.run.until_blocked) line += fmt::format(" blocked={}", result.blocked ? "yes" : "no");
  line += fmt::format(" steps={} sweeps/step={:.1f} wall={:.2f}s", result.steps,
                      static_cast<double>(result.total_sweeps) /
                          static_cast<double>(std::max<std::int64_t>(1, result.steps)),
                      result.wall_seconds);
  std::printf("%s\n", line.c_str());
  return 0;
}

}  // namespace cdpowder::app
