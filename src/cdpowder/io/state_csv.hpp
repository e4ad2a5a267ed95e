// state_csv.hpp — the final state as CSV: particles.csv (one row per sphere, readable
// again as a scene's [particles] file) and contacts.csv (one row per candidate contact).
#pragma once

#include "cdpowder/contact/local_problem.hpp"
#include "cdpowder/io/output_sink.hpp"
#include "cdpowder/model/world.hpp"

#include <string>

namespace cdpowder {

/// Columns: id, x, y, z, r, vx, vy, vz, wx, wy, wz, fx, fy, fz, tx, ty, tz, fixed
/// [R, R/t0, 1/t0, F_coh, F_coh R]; after `header` ('#' lines). Into `out` in chunks.
void write_particles_csv(OutputSink& out, const Bodies& bodies, const std::string& header);
std::string particles_csv(const Bodies& bodies, const std::string& header);

/// Columns: a, b (sphere ids; bottom wall −1, piston −2, always as a), nx, ny, nz (from a
/// to b), normal_force (R_n, > 0 repulsive), tx, ty, tz (tangential force R_t), rx, ry, rz
/// (rolling torque T_t), twist (T_n), gap (start-of-step gap g [R]), cohesive (0/1), state
/// (closed: S = R_n + F_c > 0; open otherwise). Forces and torques act on b. Into `out` in
/// chunks.
void write_contacts_csv(OutputSink& out, const Contacts& contacts, const std::string& header);
std::string contacts_csv(const Contacts& contacts, const std::string& header);

}  // namespace cdpowder
