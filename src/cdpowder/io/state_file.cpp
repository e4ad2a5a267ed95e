// state_file.cpp — sections in a fixed order, each behind a four-letter tag, and an FNV-1a
// checksum of everything before it at the end.
#include "cdpowder/io/state_file.hpp"

#include "cdpowder/io/atomic_file.hpp"
#include "cdpowder/version.hpp"

#include <fmt/format.h>

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace cdpowder {

namespace {

// Bytes of the smallest record of each kind: a corrupted count is refused before anything
// is allocated for it (ByteReader::count).
constexpr std::size_t kDoubleBytes = 8;
constexpr std::size_t kCachedActionBytes = 8 + 8 * 8 + 1;

template <typename T, typename Write>
void write_array(ByteWriter& out, const std::vector<T>& values, Write write) {
  out.u64(values.size());
  for (const T& v : values) write(v);
}

void write_action(ByteWriter& out, const ContactAction& a) {
  out.f64(a.normal_force);
  out.vec3(a.tangential_force);
  out.vec3(a.rolling_torque);
  out.f64(a.twisting_torque);
}

ContactAction read_action(ByteReader& in) {
  ContactAction a;
  a.normal_force = in.f64();
  a.tangential_force = in.vec3();
  a.rolling_torque = in.vec3();
  a.twisting_torque = in.f64();
  return a;
}

void write_entries(ByteWriter& out, const std::vector<CachedAction>& entries) {
  write_array(out, entries, [&](const CachedAction& e) {
    out.u64(e.key);
    write_action(out, e.action);
    out.boolean(e.cohesive);
  });
}

std::vector<CachedAction> read_entries(ByteReader& in, std::string_view family) {
  std::vector<CachedAction> entries(in.count(kCachedActionBytes));
  for (std::size_t k = 0; k < entries.size(); ++k) {
    CachedAction& e = entries[k];
    e.key = in.u64();
    e.action = read_action(in);
    e.cohesive = in.boolean();
    // the warm start's merge join needs ascending keys (action_cache.hpp)
    if (k > 0 && e.key <= entries[k - 1].key) {
      in.fail(fmt::format("the {} actions are not in ascending key order", family));
    }
  }
  return entries;
}

void write_solver_stats(ByteWriter& out, const SolverStats& s) {
  out.i64(s.sweeps);
  out.boolean(s.converged);
  out.f64(s.residual);
  out.f64(s.contraction);
  out.f64(s.error_estimate);
  out.f64(s.relative_change);
  out.f64(s.force_scale);
}

SolverStats read_solver_stats(ByteReader& in) {
  SolverStats s;
  s.sweeps = static_cast<int>(in.i64());
  s.converged = in.boolean();
  s.residual = in.f64();
  s.contraction = in.f64();
  s.error_estimate = in.f64();
  s.relative_change = in.f64();
  s.force_scale = in.f64();
  return s;
}

void write_step_report(ByteWriter& out, const StepReport& r) {
  out.f64(r.dt);
  write_solver_stats(out, r.solver);
  const StepDiagnostics& d = r.diagnostics;
  out.u64(d.contacts);
  out.u64(d.closed_contacts);
  out.u64(d.cohesive_contacts);
  for (const double x : {d.mean_overlap, d.max_overlap, d.kinetic_energy, d.max_speed, d.rms_speed,
                         d.piston_contact_force, d.piston_imbalance, d.max_net_force,
                         d.max_cohesive_opening_speed, d.max_cohesive_opening_per_range}) {
    out.f64(x);
  }
  for (const double t : r.times) out.f64(t);
}

StepReport read_step_report(ByteReader& in) {
  StepReport r;
  r.dt = in.f64();
  r.solver = read_solver_stats(in);
  StepDiagnostics& d = r.diagnostics;
  d.contacts = in.u64();
  d.closed_contacts = in.u64();
  d.cohesive_contacts = in.u64();
  for (double* x : {&d.mean_overlap, &d.max_overlap, &d.kinetic_energy, &d.max_speed, &d.rms_speed,
                    &d.piston_contact_force, &d.piston_imbalance, &d.max_net_force,
                    &d.max_cohesive_opening_speed, &d.max_cohesive_opening_per_range}) {
    *x = in.f64();
  }
  for (double& t : r.times) t = in.f64();
  return r;
}

void write_run_result(ByteWriter& out, const RunResult& r) {
  out.boolean(r.blocked);
  out.boolean(r.interrupted);
  out.i64(r.steps);
  out.i64(r.total_sweeps);
  out.i64(r.capped_steps);
  out.f64(r.min_dt);
  out.f64(r.max_dt);
  out.i64(r.repeated_steps);
  out.i64(r.repeated_sweeps);
  out.f64(r.max_overlap_seen);
  out.f64(r.max_cohesive_opening_per_range);
  out.f64(r.wall_seconds);
  for (const double t : r.stage_seconds) out.f64(t);
  write_step_report(out, r.last);
  out.boolean(r.final_solve.has_value());
  if (r.final_solve) write_solver_stats(out, *r.final_solve);
  out.i64(r.probes);
  out.i64(r.probe_sweeps);
  out.f64(r.probe_seconds);
  out.boolean(r.blocked_by_probe);
  out.i64(r.unbalanced_rest_solves);
}

RunResult read_run_result(ByteReader& in) {
  RunResult r;
  r.blocked = in.boolean();
  r.interrupted = in.boolean();
  r.steps = in.i64();
  r.total_sweeps = in.i64();
  r.capped_steps = in.i64();
  r.min_dt = in.f64();
  r.max_dt = in.f64();
  r.repeated_steps = in.i64();
  r.repeated_sweeps = in.i64();
  r.max_overlap_seen = in.f64();
  r.max_cohesive_opening_per_range = in.f64();
  r.wall_seconds = in.f64();
  for (double& t : r.stage_seconds) t = in.f64();
  r.last = read_step_report(in);
  if (in.boolean()) r.final_solve = read_solver_stats(in);
  r.probes = static_cast<int>(in.i64());
  r.probe_sweeps = in.i64();
  r.probe_seconds = in.f64();
  r.blocked_by_probe = in.boolean();
  r.unbalanced_rest_solves = static_cast<int>(in.i64());
  return r;
}

std::string rng_text(const Rng& rng) {
  std::ostringstream text;
  text << rng;  // pcg-cpp's own exact text form: multiplier, increment, state
  return text.str();
}

Rng read_rng(ByteReader& in) {
  std::istringstream text(in.string());
  Rng rng;
  text >> rng;
  if (text.fail()) in.fail("the sweep-order stream cannot be read back");
  return rng;
}

}  // namespace

void write_world(ByteWriter& out, const World& world) {
  const Bodies& b = world.bodies;
  out.tag("WRLD");
  out.u64(b.size());
  const auto vecs = [&](const std::vector<Vec3>& values) {
    for (const Vec3& v : values) out.vec3(v);
  };
  const auto doubles = [&](const std::vector<double>& values) {
    for (const double v : values) out.f64(v);
  };
  vecs(b.position);
  vecs(b.velocity);
  vecs(b.angular_velocity);
  doubles(b.radius);
  doubles(b.inverse_mass);
  doubles(b.inverse_inertia);
  vecs(b.external_force);
  vecs(b.external_torque);
  for (const std::uint8_t f : b.fixed) out.u8(f);
  const Piston& piston = world.walls.piston;
  out.boolean(world.walls.bottom.enabled);
  out.boolean(piston.enabled);
  out.f64(piston.height);
  out.f64(piston.velocity);
  out.f64(piston.mass);
  out.f64(piston.force);
  out.f64(world.box.lx);
  out.f64(world.box.ly);
  out.vec3(world.gravity);
  out.f64(world.time);
  out.i64(world.step);
}

World read_world(ByteReader& in) {
  World world;
  Bodies& b = world.bodies;
  in.tag("WRLD");
  // per sphere: 5 vectors (15 doubles) and 3 scalars, and the fixed flag
  constexpr std::size_t kSphereBytes = 18 * kDoubleBytes + 1;
  const std::size_t n = in.count(kSphereBytes);
  const auto vecs = [&](std::vector<Vec3>& values) {
    values.resize(n);
    for (Vec3& v : values) v = in.vec3();
  };
  const auto doubles = [&](std::vector<double>& values) {
    values.resize(n);
    for (double& v : values) v = in.f64();
  };
  vecs(b.position);
  vecs(b.velocity);
  vecs(b.angular_velocity);
  doubles(b.radius);
  doubles(b.inverse_mass);
  doubles(b.inverse_inertia);
  vecs(b.external_force);
  vecs(b.external_torque);
  b.fixed.resize(n);
  for (std::uint8_t& f : b.fixed) f = in.u8();
  Piston& piston = world.walls.piston;
  world.walls.bottom.enabled = in.boolean();
  piston.enabled = in.boolean();
  piston.height = in.f64();
  piston.velocity = in.f64();
  piston.mass = in.f64();
  piston.force = in.f64();
  world.box.lx = in.f64();
  world.box.ly = in.f64();
  world.gravity = in.vec3();
  world.time = in.f64();
  world.step = in.i64();
  return world;
}

void write_actions(ByteWriter& out, const ActionCache& actions) {
  out.tag("ACTS");
  write_entries(out, actions.pair_entries());
  write_entries(out, actions.wall_entries());
}

ActionCache read_actions(ByteReader& in) {
  in.tag("ACTS");
  std::vector<CachedAction> pairs = read_entries(in, "sphere pair");
  std::vector<CachedAction> walls = read_entries(in, "wall");
  ActionCache cache;
  cache.restore(std::move(pairs), std::move(walls));
  return cache;
}

std::string encode_state(std::string_view scene_toml, const World& world, const StepWorkspace& work,
                         const RunState& run) {
  ByteWriter out;
  out.tag(kStateFileMagic.substr(0, 4));
  out.tag(kStateFileMagic.substr(4, 4));
  out.u32(kStateFormatVersion);
  out.string(kVersion);
  out.string(kGitCommit);
  out.tag("SCEN");
  out.string(scene_toml);
  write_world(out, world);
  write_actions(out, work.action_cache);
  out.tag("RNGS");
  out.string(rng_text(work.solver.rng));
  out.tag("RUNS");
  write_run_result(out, run.result);
  out.boolean(run.detector.has_value());
  if (run.detector) {
    const BlockedStateDetector::Memory memory = run.detector->memory();
    out.f64(memory.clock);
    out.f64(memory.time_held);
    out.i64(memory.steps_held);
    write_array(out, memory.entries, [&](const BlockedStateDetector::Entry& e) {
      out.f64(e.time);
      out.f64(e.height);
      out.f64(e.imbalance);
    });
  }
  out.f64(run.last_rest_check);
  out.f64(run.last_probe);
  out.i64(run.deferred_windows);
  out.boolean(run.probing);
  out.boolean(run.started);
  out.f64(run.start_time);
  out.f64(run.dt);
  out.tag("SUM ");
  std::string bytes = out.bytes();
  ByteWriter checksum;
  checksum.u64(fnv1a64(bytes));
  bytes += checksum.bytes();
  return bytes;
}

SavedRun decode_state(std::string_view bytes, const std::string& source) {
  ByteReader in(bytes, source);
  if (bytes.substr(0, kStateFileMagic.size()) != kStateFileMagic) {
    in.fail("not a cdpowder state file (it does not start with CDPSTATE)");
  }
  in.tag(kStateFileMagic.substr(0, 4));
  in.tag(kStateFileMagic.substr(4, 4));
  SavedRun saved;
  saved.format_version = in.u32();
  if (saved.format_version != kStateFormatVersion) {
    in.fail(fmt::format("state format {}; this build of cdpowder reads format {} only",
                        saved.format_version, kStateFormatVersion));
  }
  // the checksum before anything else: a damaged file is named as damaged, not as whatever
  // field the damage happened to hit
  if (bytes.size() < 16) in.fail("the file ends early: truncated");
  ByteReader tail(bytes.substr(bytes.size() - 8), source);
  if (tail.u64() != fnv1a64(bytes.substr(0, bytes.size() - 8))) {
    in.fail("the checksum does not match: the file is truncated or damaged");
  }
  saved.program_version = in.string();
  saved.git_commit = in.string();
  in.tag("SCEN");
  saved.scene_toml = in.string();
  saved.world = read_world(in);
  saved.actions = read_actions(in);
  in.tag("RNGS");
  saved.sweep_order = read_rng(in);
  in.tag("RUNS");
  saved.result = read_run_result(in);
  if (in.boolean()) {
    BlockedStateDetector::Memory memory;
    memory.clock = in.f64();
    memory.time_held = in.f64();
    memory.steps_held = in.i64();
    memory.entries.resize(in.count(3 * kDoubleBytes));
    for (BlockedStateDetector::Entry& e : memory.entries) {
      e.time = in.f64();
      e.height = in.f64();
      e.imbalance = in.f64();
    }
    saved.detector = std::move(memory);
  }
  saved.last_rest_check = in.f64();
  saved.last_probe = in.f64();
  saved.deferred_windows = static_cast<int>(in.i64());
  saved.probing = in.boolean();
  saved.started = in.boolean();
  saved.start_time = in.f64();
  saved.dt = in.f64();
  in.tag("SUM ");
  in.u64();
  if (!in.at_end()) in.fail("unexpected bytes after the checksum");
  return saved;
}

void save_state(const std::filesystem::path& path, std::string_view scene_toml, const World& world,
                const StepWorkspace& work, const RunState& run) {
  write_file_atomically(path, encode_state(scene_toml, world, work, run));
}

SavedRun load_state(const std::filesystem::path& path) {
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  std::ifstream file(path, std::ios::binary);
  if (error || !file) {
    throw StateFileError(fmt::format("{}: cannot open the state file{}", path.string(),
                                     error ? ": " + error.message() : std::string()));
  }
  std::string bytes(static_cast<std::size_t>(size), '\0');
  file.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (static_cast<std::size_t>(file.gcount()) != bytes.size()) {
    throw StateFileError(fmt::format("{}: cannot read the state file", path.string()));
  }
  return decode_state(bytes, path.string());
}

void restore_run(SavedRun saved, const RunConfig& run, double dt, World& world, StepWorkspace& work,
                 RunState& state) {
  state = RunState{};
  state.result = saved.result;
  if (saved.detector) {
    state.detector.emplace(run.blocked, dt);
    try {
      state.detector->restore(*saved.detector);
    } catch (const std::invalid_argument& mismatch) {
      throw StateFileError(
          fmt::format("the saved run does not fit this scene: {}", mismatch.what()));
    }
  }
  state.last_rest_check = saved.last_rest_check;
  state.last_probe = saved.last_probe;
  state.deferred_windows = saved.deferred_windows;
  state.probing = saved.probing;
  state.started = saved.started;
  state.start_time = saved.start_time;
  state.dt = saved.dt;
  world = std::move(saved.world);
  work.action_cache = std::move(saved.actions);
  work.solver.rng = saved.sweep_order;
}

}  // namespace cdpowder
