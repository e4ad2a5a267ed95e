// cdpowder.hpp — everything a program needs to run cdpowder's experiments as a library:
//
//   #include <cdpowder/cdpowder.hpp>
//   cdpowder::Scene scene = cdpowder::read_scene("scene.toml", {"contact.mu_roll=0.3"},
//                                                {.compaction = true});
//   cdpowder::World world = cdpowder::make_world(scene);   // the deposit, walls and piston
//   cdpowder::StepWorkspace work(scene.step.solver.seed);
//   cdpowder::RunResult result =
//       cdpowder::run_simulation(world, work, scene.step, scene.run, /*observer=*/{});
//   double e = cdpowder::porosity(world);
//
// - scenes: read_scene / read_scene_text (TOML with --set style overrides, every mistake
//   reported at once by ConfigError), or a Scene filled in code (plain structs with the
//   defaults of docs/config.md);
// - the world: make_world (a ballistic deposit or a particles CSV, walls and piston as the
//   scene says), or make_world(scene, spheres) around spheres made in code (Bodies is a
//   structure of arrays; the scene read with {.spheres_from_caller = true});
// - stepping: step() for one time step, run_simulation() to the end of the scene's run (until
//   the blocked state for a compaction), with an observer after every step and a stop request;
// - measurements: porosity, the stress tensors with their compressive and tensile parts,
//   coordination, and every step's accuracy gauges (StepReport::diagnostics);
// - outputs: RunFolder writes the command line's files (CSV, VTK, summary.json), run_summary
//   reads a summary back, save_state / load_state the full engine state (a checkpoint).
//
// The library never prints or exits: errors are exceptions whose messages the command line
// prints as they are. Third-party headers reached from here: Eigen only (Vec3).
#pragma once

#include "cdpowder/analysis/coordination.hpp"
#include "cdpowder/analysis/porosity.hpp"
#include "cdpowder/analysis/sphere_loads.hpp"
#include "cdpowder/analysis/step_diagnostics.hpp"
#include "cdpowder/analysis/stress.hpp"
#include "cdpowder/config/config_error.hpp"
#include "cdpowder/config/scene.hpp"
#include "cdpowder/config/scene_reader.hpp"
#include "cdpowder/contact/contact_view.hpp"
#include "cdpowder/core/stop_request.hpp"
#include "cdpowder/model/world.hpp"
#include "cdpowder/model/world_check.hpp"
#include "cdpowder/run/folder_lock.hpp"
#include "cdpowder/run/run_folder.hpp"
#include "cdpowder/run/run_loop.hpp"
#include "cdpowder/run/run_messages.hpp"
#include "cdpowder/run/run_summary.hpp"
#include "cdpowder/run/state_file.hpp"
#include "cdpowder/setup/deposition.hpp"
#include "cdpowder/setup/scene_setup.hpp"
#include "cdpowder/solver/step.hpp"
#include "cdpowder/version.hpp"
