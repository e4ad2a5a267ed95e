// scene.hpp — everything a `cdpowder simulate` run is made of, as plain structs with
// in-class defaults. read_scene() (scene_reader.hpp) fills and validates them once;
// the engine receives validated values and never re-checks them.
// Units: R = ρ = F_coh = 1 unless stated (physics.md §2); docs/config.md lists every key.
#pragma once

#include "cdpowder/config/deposition_config.hpp"
#include "cdpowder/core/vec3.hpp"
#include "cdpowder/solver/settings.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace cdpowder {

/// [system]: the cell, gravity, the bottom wall and the grain density.
struct SystemConfig {
  double lx = 25.0;             ///< L_x, period along x [R]
  double ly = 25.0;             ///< L_y [R]
  Vec3 gravity = Vec3::Zero();  ///< acceleration of spheres and piston [R/t0²]
  double density = 1.0;         ///< ρ of every sphere [ρ]
  bool bottom_wall = true;      ///< the immobile plane z = 0
};

/// [piston]: the horizontal rigid plate pushed down along −z (physics.md §9).
struct PistonConfig {
  bool enabled = false;
  double mass = 1000.0;  ///< M_P [ρR³] (paper: 1000)
  /// Exactly one of pressure / force sets the constant push; pressure = F/(L_x L_y).
  std::optional<double> pressure;  ///< [F_coh/R²] (paper: 1/400)
  std::optional<double> force;     ///< [F_coh]
  /// Initial Z_P; unset: touching the highest sphere plus start_gap.
  std::optional<double> height;  ///< [R]
  double start_gap = 0.0;        ///< gap above the highest sphere when height is unset [R]
  double velocity = 0.0;         ///< initial V_P [R/t0]

  /// F = pressure × L_x L_y or the given force.
  [[nodiscard]] double push(double area) const {
    return force ? *force : pressure.value_or(0.0) * area;
  }
};

/// [run.blocked]: the piston has come to rest (physics.md §9) when all of these hold at
/// every step of a window of `window` time units.
struct BlockedCriteria {
  double window = 20.0;         ///< [t0]
  double piston_speed = 1e-7;   ///< |V_P| below [R/t0]
  double sphere_speed = 1e-6;   ///< RMS sphere speed below (StepDiagnostics::rms_speed) [R/t0]
  double force_balance = 1e-3;  ///< |Σ R_c→P·e_z − F|/F below [-]
  double height_change = 1e-6;  ///< |ΔZ_P|/Z_P over the window below [-]
  /// Once blocked, one more step is solved to this tolerance (at most final_max_passes
  /// passes), and the stress is measured on its forces [-]
  double final_tolerance = 1e-6;
  int final_max_passes = 20000;
};

/// How the VTK files hold their arrays: text, one tuple a line (readable, diffable), or
/// appended base64-encoded binary (smaller, full precision, faster to load).
enum class VtkFormat { Ascii, Binary, Zlib, Auto };

/// From this many spheres on, VtkFormat::Auto writes zlib: below it, text (readable and
/// diffable; 0.6 MB of particles.vtp at 10 000 spheres), above it the smallest files (a
/// particles.vtp of 16 240 spheres is 1.01 MB as text, 0.44 MB compressed; at 10⁶ spheres text
/// would be 60 MB a file).
inline constexpr std::size_t kZlibFromSpheres = 10000;

/// The format the files of `spheres` spheres are written in: `format`, or for Auto text below
/// kZlibFromSpheres and zlib from there on.
constexpr VtkFormat vtk_format_for(VtkFormat format, std::size_t spheres) {
  if (format != VtkFormat::Auto) return format;
  return spheres < kZlibFromSpheres ? VtkFormat::Ascii : VtkFormat::Zlib;
}

/// [run]: how long to run and how often to record.
struct RunConfig {
  double duration = 10.0;       ///< simulated time when until_blocked is false [t0]
  bool until_blocked = false;   ///< stop at the blocked state (needs an enabled piston)
  double max_duration = 1.0e5;  ///< give up on blocking after this simulated time [t0]
  int timeseries_every = 1;     ///< a timeseries.csv row every K steps
  int snapshot_every = 0;       ///< a VTK snapshot (.vtp + .pvd) every K steps; 0 = none
  /// > 0: a row / a snapshot every this much simulated time instead of every K steps (for
  /// an adaptive Δt, whose steps differ in length) [t0]
  double timeseries_interval = 0.0;
  double snapshot_interval = 0.0;
  /// a step after which any contact overlaps by more than this ends the run as failed
  /// (run_fault.hpp): rigid contacts keep the mean overlap near 1e-3 R (physics.md §17) [R]
  double max_overlap = 0.1;
  VtkFormat vtk_format = VtkFormat::Auto;  ///< of every .vtp the run writes
  BlockedCriteria blocked;
};

/// A whole scene as read from TOML (plus --set overrides).
struct Scene {
  SystemConfig system;
  StepSettings step;  ///< [solver] and [contact], [contact.wall]
  PistonConfig piston;
  RunConfig run;
  /// Where the spheres come from: exactly one of a particles CSV ([particles] file, resolved
  /// against the scene's folder) and a ballistic deposit ([deposition]; its L_x, L_y are
  /// those of [system]).
  std::filesystem::path particles_file;
  std::optional<DepositionConfig> deposition;
  std::filesystem::path source;  ///< the scene file itself
  std::string effective_toml;    ///< the fully resolved scene (defaults filled in) as TOML
};

}  // namespace cdpowder
