// state_file.cpp — sections in a fixed order, each behind a four-letter tag, and an FNV-1a
// checksum of everything before it at the end.
#include "cdpowder/run/state_file.hpp"

#include "cdpowder/io/atomic_file.hpp"
#include "cdpowder/model/world_check.hpp"
#include "cdpowder/version.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace cdpowder {

namespace {

// Bytes of the smallest record of each kind: a corrupted count is refused before anything
// is allocated for it (ByteReader::count).
constexpr std::size_t kDoubleBytes = 8;
constexpr std::size_t kCachedActionBytes = 8 + 8 * kDoubleBytes + 1;
constexpr std::size_t kWindowEntryBytes = 3 * kDoubleBytes;
// per sphere: 5 vectors (15 doubles) and 3 scalars, and the fixed flag
constexpr std::size_t kSphereBytes = 18 * kDoubleBytes + 1;

// Every section is written and read by one list of its fields, a template over Encode or
// Decode: the reader cannot fall out of step with the writer. Encode takes the fields as
// const, Decode assigns them.
struct Encode {
  ByteWriter& out;

  /// Whether the file has the fields added in format `version`: every file written now has.
  [[nodiscard]] static bool has(std::uint32_t /*version*/) { return true; }

  void operator()(const double& x) { out.f64(x); }

  void operator()(const Vec3& x) { out.vec3(x); }

  void operator()(const bool& x) { out.boolean(x); }

  void operator()(const int& x) { out.i64(x); }

  void operator()(const std::int64_t& x) { out.i64(x); }

  void operator()(const std::uint64_t& x) { out.u64(x); }

  void operator()(const std::uint8_t& x) { out.u8(x); }

  template <typename T, std::size_t N>
  void operator()(const std::array<T, N>& values) {
    for (const T& x : values) (*this)(x);
  }

  void tag(std::string_view four_letters) { out.tag(four_letters); }

  /// A length and the items.
  template <typename T, typename Fields>
  void array(const std::vector<T>& values, std::size_t /*min_item_bytes*/, Fields fields) {
    out.u64(values.size());
    for (const T& v : values) fields(v);
  }

  /// The items of an array whose length was written before (arrays of one length).
  template <typename T>
  void items(const std::vector<T>& values, std::size_t /*n*/) {
    for (const T& v : values) (*this)(v);
  }

  std::size_t length(std::size_t n, std::size_t /*min_item_bytes*/) {
    out.u64(n);
    return n;
  }

  template <typename T, typename Fields>
  void optional(const std::optional<T>& value, Fields fields) {
    out.boolean(value.has_value());
    if (value) fields(*value);
  }
};

struct Decode {
  ByteReader& in;
  std::uint32_t format = kStateFormatVersion;  ///< the file's

  /// Whether the file has the fields added in format `version`.
  [[nodiscard]] bool has(std::uint32_t version) const { return format >= version; }

  void operator()(double& x) { x = in.f64(); }

  void operator()(Vec3& x) { x = in.vec3(); }

  void operator()(bool& x) { x = in.boolean(); }

  void operator()(int& x) { x = static_cast<int>(in.i64()); }

  void operator()(std::int64_t& x) { x = in.i64(); }

  void operator()(std::uint64_t& x) { x = in.u64(); }

  void operator()(std::uint8_t& x) { x = in.u8(); }

  template <typename T, std::size_t N>
  void operator()(std::array<T, N>& values) {
    for (T& x : values) (*this)(x);
  }

  void tag(std::string_view four_letters) { in.tag(four_letters); }

  template <typename T, typename Fields>
  void array(std::vector<T>& values, std::size_t min_item_bytes, Fields fields) {
    values.resize(in.count(min_item_bytes));
    for (T& v : values) fields(v);
  }

  template <typename T>
  void items(std::vector<T>& values, std::size_t n) {
    values.resize(n);
    for (T& v : values) (*this)(v);
  }

  std::size_t length(std::size_t /*n*/, std::size_t min_item_bytes) {
    return in.count(min_item_bytes);
  }

  template <typename T, typename Fields>
  void optional(std::optional<T>& value, Fields fields) {
    value.reset();
    if (in.boolean()) fields(value.emplace());
  }
};

template <typename Io, typename Action>
void action_fields(Io& io, Action& a) {
  io(a.normal_force);
  io(a.tangential_force);
  io(a.rolling_torque);
  io(a.twisting_torque);
}

template <typename Io, typename Entries>
void entries_fields(Io& io, Entries& entries) {
  io.array(entries, kCachedActionBytes, [&](auto& e) {
    io(e.key);
    action_fields(io, e.action);
    io(e.cohesive);
  });
}

template <typename Io, typename Stats>
void solver_stats_fields(Io& io, Stats& s) {
  io(s.passes);
  io(s.converged);
  io(s.residual);
  io(s.contraction);
  io(s.error_estimate);
  io(s.relative_change);
  io(s.force_scale);
}

/// A run read from a format-1 file, which kept no energy budget (writing changes nothing).
void mark_energy_unknown(RunResult& r) {
  r.energy_known = false;
}

void mark_energy_unknown(const RunResult& /*r*/) {}

template <typename Io, typename Bonds>
void bond_fields(Io& io, Bonds& b) {
  io(b.pairs_formed);
  io(b.pairs_broken);
  io(b.walls_formed);
  io(b.walls_broken);
}

template <typename Io, typename Report>
void step_report_fields(Io& io, Report& r) {
  io(r.dt);
  solver_stats_fields(io, r.solver);
  auto& d = r.diagnostics;
  io(d.contacts);
  io(d.closed_contacts);
  io(d.cohesive_contacts);
  io(d.mean_overlap);
  io(d.max_overlap);
  io(d.kinetic_energy);
  io(d.max_speed);
  io(d.rms_speed);
  io(d.piston_contact_force);
  io(d.piston_imbalance);
  io(d.max_net_force);
  io(d.max_cohesive_opening_speed);
  io(d.max_cohesive_opening_per_range);
  if (io.has(2)) bond_fields(io, d.bonds);  // the energy budget's (analysis/energy_budget.hpp)
  io(r.times);
}

template <typename Io, typename Result>
void run_result_fields(Io& io, Result& r) {
  io(r.blocked);
  io(r.interrupted);
  io(r.steps);
  io(r.total_passes);
  io(r.capped_steps);
  io(r.min_dt);
  io(r.max_dt);
  io(r.repeated_steps);
  io(r.repeated_passes);
  io(r.max_overlap_seen);
  io(r.max_cohesive_opening_per_range);
  if (io.has(2)) {  // the energy budget's; a format-1 run's budget is unknown
    bond_fields(io, r.bonds);
    io(r.energy_start.piston_height);
    io(r.energy_start.kinetic_energy);
    io(r.energy_start.height_moment);
    io(r.energy_start.cohesive_energy);
    io(r.energy_known);
  } else {
    mark_energy_unknown(r);
  }
  io(r.wall_seconds);
  io(r.stage_seconds);
  step_report_fields(io, r.last);
  io.optional(r.final_solve, [&](auto& s) { solver_stats_fields(io, s); });
  io(r.probes);
  io(r.probe_passes);
  io(r.probe_seconds);
  io(r.blocked_by_probe);
  io(r.unbalanced_rest_solves);
}

/// The RUNS section: the run's result, the blocked-state window, the loop's schedule.
/// `Loop` is a RunState (writing) or a SavedRun (reading): the same member names.
template <typename Io, typename Result, typename Flag, typename Memory, typename Loop>
void run_fields(Io& io, Result& result, Flag& has_detector, Memory& m, Loop& loop) {
  io.tag("RUNS");
  run_result_fields(io, result);
  io(has_detector);
  if (has_detector) {
    io(m.clock);
    io(m.time_held);
    io(m.steps_held);
    io.array(m.entries, kWindowEntryBytes, [&](auto& e) {
      io(e.time);
      io(e.height);
      io(e.imbalance);
    });
  }
  io(loop.last_rest_check);
  io(loop.last_probe);
  io(loop.deferred_windows);
  io(loop.probing);
  io(loop.started);
  io(loop.start_time);
  io(loop.dt);
}

template <typename Io, typename WorldRef>
void world_fields(Io& io, WorldRef& world) {
  auto& b = world.bodies;
  io.tag("WRLD");
  const std::size_t n = io.length(b.position.size(), kSphereBytes);
  io.items(b.position, n);
  io.items(b.velocity, n);
  io.items(b.angular_velocity, n);
  io.items(b.radius, n);
  io.items(b.inverse_mass, n);
  io.items(b.inverse_inertia, n);
  io.items(b.external_force, n);
  io.items(b.external_torque, n);
  io.items(b.fixed, n);
  auto& piston = world.walls.piston;
  io(world.walls.bottom.enabled);
  io(piston.enabled);
  io(piston.height);
  io(piston.velocity);
  io(piston.mass);
  io(piston.force);
  io(world.box.lx);
  io(world.box.ly);
  io(world.gravity);
  io(world.time);
  io(world.step);
}

void check_ascending(const ByteReader& in, const std::vector<CachedAction>& entries,
                     std::string_view family) {
  // the warm start's merge join needs ascending keys (action_cache.hpp)
  for (std::size_t k = 1; k < entries.size(); ++k) {
    if (entries[k].key <= entries[k - 1].key) {
      in.fail(fmt::format("the {} actions are not in ascending key order", family));
    }
  }
}

/// pcg-cpp's own exact text form: multiplier, increment, state (Rng::text).
std::string rng_text(const Rng& rng) {
  return rng.text();
}

/// What no saved run holds: a World value out of its range (model/world_check.hpp), or a Δt
/// of a started run that is not finite and > 0 or that no longer advances its time.
std::optional<std::string> saved_state_problem(const SavedRun& saved) {
  if (std::optional<std::string> problem = world_problem(saved.world)) return problem;
  if (!saved.started) return std::nullopt;
  if (!std::isfinite(saved.dt) || saved.dt <= 0.0) {
    return fmt::format("the next Δt is {}, expected a finite number > 0", saved.dt);
  }
  const double time = saved.world.time;
  // a step must move the time on by about Δt, not by the rounding of a huge time
  if (std::nextafter(time, std::numeric_limits<double>::infinity()) - time > 1e-6 * saved.dt) {
    return fmt::format(
        "the time {} t0 is too large for Δt = {} t0: the time would not advance "
        "step by step",
        time, saved.dt);
  }
  if (saved.started &&
      (!std::isfinite(saved.start_time) || saved.start_time < 0.0 || saved.start_time > time)) {
    return fmt::format(
        "the run started at t = {} t0, expected a finite time from 0 to the "
        "state's {} t0",
        saved.start_time, time);
  }
  return std::nullopt;
}

Rng read_rng(ByteReader& in) {
  std::optional<Rng> rng = Rng::from_text(in.string());
  if (!rng) in.fail("the pass-order stream cannot be read back");
  return *rng;
}

}  // namespace

void write_world(ByteWriter& out, const World& world) {
  Encode io{out};
  world_fields(io, world);
}

World read_world(ByteReader& in) {
  World world;
  Decode io{in};
  world_fields(io, world);
  return world;
}

void write_actions(ByteWriter& out, const CarriedActions& last_step) {
  Encode io{out};
  io.tag("ACTS");
  entries_fields(io, last_step.pairs);
  entries_fields(io, last_step.walls);
}

ActionCache read_actions(ByteReader& in) {
  Decode io{in};
  io.tag("ACTS");
  std::vector<CachedAction> pairs;
  std::vector<CachedAction> walls;
  entries_fields(io, pairs);
  check_ascending(in, pairs, "sphere pair");
  entries_fields(io, walls);
  check_ascending(in, walls, "wall");
  ActionCache cache;
  cache.restore(pairs, walls);
  return cache;
}

namespace {

/// The state file's sections into `out`, then the FNV-1a checksum of all bytes before it.
void write_state(ByteWriter& out, std::string_view scene_toml, const World& world,
                 const StepWorkspace& work, const RunState& run) {
  out.tag(kStateFileMagic.substr(0, 4));
  out.tag(kStateFileMagic.substr(4, 4));
  out.u32(kStateFormatVersion);
  out.string(kVersion);
  out.string(kGitCommit);
  out.tag("SCEN");
  out.string(scene_toml);
  write_world(out, world);
  write_actions(out, last_step_actions(work));
  out.tag("RNGS");
  out.string(rng_text(work.solver.rng));
  Encode io{out};
  const bool has_detector = run.detector.has_value();
  const BlockedStateDetector::Memory memory =
      has_detector ? run.detector->memory() : BlockedStateDetector::Memory{};
  run_fields(io, run.result, has_detector, memory, run);
  out.tag("SUM ");
  out.u64(out.checksum());
}

}  // namespace

std::string encode_state(std::string_view scene_toml, const World& world, const StepWorkspace& work,
                         const RunState& run) {
  ByteWriter out;
  write_state(out, scene_toml, world, work, run);
  return out.bytes();
}

namespace {

/// Everything after the format version, read into `saved` (the checksum not checked).
void decode_sections(ByteReader& in, std::uint32_t format, SavedRun& saved) {
  saved.program_version = in.string();
  saved.git_commit = in.string();
  in.tag("SCEN");
  saved.scene_toml = in.string();
  saved.world = read_world(in);
  saved.actions = read_actions(in);
  in.tag("RNGS");
  saved.pass_order = read_rng(in);
  Decode io{in, format};
  bool has_detector = false;
  BlockedStateDetector::Memory memory;
  run_fields(io, saved.result, has_detector, memory, saved);
  if (has_detector) saved.detector = std::move(memory);
  in.tag("SUM ");
  in.u64();
  if (!in.at_end()) in.fail("unexpected bytes after the checksum");
}

/// Where a file whose checksum fails is damaged, as far as reading it shows: the section a
/// read of it stops in, or, when every section still reads, a changed value.
std::string damage_of(std::string_view bytes) {
  ByteReader in(bytes, "");
  static_cast<void>(in.u64());  // the magic
  const std::uint32_t format = in.u32();
  SavedRun ignored;
  try {
    decode_sections(in, format, ignored);
  } catch (const StateFileError&) {
    if (in.section().empty())
      return fmt::format("its header is damaged (before byte {})", in.offset());
    return fmt::format(
        "reading stops at byte {}, in the section '{}' (from byte {}) or where "
        "the next one should begin",
        in.offset(), in.section(), in.section_offset());
  }
  return "every section still reads: a value in it was changed";
}

}  // namespace

SavedRun decode_state(std::string_view bytes, const std::string& source) {
  ByteReader in(bytes, source);
  if (!bytes.starts_with(kStateFileMagic)) {
    in.fail("not a cdpowder state file (it does not start with CDPSTATE)");
  }
  in.tag(kStateFileMagic.substr(0, 4));
  in.tag(kStateFileMagic.substr(4, 4));
  SavedRun saved;
  saved.format_version = in.u32();
  if (!readable_state_format(saved.format_version)) {
    in.fail(fmt::format("state format {}; this build of cdpowder reads formats {} to {}",
                        saved.format_version, kOldestStateFormatVersion, kStateFormatVersion));
  }
  // the checksum before anything else: a damaged file is named as damaged, not as whatever
  // field the damage happened to hit
  if (bytes.size() < 16) in.fail("the file ends early: truncated");
  ByteReader tail(bytes.substr(bytes.size() - 8), source);
  if (tail.u64() != fnv1a64(bytes.substr(0, bytes.size() - 8))) {
    throw StateFileError(fmt::format(
        "{}: the checksum does not match: the file is truncated or damaged ({} bytes; {})", source,
        bytes.size(), damage_of(bytes)));
  }
  decode_sections(in, saved.format_version, saved);
  // a file whose checksum was fitted again after an edit: its values are checked as a
  // particles file's are, so a forged state is refused instead of run
  if (const std::optional<std::string> problem = saved_state_problem(saved)) {
    throw StateFileError(
        fmt::format("{}: {}: no run reaches this state (was the file edited?)", source, *problem));
  }
  return saved;
}

void require_same_spheres(const World& initial, const World& saved,
                          const std::string& initial_source, const std::string& saved_source) {
  const Bodies& a = initial.bodies;
  const Bodies& b = saved.bodies;
  std::string problem;
  if (a.size() != b.size()) {
    problem =
        fmt::format("{} holds {} spheres, {} {}", saved_source, b.size(), initial_source, a.size());
  } else if (initial.box.lx != saved.box.lx || initial.box.ly != saved.box.ly) {
    problem = fmt::format("{} has a cell of {} × {}, {} one of {} × {}", saved_source, saved.box.lx,
                          saved.box.ly, initial_source, initial.box.lx, initial.box.ly);
  } else {
    for (std::size_t i = 0; i < a.size(); ++i) {
      // a run never changes a radius or a fixed flag
      if (a.radius[i] != b.radius[i] || a.fixed[i] != b.fixed[i]) {
        problem = fmt::format("sphere {} has radius {} (fixed {}) in {}, {} (fixed {}) in {}", i,
                              b.radius[i], b.fixed[i], saved_source, a.radius[i], a.fixed[i],
                              initial_source);
        break;
      }
    }
  }
  if (!problem.empty()) {
    throw StateFileError(
        fmt::format("{}: the saved run is not the run of these files: {}", saved_source, problem));
  }
}

void save_state(const std::filesystem::path& path, std::string_view scene_toml, const World& world,
                const StepWorkspace& work, const RunState& run) {
  // streamed: a checkpoint of 10⁶ spheres is never held whole beside the state
  write_file_atomically(path, [&](OutputSink& sink) {
    ByteWriter out(sink);
    write_state(out, scene_toml, world, work, run);
    out.flush();
  });
}

namespace {

/// Opens a state file for reading and returns its size in bytes. Throws StateFileError.
std::uintmax_t open_state_file(const std::filesystem::path& path, std::ifstream& file) {
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  file.open(path, std::ios::binary);
  if (error || !file) {
    throw StateFileError(fmt::format("{}: cannot open the state file{}", path.string(),
                                     error ? ": " + error.message() : std::string()));
  }
  return size;
}

}  // namespace

SavedRun load_state(const std::filesystem::path& path) {
  std::ifstream file;
  const std::uintmax_t size = open_state_file(path, file);
  std::string bytes(static_cast<std::size_t>(size), '\0');
  file.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (static_cast<std::size_t>(file.gcount()) != bytes.size()) {
    throw StateFileError(fmt::format("{}: cannot read the state file", path.string()));
  }
  return decode_state(bytes, path.string());
}

StateHeader read_state_header(const std::filesystem::path& path) {
  std::ifstream file;
  const std::uintmax_t size = open_state_file(path, file);
  // the fields one by one from the stream: the rest of the file is never read
  std::string bytes;
  const auto take = [&](std::uintmax_t n) {
    if (n > size - std::min<std::uintmax_t>(size, bytes.size())) {
      ByteReader(bytes, path.string()).fail("the file ends early: truncated");
    }
    const std::size_t had = bytes.size();
    bytes.resize(had + static_cast<std::size_t>(n));
    file.read(bytes.data() + had, static_cast<std::streamsize>(n));
  };
  const auto length_and_text = [&] {
    take(8);
    ByteReader length(std::string_view(bytes).substr(bytes.size() - 8), path.string());
    take(length.u64());
  };
  take(kStateFileMagic.size() + 4);
  ByteReader start(bytes, path.string());
  if (!bytes.starts_with(kStateFileMagic)) {
    start.fail("not a cdpowder state file (it does not start with CDPSTATE)");
  }
  StateHeader header;
  start.tag(kStateFileMagic.substr(0, 4));
  start.tag(kStateFileMagic.substr(4, 4));
  header.format_version = start.u32();
  if (!readable_state_format(header.format_version)) return header;
  length_and_text();
  length_and_text();
  take(4);
  length_and_text();
  ByteReader in(bytes, path.string());
  in.tag(kStateFileMagic.substr(0, 4));
  in.tag(kStateFileMagic.substr(4, 4));
  in.u32();
  header.program_version = in.string();
  header.git_commit = in.string();
  in.tag("SCEN");
  header.scene_toml = in.string();
  return header;
}

bool written_by_another_build(std::string_view program_version, std::string_view git_commit) {
  return program_version != kVersion || git_commit != kGitCommit;
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
  work.last_step_in_contacts = false;
  work.solver.rng = saved.pass_order;
}

}  // namespace cdpowder
